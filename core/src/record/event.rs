//! What happened between ticks, in words: faults with their causes, mode changes,
//! notices, and ticks the record could not keep. Events are rare, so they travel on
//! their own queue and are not lost when the tick queue is full.

use super::request_text::event_text;
use crate::state::fault_cause::FaultCause;
use crate::state::modes::{Mode, Refusal, Request};
use crate::state::status::Notice;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventKind {
    Mode {
        from: Mode,
        to: Mode,
    },
    Fault(FaultCause),
    Notice(Notice),
    /// Ticks the queue had no room for (the disk was slow), just before this event.
    Dropped {
        ticks: u64,
    },
    /// An operator's request, handled just before the tick, and the answer.
    Request {
        request: Request,
        answer: Result<(), Refusal>,
    },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordEvent {
    pub t_s: f64,
    pub tick: u64,
    pub kind: EventKind,
}

/// The columns of an event, in file order (CSV header and JSON keys).
pub const EVENT_COLUMNS: [&str; 4] = ["t_s", "tick", "kind", "text"];

impl RecordEvent {
    /// One word for the kind: mode, fault, notice, dropped or request.
    pub(crate) fn kind_name(&self) -> &'static str {
        match self.kind {
            EventKind::Mode { .. } => "mode",
            EventKind::Fault(_) => "fault",
            EventKind::Notice(_) => "notice",
            EventKind::Dropped { .. } => "dropped",
            EventKind::Request { .. } => "request",
        }
    }

    /// The event as one JSON object with the keys of `EVENT_COLUMNS`.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "t_s": self.t_s,
            "tick": self.tick,
            "kind": self.kind_name(),
            "text": self.text(),
        })
    }

    /// What happened, as the console says it.
    pub fn text(&self) -> String {
        match self.kind {
            EventKind::Mode { from, to } => format!("{from} -> {to}"),
            EventKind::Fault(cause) => cause.to_string(),
            EventKind::Notice(notice) => notice.to_string(),
            EventKind::Dropped { ticks } => {
                format!("{ticks} ticks not recorded: the recorder fell behind")
            }
            EventKind::Request { request, answer } => event_text(&request, &answer),
        }
    }
}
