//! A program's session to the robot mends itself: one that is linked but hears no
//! status, or brings a message its program cannot read, is opened again, and says so.
//! The "robot" here is a bare session that is linked but says nothing, or nonsense.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use mechweed::bus::hearing::{Ear, Hearing};
use mechweed::bus::session::{Role, open};
use zenoh::Wait;

use super::{endpoint, free_port};

/// A session listening at a port of its own, as a robot that says nothing would.
fn silent_robot() -> (zenoh::Session, String) {
    let at = endpoint(free_port());
    let session = open(Role::Master { listen: at.clone() }, None).unwrap();
    (session, at)
}

fn ear(at: &str) -> Ear<u8> {
    Ear {
        endpoint: at.to_string(),
        robot: "mechweed".into(),
        tls: None,
        token: "alive/hearing-test".into(),
        flows: vec![(0, "status")],
        program: "hearing test",
        queue: 16,
    }
}

/// Wait until the hearing has opened its session again `times` times.
fn reopened(hearing: &Hearing<u8>, times: u64, within: Duration) -> Duration {
    let from = Instant::now();
    while hearing.counts.reopened.load(Ordering::Relaxed) < times {
        assert!(
            from.elapsed() < within,
            "not opened again within {within:?}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    from.elapsed()
}

#[test]
fn a_session_linked_to_a_robot_that_sends_no_status_is_opened_again() {
    let (robot, at) = silent_robot();
    let hearing = Hearing::start(ear(&at)).unwrap();
    let took = reopened(&hearing, 1, Duration::from_secs(8));
    eprintln!("opened again {took:?} after the start");
    assert!(
        hearing
            .line()
            .contains("the session was opened again 1 times"),
        "{}",
        hearing.line()
    );
    // The new session hears what the robot sends.
    robot.put("mechweed/status", "{}").wait().unwrap();
    let (flow, bytes, _) = hearing.rx.recv_timeout(Duration::from_secs(3)).unwrap();
    assert_eq!((flow, bytes.as_slice()), (0, &b"{}"[..]));
}

#[test]
fn a_message_its_program_cannot_read_opens_the_session_again() {
    let (robot, at) = silent_robot();
    let hearing = Hearing::start(ear(&at)).unwrap();
    // Status keeps coming: only what the program says of it opens the session again.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let talking = {
        let (robot, stop) = (robot.clone(), stop.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                robot.put("mechweed/status", "not json").wait().unwrap();
                std::thread::sleep(Duration::from_millis(100));
            }
        })
    };
    hearing.rx.recv_timeout(Duration::from_secs(5)).unwrap();
    assert_eq!(hearing.counts.reopened.load(Ordering::Relaxed), 0);
    hearing.unreadable();
    reopened(&hearing, 1, Duration::from_secs(3));
    std::thread::sleep(Duration::from_secs(1));
    // Heard, so no more: the status kept it from being opened again for silence.
    assert_eq!(hearing.counts.reopened.load(Ordering::Relaxed), 1);
    stop.store(true, Ordering::Relaxed);
    talking.join().unwrap();
}
