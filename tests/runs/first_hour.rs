//! A new user's first hour: what the README's steps print, through the real program.

use crate::common;

use common::mechweed;

use std::process::Output;

/// `mechweed run --headless ARGS`, its record in a temporary folder.
fn run_headless(args: &[&str]) -> (Output, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = mechweed()
        .args(["run", "--headless"])
        .args(common::test_run_settings(dir.path()))
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    (out, stdout)
}

#[test]
fn the_readme_s_scripted_events_each_print_a_line_as_they_happen() {
    let (out, stdout) = run_headless(&[
        "--mode",
        "autonomous",
        "--duration",
        "10",
        "--set",
        "sim.events=4 estop_front, 6 estop_release, 7 power_up, 8 mode autonomous",
    ]);
    assert!(out.status.success(), "{stdout}");
    let line = |what: &str| {
        stdout
            .lines()
            .position(|l| l.contains(what))
            .unwrap_or_else(|| panic!("no line with {what:?} in\n{stdout}"))
    };
    let release = line("scripted event: estop_release");
    let power_up = line("scripted event: power_up");
    let mode = line("scripted event: mode autonomous");
    assert!(line("scripted event: estop_front") < release && release < power_up);
    assert!(power_up < mode);
    // The mode changes, with the way back to autonomous after the fault.
    let fault = line("mode: autonomous -> fault");
    assert!(line("mode: halt -> autonomous") < fault);
    let lines: Vec<&str> = stdout.lines().collect();
    let back = lines
        .iter()
        .rposition(|l| l.contains("mode: ") && l.ends_with("-> autonomous"));
    assert!(back.is_some_and(|b| b > mode), "{stdout}");
}

/// A run driving autonomous with no --duration, ended by `signal` once it drives: what
/// it printed, and whether it ended well.
fn stopped_by(signal: i32) -> (bool, String) {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let mut child = mechweed()
        .args(["run", "--headless", "--mode", "autonomous"])
        .args(common::test_run_settings(dir.path()))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Its lines come through a thread, so that a run that never drives fails the test
    // in a minute instead of holding it (the run itself has no end).
    let stdout = BufReader::new(child.stdout.take().unwrap());
    let (lines, said) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in stdout.lines() {
            if lines.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    let mut seen = String::new();
    let until = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !seen.contains("-> autonomous") {
        let wait = until.saturating_duration_since(std::time::Instant::now());
        match said.recv_timeout(wait) {
            Ok(line) => seen += &(line + "\n"),
            Err(why) => {
                let _ = child.kill();
                panic!("no \"-> autonomous\" ({why:?}):\n{seen}");
            }
        }
    }
    let pid = i32::try_from(child.id()).unwrap();
    // SAFETY: kill() with a child's own pid and a signal number has no memory effects.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
    reader.join().unwrap();
    seen.extend(said.try_iter().map(|line| line + "\n"));
    let status = child.wait().unwrap();
    (status.success(), seen)
}

#[test]
fn ctrl_c_ends_a_run_saying_the_operator_stopped_it_and_the_outputs_are_safe() {
    let (ok, seen) = stopped_by(libc::SIGINT);
    assert!(ok, "{seen}");
    assert!(
        seen.contains("run stopped by the operator (Ctrl-C); the outputs are safe"),
        "{seen}"
    );
    assert!(seen.contains("final mode: autonomous"), "{seen}");
}

#[test]
fn sigterm_is_named_as_the_systems_stop_request_not_the_operators() {
    // A service manager or a shutdown sends SIGTERM: it was reported as Ctrl-C.
    let (ok, seen) = stopped_by(libc::SIGTERM);
    assert!(ok, "{seen}");
    assert!(
        seen.contains("run stopped by a stop request from the system (SIGTERM"),
        "{seen}"
    );
    assert!(seen.contains("the outputs are safe"), "{seen}");
    assert!(!seen.contains("Ctrl-C"), "{seen}");
}

#[test]
fn a_run_shorter_than_the_lead_in_says_it_has_no_cross_track_figures_and_writes_null() {
    let dir = tempfile::tempdir().unwrap();
    let report_path = dir.path().join("report.json");
    let report_arg = report_path.to_str().unwrap();
    // Standing in halt for a second: the robot drives nothing at all.
    let (out, stdout) = run_headless(&["--duration", "1", "--report", report_arg]);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains(
            "no cross-track figures: the robot drove 0.0 m, fewer than the first 5 m left out"
        ),
        "{stdout}"
    );
    assert!(!stdout.contains("mean 0.00 cm"), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    let c = &report["cross_track_cm"];
    for key in [
        "mean_cm",
        "sd_cm",
        "rms_cm",
        "p95_cm",
        "max_cm",
        "share_over_2cm",
    ] {
        assert!(c[key].is_null(), "{key}: {report:#}");
    }
    assert_eq!(c["distance_m"], 0.0, "{report:#}");
}

#[test]
fn from_m_gives_a_short_run_its_cross_track_figures() {
    let (out, stdout) =
        run_headless(&["--mode", "autonomous", "--duration", "3", "--from-m", "0.2"]);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("tool cross-track (after the first 0.2 m, over "),
        "{stdout}"
    );
    assert!(!stdout.contains("no cross-track figures"), "{stdout}");
}

