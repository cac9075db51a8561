//! The supervisor's own loop, doing no work, for `mechweed doctor`'s latency test: how
//! late this PC wakes a thread at the supervisor's rate and priority (as cyclictest
//! does, with the program's own clock and sleep).

use super::{LoopSummary, Periodic, set_this_thread};

/// Run an empty loop at `rate_hz` for `duration_s` on a thread of its own at
/// `priority` (SCHED_FIFO; 0 = normal) pinned to `cpu` (-1 = any): its figures, and
/// the system's refusal of the priority if it refused.
pub fn empty_loop(
    rate_hz: f64,
    priority: u8,
    cpu: i32,
    duration_s: f64,
) -> (LoopSummary, Option<String>) {
    let ticks = (rate_hz * duration_s).ceil().max(1.0) as u64;
    let thread = std::thread::Builder::new()
        .name("latency".into())
        .spawn(move || {
            let refused = set_this_thread(priority, cpu);
            let mut periodic = Periodic::new(rate_hz);
            for _ in 0..ticks {
                periodic.wait();
                periodic.done();
            }
            (periodic.stats.summary(), refused)
        })
        .expect("cannot start the latency test's thread");
    thread.join().unwrap_or_default()
}
