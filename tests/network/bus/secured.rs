//! A secured bus between real processes on loopback: the robot program with the
//! cluster's keys (TLS, both ends showing a certificate of its authority, access rules
//! by role), and tools with and without an identity. Each test starts from what an
//! attacker on the field network would try.

use std::path::PathBuf;
use std::process::{Output, Stdio};
use std::time::Duration;

use mechweed::bus::session::{Role, open};
use mechweed::config::TlsFiles;
use zenoh::Wait;

use super::{Robot, free_port, json_lines};
use crate::common::{mechweed, text};

/// A cluster's keys, made by `mechweed keys new`, in a folder deleted when dropped.
pub struct Keys {
    /// Deleted when dropped; None for keys another process made.
    _dir: Option<tempfile::TempDir>,
    path: PathBuf,
}

impl Keys {
    pub fn new() -> Keys {
        let dir = tempfile::tempdir().unwrap();
        let made = mechweed()
            .args(["keys", "new"])
            .arg(dir.path().join("keys"))
            .output()
            .unwrap();
        assert!(made.status.success(), "{}", text(&made.stderr));
        Keys {
            path: dir.path().join("keys"),
            _dir: Some(dir),
        }
    }

    /// The keys another process made in `path` (a sender process of the flood tests).
    pub fn at(path: &std::path::Path) -> Keys {
        Keys {
            _dir: None,
            path: path.to_path_buf(),
        }
    }

    pub fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// `--keys DIR --as NAME`.
    pub fn as_(&self, name: &str) -> Vec<String> {
        vec![
            "--keys".into(),
            self.path().display().to_string(),
            "--as".into(),
            name.into(),
        ]
    }

    /// A Zenoh session of this test as identity `name`, linked to `endpoint`.
    pub fn session(&self, endpoint: &str, name: &str) -> zenoh::Session {
        open(
            Role::Tool {
                connect: vec![endpoint.to_string()],
                wait: false,
            },
            Some(&TlsFiles::in_folder(&self.path(), name)),
        )
        .unwrap()
    }

    /// The robot's three settings.
    pub(super) fn robot_settings(&self) -> Vec<String> {
        let file = |f: &str| self.path().join(f).display().to_string();
        [
            format!("bus.tls_ca={}", file("ca.pem")),
            format!("bus.tls_cert={}", file("robot.pem")),
            format!("bus.tls_key={}", file("robot.key")),
        ]
        .into_iter()
        .flat_map(|item| ["--set".to_string(), item])
        .collect()
    }
}

/// A robot program on a secured bus at a loopback port of its own, with `args`, once
/// it answers its operator.
pub fn secured_robot(keys: &Keys, args: &[&str]) -> Robot {
    let listen = format!("tls/127.0.0.1:{}", free_port());
    let settings = keys.robot_settings();
    let mut all: Vec<&str> = settings.iter().map(String::as_str).collect();
    all.extend(args);
    let mut robot = Robot::spawn(Some(listen), &all);
    robot.tool_args = keys.as_("operator");
    robot.wait_until_answering();
    robot
}

/// `mechweed ARGS`, ended after `seconds` if it has not ended by itself.
fn run_for(args: &[String], seconds: f64) -> Output {
    let child = mechweed()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id();
    // The killer waits for the child's end or the time, whichever comes first: once the
    // child is reaped its pid may be another process's (a later test's), never killed.
    let (ended, ended_rx) = crossbeam_channel::bounded::<()>(1);
    let killer = std::thread::spawn(move || {
        let waited = ended_rx.recv_timeout(Duration::from_secs_f64(seconds));
        if waited == Err(crossbeam_channel::RecvTimeoutError::Timeout) {
            // SAFETY: kill(2) on the child's pid, not yet reaped (we wait for it).
            unsafe { libc::kill(pid as i32, libc::SIGKILL) };
        }
    });
    let out = child.wait_with_output();
    drop(ended);
    killer.join().unwrap();
    out.unwrap()
}

fn bus_args(robot: &Robot, args: &[&str], identity: &[String]) -> Vec<String> {
    let mut all = vec!["bus".to_string()];
    all.extend(args.iter().map(|a| a.to_string()));
    all.extend(["--connect".to_string(), robot.endpoint.clone()]);
    all.extend(identity.iter().cloned());
    all
}

