//! One machine of a cluster: when its master goes away, its processes run on or stop as
//! the graph says; a program that is not mechweed's gets the robot's name and endpoint
//! and is stopped with the rest.

use std::fs::File;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use serde_json::Value;

use super::common::text;
use super::{Started, alive, free_port, mechweed_in, process, robot_status, wait_ended, wait_for};

/// A graph of one machine running the controller alone, and what happens to it when
/// the master is killed (a dropped link looks the same to a launcher).
fn master_killed(master_lost: &str) -> (tempfile::TempDir, Child, String) {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    let (master, robot) = (free_port(), free_port());
    let graph = folder.join("one.ini");
    std::fs::write(
        &graph,
        format!(
            "[cluster]\nrobot = mechweed\nmaster = tcp/127.0.0.1:{master}\nmaster_lost = {master_lost}\n\
             [machine robot-pc]\nendpoint = tcp/127.0.0.1:{robot}\n\
             [process controller]\nmachine = robot-pc\nprogram = run\nargs = --headless\n\
             set.rt.max_overruns = 1000000\nset.rt.max_late_periods = 20\n"
        ),
    )
    .unwrap();
    let mut master_process = mechweed_in(folder)
        .args(["cluster", "master"])
        .arg(&graph)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let launcher = mechweed_in(folder)
        .args(["cluster", "launcher", "--machine", "robot-pc"])
        .args(["--connect", &format!("tcp/127.0.0.1:{master}")])
        .stdout(File::create(folder.join("robot-pc.log")).unwrap())
        .spawn()
        .unwrap();
    let robot = format!("tcp/127.0.0.1:{robot}");
    wait_for("the controller's status", 40.0, || {
        robot_status(folder, &robot)
    });
    master_process.kill().unwrap();
    master_process.wait().unwrap();
    (dir, launcher, robot)
}

#[test]
fn when_the_master_goes_away_the_processes_run_on_or_stop_as_the_graph_says() {
    let _machine = crate::shared_machine();
    // run_on (the default of the shipped graphs): the robot's program goes on.
    let (dir, launcher, robot) = master_killed("run_on");
    let mut started = Started(vec![launcher]);
    std::thread::sleep(Duration::from_secs(3));
    let before = robot_status(dir.path(), &robot).expect("the controller runs on");
    let after = wait_for("newer statuses", 10.0, || {
        let status = robot_status(dir.path(), &robot)?;
        (status["t_s"].as_f64()? > before["t_s"].as_f64()? + 1.0).then_some(status)
    });
    assert_eq!(after["mode"], "halt");
    // Ctrl-C on the launcher stops its controller with safe outputs.
    unsafe { libc::kill(started.0[0].id() as i32, libc::SIGINT) };
    wait_ended(&mut started.0, 30, "the launcher, at Ctrl-C,");
    let log = std::fs::read_to_string(dir.path().join("robot-pc.log")).unwrap();
    assert!(
        log.contains("the master went away; the processes run on"),
        "{log}"
    );
    assert!(log.contains("the outputs are safe"), "{log}");

    // stop: the launcher stops the controller (safe outputs) and ends.
    let (dir, launcher, _) = master_killed("stop");
    let mut started = Started(vec![launcher]);
    wait_ended(&mut started.0, 30, "the launcher, when the master went,");
    let log = std::fs::read_to_string(dir.path().join("robot-pc.log")).unwrap();
    assert!(
        log.contains("the master went away ([cluster] master_lost = stop)"),
        "{log}"
    );
    assert!(
        log.contains("the outputs are safe: amplifiers 0 V"),
        "{log}"
    );
}

