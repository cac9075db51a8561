//! The camera-link thread when its transport fails: a serial device that vanishes and
//! a TCP peer that closes are named in the link's status, nothing stalls (not even a
//! name look-up that hangs), and the link opens again by itself when it can.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, ToSocketAddrs};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::bounded;
use mechweed::camlink::thread::{LinkThread, LinkWires};
use mechweed::camlink::transport::{Resolver, system_resolver};
use mechweed::camlink::{LinkCore, LinkProblem, LinkStatus, OpenStep};
use mechweed::config::CameraPort;
use mechweed::config::Settings;
use mechweed::state::modes::Mode;
use mechweed::state::status::Status;
use mechweed::state::{Reader, shared};
use mechweed_hw::camproto::{CMD_PING, CMD_START, RowEstimate, encode_pong, encode_row};
use serialport::{SerialPort, TTYPort};

/// Start a link thread on `port` that wants rows; returns its status and its stop flag.
fn start_link(port: CameraPort) -> (Reader<LinkStatus>, Arc<AtomicBool>) {
    start_link_resolving(port, system_resolver)
}

/// The same, looking host names up with `resolve`.
fn start_link_resolving(
    port: CameraPort,
    resolve: Resolver,
) -> (Reader<LinkStatus>, Arc<AtomicBool>) {
    let (status_w, status_r) = shared(LinkStatus::default());
    // A robot driving: the link streams rows.
    let (robot_w, robot_r) = shared(Status {
        mode: Mode::Autonomous,
        ..Status::default()
    });
    let (estimate_tx, _estimate_rx) = bounded(1);
    let (_ping_tx, ping_rx) = bounded(1);
    let stop = Arc::new(AtomicBool::new(false));
    let wires = LinkWires {
        new_estimate: estimate_tx,
        ping_requests: ping_rx,
        status: status_w,
        robot: robot_r,
        panics: Default::default(),
        stop: stop.clone(),
    };
    let core = LinkCore::new(&Settings::shipped().camera);
    let link = LinkThread::new(core, port, Instant::now(), wires).with_resolver(resolve);
    std::thread::spawn(move || {
        let _keep_robot_writer = robot_w;
        link.run();
    });
    (status_r, stop)
}