#[test]
fn without_a_certificate_of_the_authority_nothing_is_seen_or_answered() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let stranger = Keys::new(); // another authority: its operator is nobody here
    let robot = secured_robot(
        &keys,
        &["--duration", "12", "--set", "bus.accept_requests=operator"],
    );
    let plain = robot.endpoint.replace("tls/", "tcp/");
    for (who, identity, endpoint) in [
        ("no certificate", Vec::new(), robot.endpoint.clone()),
        (
            "another authority",
            stranger.as_("operator"),
            robot.endpoint.clone(),
        ),
        ("plain TCP", Vec::new(), plain),
    ] {
        let ask = |args: &[&str]| {
            let mut all = vec!["bus".to_string()];
            all.extend(args.iter().map(|a| a.to_string()));
            all.extend(["--connect".to_string(), endpoint.clone()]);
            all.extend(identity.iter().cloned());
            run_for(&all, 8.0)
        };
        for request in [
            &["request", "power_up"][..],
            &["request", "mode", "autonomous"],
        ] {
            let out = ask(request);
            assert!(!out.status.success(), "{who}: {request:?} answered");
            assert!(!text(&out.stdout).contains("accepted"), "{who}");
        }
        let echo = ask(&["echo", "status", "--seconds", "3"]);
        assert!(
            json_lines(&echo).is_empty(),
            "{who} saw {:?}",
            text(&echo.stdout)
        );
    }
    let (stdout, _, _) = robot.finish();
    assert!(!stdout.contains("-> autonomous"), "{stdout}");
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    assert!(stdout.contains("secured: TLS"), "{stdout}");
}

#[test]
fn a_viewer_sees_and_halts_but_cannot_power_up_or_drive() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &[
            "--mode",
            "autonomous",
            "--duration",
            "12",
            "--set",
            "bus.accept_requests=operator",
        ],
    );
    let viewer = keys.as_("viewer");
    let status = run_for(
        &bus_args(&robot, &["echo", "status", "--count", "2"], &viewer),
        8.0,
    );
    assert_eq!(json_lines(&status).len(), 2, "{}", text(&status.stderr));
    for request in [
        &["request", "power_up"][..],
        &["request", "mode", "joystick"],
    ] {
        let out = run_for(&bus_args(&robot, request, &viewer), 8.0);
        assert!(!out.status.success(), "{request:?}: {}", text(&out.stdout));
        let why = text(&out.stderr);
        assert!(why.contains("only an operator"), "{request:?}: {why}");
    }
    // The old key takes HALT only from anyone: a power-up there is refused by rule.
    let session = keys.session(&robot.endpoint, "viewer");
    let answer = ask(&session, "mechweed/request", r#"{"request": "power_up"}"#);
    assert!(answer.contains("takes HALT only"), "{answer}");
    let halt = run_for(&bus_args(&robot, &["request", "halt"], &viewer), 8.0);
    assert_eq!(
        text(&halt.stdout).trim(),
        "accepted",
        "{}",
        text(&halt.stderr)
    );
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("mode: autonomous -> halt"), "{stdout}");
    assert!(!stdout.contains("-> joystick"), "{stdout}");
}

/// The first answer on `key` to `payload`, as text.
pub(super) fn ask(session: &zenoh::Session, key: &str, payload: &str) -> String {
    let replies = session
        .get(key)
        .payload(payload.to_string())
        .timeout(Duration::from_secs(3))
        .wait()
        .unwrap();
    super::reply_text(&replies.recv().expect("an answer"))
}

#[test]
fn an_operator_powers_up_and_drives() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &["--duration", "8", "--set", "bus.accept_requests=operator"],
    );
    robot.power_up_and_drive();
    // The robot says its bus is secured, by which authority, and who came.
    let list = robot.bus(&["list", "--seconds", "1"]);
    let said = text(&list.stdout);
    assert!(
        said.contains("the robot's bus: secured: TLS, identities of the authority"),
        "{said}"
    );
    assert!(said.contains("identities: operator x"), "{said}");
    assert!(
        said.contains("this program: TLS, as operator (operator)"),
        "{said}"
    );
    let (stdout, stderr, _) = robot.finish();
    assert!(stdout.contains("mode: halt -> autonomous"), "{stdout}");
    assert!(stdout.contains("identities: operator x"), "{stdout}");
    // The robot's console names the identity that asked.
    assert!(
        stderr.contains("bus: mode autonomous requested by 'operator': accepted"),
        "{stderr}"
    );
    // The test's keys folder holds the authority's key beside the robot's: said.
    assert!(
        stderr.contains("ca.key is here: whoever reads it can make identities"),
        "{stderr}"
    );
}

