//! Deliberate failures, injected into a run to test that the supervisor catches them
//! (tests/runs/threads.rs): a thread that panics, stalls, or runs slow.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::rt::health::ThreadName;

/// A deliberate failure, to test that the supervisor catches it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Injection {
    pub thread: ThreadName,
    pub at_s: f64,
    pub action: Fail,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fail {
    Panic,
    /// Stop beating (hang) until the run ends.
    Stall,
    /// Make every tick this much longer (supervisor only).
    Slow {
        ms: u64,
    },
    /// Stall once, for this long, as a hung card read would (supervisor only).
    Pause {
        ms: u64,
    },
}

impl Injection {
    /// Fail now, from the thread named.
    pub(crate) fn strike(&self, stop: &AtomicBool) {
        match self.action {
            Fail::Panic => panic!("injected failure of the {} thread", self.thread.label()),
            Fail::Stall => {
                while !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(10));
                }
            }
            Fail::Slow { ms } | Fail::Pause { ms } => std::thread::sleep(Duration::from_millis(ms)),
        }
    }
}
