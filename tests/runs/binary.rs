//! The real program, from outside: a short real-time run, and check-config.

use crate::common;

use common::mechweed;

/// `mechweed run --headless ARGS --report FILE`: its standard output and its report.
fn run_with_report(args: &[&str]) -> (String, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let (out, report) = common::run_headless(dir.path(), args);
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The exit status is the report's: 0, or 3 for a run that ended in Fault.
    let want = if report["mode_final"] == "fault" {
        3
    } else {
        0
    };
    assert_eq!(out.status.code(), Some(want), "{stdout}\n{stderr}");
    assert_eq!(report["exit_code"], want, "{report:#}");
    (stdout, report)
}

#[test]
fn a_short_autonomous_run_on_real_threads_writes_its_report() {
    let (stdout, report) =
        // 4 s drive about 2 m: the figures start at 0 m, not after the usual 5 m.
        run_with_report(&["--mode", "autonomous", "--duration", "4", "--seed", "3", "--from-m", "0"]);
    assert!(stdout.contains("tool cross-track"), "{stdout}");
    assert_eq!(report["mode_final"], "autonomous", "{report:#}");
    assert_eq!(report["faults"].as_array().unwrap().len(), 0, "{report:#}");
    assert!(report["distance_m"].as_f64().unwrap() > 0.5, "{report:#}");
    let sup = &report["loops"]["supervisor"];
    assert!(sup["ticks"].as_u64().unwrap() > 300, "{report:#}");
    for key in ["p50", "p99", "p999", "max"] {
        assert!(sup["late_us"][key].is_u64() && sup["exec_us"][key].is_u64());
    }
    assert!(sup["worst_lock_us"].is_u64() && sup["overruns"].is_u64());
    assert!(report["loops"]["steer"]["ticks"].as_u64().unwrap() > 30);
    assert!(report["loops"]["liu_layland"]["schedulable"].is_boolean());
    let link = &report["link"];
    assert!(link["frames_ok"].as_u64().unwrap() > 20, "{report:#}");
    for key in [
        "crc_errors",
        "resyncs",
        "seq_gaps",
        "bytes_skipped",
        "pongs",
    ] {
        assert!(link[key].is_u64(), "{key}");
    }
    assert!(
        link["ping_rtt_ms"].is_f64(),
        "the link test at start got no answer"
    );
    for key in ["mean_cm", "sd_cm", "rms_cm", "p95_cm", "max_cm"] {
        assert!(report["cross_track_cm"][key].is_f64(), "{key}");
    }
}

#[test]
fn a_scripted_estop_shows_in_the_report_with_its_cause() {
    let (stdout, report) = run_with_report(&[
        "--mode",
        "autonomous",
        "--duration",
        "3",
        "--set",
        "sim.events=2 estop_front",
    ]);
    assert!(stdout.contains("FAULT: front emergency stop"), "{stdout}");
    // The cause before its effect: the fault line, then the mode change it made.
    let lines: Vec<&str> = stdout.lines().collect();
    let fault_at = lines.iter().position(|l| l.contains("FAULT: ")).unwrap();
    let mode_at = (lines
        .iter()
        .position(|l| l.contains("mode: autonomous -> fault")))
    .unwrap_or_else(|| panic!("{stdout}"));
    assert!(fault_at < mode_at, "{stdout}");
    assert_eq!(report["mode_final"], "fault");
    assert_eq!(
        report["exit_code"], 3,
        "a run that ends in Fault is no success"
    );
    assert!(
        stdout.contains("the run ended in fault: mechweed exits with status 3"),
        "{stdout}"
    );
    let fault = &report["faults"][0];
    let cause = fault["cause"].as_str().unwrap();
    assert!(cause.contains("front emergency stop"), "{report:#}");
    assert_eq!(fault["safe_after_ticks"], 0);
    assert!((fault["t_s"].as_f64().unwrap() - 2.0).abs() < 0.1);
}

