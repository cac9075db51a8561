//! The virtual cluster between real processes on loopback: the one-machine graph
//! (config/cluster-local.ini) run secured, as the field's graph is (TLS, the cluster's
//! own identities made by `mechweed keys`), as a master and three launchers with three
//! machine names, each on ports of its own; and (`alone.rs`) one machine when its
//! master goes away, a program that is not mechweed's, and a rogue master.

mod alone;
use crate::common;
mod guarded;
mod orphans;

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::text;
use serde_json::Value;

pub fn free_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    listener.local_addr().unwrap().port()
}

/// The program, run in `folder` (no robot.ini there: the built-in settings; records
/// land there).
pub fn mechweed_in(folder: &Path) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mechweed"));
    cmd.current_dir(folder);
    // A robot PC's own settings never reach a test.
    cmd.env("MECHWEED_SYSTEM_INI", "/nonexistent/robot.ini");
    cmd
}

/// The processes of a test, killed if it fails half-way (the launchers' children run in
/// process groups of their own: killed by group).
pub struct Started(pub Vec<Child>);

impl Drop for Started {
    fn drop(&mut self) {
        for child in &mut self.0 {
            if child.try_wait().ok().flatten().is_none() {
                unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
            }
        }
        std::thread::sleep(Duration::from_secs(2));
        for child in &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

pub fn wait_for<T>(what: &str, seconds: f64, mut check: impl FnMut() -> Option<T>) -> T {
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    loop {
        if let Some(found) = check() {
            return found;
        }
        assert!(Instant::now() < end, "{what}: not within {seconds} s");
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// A tool's identity for `endpoint`: on a secured one (tls/), the operator's in the
/// folder's keys/.
fn identity_for(endpoint: &str) -> Vec<&'static str> {
    if endpoint.starts_with("tls/") {
        vec!["--keys", "keys", "--as", "operator"]
    } else {
        Vec::new()
    }
}

/// The robot's newest status, from `bus echo`.
pub fn robot_status(folder: &Path, robot: &str) -> Option<Value> {
    let out = mechweed_in(folder)
        .args(["bus", "echo", "status", "--count", "1", "--seconds", "2"])
        .args(["--connect", robot])
        .args(identity_for(robot))
        .output()
        .unwrap();
    let line: Value = serde_json::from_str(text(&out.stdout).lines().next()?).ok()?;
    Some(line["payload"].clone())
}

pub fn cluster_status(folder: &Path, master: &str) -> Option<Value> {
    let out = cluster_status_as(folder, master, &identity_for(master));
    serde_json::from_slice(&out.stdout).ok()
}

/// `cluster status --json` asked with `identity` (`--keys DIR --as NAME`, or none).
pub fn cluster_status_as(folder: &Path, master: &str, identity: &[&str]) -> std::process::Output {
    mechweed_in(folder)
        .args([
            "cluster",
            "status",
            "--json",
            "--seconds",
            "1",
            "--connect",
            master,
        ])
        .args(identity)
        .output()
        .unwrap()
}

pub fn process<'a>(cluster: &'a Value, name: &str) -> &'a Value {
    let all = cluster["processes"].as_array().unwrap();
    all.iter().find(|p| p["process"] == name).unwrap()
}

/// A master serving a one-machine graph (machine robot-pc, plain TCP on loopback) whose
/// processes are the INI sections `processes`, started in `folder`: its process, for a
/// `Started`, and the endpoint a launcher connects to.
pub fn one_machine_master(folder: &Path, processes: &str) -> (Child, String) {
    let master = format!("tcp/127.0.0.1:{}", free_port());
    let graph = folder.join("g.ini");
    let text = format!(
        "[cluster]\nrobot = mechweed\nmaster = {master}\nmaster_lost = run_on\n\
         [machine robot-pc]\nendpoint = tcp/127.0.0.1:{}\n{processes}",
        free_port()
    );
    std::fs::write(&graph, text).unwrap();
    let child = mechweed_in(folder)
        .args(["cluster", "master"])
        .arg(&graph)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    (child, master)
}

/// Wait for each of `children` to end (they were asked to), at most `seconds` each.
pub fn wait_ended(children: &mut [Child], seconds: u64, what: &str) {
    for child in children {
        let end = Instant::now() + Duration::from_secs(seconds);
        while child.try_wait().unwrap().is_none() {
            assert!(Instant::now() < end, "{what} did not end");
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

pub fn alive(pid: u64) -> bool {
    unsafe { libc::kill(pid as i32, 0) == 0 }
}

/// Make the cluster's keys in `folder`/keys, with a launcher identity per machine.
pub fn make_keys(folder: &Path, machines: &[&str]) {
    let run = |args: &[&str]| {
        let out = mechweed_in(folder).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    };
    run(&["keys", "new", "keys"]);
    for machine in machines {
        run(&["keys", "add", "keys", "launcher", machine]);
    }
}

/// The one-machine graph on ports of this test, with a busy test machine's late ticks
/// tolerated (as every test run of the controller), secured with the keys in
/// `folder`/keys: every endpoint tls/, the master with its identity.
fn local_graph(folder: &Path) -> (PathBuf, String, String) {
    let mut graph = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/config/cluster-local.ini"
    ))
    .unwrap();
    let ports: Vec<u16> = (0..4).map(|_| free_port()).collect();
    for (shipped, port) in [7450, 7451, 7452, 7453].iter().zip(&ports) {
        graph = graph.replace(
            &format!("127.0.0.1:{shipped}"),
            &format!("127.0.0.1:{port}"),
        );
    }
    graph = graph.replace(
        "after = camera\n",
        "after = camera\nset.rt.max_overruns = 1000000\nset.rt.max_late_periods = 20\n",
    );
    graph = graph.replace("tcp/127.0.0.1", "tls/127.0.0.1").replacen(
        "master_lost",
        "tls_ca = keys/ca.pem\ntls_cert = keys/master.pem\ntls_key = keys/master.key\nmaster_lost",
        1,
    );
    let path = folder.join("cluster.ini");
    std::fs::write(&path, graph).unwrap();
    let at = |port: u16| format!("tls/127.0.0.1:{port}");
    (path, at(ports[0]), at(ports[1]))
}

#[test]
fn the_one_machine_graph_drives_restarts_the_camera_and_stops_with_safe_outputs() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    make_keys(folder, &["robot-pc", "camera-pc", "laptop"]);
    let (graph, master, robot) = local_graph(folder);
    let log = |name: &str| File::create(folder.join(format!("{name}.log"))).unwrap();
    let mut started = Started(Vec::new());
    let mut master_cmd = mechweed_in(folder);
    master_cmd.args(["cluster", "master"]).arg(&graph);
    master_cmd.stdout(log("master")).stderr(Stdio::inherit());
    started.0.push(master_cmd.spawn().unwrap());
    for machine in ["robot-pc", "camera-pc", "laptop"] {
        let mut launcher = mechweed_in(folder);
        launcher.args([
            "cluster",
            "launcher",
            "--machine",
            machine,
            "--connect",
            &master,
            "--keys",
            "keys",
            "--as",
            machine,
        ]);
        launcher
            .stdout(log(machine))
            .stderr(log(&format!("{machine}.err")));
        started.0.push(launcher.spawn().unwrap());
    }

    // The controller follows the row on the camera process's rows, over the bus.
    let driving = wait_for("the controller driving in autonomous", 60.0, || {
        let status = robot_status(folder, &robot)?;
        let going = status["mode"] == "autonomous" && status["distance_m"].as_f64()? > 1.0;
        going.then_some(status)
    });
    assert!(driving["fault"].is_null(), "{driving}");
    assert_eq!(driving["camera"]["streaming"], true, "{driving}");
    let cluster = cluster_status(folder, &master).expect("cluster status answers");
    for name in ["controller", "camera", "recorder"] {
        let state = &process(&cluster, name)["state"];
        assert!(
            state == "running" || state == "restarted",
            "{name}: {cluster}"
        );
    }
    assert_eq!(process(&cluster, "operator-view")["state"], "manual");
    // A launcher's identity gets no command line: the cluster's status is not for it
    // (its launcher waited for the camera through the processes' states alone).
    let as_launcher = cluster_status_as(folder, &master, &["--keys", "keys", "--as", "robot-pc"]);
    assert!(
        !as_launcher.status.success(),
        "{}",
        text(&as_launcher.stdout)
    );
    assert!(!text(&as_launcher.stdout).contains("\"command\""));
    let rows_per_s = cluster["rates"]["rows"].as_f64().unwrap();
    assert!(rows_per_s > 5.0, "rows: {cluster}");
    let later = wait_for("driving on", 20.0, || {
        let status = robot_status(folder, &robot)?;
        (status["distance_m"].as_f64()? > driving["distance_m"].as_f64()? + 0.5).then_some(status)
    });
    assert!(later["fault"].is_null(), "{later}");

    // Killing the camera process faults the robot with the link's cause; the launcher
    // starts it again, as the graph says.
    let camera_pid = process(&cluster, "camera")["pid"].as_u64().unwrap();
    unsafe { libc::kill(camera_pid as i32, libc::SIGKILL) };
    let faulted = wait_for("the fault", 15.0, || {
        let status = robot_status(folder, &robot)?;
        let fault = status["fault"].as_str()?.to_string();
        Some(fault)
    });
    assert!(faulted.contains("camera link lost"), "{faulted}");
    let cluster = wait_for("the camera restarted", 20.0, || {
        let cluster = cluster_status(folder, &master)?;
        let camera = process(&cluster, "camera");
        (camera["restarts"] == 1 && camera["state"] == "restarted").then_some(cluster)
    });
    let camera = process(&cluster, "camera");
    assert_eq!(camera["exit"], "killed by SIGKILL", "{cluster}");
    let pids: Vec<u64> = ["controller", "camera", "recorder"]
        .iter()
        .map(|name| process(&cluster, name)["pid"].as_u64().unwrap())
        .collect();
    assert_ne!(pids[1], camera_pid);

    // Stopping the master ends every process, the controller first, in safe outputs.
    let master_pid = started.0[0].id();
    unsafe { libc::kill(master_pid as i32, libc::SIGINT) };
    wait_ended(&mut started.0, 60, "a launcher or the master");
    for pid in pids {
        assert!(
            !alive(pid),
            "process {pid} still runs after the master stopped"
        );
    }
    let read = |name: &str| std::fs::read_to_string(folder.join(format!("{name}.log"))).unwrap();
    let robot_log = read("robot-pc");
    assert!(
        robot_log
            .contains("the outputs are safe: amplifiers 0 V, motor power off, brakes on, tool off"),
        "{robot_log}"
    );
    let master_log = read("master");
    let controller_at = master_log.find("controller on robot-pc stopped").unwrap();
    let camera_at = master_log.find("camera on camera-pc stopped").unwrap();
    assert!(
        controller_at < camera_at,
        "the controller first: {master_log}"
    );

    // The off-board recorder's record reads back as a run record.
    let laptop = read("laptop");
    let files = laptop
        .lines()
        .find_map(|l| l.split("recording into ").nth(1))
        .expect("the recorder says where it records");
    let csv = files.split(", ").next().unwrap();
    let summary = mechweed_in(folder)
        .args(["record", "summary", csv, "--from-m", "0"])
        .output()
        .unwrap();
    let said = text(&summary.stdout);
    assert!(summary.status.success(), "{said}{}", text(&summary.stderr));
    assert!(said.contains("modes: halt at"), "{said}");
    assert!(said.contains("autonomous at"), "{said}");
    assert!(said.contains("camera link lost"), "{said}");
    // The rows came from camsim on the bus, not the simulated field: neither the
    // off-board record nor the controller's own gives a cross-track figure.
    let controller_csv = (robot_log.lines())
        .find_map(|l| l.split("recording into ").nth(1))
        .and_then(|files| files.split(", ").next())
        .expect("the controller says where it records")
        .to_string();
    for record in [csv, controller_csv.as_str()] {
        let mut summary = mechweed_in(folder);
        summary.args(["record", "summary", record, "--from-m", "0"]);
        common::assert_no_cross_track_in_summary(&mut summary, record);
    }
}

#[test]
fn a_broken_graph_is_refused_with_line_and_key_before_anything_starts() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let port = free_port();
    let graph = dir.path().join("broken.ini");
    std::fs::write(
        &graph,
        format!(
            "[cluster]\nrobot = mechweed\nmaster = tcp/127.0.0.1:{port}\nmaster_lost = run_on\n\
             [machine robot-pc]\nendpoint = tcp/127.0.0.1:7451\n\
             [process controller]\nmachine = robot-pc\nprogram = run\n\
             [process camera]\nmachine = camera-pc\nprogram = camsim\n\
             [process recorder]\nprogram = record\n\
             [process camera]\nmachine = robot-pc\n\
             [flow rows]\nfrom = camera.rows\nto = controler.rows\n"
        ),
    )
    .unwrap();
    let out = mechweed_in(dir.path())
        .args(["cluster", "master"])
        .arg(&graph)
        .output()
        .unwrap();
    let said = text(&out.stderr);
    assert!(!out.status.success());
    let file = graph.display().to_string();
    for expected in [
        format!("{file} line 11: [process camera] machine: 'camera-pc' is not a machine"),
        format!("{file} line 13: [process recorder] machine is missing"),
        format!("{file} line 15: [process camera] appears again (first at line 10)"),
        format!("{file} line 19: [flow rows] to: 'controler' is not a process of this graph"),
        "nothing was started".to_string(),
    ] {
        assert!(said.contains(&expected), "{expected:?} not in:\n{said}");
    }
    // Nothing listens where the master would have.
    assert!(std::net::TcpStream::connect(("127.0.0.1", port)).is_err());
}
