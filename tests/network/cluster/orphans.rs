//! A launcher that ends without stopping its processes (here killed with SIGKILL, as a
//! panic or the OOM killer would end it) leaves none of them running unwatched.

use std::process::Stdio;

use super::{Started, alive, mechweed_in, one_machine_master, wait_for};

#[test]
fn a_killed_launcher_takes_its_processes_with_it() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    let (master_process, master) = one_machine_master(
        folder,
        "[process worker]\nmachine = robot-pc\nprogram = /bin/sh\nargs = -c \"echo $$ > worker.pid; exec sleep 60\"\n",
    );
    let mut started = Started(vec![master_process]);
    let launcher = mechweed_in(folder)
        .args([
            "cluster",
            "launcher",
            "--machine",
            "robot-pc",
            "--allow",
            "/bin/sh",
        ])
        .args(["--connect", &master])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid_file = folder.join("worker.pid");
    let worker: u64 = wait_for("the worker's start", 20.0, || {
        std::fs::read_to_string(&pid_file).ok()?.trim().parse().ok()
    });
    assert!(alive(worker));
    // SAFETY: kill(2) on the launcher's pid.
    unsafe { libc::kill(launcher.id() as i32, libc::SIGKILL) };
    started.0.push(launcher);
    wait_for("the worker's end after its launcher's", 5.0, || {
        (!running(worker)).then_some(())
    });
}

/// Alive and not a zombie waiting for a parent that may never reap it (a container's
/// first process).
fn running(pid: u64) -> bool {
    let state = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    let state = state
        .rsplit(") ")
        .next()
        .and_then(|rest| rest.chars().next());
    alive(pid) && !matches!(state, Some('Z') | None)
}
