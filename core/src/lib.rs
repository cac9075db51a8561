//! The controller's core: everything that decides what the robot does, and nothing
//! that talks to a network or draws a window. It builds and tests without the bus
//! (Zenoh) or the GUI (egui), so a change to a rule here is checked in seconds.
//!
//! - `config`: robot.ini, read and checked; every setting the core obeys.
//! - `rt`: real time: periodic loops and their figures, priorities, heartbeats and
//!   the panic hook, deliberate failures for tests.
//! - `state`: what the threads share: the protected objects, the modes, the status,
//!   the fault causes, the requests and the words the operator sees.
//! - `supervisor`: the 100 Hz tick: inputs, measurements, modes, regulators, outputs.
//! - `faults`: every fault check the supervisor makes, in one file.
//! - `steer`: the 10 Hz steer thread: the row filter, its gate and the steering law.
//! - `camlink`: the serial link to the camera computer and its watchdog.
//! - `gnss`: the GNSS receiver's link, the fixes and the row maps.
//! - `record`: the run's record (MCAP and CSV), read back and summed up.
//! - `bench`: the row-following benchmark and the bounds it is held against.
//! - `threads`: how the loops run: on real threads in real time, or in lockstep on
//!   simulated time, with the same tick functions.

pub mod bench;
pub mod camlink;
pub mod config;
pub mod faults;
pub mod gnss;
pub mod record;
pub mod rt;
pub mod state;
pub mod steer;
pub mod supervisor;
pub mod threads;

/// `println!` for what a run prints on stdout, where a closed stdout (a pipe to `head`
/// that has ended) is no error: the run goes on, and ends with its report and a whole
/// record, instead of a thread panicking on the broken pipe.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}
