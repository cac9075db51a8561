//! What a launcher refuses: a plan from anyone but the master's identity, and a program
//! its own command line does not allow. Each starts from a plan that would run a shell
//! command on the robot computer.

use std::process::Stdio;
use std::time::Duration;

use mechweed::bus::session::{Role, open};
use mechweed::config::TlsFiles;
use zenoh::Wait;

use super::{Started, free_port, make_keys, mechweed_in, one_machine_master, wait_for};
use crate::common::text;

/// A plan for robot-pc that runs `sh -c "touch pwned"`, as a rogue would send it.
fn rogue_plan() -> String {
    serde_json::json!({
        "machine": "robot-pc",
        "graph": "rogue.ini",
        "stop_when_master_lost": false,
        "processes": [{
            "name": "payload",
            "program": "/bin/sh",
            "args": ["-c", "touch pwned"],
            "env": [["LD_PRELOAD", "/tmp/evil.so"]],
            "auto": true,
            "restart": false,
            "restart_delay_s": 0.0,
            "after": [],
            "controller": false
        }]
    })
    .to_string()
}

/// A rogue at the master's address, as `identity` of the cluster or (`other`) as the
/// master of another authority, answering every plan query with `rogue_plan`; the
/// launcher of robot-pc with the cluster's keys must run nothing.
fn launcher_facing_a_rogue(identity: &str, other: bool) {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    make_keys(folder, &["robot-pc"]);
    let stranger = tempfile::tempdir().unwrap();
    make_keys(stranger.path(), &[]);
    let keys = if other { stranger.path() } else { folder };
    let listen = format!("tls/127.0.0.1:{}", free_port());
    let tls = TlsFiles::in_folder(&keys.join("keys"), identity);
    let rogue = open(
        Role::Master {
            listen: listen.clone(),
        },
        Some(&tls),
    )
    .unwrap();
    let plan = rogue_plan();
    let _answering = rogue
        .declare_queryable("mechweed/cluster/plan/robot-pc")
        .callback(move |q| {
            let _ = q.reply(q.key_expr().clone(), plan.clone()).wait();
        })
        .wait()
        .unwrap();
    let mut started = Started(Vec::new());
    let launcher = mechweed_in(folder)
        .args([
            "cluster",
            "launcher",
            "--machine",
            "robot-pc",
            "--connect",
            &listen,
        ])
        .args(["--keys", "keys", "--as", "robot-pc", "--allow", "/bin/sh"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    started.0.push(launcher);
    std::thread::sleep(Duration::from_secs(6));
    let mut launcher = started.0.pop().unwrap();
    unsafe { libc::kill(launcher.id() as i32, libc::SIGINT) };
    let out = launcher_output(&mut launcher);
    assert!(
        !folder.join("pwned").exists(),
        "{identity} (another authority: {other}): the rogue's plan ran: {out}"
    );
    assert!(out.contains("waiting for the master"), "{out}");
}

fn launcher_output(launcher: &mut std::process::Child) -> String {
    let _ = wait_for("the launcher ends", 20.0, || {
        launcher.try_wait().ok().flatten()
    });
    let mut out = String::new();
    for pipe in [
        launcher.stdout.take().map(|mut p| read_all(&mut p)),
        launcher.stderr.take().map(|mut p| read_all(&mut p)),
    ]
    .into_iter()
    .flatten()
    {
        out += &pipe;
    }
    out
}

fn read_all(pipe: &mut impl std::io::Read) -> String {
    let mut bytes = Vec::new();
    let _ = pipe.read_to_end(&mut bytes);
    text(&bytes)
}

#[test]
fn a_rogue_at_the_masters_address_cannot_make_a_launcher_run_anything() {
    let _machine = crate::shared_machine();
    // The master's identity of another authority (the TLS handshake fails), and one of
    // the cluster's own identities that is not the master's (the access rules drop its
    // answers).
    launcher_facing_a_rogue("master", true);
    launcher_facing_a_rogue("viewer", false);
}

#[test]
fn a_plan_naming_a_program_the_launcher_does_not_allow_is_refused() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    let (master_process, master) = one_machine_master(
        folder,
        "[process payload]\nmachine = robot-pc\nprogram = sh\nargs = -c \"touch pwned\"\n",
    );
    let _started = Started(vec![master_process]);
    let launcher = mechweed_in(folder)
        .args(["cluster", "launcher", "--machine", "robot-pc"])
        .args(["--connect", &master])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(5));
    let mut launcher = launcher;
    unsafe { libc::kill(launcher.id() as i32, libc::SIGINT) };
    let out = launcher_output(&mut launcher);
    assert!(!folder.join("pwned").exists(), "it ran: {out}");
    assert!(
        out.contains("payload is refused: sh is not a program this launcher allows"),
        "{out}"
    );
}

#[test]
fn a_launcher_refuses_a_plain_master_beyond_this_computer_and_a_name_not_its_machines() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path();
    make_keys(folder, &["robot-pc", "laptop"]);
    let launcher = |args: &[&str]| {
        mechweed_in(folder)
            .args(["cluster", "launcher", "--machine", "robot-pc"])
            .args(args)
            .output()
            .unwrap()
    };
    // Refused before any connection is tried.
    let plain = launcher(&["--connect", "tcp/0.0.0.0:7450"]);
    assert!(!plain.status.success());
    assert!(
        text(&plain.stderr).contains("over plain TCP beyond this computer"),
        "{}",
        text(&plain.stderr)
    );
    let other = launcher(&[
        "--connect",
        "tls/127.0.0.1:7450",
        "--keys",
        "keys",
        "--as",
        "laptop",
    ]);
    assert!(!other.status.success());
    assert!(
        text(&other.stderr).contains("its identity must be its machine's name (--as robot-pc)"),
        "{}",
        text(&other.stderr)
    );
    // The laptop's certificate under robot-pc's file names: refused at once, by the
    // name inside it (before, it waited for ever for a plan the rules kept from it).
    let keys = folder.join("keys");
    for ending in ["pem", "key"] {
        let laptop = keys.join(format!("laptop.{ending}"));
        std::fs::copy(&laptop, keys.join(format!("robot-pc.{ending}"))).unwrap();
    }
    let started = std::time::Instant::now();
    let borrowed = launcher(&[
        "--connect",
        "tls/127.0.0.1:7450",
        "--keys",
        "keys",
        "--as",
        "robot-pc",
    ]);
    assert!(!borrowed.status.success());
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "{:?}",
        started.elapsed()
    );
    assert!(
        text(&borrowed.stderr).contains("is laptop's, not robot-pc's"),
        "{}",
        text(&borrowed.stderr)
    );
}
