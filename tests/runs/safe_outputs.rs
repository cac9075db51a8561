//! `mechweed safe`, and a `run` or `probe` that refuses robot.ini: the cards get their
//! safe outputs from [hw] and [io] alone, whatever the other sections say, so that a
//! robot a killed run left driving stops. On a computer without the cards each must
//! have gone to the cards and say which one it could not reach (the emulated cards'
//! side is src/programs/safe.rs's test); on one with them, these tests stay off the
//! real robot's cards.

use crate::common;

use common::mechweed;

/// A robot.ini for the real robot whose [pid.left] is broken, written into `dir`.
fn broken_outside_hw_and_io(dir: &std::path::Path) -> std::path::PathBuf {
    let text = mechweed::config::DEFAULT_INI
        .replace("backend = sim", "backend = cards")
        .replace("[pid.left]", "[pid.left]\nkp_typo = 3");
    let path = dir.join("robot.ini");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn safe_run_and_probe_go_to_the_cards_from_a_file_broken_outside_hw_and_io() {
    if common::has_mcc_cards() {
        eprintln!("skipped: this computer has the robot's cards, which these runs would open");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let file = broken_outside_hw_and_io(dir.path());
    for args in [
        vec!["safe", "--config"],
        vec!["run", "--headless", "--config"],
        vec!["probe", "--config"],
    ] {
        let out = mechweed().args(&args).arg(&file).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("no PCI-DAS08 (PCI id 1307:0029) found"),
            "{args:?} did not go to the cards: {stderr}"
        );
        if args[0] != "safe" {
            assert!(stderr.contains("kp_typo"), "{args:?}: {stderr}");
        }
    }
}

#[test]
fn safe_with_a_broken_io_says_that_it_wrote_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let text = mechweed::config::DEFAULT_INI.replace(
        "amp_left_v = dda06 ao 0, scale 1",
        "amp_left_v = dda06 ao 9",
    );
    let file = dir.path().join("robot.ini");
    std::fs::write(&file, text).unwrap();
    let out = mechweed()
        .args(["safe", "--config"])
        .arg(&file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("amp_left_v"), "{stderr}");
    assert!(stderr.contains("no safe outputs written"), "{stderr}");
}

#[test]
fn a_refused_run_on_the_simulated_robot_does_not_go_to_any_card() {
    let dir = tempfile::tempdir().unwrap();
    let text = mechweed::config::DEFAULT_INI.replace("[pid.left]", "[pid.left]\nkp_typo = 3");
    let file = dir.path().join("robot.ini");
    std::fs::write(&file, text).unwrap();
    let out = mechweed()
        .args(["run", "--headless", "--config"])
        .arg(&file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("kp_typo"), "{stderr}");
    assert!(!stderr.contains("PCI-DAS08"), "{stderr}");
}
