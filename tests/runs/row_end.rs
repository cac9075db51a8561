//! The end of a row stops the robot with a notice; a row lost before its end is still a
//! fault. Through the program, on the simulated robot and field.

use crate::common;

use common::{mechweed, text};

/// `mechweed run --headless --mode autonomous` at 1 m/s for 20 s with `set` items;
/// its stdout and its JSON report.
fn drive_a_row(set: &[&str]) -> (String, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let mut cmd = mechweed();
    cmd.args([
        "run",
        "--headless",
        "--mode",
        "autonomous",
        "--duration",
        "20",
    ])
    .args(common::test_run_settings(dir.path()))
    .args(["--set", "steer.speed_mps=1.0", "--report"])
    .arg(&report);
    for item in set {
        cmd.args(["--set", item]);
    }
    let out = cmd.output().unwrap();
    let stdout = text(&out.stdout);
    let json = std::fs::read_to_string(&report).unwrap();
    let report: serde_json::Value = serde_json::from_str(&json).unwrap();
    // A run that ended in Fault exits with 3, any other with 0.
    let want = if report["mode_final"] == "fault" {
        3
    } else {
        0
    };
    assert_eq!(
        out.status.code(),
        Some(want),
        "{stdout}\n{}",
        text(&out.stderr)
    );
    (stdout, report)
}

/// The distance N in "end of row after N m", from the first line that has it.
fn end_of_row_m(stdout: &str) -> Option<f64> {
    let (_, rest) = stdout.split_once("end of row after ")?;
    rest.split_once(" m")?.0.parse().ok()
}

#[test]
fn the_end_of_the_simulated_row_stops_the_robot_in_halt_with_a_notice_not_a_fault() {
    // An 8 m row: the tool, 0.4 m behind the rear axle, passes its end after 8.4 m,
    // while the plants (and the camera's row) go on 2 m further.
    let (stdout, report) = drive_a_row(&["sim.row_length_m=8"]);
    let ended_m = end_of_row_m(&stdout).unwrap_or_else(|| panic!("no end of row in\n{stdout}"));
    assert!((8.35..8.6).contains(&ended_m), "ended after {ended_m} m");
    assert!(stdout.contains("mode: autonomous -> halt"), "{stdout}");
    assert!(stdout.contains("faults: none"), "{stdout}");
    assert_eq!(report["mode_final"], "halt", "{report}");
    let notices = report["notices"].as_array().unwrap();
    assert_eq!(notices.len(), 1, "{report}");
    assert!(
        notices[0]["what"]
            .as_str()
            .unwrap()
            .starts_with("end of row after")
    );
    // It stopped there: the brakes hold it within half a metre of the end.
    let distance_m = report["distance_m"].as_f64().unwrap();
    assert!(distance_m < ended_m + 0.5, "rolled on to {distance_m} m");
}

#[test]
fn a_row_lost_before_its_set_length_is_still_a_fault() {
    // The row is said to be 20 m long; the field's plants end after 10 m.
    let (stdout, report) = drive_a_row(&["sim.row_length_m=8", "supervisor.row_length_m=20"]);
    assert_eq!(end_of_row_m(&stdout), None, "{stdout}");
    assert!(stdout.contains("FAULT: camera sees no row"), "{stdout}");
    assert_eq!(report["mode_final"], "fault", "{report}");
}

#[test]
fn a_set_row_length_ends_the_row_there_on_the_simulated_field_too() {
    let (stdout, _) = drive_a_row(&["sim.row_length_m=60", "supervisor.row_length_m=6"]);
    let ended_m = end_of_row_m(&stdout).unwrap_or_else(|| panic!("no end of row in\n{stdout}"));
    assert!((6.35..6.6).contains(&ended_m), "ended after {ended_m} m");
}
