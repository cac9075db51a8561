//! `mechweed bench ...`: the benchmarks, one file each. `loop` (control_loop.rs) times
//! the real threads; `rows` (rows.rs) scores row following in simulated time, with the
//! bound no filter and law can beat (bound.rs) and the filter's own floor (floor.rs);
//! halt.rs measures the time from a key press to the supervisor's HALT; `ros2`
//! (ros2.rs) the ROS 2 bridge's latency and CPU.

pub mod control_loop;
pub mod halt;
pub mod ros2;
pub mod rows;

use std::process::ExitCode;

use clap::Subcommand;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// The real threads on the simulated robot: loop lateness and execution time.
    Loop(control_loop::LoopArgs),
    /// The row-following benchmark: 3 rows x 3 speeds, in simulated time.
    Rows(rows::RowsArgs),
    /// The ROS 2 bridge on loopback: latency from the robot's tick to a ROS client, and
    /// the bridge's CPU.
    Ros2(ros2::Ros2BenchArgs),
}

/// The nearest-rank `p` percentile (0..1) of `sorted`, ascending; NaN when empty.
pub(crate) fn nearest_rank(sorted: &[f64], p: f64) -> f64 {
    let k = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len().max(1));
    sorted.get(k - 1).copied().unwrap_or(f64::NAN)
}

/// Runs the benchmark asked for.
pub fn bench(command: BenchCommand) -> ExitCode {
    match command {
        BenchCommand::Loop(args) => control_loop::program(args),
        BenchCommand::Rows(args) => rows::program(args),
        BenchCommand::Ros2(args) => ros2::program(args),
    }
}
