//! The notify protocol against a socket the test listens on, as systemd does.

use std::os::unix::net::UnixDatagram;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::Notifier;
use crate::state::fault_cause::FaultCause;
use crate::state::shared;
use crate::state::status::{FaultRecord, Status};

/// A listening socket standing in for systemd, and a notifier that speaks to it with a
/// watchdog of `watchdog_ms`.
fn systemd(dir: &tempfile::TempDir, watchdog_ms: u64) -> (UnixDatagram, Notifier) {
    let path = dir.path().join("notify");
    let listener = UnixDatagram::bind(&path).unwrap();
    listener
        .set_read_timeout(Some(Duration::from_millis(50)))
        .unwrap();
    let usec = (watchdog_ms * 1000).to_string();
    let notifier = Notifier::new(path.as_os_str(), Some(&usec), None).unwrap();
    (listener, notifier)
}

/// Every message that arrives within `for_ms`.
fn heard(listener: &UnixDatagram, for_ms: u64) -> Vec<String> {
    let until = Instant::now() + Duration::from_millis(for_ms);
    let mut messages = Vec::new();
    let mut buf = [0u8; 4096];
    while Instant::now() < until {
        if let Ok(n) = listener.recv(&mut buf) {
            messages.push(String::from_utf8_lossy(&buf[..n]).into_owned());
        }
    }
    messages
}

fn count(messages: &[String], what: &str) -> usize {
    messages.iter().filter(|m| m.contains(what)).count()
}

#[test]
fn ready_and_the_watchdog_wait_for_the_supervisors_first_tick_and_stop_when_it_falls_silent() {
    let dir = tempfile::tempdir().unwrap();
    let (listener, notifier) = systemd(&dir, 100);
    let (writer, reader) = shared(Status::default());
    let clock = Instant::now();
    let stop = Arc::new(AtomicBool::new(false));
    let notifier: &'static Notifier = Box::leak(Box::new(notifier));
    let thread = notifier.start(reader, clock, 0.2, stop.clone());

    // No tick yet: the hardware may still be opening. Nothing is ready, nothing fed.
    let before = heard(&listener, 300);
    assert_eq!(count(&before, "READY=1"), 0, "{before:?}");
    assert_eq!(count(&before, "WATCHDOG=1"), 0, "{before:?}");

    // The supervisor ticks: READY once, its status, and the watchdog fed.
    let ticking = std::thread::spawn({
        let stop = stop.clone();
        move || {
            let mut tick = 0;
            while clock.elapsed() < Duration::from_millis(1100) && !stop.load(Ordering::Relaxed) {
                tick += 1;
                let s = Status {
                    t_s: clock.elapsed().as_secs_f64(),
                    tick,
                    ..Status::default()
                };
                writer.publish(&s);
                std::thread::sleep(Duration::from_millis(10));
            }
            writer
        }
    });
    let running = heard(&listener, 800);
    assert_eq!(count(&running, "READY=1"), 1, "{running:?}");
    assert!(count(&running, "STATUS=halt; no fault") >= 1, "{running:?}");
    assert!(
        count(&running, "WATCHDOG=1") >= 3,
        "fed every 50 ms: {running:?}"
    );

    // The supervisor stops publishing (a hung tick): the feeding stops with it.
    let writer = ticking.join().unwrap();
    let _ = heard(&listener, 300);
    let silent = heard(&listener, 600);
    assert_eq!(count(&silent, "WATCHDOG=1"), 0, "{silent:?}");

    // A fault is said in the status once the supervisor ticks again.
    let fault = FaultRecord {
        cause: FaultCause::EstopFront,
        t_s: 1.5,
        tick_seen: 150,
        tick_safe: 150,
        came_back_after_s: None,
    };
    let s = Status {
        t_s: clock.elapsed().as_secs_f64(),
        tick: 200,
        fault: Some(fault),
        ..Status::default()
    };
    writer.publish(&s);
    let faulted = heard(&listener, 150);
    assert!(count(&faulted, "fault at 1.5 s") >= 1, "{faulted:?}");

    stop.store(true, Ordering::Relaxed);
    thread.join().unwrap();
    let end = heard(&listener, 100);
    assert_eq!(count(&end, "STOPPING=1"), 1, "{end:?}");
}

#[test]
fn a_watchdog_meant_for_another_process_is_not_fed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("notify");
    let _listener = UnixDatagram::bind(&path).unwrap();
    let ours = Notifier::new(path.as_os_str(), Some("2000000"), None).unwrap();
    assert_eq!(ours.feed_every, Some(Duration::from_secs(1)));
    let other_pid = (std::process::id() + 1).to_string();
    let theirs = Notifier::new(path.as_os_str(), Some("2000000"), Some(&other_pid)).unwrap();
    assert_eq!(theirs.feed_every, None);
    let none = Notifier::new(path.as_os_str(), None, None).unwrap();
    assert_eq!(none.feed_every, None);
}
