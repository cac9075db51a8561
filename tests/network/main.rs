//! The bus between real processes on loopback: the robot program, the bus tools, the
//! simulated peers, the off-board recorder and the cluster's master and launchers,
//! each test on ports of its own.

#[path = "../common/mod.rs"]
mod common;

mod bus;
mod cluster;
