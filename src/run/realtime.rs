//! Real-time scheduling at the start of a run, and what the operator must be told when
//! the real robot runs without it.

use crate::config::{Backend, RtSettings};
use crate::rt;

/// Lock memory and find out whether real-time priorities are granted: one warning for
/// each thing the system refuses, printed once, and the program runs on. Also returns
/// the refusal of the priorities on its own, as the threads then run without them.
pub(super) fn rt_setup(rt: &RtSettings) -> (Vec<String>, Option<String>) {
    let priorities_refused = rt::priorities_allowed(rt);
    let warnings: Vec<String> = [
        rt.lock_memory.then(rt::lock_memory).flatten(),
        priorities_refused.clone(),
    ]
    .into_iter()
    .flatten()
    .collect();
    for warning in &warnings {
        tracing::warn!("{warning}");
    }
    (warnings, priorities_refused)
}

/// What the operator must see at all times when the real robot drives without
/// real-time priorities, refused by the system or set to 0 in [rt] (the status line, the
/// GUI's header); None when it has them or is the simulated robot.
pub fn not_realtime(
    backend: Backend,
    rt: &RtSettings,
    priorities_refused: Option<&str>,
) -> Option<String> {
    if backend != Backend::Cards {
        return None;
    }
    if let Some(why) = priorities_refused {
        return Some(format!(
            "NOT REAL-TIME: the robot drives without real-time priorities ({why})"
        ));
    }
    (rt.supervisor_priority == 0).then(|| {
        "NOT REAL-TIME: [rt] supervisor_priority = 0, the robot drives at normal priority"
            .to_string()
    })
}
