//! A new user's first hour, continued: what the console, bench and camsim steps print,
//! through the real program.

use crate::common;

use common::{mechweed, text};

use std::process::{Command, Output};

/// `mechweed ARGS` with its record in `folder`, as a busy test machine allows.
fn mechweed_recording(args: &[&str], folder: &std::path::Path) -> Output {
    mechweed()
        .args(args)
        .args(common::test_run_settings(folder))
        .output()
        .unwrap()
}

#[test]
fn log_lines_go_to_stderr_plain_without_timestamps_or_levels() {
    let dir = tempfile::tempdir().unwrap();
    // Nothing listens on port 1: the camera link warns that it cannot open.
    let out = mechweed_recording(
        &[
            "run",
            "--headless",
            "--duration",
            "1",
            "--set",
            "camera.port=tcp://127.0.0.1:1",
        ],
        dir.path(),
    );
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr
            .lines()
            .any(|l| l.starts_with("warning: camera link: cannot open tcp://127.0.0.1:1")),
        "{stderr}"
    );
    for line in stdout.lines().chain(stderr.lines()) {
        assert!(
            !line.contains(" WARN ") && !line.contains(" INFO ") && !line.starts_with("20"),
            "a log line in the tracing style: {line}"
        );
    }
}

/// No X server answers on display 99 (checked), and no Wayland display is set.
fn stale_display(cmd: &mut Command) -> &mut Command {
    assert!(!std::path::Path::new("/tmp/.X11-unix/X99").exists());
    cmd.env("DISPLAY", ":99").env_remove("WAYLAND_DISPLAY")
}

#[test]
fn a_stale_display_stops_the_run_before_anything_starts_or_is_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let out = stale_display(&mut mechweed())
        .args(["run", "--duration", "2", "--set"])
        .arg(format!("record.folder={}", dir.path().display()))
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("cannot open a window on DISPLAY=:99") && stderr.contains("--headless"),
        "{stderr}"
    );
    assert!(!stderr.contains(".cargo"), "{stderr}");
    assert!(!stdout.contains("recording into"), "{stdout}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn bench_loop_gui_without_a_display_advises_dropping_gui() {
    let dir = tempfile::tempdir().unwrap();
    let out = stale_display(&mut mechweed())
        .current_dir(dir.path())
        .args(["bench", "loop", "--gui", "--seconds", "1"])
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot open a window on DISPLAY=:99"),
        "{stderr}"
    );
    assert!(stderr.contains("drop --gui"), "{stderr}");
    assert!(!stderr.contains("--headless"), "{stderr}");
    assert!(!dir.path().join("records").exists());
}

/// `mechweed camsim --listen 127.0.0.1:0`, the address it listens on, and its lines.
fn camsim_on_tcp(
    args: &[&str],
) -> (
    std::process::Child,
    String,
    std::sync::mpsc::Receiver<String>,
) {
    use std::io::BufRead;
    let mut child = mechweed()
        .args(["camsim", "--listen", "127.0.0.1:0"])
        .args(args)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let address = first.rsplit(' ').next().unwrap().to_string();
    // Keep reading its lines, so that it never blocks on a full pipe.
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in lines.map_while(Result::ok) {
            let _ = send.send(line);
        }
    });
    (child, address, receive)
}