#[test]
fn check_config_says_ok_or_lists_every_error() {
    let out = mechweed()
        .args(["check-config", "config/robot.ini"])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "ok");

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.ini");
    let text = std::fs::read_to_string("config/robot.ini").unwrap();
    std::fs::write(
        &bad,
        text.replacen("kd = 2.0", "kd = fast", 1)
            .replacen("rate_hz = 10\n", "rate_hz = -1\n", 1),
    )
    .unwrap();
    let out = mechweed().arg("check-config").arg(&bad).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("[pid.steer] kd = 'fast' is not a number"),
        "{stderr}"
    );
    assert!(
        stderr.contains("[steer] rate_hz = -1 is out of range"),
        "{stderr}"
    );
    assert!(stderr.contains(&bad.display().to_string()), "{stderr}");

    let out = mechweed()
        .args(["check-config", "/nonexistent/robot.ini"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read the settings file"));
}

#[test]
fn camsim_serves_a_robot_computer_over_tcp() {
    use mechweed_hw::camproto::{CMD_PING, CMD_START, CMD_STOP, Decoder, Frame};
    use std::io::{BufRead, BufReader, Read, Write};

    let mut child = mechweed()
        .args(["camsim", "--listen", "127.0.0.1:0", "--pattern", "sway"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let address = first.rsplit(' ').next().unwrap().to_string();
    assert!(address.starts_with("127.0.0.1:"), "{first}");

    let mut stream = std::net::TcpStream::connect(&address).unwrap();
    stream
        .set_read_timeout(Some(std::time::Duration::from_millis(50)))
        .unwrap();
    let read_for = |stream: &mut std::net::TcpStream, seconds: f64| {
        let (mut dec, mut frames, mut buf) = (Decoder::new(), Vec::new(), [0u8; 256]);
        let end = std::time::Instant::now() + std::time::Duration::from_secs_f64(seconds);
        while std::time::Instant::now() < end {
            if let Ok(n) = stream.read(&mut buf) {
                frames.extend(buf[..n].iter().filter_map(|&b| dec.push(b)));
            }
        }
        frames
    };
    assert!(read_for(&mut stream, 0.3).is_empty(), "frames before START");
    stream.write_all(&[CMD_START, CMD_PING]).unwrap();
    let frames = read_for(&mut stream, 1.0);
    let rows = frames.iter().filter(|f| matches!(f, Frame::Row(_))).count();
    assert!((8..=12).contains(&rows), "{rows} frames in 1 s");
    assert_eq!(
        frames
            .iter()
            .filter(|f| matches!(f, Frame::Pong { .. }))
            .count(),
        1
    );
    stream.write_all(&[CMD_STOP]).unwrap();
    read_for(&mut stream, 0.2);
    assert!(read_for(&mut stream, 0.5).is_empty(), "frames after STOP");
    drop(stream);
    // Up to STOP: the once-a-second lines of what it sent come in between.
    let mut printed: Vec<String> = Vec::new();
    for line in lines.by_ref().take(20) {
        let line = line.unwrap();
        let stop_seen = line.contains("received STOP");
        printed.push(line);
        if stop_seen {
            break;
        }
    }
    child.kill().unwrap();
    let _ = child.wait();
    let printed = printed.join("\n");
    for expected in [
        "connected from",
        "received START",
        "received PING",
        "received STOP",
    ] {
        assert!(printed.contains(expected), "{printed}");
    }
}

#[test]
fn probe_on_a_computer_without_the_cards_says_so_and_fails() {
    if common::has_mcc_cards() {
        return;
    }
    let out = mechweed().arg("probe").output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("the robot's I/O cards are not usable on this computer"),
        "{stderr}"
    );
    for card in ["PCI-DAS08", "PCIM-DDA06/16", "PCI-QUAD04"] {
        assert!(
            stderr.contains(&format!("no {card} (PCI id 1307:")),
            "{stderr}"
        );
    }
    // The gamepads are listed first; of the cards nothing is read, nothing printed.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("gamepads (/dev/input):"), "{stdout}");
    assert!(
        !stdout.contains("found ") && !stdout.contains("battery_v"),
        "{stdout}"
    );
}

#[test]
fn run_on_the_cards_without_them_refuses_to_start() {
    if common::has_mcc_cards() {
        return;
    }
    let out = mechweed()
        .args([
            "run",
            "--headless",
            "--duration",
            "1",
            "--set",
            "hw.backend=cards",
            "--set",
            "camera.port=/dev/ttyS0",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("cannot start: no PCI-DAS08"), "{stderr}");
}

#[test]
fn bench_loop_never_drives_the_real_robot() {
    // It starts in autonomous without asking anyone: with robot.ini on the cards it
    // would have powered up and driven the real robot.
    let out = mechweed()
        .args([
            "bench",
            "loop",
            "--seconds",
            "1",
            "--set",
            "hw.backend=cards",
            "--set",
            "camera.port=/dev/ttyS0",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("does not run on the real robot"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("PCI-DAS08"),
        "it tried the cards: {stderr}"
    );
}

/// The shipped robot.ini on the I/O cards, with `[sim] events` as given, in a folder.
fn cards_ini(events: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let shipped =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/config/robot.ini")).unwrap();
    let text = shipped
        .replacen("\nbackend = sim\n", "\nbackend = cards\n", 1)
        .replacen("\nport = sim\n", "\nport = /dev/ttyS0\n", 1)
        .replacen("\nevents =\n", &format!("\nevents = {events}\n"), 1);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.ini");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

#[test]
fn check_config_refuses_a_scripted_operator_on_the_real_robot() {
    let (_dir, path) = cards_ini("");
    let out = mechweed().arg("check-config").arg(&path).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let (_dir, path) = cards_ini("2 estop_front, 5 power_up, 6 mode autonomous");
    let out = mechweed().arg("check-config").arg(&path).output().unwrap();
    let said =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(said.contains("[sim] events"), "{said}");
    assert!(said.contains("5 power_up, 6 mode autonomous"), "{said}");
    assert!(said.contains("with nobody there"), "{said}");
}

#[test]
fn a_moving_start_mode_on_the_real_robot_waits_for_a_yes_at_the_console() {
    // No terminal, no yes: the run starts in halt (here it then finds no cards).
    let (_dir, path) = cards_ini("");
    let out = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "1",
        ])
        .arg("--config")
        .arg(&path)
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("will power up the REAL robot and drive it"),
        "{said}"
    );
    assert!(said.contains("not confirmed: starting in halt"), "{said}");
}

/// `mechweed run --headless | head -c 300`: the console's reader goes away early. The
/// run must go on to its end, write its report, and close its record whole (an MCAP
/// file with its footer, read back by the program's own reader).
#[test]
fn a_closed_stdout_does_not_end_the_run_or_spoil_its_record() {
    use std::io::Read;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let report_path = dir.path().join("report.json");
    let mut child = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "4",
        ])
        .args(common::test_run_settings(dir.path()))
        .arg("--report")
        .arg(&report_path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 300];
    let mut stdout = child.stdout.take().unwrap();
    stdout.read_exact(&mut first).unwrap();
    drop(stdout); // as `head -c 300` does
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    assert_eq!(report["mode_final"], "autonomous", "{report:#}");
    let mcap = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "mcap"))
        .expect("an MCAP record");
    let read = mechweed::record::read::read(&mcap, &["t_s", "mode"]).unwrap();
    assert!(
        read.ticks.rows.len() > 300,
        "{} ticks",
        read.ticks.rows.len()
    );
}
