//! The bus between real processes on loopback: the robot program, the bus tools, the
//! simulated peers, the off-board recorder, the ROS 2 bridge and the cluster's master
//! and launchers,
//! each test on ports of its own.

#[path = "../common/mod.rs"]
mod common;

mod bus;
mod cluster;
mod ros2;

/// The flood tests load the machine on purpose (processes that flood the robot with
/// requests and huge payloads): beside the others, when the tests ran six at a time, a
/// flood test's HALT came back late. A flood test takes the machine whole; every other
/// test here shares it.
static MACHINE: std::sync::RwLock<()> = std::sync::RwLock::new(());

fn shared_machine() -> std::sync::RwLockReadGuard<'static, ()> {
    MACHINE
        .read()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn whole_machine() -> std::sync::RwLockWriteGuard<'static, ()> {
    MACHINE
        .write()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}