#[test]
fn an_outside_camera_on_the_simulated_robot_leaves_cross_track_out_and_says_so() {
    let (mut camsim, address, _lines) = camsim_on_tcp(&[]);
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let port = format!("camera.port=tcp://{address}");
    let out = mechweed_recording(
        &[
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "6",
            "--from-m",
            "0",
            "--set",
            &port,
            "--report",
            report.to_str().unwrap(),
        ],
        dir.path(),
    );
    camsim.kill().unwrap();
    let _ = camsim.wait();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}\n{stderr}");
    let said = |l: &&str| l.contains("cross-track is not meaningful");
    let lines: Vec<&str> = stdout.lines().collect();
    let at_start = lines.iter().position(said).expect(&stdout);
    let in_summary = lines.iter().rposition(said).unwrap();
    assert!(at_start < 3 && in_summary > at_start, "{stdout}");
    assert!(!stdout.contains("tool cross-track (after"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    // The robot drove along the camera's rows: there was travel to (mis)measure.
    assert!(json["distance_m"].as_f64().unwrap() > 0.5, "{json}");
    assert!(json["cross_track_cm"]["mean_cm"].is_null(), "{json}");
    assert!(json["cross_track_cm"]["max_cm"].is_null(), "{json}");
    assert_eq!(json["outside_camera"], true);
    // The console's status line says so too, instead of the field's number.
    let status_lines: Vec<&&str> = lines
        .iter()
        .filter(|l| l.contains("tool off row"))
        .collect();
    assert!(!status_lines.is_empty(), "{stdout}");
    for line in status_lines {
        assert!(
            line.contains("tool off row not meaningful (outside camera)"),
            "{line}"
        );
    }
    // And the record's summary, read back from the header beside the record.
    let mut summary = mechweed();
    summary
        .args(["record", "summary", "latest"])
        .args(common::test_run_settings(dir.path()));
    common::assert_no_cross_track_in_summary(&mut summary, "latest");
}

#[test]
fn bench_rows_takes_config_and_set_and_says_which_settings_file_it_used() {
    let dir = tempfile::tempdir().unwrap();
    // No config/robot.ini in this folder: the built-in settings, and it says so.
    let out = mechweed()
        .current_dir(dir.path())
        .args(["bench", "rows"])
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.starts_with("settings: the built-in robot.ini"),
        "{stdout}"
    );
    let ini = dir.path().join("bench.ini");
    std::fs::copy("config/robot.ini", &ini).unwrap();
    let out = mechweed()
        .args(["bench", "rows", "--config"])
        .arg(&ini)
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.starts_with(&format!("settings: {}", ini.display())),
        "{stdout}"
    );
    // --set is read, and checked like run's.
    let out = mechweed()
        .args(["bench", "rows", "--set", "steer.nonsense=1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("--set steer.nonsense=1"));
    // A [sim] setting the benchmark would not use is refused by name, not ignored: its
    // plant is its own, but for the realistic field's field_* settings.
    let refused = |args: &[&str], says: &str| {
        let out = mechweed()
            .args(["bench", "rows"])
            .args(args)
            .output()
            .unwrap();
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    };
    let noise = "sim.camera_noise_offset_m=0.05";
    refused(
        &["--set", noise],
        "--set sim.camera_noise_offset_m: bench rows drives its own",
    );
    let gaps = "sim.field_gap_every_m=5";
    refused(&["--set", gaps], "add --field realistic");
    let out = mechweed()
        .args(["bench", "rows", "--field", "realistic", "--set", gaps])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
}

#[test]
fn bench_loop_prints_a_status_line_every_5_s_and_says_where_its_record_went() {
    let dir = tempfile::tempdir().unwrap();
    let out = mechweed()
        .current_dir(dir.path())
        .args(["bench", "loop", "--seconds", "6"])
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout
            .lines()
            .any(|l| l.trim_start().starts_with("5.0") && l.contains("speed")),
        "{stdout}"
    );
    let record = stdout
        .lines()
        .find_map(|l| l.strip_prefix("record: records/"))
        .expect(&stdout);
    let csv = record.split(',').next().unwrap();
    assert!(dir.path().join("records").join(csv).exists(), "{stdout}");
}

#[test]
fn camsim_says_once_a_second_what_it_sent_and_received() {
    use std::io::Write;
    let (mut camsim, address, lines) = camsim_on_tcp(&[]);
    let mut robot = std::net::TcpStream::connect(&address).unwrap();
    robot
        .write_all(&[mechweed_hw::camproto::CMD_START])
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let mut seen = Vec::new();
    let streaming = loop {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        match lines.recv_timeout(left) {
            Ok(line) if line.contains("streaming: sent") => break Some(line),
            Ok(line) => seen.push(line),
            Err(_) => break None,
        }
    };
    camsim.kill().unwrap();
    let _ = camsim.wait();
    let line = streaming.unwrap_or_else(|| panic!("no line a second: {seen:?}"));
    assert!(
        line.contains("ROW frames") && line.contains("commands"),
        "{line}"
    );
    assert!(!line.contains("sent 0 ROW frames"), "{line}");
}

#[test]
fn camsim_s_pty_hint_runs_headless() {
    let mut child = mechweed()
        .args(["camsim", "--port", "pty"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufRead::read_line(
        &mut std::io::BufReader::new(child.stdout.take().unwrap()),
        &mut first,
    )
    .unwrap();
    child.kill().unwrap();
    let _ = child.wait();
    assert!(
        first.contains("mechweed run --headless --set camera.port=/dev/"),
        "{first}"
    );
}

#[test]
fn a_camera_port_without_tcp_says_tcp_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let out = mechweed_recording(
        &[
            "run",
            "--headless",
            "--duration",
            "1",
            "--set",
            "camera.port=127.0.0.1:5000",
        ],
        dir.path(),
    );
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lacks tcp://"), "{stderr}");
    assert!(stderr.contains("tcp://127.0.0.1:5000"), "{stderr}");
}

/// The distance a headless joystick run driven by these scripted events reports.
fn joystick_run_distance_m(events: &str) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let events = format!("sim.events={events}");
    let out = mechweed_recording(
        &[
            "run",
            "--headless",
            "--mode",
            "joystick",
            "--duration",
            "7",
            "--set",
            &events,
            "--report",
            report.to_str().unwrap(),
        ],
        dir.path(),
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    assert!(stdout.contains("scripted event: joystick 0 2"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["faults"], serde_json::json!([]), "{json}");
    json["distance_m"].as_f64().unwrap()
}

#[test]
fn scripted_joystick_events_drive_the_robot_headless_with_the_dead_man_held() {
    // Half deflection forward (2 V of 4 V) for 3 s, the dead-man button held.
    let driven_m = joystick_run_distance_m("3 deadman on, 3 joystick 0 2, 6 joystick 0 0");
    assert!(driven_m > 0.5, "drove {driven_m} m");
    // The same stick without the dead-man button: the robot stays put.
    let held_m = joystick_run_distance_m("3 joystick 0 2, 6 joystick 0 0");
    assert!(
        held_m < 0.05,
        "drove {held_m} m without the dead-man button"
    );
}
