//! The camera link end to end: the real `mechweed` binary against a simulated camera
//! computer played by this test, over a pseudo-terminal pair and over TCP on 127.0.0.1.
//! START on entering autonomous, frames counted, a rebooted camera gets START again,
//! STOP on halt, and a camera that falls silent faults the robot with its cause.

use std::net::TcpListener;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use mechweed::camlink::transport::ByteStream;
use mechweed::programs::camsim::computer::{CamSim, CamSimOptions, Pattern};
use serialport::{SerialPort, TTYPort};

type Log = Arc<Mutex<Vec<(f64, &'static str)>>>;

/// The camera computer's script, in seconds after the first START it hears.
const REBOOT_AFTER_S: f64 = 1.2;
const SILENT_AFTER_S: f64 = 4.5;

/// Play a camera computer that reboots once and later falls silent for good.
fn camera(
    mut stream: Box<dyn ByteStream>,
    clock: Instant,
    log: Log,
    stop: Arc<AtomicBool>,
) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut sim = CamSim::new(CamSimOptions {
            pattern: Pattern::Straight,
            seed: 2,
            drop: 0.0,
            corrupt: 0.0,
        });
        let (mut buf, mut out) = ([0u8; 64], Vec::new());
        let (mut first_start, mut rebooted) = (None, false);
        while !stop.load(Ordering::Relaxed) {
            let now = clock.elapsed().as_secs_f64();
            match stream.read(&mut buf) {
                Ok(0) => return,
                Ok(n) => {
                    for &b in &buf[..n] {
                        if let Some(name) = sim.receive(b, now) {
                            log.lock().unwrap().push((now, name));
                            if name == "START" {
                                first_start.get_or_insert(now);
                            }
                        }
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
                    ) => {}
                Err(_) => return,
            }
            let since_start = first_start.map_or(0.0, |t| now - t);
            if since_start >= REBOOT_AFTER_S && !rebooted {
                rebooted = true;
                sim.reboot();
                log.lock().unwrap().push((now, "(reboot)"));
            }
            out.clear();
            sim.poll(now, &mut out);
            if since_start < SILENT_AFTER_S && !out.is_empty() && stream.write_all(&out).is_err() {
                return;
            }
        }
    })
}

/// Run the binary for 6.5 s with the camera on `port`; check what both sides saw.
fn scenario(port: &str, serve: impl FnOnce(Instant, Log, Arc<AtomicBool>) -> JoinHandle<()>) {
    let dir = tempfile::tempdir().unwrap();
    let report_path = dir.path().join("report.json");
    let (log, stop): (Log, _) = (Arc::default(), Arc::new(AtomicBool::new(false)));
    let clock = Instant::now();
    let camera = serve(clock, log.clone(), stop.clone());
    let out = Command::new(env!("CARGO_BIN_EXE_mechweed"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "6.5",
        ])
        .args(["--set", &format!("camera.port={port}")])
        .args(["--set", "sim.events=3 mode halt, 3.6 mode autonomous"])
        // A busy test machine may overrun now and then; that fault has its own test.
        .args([
            "--set",
            "rt.max_overruns=1000000",
            "--set",
            "rt.max_late_periods=20",
        ])
        // The run's record goes to the temporary folder, not into the repository.
        .arg("--set")
        .arg(format!(
            "record.folder={}",
            dir.path().join("records").display()
        ))
        .arg("--report")
        .arg(&report_path)
        .output()
        .unwrap();
    stop.store(true, Ordering::Relaxed);
    let _ = camera.join();
    let stdout = String::from_utf8_lossy(&out.stdout);
    // The camera's silence ends the run in Fault: exit status 3.
    assert_eq!(
        out.status.code(),
        Some(3),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    let log = log.lock().unwrap().clone();
    let at =
        |name: &str, from: f64, to: f64| log.iter().any(|&(t, n)| n == name && t > from && t <= to);
    let first_start = log
        .iter()
        .find(|(_, n)| *n == "START")
        .expect("no START at all")
        .0;
    assert!(first_start < 1.5, "first START at {first_start}: {log:?}");
    let reboot = first_start + REBOOT_AFTER_S;
    assert!(
        at("START", reboot, reboot + 0.6),
        "no START after the reboot: {log:?}"
    );
    assert!(at("STOP", 2.9, 3.5), "no STOP on halt: {log:?}");
    assert!(
        at("START", 3.5, 4.2),
        "no START on autonomous again: {log:?}"
    );
    assert!(
        log.iter().any(|(_, n)| *n == "PING"),
        "no link test: {log:?}"
    );

    let faults = report["faults"].as_array().unwrap();
    assert_eq!(faults.len(), 1, "{report:#}");
    assert!(
        faults[0]["cause"]
            .as_str()
            .unwrap()
            .starts_with("camera link lost"),
        "{report:#}"
    );
    let silent = first_start + SILENT_AFTER_S;
    let fault_t = faults[0]["t_s"].as_f64().unwrap();
    assert!(
        fault_t > silent && fault_t < silent + 0.5 + 0.15,
        "fault at {fault_t}, silent from {silent}"
    );
    assert!(
        at("STOP", fault_t - 0.1, 6.6),
        "no STOP after the fault: {log:?}"
    );
    let link = &report["link"];
    assert!(link["frames_ok"].as_u64().unwrap() > 25, "{link:#}");
    assert!(link["starts_sent"].as_u64().unwrap() >= 3, "{link:#}");
    assert!(link["ping_rtt_ms"].as_f64().unwrap() < 100.0, "{link:#}");
    // Duplicated frames are counted beside the gaps, in the report and the summary.
    assert_eq!(link["duplicates"].as_u64(), Some(0), "{link:#}");
    assert!(
        stdout.contains(" sequence gaps, 0 duplicates, "),
        "no duplicates in the summary: {stdout}"
    );
}

#[test]
fn over_a_pseudo_terminal() {
    let (mut master, slave) = TTYPort::pair().unwrap();
    master.set_timeout(Duration::from_millis(5)).unwrap();
    let path = slave.name().unwrap();
    scenario(&path, move |clock, log, stop| {
        let handle = camera(Box::new(master), clock, log, stop);
        // Our end of the far side stays open while the camera runs.
        std::thread::spawn(move || {
            let _slave = slave;
            std::thread::sleep(Duration::from_secs(8));
        });
        handle
    });
}

#[test]
fn over_tcp_on_loopback() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = format!("tcp://{}", listener.local_addr().unwrap());
    scenario(&port, move |clock, log, stop| {
        std::thread::spawn(move || {
            let (stream, _) = listener.accept().unwrap();
            stream
                .set_read_timeout(Some(Duration::from_millis(5)))
                .unwrap();
            camera(Box::new(stream), clock, log, stop).join().unwrap();
        })
    });
}
