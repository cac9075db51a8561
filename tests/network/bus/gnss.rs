//! The status flow of a robot steering by the fused row: which sensors steer, the GNSS
//! fix and the row filter's estimate, as a laptop watching on the bus sees them.

use super::{Robot, json_lines};

#[test]
fn a_fused_run_publishes_which_sensors_steer_the_fix_and_the_filter() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&[
        "--mode",
        "autonomous",
        "--duration",
        "10",
        "--set",
        "gnss.port=sim",
        "--set",
        "steer.source=fused",
    ]);
    // Ten statuses a second: 5 s reaches autonomous with the filter running.
    let status = robot.bus(&["echo", "status", "--count", "50"]);
    let (stdout, _, _) = robot.finish();
    let status = json_lines(&status);
    let last = &status.last().expect("statuses came")["payload"];
    assert_eq!(last["mode"], "autonomous", "{last}\n{stdout}");
    assert_eq!(last["steering"], "fused", "{last}");
    // The simulated receiver: RTK fixed (GGA quality 4), with its satellites and s.d.
    let gnss = &last["gnss"];
    assert_eq!(gnss["quality"], 4, "{gnss}");
    assert!(gnss["satellites"].as_u64().unwrap() > 4, "{gnss}");
    let sd_m = gnss["sd_m"].as_f64().unwrap();
    assert!(sd_m > 0.0 && sd_m < 0.05, "{gnss}");
    assert!(gnss["lat_deg"].as_f64().unwrap().abs() <= 90.0, "{gnss}");
    // The filter holds the row within centimetres and says how sure it is.
    let filter = &last["filter"];
    let offset_sd_m = filter["offset_sd_m"].as_f64().unwrap();
    assert!(offset_sd_m > 0.0 && offset_sd_m < 0.05, "{filter}");
    assert!(filter["offset_m"].as_f64().unwrap().abs() < 0.1, "{filter}");
    assert!(filter["gnss_rejected"].is_u64(), "{filter}");
}

#[test]
fn a_camera_run_publishes_no_filter_and_no_fix() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "4"]);
    let status = robot.bus(&["echo", "status", "--count", "2"]);
    robot.finish();
    let status = json_lines(&status);
    let p = &status[0]["payload"];
    assert_eq!(p["steering"], "camera", "{p}");
    assert_eq!(p["gnss"]["quality"], 0, "{p}");
    assert!(p["gnss"]["sd_m"].is_null(), "{p}");
    assert!(p["filter"].is_null(), "{p}");
}
