//! Floods on a secured bus: many requests from two sessions, and huge payloads. A real
//! HALT must still be answered and stop the robot, the console must not drown, and the
//! robot program's memory must not grow with what it is sent.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use zenoh::Wait;

use super::secured::{Keys, secured_robot};
use crate::common::text;

/// The robot program's resident memory, kB.
fn resident_kb(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap()
}

#[test]
fn a_halt_is_answered_through_a_flood_of_requests_and_the_console_stays_readable() {
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &[
            "--mode",
            "autonomous",
            "--duration",
            "14",
            "--set",
            "bus.accept_requests=operator",
        ],
    );
    let stop = Arc::new(AtomicBool::new(false));
    let sent = Arc::new(AtomicU64::new(0));
    // Two sessions asking for power-up as fast as they can (refused: it is on), for at
    // most 8 s.
    let flooders: Vec<_> = (0..2)
        .map(|_| {
            let session = keys.session(&robot.endpoint, "operator");
            let (stop, sent) = (stop.clone(), sent.clone());
            std::thread::spawn(move || {
                let end = Instant::now() + Duration::from_secs(8);
                while !stop.load(Ordering::Relaxed) && Instant::now() < end {
                    let _ = session
                        .get("mechweed/request/operator")
                        .payload(r#"{"request": "power_up"}"#)
                        .timeout(Duration::from_secs(1))
                        .callback(|_| {})
                        .wait();
                    sent.fetch_add(1, Ordering::Relaxed);
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_secs(3));
    let asked = Instant::now();
    let halt = robot.bus(&["request", "halt"]);
    let waited = asked.elapsed();
    stop.store(true, Ordering::Relaxed);
    for f in flooders {
        f.join().unwrap();
    }
    assert_eq!(
        text(&halt.stdout).trim(),
        "accepted",
        "{}",
        text(&halt.stderr)
    );
    println!(
        "HALT answered {:.0} ms after it was asked (the tool's own connect included), through {} flooding requests",
        waited.as_secs_f64() * 1e3,
        sent.load(Ordering::Relaxed)
    );
    let (stdout, stderr, _) = robot.finish();
    assert!(stdout.contains("mode: autonomous -> halt"), "{stdout}");
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    // Thousands of refusals, a line a second at most.
    let refusal_lines = stderr.lines().filter(|l| l.contains("refused")).count();
    assert!(sent.load(Ordering::Relaxed) > 100, "the flood was no flood");
    assert!(refusal_lines <= 16, "{refusal_lines} lines:\n{stderr}");
    assert!(stderr.contains("more refused"), "{stderr}");
}

#[test]
fn huge_payloads_are_dropped_and_the_robot_s_memory_does_not_grow() {
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &["--duration", "14", "--set", "bus.accept_requests=operator"],
    );
    let session = keys.session(&robot.endpoint, "operator");
    std::thread::sleep(Duration::from_secs(1));
    let before_kb = resident_kb(robot.pid());
    let huge = vec![b'x'; 10 * 1024 * 1024];
    let mut answered = 0;
    for _ in 0..8 {
        let replies = session
            .get("mechweed/request/operator")
            .payload(huge.clone())
            .timeout(Duration::from_millis(500))
            .wait()
            .unwrap();
        if let Ok(reply) = replies.recv() {
            let body = match reply.result() {
                Ok(sample) => sample.payload().to_bytes().into_owned(),
                Err(error) => error.payload().to_bytes().into_owned(),
            };
            // Zenoh's own "Timeout" is no answer; the robot answers in JSON.
            if serde_json::from_slice::<serde_json::Value>(&body).is_ok() {
                answered += 1;
            }
        }
    }
    std::thread::sleep(Duration::from_secs(1));
    let after_kb = resident_kb(robot.pid());
    assert_eq!(answered, 0, "a 10 MB request was taken");
    // 80 MB were sent; the program keeps none of it.
    assert!(
        after_kb < before_kb + 20 * 1024,
        "{before_kb} kB -> {after_kb} kB"
    );
    // The bus still works for a request of the right size.
    let get = robot.bus(&["get", "pid.left.kp"]);
    assert!(
        text(&get.stdout).starts_with("pid.left.kp = "),
        "{}",
        text(&get.stderr)
    );
    robot.finish();
}
