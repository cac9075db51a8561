//! mechweed: the control program of an agricultural weeding robot.
//!
//! Three crates, one per layer (docs/architecture.md). `mechweed_hw` is the hardware
//! behind one trait (the I/O cards or the simulated robot); `mechweed_core` is the
//! controller (supervisor, steering, filter, faults, records), with no network and no
//! window. This crate adds what a person and other computers meet:
//!
//! - `run`: starts a run: the hardware, real time, the records, the bus, the threads.
//! - `console`: the run on a terminal: status lines, Ctrl-C, the closing report.
//! - `gui`: the operator GUI (egui), on the robot or, fed by the bus, on a laptop.
//! - `gamepad`: a gamepad as the joystick.
//! - `bus`: the data flows to other programs and machines (Zenoh), and who may act.
//! - `cluster`: one graph file starts the programs of several machines.
//! - `replay`: a record's inputs through the supervisor again.
//! - `ros2`: the robot's flows as ROS 2 topics and bags (rmw_zenoh's wire format).
//! - `programs`: each command of the `mechweed` program, with its options.
//!
//! The core's modules are re-exported here, so that `mechweed::config` and
//! `mechweed_core::config` are one module.

pub mod bus;
mod cluster;
pub mod console;
pub mod gamepad;
pub mod gui;
pub mod programs;
pub mod replay;
pub mod ros2;
pub mod run;

pub use mechweed_core::{
    bench, camlink, config, faults, gnss, record, rt, say, state, steer, supervisor, threads,
};
