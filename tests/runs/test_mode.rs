//! Entering Test on the real threads says, on the console, that the robot must be on
//! its stand and that nothing moves unless held: the binary as a user starts it, with
//! the scripted operator entering Test. (What is held, and what reaches the amplifiers,
//! is core/tests/lockstep/hold_to_run.rs, through the emulated cards.)

use crate::common;

use common::mechweed;

#[test]
fn entering_test_says_the_robot_must_be_on_its_stand() {
    let dir = tempfile::tempdir().unwrap();
    let out = mechweed()
        .args(["run", "--headless", "--duration", "2"])
        .args(common::test_run_settings(dir.path()))
        .args(["--set", "sim.events=1 mode test"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout
        .lines()
        .find(|l| l.contains("test mode: the robot must be on its stand"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("only while Hold to run (or the dead-man) is held"),
        "{line}"
    );
    assert_eq!(out.status.code(), Some(0), "{stdout}");
}
