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
use crate::modes::{Mode, Request};
use crate::operator::OperatorScript;

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

    /// The script has steps left to take or an answer to wait for.
    pub fn busy(&self) -> bool {
        !matches!(self.waiting, Waiting::Nothing) || self.script.has_more()
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