/// config/robot.ini with one line replaced, in a temporary folder.
fn robot_ini_with(line: &str, replacement: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let shipped = std::fs::read_to_string("config/robot.ini").unwrap();
    let lines: Vec<&str> = shipped.lines().collect();
    assert_eq!(lines.iter().filter(|l| **l == line).count(), 1, "{line}");
    let edited: Vec<&str> = (lines.iter())
        .map(|l| if *l == line { replacement } else { l })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.ini");
    std::fs::write(&path, edited.join("\n")).unwrap();
    (dir, path)
}

#[test]
fn a_speed_above_the_limit_is_refused_by_check_config_and_run() {
    let expected = "[steer] speed_mps = 2 is above [supervisor] max_speed_mps = 1.2";
    let (_dir, ini) = robot_ini_with("speed_mps = 0.5", "speed_mps = 2");
    let out = mechweed().arg("check-config").arg(&ini).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains(expected),
        "{stderr}"
    );
    // --set is checked the same way, before anything starts.
    let (out, stdout) = run_headless(&["--duration", "1", "--set", "steer.speed_mps=2"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains(expected),
        "{stderr}"
    );
    assert!(
        !stdout.contains("mechweed on the simulated robot"),
        "{stdout}"
    );
}

#[test]
fn a_steer_priority_above_the_supervisor_s_is_refused_by_check_config_and_run() {
    let expected = "[rt] steer_priority = 90 must be below [rt] supervisor_priority = 80";
    let (_dir, ini) = robot_ini_with("steer_priority = 70", "steer_priority = 90");
    let out = mechweed().arg("check-config").arg(&ini).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains(expected),
        "{stderr}"
    );
    let (out, _) = run_headless(&["--duration", "1", "--set", "rt.steer_priority=90"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains(expected),
        "{stderr}"
    );
}

#[test]
fn a_report_file_that_cannot_be_written_stops_the_run_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("no such folder").join("report.json");
    // 30 s: the old program ran all of it before it said the report could not be written.
    let (out, stdout) = run_headless(&["--duration", "30", "--report", report.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stdout}");
    assert!(
        stderr.contains(&format!("cannot write the report to {}", report.display())),
        "{stderr}"
    );
    assert!(
        !stdout.contains("mechweed on the simulated robot"),
        "{stdout}"
    );
    // A writable one is left as it was until the run writes it.
    let fine = dir.path().join("report.json");
    let (out, stdout) = run_headless(&["--duration", "0.5", "--report", fine.to_str().unwrap()]);
    assert!(out.status.success(), "{stdout}");
    assert!(
        std::fs::read_to_string(&fine)
            .unwrap()
            .contains("mode_final")
    );
}

#[test]
fn list_events_shows_every_scripted_event_with_its_argument_and_an_example() {
    let out = mechweed().args(["run", "--list-events"]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    for (action, argument, example) in [
        ("estop_front", "no argument", "estop_front"),
        (
            "mode",
            "halt, joystick, autonomous or test",
            "mode autonomous",
        ),
        ("link_silent", "a duration in seconds", "link_silent 2"),
        ("steer_slip", "an angle in degrees", "steer_slip -3"),
        ("contactor_welded", "no argument", "contactor_welded"),
    ] {
        let line = stdout
            .lines()
            .position(|l| l.starts_with(&format!("{action} ")))
            .unwrap_or_else(|| panic!("no {action} in\n{stdout}"));
        let lines: Vec<&str> = stdout.lines().collect();
        assert!(lines[line].contains(argument), "{}", lines[line]);
        assert!(
            lines[line + 1].contains("example: ") && lines[line + 1].ends_with(example),
            "{}",
            lines[line + 1]
        );
    }
    // Nothing ran: no start line, no record.
    assert!(!stdout.contains("mechweed on the"), "{stdout}");
}

#[test]
fn probe_without_the_cards_points_to_the_robot_computer_s_set_up() {
    let out = mechweed().arg("probe").output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.success() {
        return; // a computer with the cards: nothing to point to
    }
    assert!(
        stderr.contains("the robot's I/O cards are not usable on this computer"),
        "{stderr}"
    );
    assert!(stderr.contains("see docs/robot-pc.md"), "{stderr}");
    assert!(std::path::Path::new("docs/robot-pc.md").exists());
}

#[test]
fn mechweed_without_a_command_takes_the_run_options() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let out = mechweed()
        .args(["--headless", "--duration", "1"])
        .args(common::test_run_settings(dir.path()))
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("mechweed on the simulated robot"),
        "{stdout}"
    );
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    assert!(report.exists());
    // A run's option before another command is an error, not silently dropped.
    let out = mechweed()
        .args(["--headless", "check-config"])
        .output()
        .unwrap();
    assert!(!out.status.success());
}