#[test]
fn any_executable_runs_with_the_robots_name_and_endpoint_in_its_environment() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    let (master, robot) = (free_port(), free_port());
    let graph = folder.join("tool.ini");
    std::fs::write(
        &graph,
        format!(
            "[cluster]\nrobot = farm/robot2\nmaster = tcp/127.0.0.1:{master}\nmaster_lost = run_on\n\
             [machine robot-pc]\nendpoint = tcp/127.0.0.1:{robot}\n\
             [process controller]\nmachine = robot-pc\nprogram = run\nargs = --headless\n\
             set.rt.max_overruns = 1000000\nset.rt.max_late_periods = 20\n\
             [process logger]\nmachine = robot-pc\nprogram = sh\n\
             args = -c \"echo $MECHWEED_ROBOT at $MECHWEED_CONNECT > env.txt; sleep 60\"\n\
             [flow status]\nfrom = controller.status\nto = logger.status\n"
        ),
    )
    .unwrap();
    let mut started = Started(Vec::new());
    let mut master_cmd = mechweed_in(folder);
    master_cmd
        .args(["cluster", "master"])
        .arg(&graph)
        .stdout(Stdio::null());
    started.0.push(master_cmd.spawn().unwrap());
    let mut launcher = mechweed_in(folder);
    launcher
        .args([
            "cluster",
            "launcher",
            "--machine",
            "robot-pc",
            "--robot",
            "farm/robot2",
            // Not mechweed's: run only because this launcher allows it.
            "--allow",
            "sh",
        ])
        .args(["--connect", &format!("tcp/127.0.0.1:{master}")])
        .stdout(Stdio::null());
    started.0.push(launcher.spawn().unwrap());
    let said = wait_for("the executable's output", 30.0, || {
        std::fs::read_to_string(folder.join("env.txt")).ok()
    });
    assert_eq!(said, format!("farm/robot2 at tcp/127.0.0.1:{robot}\n"));
    // It is stopped with the rest when the master stops the cluster.
    let cluster = wait_for("the logger running", 20.0, || {
        let out = mechweed_in(folder)
            .args([
                "cluster",
                "status",
                "--json",
                "--seconds",
                "0.2",
                "--robot",
                "farm/robot2",
            ])
            .args(["--connect", &format!("tcp/127.0.0.1:{master}")])
            .output()
            .unwrap();
        let cluster: Value = serde_json::from_slice(&out.stdout).ok()?;
        (process(&cluster, "logger")["state"] == "running").then_some(cluster)
    });
    let logger = process(&cluster, "logger")["pid"].as_u64().unwrap();
    unsafe { libc::kill(started.0[0].id() as i32, libc::SIGINT) };
    wait_ended(&mut started.0, 40, "a launcher or the master");
    assert!(
        !alive(logger),
        "the executable still runs after the master stopped"
    );
    // Its own child (the shell's sleep) went with it: nothing of the test's runs on.
    let left = Command::new("pgrep").args(["-f", "sleep 60"]).output();
    if let Ok(left) = left {
        let mine: Vec<String> = text(&left.stdout)
            .lines()
            .filter(|pid| {
                let cwd = std::fs::read_link(format!("/proc/{pid}/cwd"));
                cwd.is_ok_and(|cwd| cwd == folder)
            })
            .map(str::to_string)
            .collect();
        assert!(mine.is_empty(), "the shell's sleep still runs: {mine:?}");
    }
}

/// Two launchers for one machine would both run its processes, and the master would see
/// that machine's states flip twice a second: the second is refused, naming the first.
#[test]
fn a_second_launcher_for_a_machine_is_refused() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    let (master, robot) = (free_port(), free_port());
    let graph = folder.join("one.ini");
    std::fs::write(
        &graph,
        format!(
            "[cluster]\nrobot = mechweed\nmaster = tcp/127.0.0.1:{master}\nmaster_lost = run_on\n\
             [machine robot-pc]\nendpoint = tcp/127.0.0.1:{robot}\n\
             [process waiter]\nmachine = robot-pc\nprogram = sh\nargs = -c \"touch started; sleep 60\"\n"
        ),
    )
    .unwrap();
    let launcher = || {
        let mut cmd = mechweed_in(folder);
        cmd.args([
            "cluster",
            "launcher",
            "--machine",
            "robot-pc",
            "--allow",
            "sh",
        ])
        .args(["--connect", &format!("tcp/127.0.0.1:{master}")]);
        cmd
    };
    let mut started = Started(Vec::new());
    let mut master_cmd = mechweed_in(folder);
    master_cmd
        .args(["cluster", "master"])
        .arg(&graph)
        .stdout(Stdio::null());
    started.0.push(master_cmd.spawn().unwrap());
    started
        .0
        .push(launcher().stdout(Stdio::null()).spawn().unwrap());
    wait_for("the first launcher's process", 30.0, || {
        folder.join("started").exists().then_some(())
    });
    let second = launcher().output().unwrap();
    let said = text(&second.stderr);
    assert!(!second.status.success(), "{said}");
    assert!(
        said.contains("a launcher of robot-pc runs already (session "),
        "{said}"
    );
    assert!(said.contains("stop that one first"), "{said}");
}