/// camsim on the bus as `name`, for `seconds`: its output.
fn camsim_as(
    keys: &Keys,
    robot: &Robot,
    name: &str,
    seconds: f64,
) -> std::thread::JoinHandle<Output> {
    let mut args: Vec<String> = ["camsim", "--bus", "--connect", &robot.endpoint]
        .iter()
        .map(|a| a.to_string())
        .collect();
    args.extend(keys.as_(name));
    std::thread::spawn(move || run_for(&args, seconds))
}

#[test]
fn rows_steer_only_from_the_camera_identity() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let drive = [
        "--duration",
        "10",
        "--set",
        "camera.port=bus",
        "--set",
        "sim.events=3 power_up, 4 mode autonomous",
    ];
    // An operator's rows never arrive: the robot faults on a lost camera.
    let robot = secured_robot(&keys, &drive);
    let impostor = camsim_as(&keys, &robot, "operator", 9.0);
    let (stdout, _, _) = robot.finish();
    let impostor = impostor.join().unwrap();
    assert!(
        text(&impostor.stdout).contains("published"),
        "{}",
        text(&impostor.stdout)
    );
    assert!(!stdout.contains("row estimates:"), "{stdout}");
    assert!(stdout.contains("camera"), "{stdout}");
    assert!(!stdout.contains("faults: none"), "{stdout}");

    // The camera's rows steer it; the camera's own requests are nobody's.
    let robot = secured_robot(&keys, &drive);
    let camera = camsim_as(&keys, &robot, "camera", 9.0);
    std::thread::sleep(Duration::from_secs(5));
    let halt = run_for(
        &bus_args(&robot, &["request", "halt"], &keys.as_("camera")),
        8.0,
    );
    assert!(!halt.status.success(), "{}", text(&halt.stdout));
    let (stdout, _, _) = robot.finish();
    camera.join().unwrap();
    assert!(stdout.contains("mode: halt -> autonomous"), "{stdout}");
    assert!(stdout.contains("row estimates:"), "{stdout}");
    assert!(!stdout.contains("autonomous -> halt"), "{stdout}");
}

#[test]
fn a_revoked_laptop_gets_nothing_and_the_robot_says_it_came() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let keys_cmd = |args: &[&str]| {
        let out = mechweed().arg("keys").args(args).output().unwrap();
        assert!(out.status.success(), "{}", text(&out.stderr));
    };
    let dir = keys.path().display().to_string();
    keys_cmd(&["add", &dir, "operator", "laptop-2"]);
    keys_cmd(&["revoke", &dir, "laptop-2"]);
    let robot = secured_robot(
        &keys,
        &["--duration", "10", "--set", "bus.accept_requests=operator"],
    );
    let lost = keys.as_("laptop-2");
    let echo = run_for(
        &bus_args(&robot, &["echo", "status", "--seconds", "3"], &lost),
        8.0,
    );
    assert!(json_lines(&echo).is_empty(), "{}", text(&echo.stdout));
    let power = run_for(&bus_args(&robot, &["request", "power_up"], &lost), 8.0);
    assert!(!power.status.success(), "{}", text(&power.stdout));
    let (stdout, stderr, _) = robot.finish();
    assert!(!stdout.contains("-> autonomous"), "{stdout}");
    assert!(
        stderr.contains("laptop-2 linked with a certificate of this authority, but the roster gives it no rights"),
        "{stderr}"
    );
    assert!(stdout.contains("refused (no rights): laptop-2"), "{stdout}");
}

#[test]
fn a_second_program_sending_camera_rows_is_a_fault_that_names_both() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(
        &keys,
        &[
            "--duration",
            "12",
            "--set",
            "camera.port=bus",
            "--set",
            "sim.events=3 power_up, 4 mode autonomous",
        ],
    );
    let camera = camsim_as(&keys, &robot, "camera", 11.0);
    std::thread::sleep(Duration::from_secs(6));
    // Driving on the camera's rows: now a second program sends rows too.
    let second = camsim_as(&keys, &robot, "camera", 5.0);
    let (stdout, stderr, _) = robot.finish();
    camera.join().unwrap();
    second.join().unwrap();
    assert!(stdout.contains("mode: halt -> autonomous"), "{stdout}");
    assert!(
        stdout.contains("FAULT: two programs send camera rows"),
        "{stdout}"
    );
    assert!(
        stderr.contains("bus: two programs send camera rows: camera (session"),
        "{stderr}"
    );
    assert!(stderr.contains(") and camera (session"), "{stderr}");
}
