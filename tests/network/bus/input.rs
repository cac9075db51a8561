//! What comes into the robot over the bus: row estimates from a vision program, and
//! bad input of every kind.

use std::process::Stdio;
use std::time::Duration;

use mechweed::programs::bus::tools::Tool;
use zenoh::Wait;

use super::Robot;
use crate::common::{mechweed, text};

/// The tool's cross-track, m, at each recorded tick where the robot drove autonomously
/// past its first metre, read with the program's own record reader.
fn cross_track_m(folder: &std::path::Path) -> Vec<f64> {
    let newest = mechweed::record::keep::latest(folder).expect("a record");
    let columns = ["sim_tool_cross_track_m", "mode", "sim_distance_m"];
    let ticks = mechweed::record::read::read(&newest, &columns)
        .unwrap()
        .ticks;
    let col = |name| ticks.column(name).unwrap();
    let (cross, mode, distance) = (col(columns[0]), col(columns[1]), col(columns[2]));
    (0..ticks.rows.len())
        .filter(|&row| ticks.text(row, mode) == "autonomous")
        .filter(|&row| ticks.number(row, distance).ok().flatten().unwrap_or(0.0) > 1.0)
        .filter_map(|row| ticks.number(row, cross).ok().flatten())
        .collect()
}

/// Drive a straight row on camsim's rows, over the bus or over its TCP link, and
/// silence camsim after 8 s: the robot's stdout and its tool's cross-track, m. The
/// plant drives straight (no slip, matched motors), so camsim's rows, which say "on
/// the row" with camera noise, are the field's rows too.
fn drive_on_camsim(over_bus: bool) -> (String, Vec<f64>) {
    let mut set = vec![
        "--duration",
        "14",
        "--set",
        "sim.row=straight",
        "--set",
        "sim.side_slip_deg=0",
        "--set",
        "sim.motor_mismatch=0",
        // In autonomous once camsim sends (the rows' time-out would fault it before).
        "--set",
        "sim.events=3 power_up, 4 mode autonomous",
    ];
    let tcp_port = super::free_port();
    let tcp_listen = format!("127.0.0.1:{tcp_port}");
    let camera = if over_bus {
        "camera.port=bus".to_string()
    } else {
        format!("camera.port=tcp://{tcp_listen}")
    };
    set.extend(["--set", &camera]);
    let mut camsim = mechweed();
    camsim.arg("camsim").stdout(Stdio::piped());
    let (robot, mut camsim) = if over_bus {
        let robot = Robot::start(&set);
        camsim.args(["--bus", "--connect", &robot.endpoint]);
        (robot, camsim.spawn().unwrap())
    } else {
        let camsim = camsim.args(["--listen", &tcp_listen]).spawn().unwrap();
        (Robot::start(&set), camsim)
    };
    std::thread::sleep(Duration::from_secs(8));
    camsim.kill().unwrap();
    let camsim_out = text(&camsim.wait_with_output().unwrap().stdout);
    assert!(
        camsim_out.contains(if over_bus { "published" } else { "streaming" }),
        "{camsim_out}"
    );
    let (stdout, _, folder) = robot.finish();
    (stdout, cross_track_m(folder.path()))
}

/// The largest |x| in cm.
fn worst_cm(values_m: &[f64]) -> f64 {
    values_m.iter().fold(0.0f64, |w, c| w.max(c.abs())) * 100.0
}

#[test]
fn camsim_on_the_bus_steers_as_on_its_serial_link_and_its_silence_faults_the_robot() {
    let _machine = crate::shared_machine();
    let serial = std::thread::spawn(|| drive_on_camsim(false));
    let (stdout, bus_m) = drive_on_camsim(true);
    let (serial_stdout, serial_m) = serial.join().unwrap();
    // Driving on the bus's rows, then the link's own fault when they stop.
    assert!(stdout.contains("FAULT: camera link lost"), "{stdout}");
    assert!(
        serial_stdout.contains("FAULT: camera link lost"),
        "{serial_stdout}"
    );
    // At least a second of driving past the first metre: about 2 s, less when a busy
    // machine starts the programs late (camsim stops 8 s after the robot started).
    assert!(
        bus_m.len() > 100 && serial_m.len() > 100,
        "drove {} and {} ticks",
        bus_m.len(),
        serial_m.len()
    );
    let (bus_cm, serial_cm) = (worst_cm(&bus_m), worst_cm(&serial_m));
    eprintln!(
        "worst tool cross-track: {bus_cm:.2} cm on the bus, {serial_cm:.2} cm on the serial link"
    );
    // Each run sees its own stretch of camsim's noise: the worst of a few metres varies
    // from run to run (0.4 to 2.1 cm on the bus, 0.4 to 0.6 cm on the serial link, on
    // this machine); a bus that delayed or lost rows would leave the row by far more.
    assert!(
        bus_cm < 3.0 && bus_cm < serial_cm + 2.5,
        "worst {bus_cm:.2} cm off the row on the bus, {serial_cm:.2} cm on the serial link"
    );
}

#[test]
fn bad_input_on_the_bus_is_answered_with_what_is_wrong_and_changes_nothing() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&[
        "--duration",
        "6",
        "--set",
        "bus.accept_requests=operator",
        "--set",
        "camera.port=bus",
    ]);
    let tool = Tool::connect(&robot.endpoint, "mechweed", false, None).unwrap();
    let asked = |key: &str, payload: &str| {
        tool.ask(key, Some(payload.to_string()))
            .expect_err("bad input is answered with an error")
    };
    assert!(asked("request", "halt please").contains("not JSON"));
    assert!(asked("request", r#"{"request": 7}"#).contains("must be a word"));
    assert!(asked("request", r#"{"request": "jump"}"#).contains("\"jump\" is not a request"));
    assert!(
        asked("config/pid.left/kp", r#"{"value": 3}"#).contains("\"value\" is not a field here")
    );
    let range = tool
        .ask("config/steer/speed_mps", Some(r#"{"set": "-4"}"#.into()))
        .unwrap_err();
    assert!(range.contains("[steer] speed_mps"), "{range}");
    assert!(asked("config/steer/nope", "").contains("not a setting"));
    // Nothing was changed by any of it.
    let speed = tool.ask("config/steer/speed_mps", None).unwrap();
    assert!(speed.contains("\"value\":\"0.5\""), "{speed}");
    // Row estimates no camera could see are counted and named, never steered by.
    let session = mechweed::bus::session::open(
        mechweed::bus::Role::Tool {
            connect: vec![robot.endpoint.clone()],
            wait: false,
        },
        None,
    )
    .unwrap();
    for bad in [
        "not json",
        r#"{"seq": 1, "angle_rad": 3.0, "offset_m": 0, "quality": 90}"#,
        r#"{"seq": 1, "angle_rad": 0, "offset_m": 0, "quality": 900}"#,
    ] {
        session.put("mechweed/camera/row", bad).wait().unwrap();
    }
    std::thread::sleep(Duration::from_millis(500));
    let (stdout, stderr, _) = robot.finish();
    assert!(
        stderr.contains("row estimate refused: the payload is not JSON"),
        "{stderr}"
    );
    assert!(
        stderr.contains("angle_rad 3 is beyond what the camera can see"),
        "{stderr}"
    );
    assert!(
        stderr.contains("\"quality\" must be a whole number 0 to 100"),
        "{stderr}"
    );
    assert!(
        stdout.contains("row estimates: 3 received, 3 refused"),
        "{stdout}"
    );
}
