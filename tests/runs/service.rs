//! The program as the robot PC's service runs it: systemd's notify protocol from a real
//! run (the test listens where systemd would), and `mechweed doctor --json` as a
//! script reads it.

use std::os::unix::net::UnixDatagram;
use std::time::Duration;

use crate::common::{mechweed, test_run_settings, text};

#[test]
fn a_run_under_systemd_says_ready_its_status_and_feeds_the_watchdog_then_stopping() {
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("notify");
    let systemd = UnixDatagram::bind(&socket).unwrap();
    systemd
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let run = std::thread::spawn({
        let socket = socket.clone();
        let settings = test_run_settings(dir.path());
        move || {
            mechweed()
                .args(["run", "--headless", "--duration", "3"])
                .args(settings)
                .env("NOTIFY_SOCKET", &socket)
                .env("WATCHDOG_USEC", "400000")
                .output()
                .unwrap()
        }
    });
    let mut heard = Vec::new();
    let mut buf = [0u8; 4096];
    while let Ok(n) = systemd.recv(&mut buf) {
        let message = String::from_utf8_lossy(&buf[..n]).into_owned();
        let stopping = message.contains("STOPPING=1");
        heard.push(message);
        if stopping {
            break;
        }
    }
    let out = run.join().unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let first = heard.first().map(String::as_str).unwrap_or("");
    assert!(first.starts_with("READY=1"), "READY first: {heard:?}");
    assert_eq!(heard.iter().filter(|m| m.contains("READY=1")).count(), 1);
    assert!(
        heard.iter().any(|m| m.starts_with("STATUS=halt; no fault")),
        "{heard:?}"
    );
    // Fed every 200 ms for about 3 s.
    let fed = heard.iter().filter(|m| *m == "WATCHDOG=1").count();
    assert!(fed >= 5, "fed {fed} times: {heard:?}");
    assert!(heard.last().unwrap().contains("STOPPING=1"), "{heard:?}");
}

#[test]
fn doctor_json_lists_every_check_and_exits_1_exactly_when_one_fails() {
    let out = mechweed()
        .args(["doctor", "--json", "--latency-s", "0.2"])
        .output()
        .unwrap();
    let answer: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("not JSON ({e}): {}", text(&out.stdout)));
    let checks = answer["checks"].as_array().unwrap();
    let names: Vec<&str> = checks
        .iter()
        .map(|c| c["check"].as_str().unwrap())
        .collect();
    for expected in [
        "settings", "kernel", "lockdown", "clock", "cards", "disk", "keys", "latency",
    ] {
        assert!(
            names.contains(&expected),
            "{expected} missing from {names:?}"
        );
    }
    for check in checks {
        let level = check["level"].as_str().unwrap();
        assert!(["ok", "warning", "fail"].contains(&level), "{check}");
        assert!(
            level == "ok" || !check["fix"].as_str().unwrap().is_empty(),
            "{check}"
        );
    }
    let fails = checks.iter().filter(|c| c["level"] == "fail").count();
    assert_eq!(answer["fails"].as_u64(), Some(fails as u64));
    assert_eq!(out.status.success(), fails == 0, "{answer:#}");

    // A settings file that does not load fails, whatever the PC.
    let dir = tempfile::tempdir().unwrap();
    let broken = dir.path().join("robot.ini");
    std::fs::write(&broken, "[steer]\nlaw = ouija\n").unwrap();
    let out = mechweed()
        .args(["doctor", "--json", "--latency-s", "0", "--config"])
        .arg(&broken)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let answer: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(answer["checks"][0]["level"], "fail", "{answer:#}");
}
