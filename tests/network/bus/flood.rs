//! Floods on a secured bus: many requests from two sessions, and huge payloads. A real
//! HALT must still be answered and stop the robot, the console must not drown, and the
//! robot program's memory must not grow with what it is sent.
//!
//! The flooding sessions run in processes of their own (this test program again, as
//! `flood_sender`): real processes, as an attacker's would be, and a sender that dies
//! with the link it overloads takes no test down with it.

use std::process::{Child, Command, Stdio};
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

const SENDER: &str = "MECHWEED_FLOOD_SENDER";

/// A sender process: `what` (requests: power-ups, 500 a second; huge: 10 MB
/// payloads) to `endpoint` as the operator in `keys`, for `seconds`.
fn sender(what: &str, endpoint: &str, keys: &Keys, seconds: u32) -> Child {
    Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "bus::flood::flood_sender",
            "--ignored",
            "--nocapture",
        ])
        .env(
            SENDER,
            format!("{what} {endpoint} {} {seconds}", keys.path().display()),
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// (sent, answered by the robot) as a sender process says them.
fn counts(child: Child) -> (u64, u64) {
    let output = child.wait_with_output().unwrap();
    let out = text(&output.stdout);
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("flood_sender: "))
        .unwrap_or_else(|| {
            let status = output.status;
            panic!(
                "no counts from the sender ({status}): {out}{}",
                text(&output.stderr)
            )
        });
    let mut words = line.split(' ');
    let mut next = || words.next().and_then(|w| w.parse().ok()).unwrap_or(0);
    (next(), next())
}

/// Not a test: the sender process the flood tests start (it does nothing without them).
#[test]
#[ignore = "a sender process of the flood tests"]
fn flood_sender() {
    let Ok(spec) = std::env::var(SENDER) else {
        return;
    };
    let words: Vec<&str> = spec.split(' ').collect();
    let [what, endpoint, keys, seconds] = words[..] else {
        panic!("{SENDER}: {spec}");
    };
    let keys = Keys::at(std::path::Path::new(keys));
    let session = keys.session(endpoint, "operator");
    let end = Instant::now() + Duration::from_secs(seconds.parse().unwrap());
    let huge = vec![b'x'; 10 * 1024 * 1024];
    let (mut sent, mut answered) = (0u64, 0u64);
    while Instant::now() < end && (what == "requests" || sent < 8) {
        let payload = if what == "huge" {
            huge.clone()
        } else {
            br#"{"request": "power_up"}"#.to_vec()
        };
        let get = session
            .get("mechweed/request/operator")
            .payload(payload)
            .timeout(Duration::from_millis(500));
        sent += 1;
        if what == "requests" {
            // No waiting for the answers: about 500 a second from each sender, a
            // hundred times what the robot takes, without taking both of a test
            // machine's CPUs from the robot it floods.
            let _ = get.callback(|_| {}).wait();
            std::thread::sleep(Duration::from_millis(2));
            continue;
        }
        if let Ok(reply) = get.wait().unwrap().recv() {
            let body = super::reply_text(&reply);
            // Zenoh's own "Timeout" is no answer; the robot answers in JSON.
            if serde_json::from_str::<serde_json::Value>(&body).is_ok() {
                answered += 1;
            }
        }
    }
    println!("flood_sender: {sent} {answered}");
}

#[test]
fn a_halt_is_answered_through_a_flood_of_requests_and_the_console_stays_readable() {
    let _machine = crate::whole_machine();
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
    // Two sessions asking for power-up, 500 times a second each (refused: it is on).
    let flooders = [
        sender("requests", &robot.endpoint, &keys, 7),
        sender("requests", &robot.endpoint, &keys, 7),
    ];
    std::thread::sleep(Duration::from_secs(3));
    let asked = Instant::now();
    let halt = robot.bus(&["request", "halt"]);
    let waited = asked.elapsed();
    let sent: u64 = flooders.into_iter().map(|f| counts(f).0).sum();
    assert_eq!(
        text(&halt.stdout).trim(),
        "accepted",
        "{}",
        text(&halt.stderr)
    );
    println!(
        "HALT answered {:.0} ms after it was asked (the tool's own connect included), through {sent} flooding requests",
        waited.as_secs_f64() * 1e3
    );
    let (stdout, stderr, _) = robot.finish();
    assert!(stdout.contains("mode: autonomous -> halt"), "{stdout}");
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    // Thousands of refusals, a line a second at most.
    let refusal_lines = stderr.lines().filter(|l| l.contains("refused")).count();
    assert!(sent > 100, "the flood was no flood: {sent}");
    assert!(refusal_lines <= 16, "{refusal_lines} lines:\n{stderr}");
    assert!(stderr.contains("more refused"), "{stderr}");
}

#[test]
fn huge_payloads_are_dropped_and_the_robot_s_memory_does_not_grow() {
    let _machine = crate::whole_machine();
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &["--duration", "14", "--set", "bus.accept_requests=operator"],
    );
    let before_kb = resident_kb(robot.pid());
    // Eight requests of 10 MB each.
    let (sent, answered) = counts(sender("huge", &robot.endpoint, &keys, 8));
    std::thread::sleep(Duration::from_secs(1));
    let after_kb = resident_kb(robot.pid());
    assert!(sent >= 1, "nothing was sent");
    assert_eq!(answered, 0, "a 10 MB request was taken");
    // Up to 80 MB were sent; the program keeps none of it.
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
