//! The scripted operator in the GUI (`--mode` and the operator actions of [sim]
//! events): the same `OperatorScript` the console follows, asked once per pass.
//!
//! The GUI does not wait for answers, so the script would otherwise ask again while its
//! last request is on its way (say Power up twice, and get "already on" back). After a
//! request it waits for the answer, then for a status from a later supervisor tick: the
//! answer leaves the supervisor before the status that shows its effect.

use mechweed_hw::sim::SimEvent;

use super::requests::{AskId, Requests};
use super::view::View;
use crate::state::modes::{Mode, Request};
use crate::state::operator::OperatorScript;

/// A status from a later tick comes within a supervisor period; look again after, s.
const STATUS_LOOK_S: f64 = 0.05;

enum Waiting {
    Nothing,
    Answer(AskId),
    /// The answer came when the status was from this tick.
    StatusAfter(u64),
}

pub struct GuiScript {
    script: OperatorScript,
    waiting: Waiting,
}

impl GuiScript {
    pub fn new(events: &[SimEvent], start_mode: Mode) -> GuiScript {
        GuiScript {
            script: OperatorScript::new(events, start_mode),
            waiting: Waiting::Nothing,
        }
    }

    /// When the script needs a pass of its own, s from `now_s`: soon while it waits for
    /// a status from after an answer, at the time of its next action, or never (the
    /// start mode is pursued on the passes that a change of status brings anyway).
    pub(crate) fn next_pass_in_s(&self, now_s: f64) -> Option<f64> {
        match self.waiting {
            Waiting::StatusAfter(_) => Some(STATUS_LOOK_S),
            // The GUI passes while an answer is awaited (`Requests::awaiting`).
            Waiting::Answer(_) => None,
            Waiting::Nothing => self.script.next_action_s().map(|t_s| t_s - now_s),
        }
    }

    /// Every pass, after the answers were taken and then the view: ask for what is due.
    pub fn pass(&mut self, view: &View, requests: &mut Requests) {
        match self.waiting {
            Waiting::Answer(id) if requests.is_open(id) => return,
            Waiting::Answer(_) => {
                // Every answer taken so far was taken before this view.
                self.waiting = Waiting::StatusAfter(view.status.tick);
                return;
            }
            Waiting::StatusAfter(tick) if view.status.tick <= tick => return,
            _ => self.waiting = Waiting::Nothing,
        }
        if let Some(request) = self.script.due(view.now_s, &view.status) {
            let what = match request {
                Request::Mode(m) => format!("operator script: mode {m}"),
                Request::PowerUp => "operator script: power up".to_string(),
                other => format!("operator script: {other:?}"),
            };
            self.waiting = Waiting::Answer(requests.ask(request, &what));
        }
    }
}
