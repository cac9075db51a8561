//! A reader cannot starve the operator: on a secured bus a recorder's identity reads the
//! settings flat out (ten times what the robot takes from readers) while the operator
//! asks for modes. Before the operator's requests had an allowance of their own, 8 of 8
//! were refused "too many requests".

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use zenoh::Wait;

use super::secured::{Keys, ask, secured_robot};
use crate::common::text;

#[test]
fn a_recorder_reading_the_settings_flat_out_leaves_every_operator_request_answered() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &["--duration", "9", "--set", "bus.accept_requests=operator"],
    );
    let stop = Arc::new(AtomicBool::new(false));
    let refused = Arc::new(AtomicU64::new(0));
    let flood = std::thread::spawn({
        let (stop, refused) = (stop.clone(), refused.clone());
        let recorder = keys.session(&robot.endpoint, "recorder");
        move || {
            // As mechweed's tools do: the session named in the attachment.
            let me = recorder.zid().to_string();
            while !stop.load(Ordering::Relaxed) {
                let refused = refused.clone();
                let _ = (recorder.get("mechweed/config/steer/speed_mps"))
                    .attachment(me.clone())
                    .timeout(Duration::from_millis(500))
                    .callback(move |reply| {
                        if super::reply_text(&reply).contains("too many requests") {
                            refused.fetch_add(1, Ordering::Relaxed);
                        }
                    })
                    .wait();
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    });
    std::thread::sleep(Duration::from_secs(2));
    let operator = keys.session(&robot.endpoint, "operator");
    let requests = [
        r#"{"request": "power_up"}"#,
        r#"{"request": "mode", "mode": "joystick"}"#,
        r#"{"request": "mode", "mode": "halt"}"#,
        r#"{"request": "power_up"}"#,
        r#"{"request": "mode", "mode": "autonomous"}"#,
        r#"{"request": "mode", "mode": "halt"}"#,
        r#"{"request": "power_up"}"#,
        r#"{"request": "mode", "mode": "joystick"}"#,
    ];
    let mut waited_ms = Vec::new();
    let answers: Vec<String> = (requests.iter())
        .map(|request| {
            std::thread::sleep(Duration::from_millis(250));
            let asked = std::time::Instant::now();
            let answer = ask(&operator, "mechweed/request/operator", request);
            waited_ms.push(asked.elapsed().as_secs_f64() * 1e3);
            answer
        })
        .collect();
    stop.store(true, Ordering::Relaxed);
    waited_ms.sort_by(f64::total_cmp);
    println!(
        "the operator's {} requests during the reader's flood: answered in {:.1} ms (median), {:.1} ms at most",
        waited_ms.len(),
        waited_ms[waited_ms.len() / 2],
        waited_ms[waited_ms.len() - 1]
    );
    flood.join().unwrap();
    let refused = refused.load(Ordering::Relaxed);
    assert!(
        refused > 50,
        "the reader's flood was refused only {refused} times: no flood"
    );
    for (request, answer) in requests.iter().zip(&answers) {
        assert!(!answer.is_empty(), "{request}: no answer");
        assert!(!answer.contains("too many requests"), "{request}: {answer}");
    }
    let (stdout, stderr, _) = robot.finish();
    assert!(stdout.contains("mode: halt -> joystick"), "{stdout}");
    // The console names who was limited.
    assert!(stderr.contains("(asked by recorder)"), "{stderr}");
}

/// A viewer reads the settings flat out naming a new session on every query (so that no
/// count by what a query says can hold it), and asks under the operator's name too,
/// while the operator reads settings with `bus get`, as a technician tuning does. Before
/// each identity had an allowance counted by its link's certificate, the operator's
/// reads shared one allowance with the flood and were refused "too many requests".
#[test]
fn a_viewer_flooding_reads_under_any_name_leaves_the_operators_reads_answered() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(&keys, &["--duration", "10"]);
    let stop = Arc::new(AtomicBool::new(false));
    let (refused, as_operator) = (Arc::new(AtomicU64::new(0)), Arc::new(AtomicU64::new(0)));
    let flood = std::thread::spawn({
        let (stop, refused, as_operator) = (stop.clone(), refused.clone(), as_operator.clone());
        let viewer = keys.session(&robot.endpoint, "viewer");
        move || {
            for n in 0u64.. {
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                // Every tenth under the operator's name: its access rules drop those.
                let key = if n % 10 == 0 {
                    "mechweed/as/operator/config/steer/speed_mps"
                } else {
                    "mechweed/config/steer/speed_mps"
                };
                let (refused, as_operator) = (refused.clone(), as_operator.clone());
                let _ = (viewer.get(key))
                    .attachment(format!("session-{n}"))
                    .timeout(Duration::from_millis(500))
                    .callback(move |reply| {
                        if key.contains("/as/") {
                            as_operator.fetch_add(1, Ordering::Relaxed);
                        } else if super::reply_text(&reply).contains("too many requests") {
                            refused.fetch_add(1, Ordering::Relaxed);
                        }
                    })
                    .wait();
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    });
    std::thread::sleep(Duration::from_secs(2));
    let mut waited_ms = Vec::new();
    let answers: Vec<(bool, String)> = (0..5)
        .map(|_| {
            let asked = std::time::Instant::now();
            let out = robot.bus(&["get", "steer.speed_mps"]);
            waited_ms.push(asked.elapsed().as_secs_f64() * 1e3);
            let said = format!("{}{}", text(&out.stdout), text(&out.stderr));
            (out.status.success(), said)
        })
        .collect();
    stop.store(true, Ordering::Relaxed);
    flood.join().unwrap();
    waited_ms.sort_by(f64::total_cmp);
    let refused = refused.load(Ordering::Relaxed);
    println!(
        "the operator's {} reads during the viewer's flood: {:.0} ms (median) and {:.0} ms at most, each a `bus get` from its start; the viewer's reads refused: {refused} in about {:.1} s",
        waited_ms.len(),
        waited_ms[waited_ms.len() / 2],
        waited_ms[waited_ms.len() - 1],
        2.0 + waited_ms.iter().sum::<f64>() / 1e3
    );
    assert!(
        refused > 50,
        "the viewer's flood was refused only {refused} times: no flood"
    );
    assert_eq!(
        as_operator.load(Ordering::Relaxed),
        0,
        "a viewer's question under the operator's name was answered"
    );
    for (ok, said) in &answers {
        assert!(*ok && said.contains("steer.speed_mps = "), "{said}");
    }
    drop(robot.finish());
}