/// Wait up to `seconds` for the status to satisfy `ok`.
fn wait_for(
    status: &Reader<LinkStatus>,
    seconds: f64,
    ok: impl Fn(&LinkStatus) -> bool,
) -> LinkStatus {
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    loop {
        let s = status.snapshot();
        if ok(&s) || Instant::now() > end {
            return s;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Answer PING and START like a camera computer, for `seconds`.
fn play_camera(stream: &mut (impl Read + Write), seconds: f64) {
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    let (mut buf, mut seq, mut streaming) = ([0u8; 16], 0u8, false);
    while Instant::now() < end {
        if let Ok(n) = stream.read(&mut buf) {
            for &b in &buf[..n] {
                if b == CMD_PING {
                    let _ = stream.write_all(&encode_pong(seq));
                    seq = seq.wrapping_add(1);
                }
                streaming |= b == CMD_START;
            }
        }
        if streaming {
            let est = RowEstimate {
                seq,
                angle_rad: 0.0,
                offset_m: 0.0,
                quality: 90,
            };
            let _ = stream.write_all(&encode_row(&est));
            seq = seq.wrapping_add(1);
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

#[test]
fn a_vanished_serial_device_is_named_and_retried() {
    let (mut master, slave) = TTYPort::pair().unwrap();
    master.set_timeout(Duration::from_millis(5)).unwrap();
    // The link opens the terminal by a name of the test's own, as udev names an adapter:
    // a pseudo-terminal's number is given to the next test that asks once this one is
    // gone, and a link reopening that number would take another test's camera line.
    let dir = tempfile::tempdir().unwrap();
    let device = dir.path().join("ttyUSB-camera");
    std::os::unix::fs::symlink(slave.name().unwrap(), &device).unwrap();
    let path = device.display().to_string();
    let (status, stop) = start_link(CameraPort::Serial { path, baud: 115200 });
    play_camera(&mut master, 0.5);
    let up = wait_for(&status, 1.0, |s| s.counters.frames_ok > 5);
    assert!(up.connected && up.counters.frames_ok > 5, "{up:?}");
    assert!(
        !up.ping_rtt_ms.is_nan(),
        "the link test at connection got no answer"
    );

    // Unplug: the adapter's name goes, and the pseudo-terminal with both of its ends.
    std::fs::remove_file(&device).unwrap();
    drop(master);
    drop(slave);
    let down = wait_for(&status, 2.0, |s| {
        matches!(s.problem, Some(LinkProblem::OpenFailed(_)))
    });
    assert!(!down.connected, "{down:?}");
    assert!(
        matches!(
            down.problem,
            Some(LinkProblem::OpenFailed(std::io::ErrorKind::NotFound))
        ),
        "{down:?}"
    );
    stop.store(true, Ordering::Relaxed);
}

#[test]
fn a_closed_tcp_peer_is_named_and_the_link_reconnects() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let (status, stop) = start_link(CameraPort::Tcp { address });
    let (mut first, _) = listener.accept().unwrap();
    first
        .set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    play_camera(&mut first, 0.4);
    let frames_before = wait_for(&status, 1.0, |s| s.counters.frames_ok > 5)
        .counters
        .frames_ok;
    assert!(frames_before > 5);
    drop(first);
    let down = wait_for(&status, 1.0, |s| s.problem.is_some());
    assert_eq!(down.problem, Some(LinkProblem::PeerClosed), "{down:?}");

    // The camera computer is back: the link opens again and asks for rows again.
    let (mut second, _) = listener.accept().unwrap();
    second
        .set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    play_camera(&mut second, 0.4);
    let up = wait_for(&status, 1.0, |s| s.counters.frames_ok > frames_before + 5);
    assert!(up.connected && up.problem.is_none(), "{up:?}");
    assert_eq!(up.reconnects, 1);
    assert!(
        up.starts_sent >= 2,
        "no START on the new connection: {up:?}"
    );
    stop.store(true, Ordering::Relaxed);
}

/// How long the look-up of `slow_resolver` hangs, s.
const LOOK_UP_S: f64 = 2.0;

/// A name look-up that hangs, as one does without a network, then finds the camera
/// computer on this machine: "HOST:PORT" -> 127.0.0.1:PORT (no real DNS in tests).
fn slow_resolver(address: &str) -> std::io::Result<Vec<SocketAddr>> {
    std::thread::sleep(Duration::from_secs_f64(LOOK_UP_S));
    let (_host, port) = address.rsplit_once(':').unwrap();
    Ok(format!("127.0.0.1:{port}").to_socket_addrs()?.collect())
}

#[test]
fn a_hanging_name_look_up_does_not_stop_the_link_thread() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let start = Instant::now();
    let (status, stop) = start_link_resolving(
        CameraPort::Tcp {
            address: format!("camera-computer.invalid:{port}"),
        },
        slow_resolver,
    );

    // While the name is looked up, the thread beats as often as the supervisor expects
    // (else: "the camera link thread stopped", in every mode) and says what it waits for.
    let timeout_s = Settings::shipped().rt.heartbeat_timeout_s;
    let first = wait_for(&status, 1.0, |s| s.opening.is_some());
    assert_eq!(first.opening, Some(OpenStep::LookingUp), "{first:?}");
    let (mut beat_s, mut longest_silence_s) = (first.beat_s, 0.0f64);
    while start.elapsed().as_secs_f64() < LOOK_UP_S - 0.2 {
        std::thread::sleep(Duration::from_millis(20));
        let s = status.snapshot();
        assert!(!s.connected, "connected before the name was found: {s:?}");
        assert_eq!(s.opening, Some(OpenStep::LookingUp), "{s:?}");
        longest_silence_s = longest_silence_s.max(s.beat_s - beat_s);
        beat_s = s.beat_s;
    }
    assert!(
        beat_s - first.beat_s > LOOK_UP_S / 2.0,
        "the link thread did not beat during the look-up (last beat at {beat_s} s)"
    );
    assert!(
        longest_silence_s < timeout_s,
        "the link thread was silent for {longest_silence_s} s (the supervisor allows {timeout_s} s)"
    );

    // Once the name is found, the link connects and the frames come.
    let up = wait_for(&status, LOOK_UP_S + 2.0, |s| s.connected);
    assert!(up.connected && up.opening.is_none(), "{up:?}");
    let (mut camera, _) = listener.accept().unwrap();
    camera
        .set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    play_camera(&mut camera, 0.4);
    let rows = wait_for(&status, 1.0, |s| s.counters.frames_ok > 5);
    assert!(rows.counters.frames_ok > 5, "{rows:?}");
    stop.store(true, Ordering::Relaxed);
}

#[test]
fn a_camera_computer_named_localhost_is_found() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let (status, stop) = start_link(CameraPort::Tcp {
        address: format!("localhost:{port}"),
    });
    let up = wait_for(&status, 5.0, |s| s.connected);
    assert!(up.connected, "{up:?}");
    let (mut camera, _) = listener.accept().unwrap();
    camera
        .set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    play_camera(&mut camera, 0.4);
    let rows = wait_for(&status, 1.0, |s| s.counters.frames_ok > 5);
    assert!(rows.counters.frames_ok > 5, "{rows:?}");
    stop.store(true, Ordering::Relaxed);
}
