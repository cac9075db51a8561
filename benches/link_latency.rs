//! Time from a frame's last byte on the serial line to the steer thread having it:
//! a frame is written into one end of a pseudo-terminal; the real camera-link thread
//! reads the other end through serialport, decodes it, publishes it and wakes the steer
//! side through the same channel the steer thread waits on.
//!
//! cargo bench --bench link_latency

use std::io::Write;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::bounded;
use mechweed::camlink::thread::{LinkThread, LinkWires};
use mechweed::camlink::{LinkCore, LinkStatus};
use mechweed::config::CameraPort;
use mechweed::config::Settings;
use mechweed::state::shared;
use mechweed::state::status::Status;
use mechweed_hw::camproto::{RowEstimate, encode_row};
use serialport::{SerialPort, TTYPort};

const FRAMES: usize = 500;

fn main() {
    // This thread plays the steer thread: give it the steer thread's priority.
    if let Some(warning) = mechweed::rt::set_this_thread(Settings::shipped().rt.steer_priority, -1)
    {
        eprintln!("{warning}");
    }
    let (mut master, slave) = TTYPort::pair().expect("a pseudo-terminal");
    master.set_timeout(Duration::from_millis(5)).unwrap();
    let (status_w, status_r) = shared(LinkStatus::default());
    let (_robot_w, robot_r) = shared(Status::default());
    let (estimate_tx, estimate_rx) = bounded(1);
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
    let port = CameraPort::Serial {
        path: slave.name().unwrap(),
        baud: 115200,
    };
    let core = LinkCore::new(&Settings::shipped().camera);
    // As in the program (where the system grants it; it runs on without).
    let link = LinkThread::new(core, port, Instant::now(), wires)
        .with_priority(Settings::shipped().rt.camlink_priority);
    let thread = std::thread::spawn(move || link.run());
    while !status_r.snapshot().connected {
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(50));

    let mut latencies_us = Vec::with_capacity(FRAMES);
    for k in 0..FRAMES {
        let est = RowEstimate {
            seq: k as u8,
            angle_rad: 0.0,
            offset_m: 0.0,
            quality: 90,
        };
        let frame = encode_row(&est);
        master.write_all(&frame).unwrap();
        let last_byte_out = Instant::now();
        estimate_rx
            .recv_timeout(Duration::from_secs(1))
            .expect("the frame reached the steer side");
        latencies_us.push(last_byte_out.elapsed().as_secs_f64() * 1e6);
        // Frames come at the camera's pace; the link thread is idle in between.
        std::thread::sleep(Duration::from_millis(10));
    }
    stop.store(true, Ordering::Relaxed);
    let _ = thread.join();
    drop(slave);

    latencies_us.sort_by(f64::total_cmp);
    let at = |q: f64| latencies_us[((latencies_us.len() - 1) as f64 * q).round() as usize];
    println!(
        "frame's last byte -> steer side woken, {FRAMES} frames over a pseudo-terminal: p50 {:.0} us, p99 {:.0} us, max {:.0} us",
        at(0.5),
        at(0.99),
        at(1.0)
    );
}
