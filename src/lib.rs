//! mechweed: the control program of an agricultural weeding robot.
//!
//! Threads and what each owns: the supervisor (supervisor/, faults/, pid.rs), the steer
//! thread (steer/), the camera link (camlink/); run.rs starts them on real time,
//! lockstep.rs runs the same tick functions on simulated time. docs/architecture.md
//! shows the layers. Exported: what the program, the tests and the benchmarks use;
//! the rest stays inside.

mod backend;
pub mod bench_bound;
pub mod bench_floor;
mod bench_halt;
pub mod bench_loop;
pub mod bench_rows;
pub mod bus;
pub mod bus_record;
pub mod bus_tools;
pub mod camlink;
pub mod camsim;
pub mod camsim_main;
pub mod cluster;
pub mod config;
pub mod console;
pub mod cross_track;
pub mod fault_cause;
mod faults;
pub mod gamepad;
pub mod gnss;
pub mod gnsssim;
pub mod gui;
pub mod health;
pub mod inject;
pub mod keys;
pub mod lockstep;
mod measure;
pub mod modes;
pub mod operator;
mod pid;
pub mod probe;
pub mod record;
pub mod replay;
pub mod report;
pub mod request_channel;
pub mod rowmap;
pub mod rt;
pub mod run;
pub mod state;
pub mod status;
pub mod steer;
pub mod steering;
mod supervisor;
pub mod teach_command;
mod threads;

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
