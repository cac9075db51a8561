//! The bus's guards that need no network beyond one robot: a person holding the
//! dead-man first, the keys as `mechweed keys` makes them, and a plain listen beyond
//! loopback refused before anything starts.

use std::time::Duration;

use super::Robot;
use super::secured::Keys;
use crate::common::{mechweed, text};

#[test]
fn a_person_holding_the_dead_man_keeps_the_robot_from_a_remote_autonomous() {
    let _machine = crate::shared_machine();
    // Not secured: the rule is the robot's, whoever asks.
    let robot = Robot::start(&[
        "--duration",
        "9",
        "--set",
        "bus.accept_requests=operator",
        "--set",
        "sim.events=1 power_up, 2 mode joystick, 2 deadman on, 2 joystick 0 1",
    ]);
    std::thread::sleep(Duration::from_secs(4));
    let out = robot.bus(&["request", "mode", "autonomous"]);
    assert!(!out.status.success(), "{}", text(&out.stdout));
    assert!(
        text(&out.stderr).contains("holds the joystick's dead-man"),
        "{}",
        text(&out.stderr)
    );
    // A HALT first, then autonomous: still the person's robot.
    let halt = robot.bus(&["request", "halt"]);
    assert_eq!(text(&halt.stdout).trim(), "accepted");
    let again = robot.bus(&["request", "mode", "autonomous"]);
    assert!(
        text(&again.stderr).contains("holds the joystick's dead-man"),
        "{}",
        text(&again.stderr)
    );
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("final mode: halt"), "{stdout}");
    assert!(!stdout.contains("-> autonomous"), "{stdout}");
}

#[test]
fn keys_new_writes_private_keys_for_their_owner_only_and_refuses_to_overwrite() {
    let _machine = crate::shared_machine();
    use std::os::unix::fs::PermissionsExt;
    let keys = Keys::new();
    for role in [
        "robot", "camera", "operator", "viewer", "recorder", "master", "launcher",
    ] {
        let key = keys.path().join(format!("{role}.key"));
        let mode = std::fs::metadata(&key).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600, "{}", key.display());
        assert!(keys.path().join(format!("{role}.pem")).is_file());
    }
    let again = mechweed()
        .args(["keys", "new"])
        .arg(keys.path())
        .output()
        .unwrap();
    assert!(!again.status.success());
    assert!(text(&again.stderr).contains("holds a cluster's keys already"));
    let add = |name: &str| {
        mechweed()
            .args(["keys", "add"])
            .arg(keys.path())
            .args(["operator", name])
            .output()
            .unwrap()
    };
    assert!(add("laptop-2").status.success());
    assert!(keys.path().join("laptop-2.key").is_file());
    assert!(!add("laptop-2").status.success(), "a name is made once");
    let revoke = mechweed()
        .args(["keys", "revoke"])
        .arg(keys.path())
        .arg("laptop-2")
        .output()
        .unwrap();
    assert!(revoke.status.success(), "{}", text(&revoke.stderr));
    let again = add("laptop-2");
    assert!(
        text(&again.stderr).contains("was revoked"),
        "{}",
        text(&again.stderr)
    );
}

#[test]
fn a_plain_listen_beyond_loopback_is_refused_before_anything_starts() {
    let _machine = crate::shared_machine();
    let dir = tempfile::tempdir().unwrap();
    let shipped =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/config/robot.ini")).unwrap();
    let open = shipped.replace("listen = tcp/127.0.0.1:7510", "listen = tcp/0.0.0.0:7510");
    assert_ne!(open, shipped);
    let file = dir.path().join("robot.ini");
    std::fs::write(&file, &open).unwrap();
    let check = mechweed().arg("check-config").arg(&file).output().unwrap();
    assert!(!check.status.success());
    let said = text(&check.stdout) + &text(&check.stderr);
    assert!(
        said.contains(
            "[bus] listen = tcp/0.0.0.0:7510 opens the bus beyond this computer without TLS"
        ),
        "{said}"
    );
    // Said trusted, it is taken, and every start says the bus is open to anyone.
    let trusted = open.replace("trusted_network = no", "trusted_network = yes");
    std::fs::write(&file, trusted).unwrap();
    let check = mechweed().arg("check-config").arg(&file).output().unwrap();
    assert!(check.status.success(), "{}", text(&check.stdout));
}

#[test]
fn a_halt_asked_before_the_robot_is_there_is_asked_again_until_it_answers() {
    let _machine = crate::shared_machine();
    let listen = super::endpoint(super::free_port());
    let halt = super::mechweed()
        .args(["bus", "request", "halt", "--connect", &listen])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Past its first try (a link waits 3 s for the robot).
    std::thread::sleep(std::time::Duration::from_secs(4));
    let robot = super::Robot::spawn(Some(listen), &["--mode", "autonomous", "--duration", "12"]);
    let out = halt.wait_with_output().unwrap();
    let (said, asked_again) = (super::text(&out.stdout), super::text(&out.stderr));
    assert!(out.status.success(), "{said}{asked_again}");
    assert_eq!(said.trim(), "accepted", "{asked_again}");
    assert!(
        asked_again.contains("HALT not answered yet"),
        "{asked_again}"
    );
    assert!(asked_again.contains("asking again, for"), "{asked_again}");
    drop(robot);
}
