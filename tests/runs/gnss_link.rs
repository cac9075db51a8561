//! The GNSS link on real threads, from outside: the simulated robot's receiver over its
//! pseudo-terminal steering the fused row, `mechweed gnsssim` over TCP on loopback, and
//! a row map file that is wrong, refused before anything starts.

use crate::common;

use std::process::{Child, Stdio};

use common::{mechweed, text};

/// `mechweed run --headless ARGS --report FILE` in `dir`: its output (stdout and
/// stderr) and its report.
fn run_with_report(dir: &std::path::Path, args: &[&str]) -> (String, serde_json::Value) {
    let report_path = dir.join("report.json");
    let out = mechweed()
        .args(["run", "--headless"])
        .args(common::test_run_settings(dir))
        .args(args)
        .arg("--report")
        .arg(&report_path)
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}\n{stderr}");
    let report = serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    // The log's lines (the links opening) go to stderr, the console's to stdout.
    (format!("{stdout}\n{stderr}"), report)
}

#[test]
fn the_simulated_robots_receiver_steers_the_fused_row_in_a_real_time_run() {
    let dir = tempfile::tempdir().unwrap();
    let (stdout, report) = run_with_report(
        dir.path(),
        &[
            "--mode",
            "autonomous",
            "--duration",
            "6",
            "--set",
            "gnss.port=sim",
            "--set",
            "steer.source=fused",
        ],
    );
    assert!(
        stdout.contains("GNSS receiver open on /dev/pts/"),
        "{stdout}"
    );
    assert_eq!(report["faults"].as_array().unwrap().len(), 0, "{report:#}");
    // Ten fixes a second, every one RTK fixed and every line good.
    let gnss = &report["gnss"];
    assert!(gnss["fixes"].as_u64().unwrap() >= 45, "{gnss:#}");
    assert_eq!(gnss["last_quality"], "RTK fixed");
    assert_eq!(gnss["sentences"]["checksum_errors"], 0);
    assert_eq!(report["filter"]["steering"], "fused", "{report:#}");
    let notices: Vec<&str> = report["notices"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["what"].as_str().unwrap())
        .collect();
    assert_eq!(notices, ["steering by camera and GNSS, fused"]);
    assert!(report["distance_m"].as_f64().unwrap() > 1.0, "{report:#}");
    assert!(
        stdout.contains("steering by camera and GNSS, fused; GNSS RTK fixed"),
        "{stdout}"
    );
}

/// Kills the simulator when the test ends, however it ends.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn gnsssim_over_tcp_feeds_the_robot_programs_gnss_link() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let address = format!("127.0.0.1:{port}");
    let _sim = Killed(
        mechweed()
            .args(["gnsssim", "--listen", &address, "--state", "float"])
            .stdout(Stdio::null())
            .spawn()
            .unwrap(),
    );
    // Give it a moment to listen; the link retries anyway.
    std::thread::sleep(std::time::Duration::from_millis(300));
    let dir = tempfile::tempdir().unwrap();
    let port_setting = format!("gnss.port=tcp://{address}");
    let (_, report) = run_with_report(dir.path(), &["--duration", "3", "--set", &port_setting]);
    let gnss = &report["gnss"];
    assert!(gnss["fixes"].as_u64().unwrap() >= 15, "{gnss:#}");
    assert_eq!(gnss["last_quality"], "RTK float", "{gnss:#}");
    // The camera steered: no filter.
    assert!(report["filter"].is_null(), "{report:#}");
}

#[test]
fn a_row_map_with_a_mistake_stops_the_run_before_it_starts_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let map = dir.path().join("rows.csv");
    std::fs::write(&map, "row,lat_deg,lon_deg\n1,52.0,5.66\n1,52.0,5.66x\n").unwrap();
    let out = mechweed()
        .args(["run", "--headless", "--duration", "2"])
        .args(common::test_run_settings(dir.path()))
        .args(["--set", "gnss.port=sim", "--set"])
        .arg(format!("gnss.map={}", map.display()))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("the row map:") && stderr.contains("line 3"),
        "{stderr}"
    );
    // Nothing started: no record was made beside the map.
    let files: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(files, ["rows.csv"], "{stderr}");
}
