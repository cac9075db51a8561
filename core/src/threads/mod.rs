//! The bodies of the two periodic threads a run starts: the supervisor thread (it owns
//! the hardware) and the steer thread. Each owns its state and meets the others only
//! through protected objects and channels; the program's src/run/ starts them and collects them.

pub mod backend;
pub mod lockstep;
mod steer;
mod supervisor;

use std::time::Duration;

use crate::rt::{LoopSummary, Periodic};
use crate::state::Writer;

pub use steer::{SteerThread, SteerWires};
pub use supervisor::{SafeOnDrop, SupervisorThread, SupervisorWires};

/// Publish `value` without blocking on a reader of lower priority that holds the lock:
/// tried again after a short sleep (the reader then runs and lets go), for at most a
/// millisecond; a value still not published is replaced by the next tick's.
fn publish_soon<T: Copy>(writer: &Writer<T>, value: &T, busy: &mut u64) {
    for _ in 0..10 {
        if writer.try_publish(value) {
            return;
        }
        *busy += 1;
        std::thread::sleep(Duration::from_micros(100));
    }
}

/// Publish a loop's figures four times a second of the monotonic clock (percentiles
/// cost a few microseconds), never waiting for a reader (the GUI, the console) that holds the
/// lock: then they go out at the next tick.
fn publish_figures_now_and_then(
    periodic: &mut Periodic,
    figures: &Writer<LoopSummary>,
    pending: &mut bool,
) {
    if periodic.figures_due() || *pending {
        *pending = !figures.try_publish(&periodic.stats.summary());
        if *pending {
            periodic.stats.locks_busy += 1;
        }
    }
}

/// The loop's figures as its thread ends, published once more (waiting for the lock:
/// no tick is timed any more) and returned: every reader (the GUI, the console, the
/// bus) ends on the very figures the run's summary prints, not on ones up to a quarter
/// of a second older (rt/liu_layland.rs).
fn final_figures(periodic: &Periodic, figures: &Writer<LoopSummary>) -> LoopSummary {
    let summary = periodic.stats.summary();
    figures.publish(&summary);
    summary
}
