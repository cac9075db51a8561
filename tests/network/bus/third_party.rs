//! A third party's program joins the secured bus with a plain Zenoh client, configured
//! as docs/bus.md says (the same keys a lab's Python program sets), checking the
//! robot's name as TLS clients do. With the robot's certificate made for its host
//! (`keys new --host localhost --ip 127.0.0.1`) it gets its answer; without, the
//! handshake fails and it sees nothing.

use std::time::Duration;

use zenoh::Wait;

use super::secured::Keys;
use super::secured::secured_robot;
use crate::common::{mechweed, text};

/// A cluster's keys whose robot certificate names `hosts` (`--host`/`--ip` items).
fn keys_for(hosts: &[&str]) -> (tempfile::TempDir, Keys) {
    let dir = tempfile::tempdir().unwrap();
    let made = mechweed()
        .args(["keys", "new"])
        .arg(dir.path().join("keys"))
        .args(hosts)
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", text(&made.stderr));
    let keys = Keys::at(&dir.path().join("keys"));
    (dir, keys)
}

/// The docs' configuration of a lab's own program as `name`, dialling `endpoint`:
/// Zenoh's own keys, name checking left on as a standard client has it.
fn standard_client(keys: &Keys, name: &str, endpoint: &str) -> zenoh::Session {
    let file = |f: &str| serde_json::to_string(&keys.path().join(f).display().to_string()).unwrap();
    let mut config = zenoh::Config::default();
    for (key, value) in [
        ("mode", r#""peer""#.to_string()),
        ("connect/endpoints", format!(r#"["{endpoint}"]"#)),
        ("listen/endpoints", "[]".to_string()),
        ("scouting/multicast/enabled", "false".to_string()),
        ("transport/link/tls/root_ca_certificate", file("ca.pem")),
        (
            "transport/link/tls/connect_certificate",
            file(&format!("{name}.pem")),
        ),
        (
            "transport/link/tls/connect_private_key",
            file(&format!("{name}.key")),
        ),
        ("transport/link/tls/enable_mtls", "true".to_string()),
    ] {
        config.insert_json5(key, &value).unwrap();
    }
    zenoh::open(config).wait().unwrap()
}

/// What the robot answers `session` for its speed setting, or "" within 3 s.
fn speed(session: &zenoh::Session) -> String {
    let replies = (session.get("mechweed/config/steer/speed_mps"))
        .timeout(Duration::from_secs(3))
        .wait()
        .unwrap();
    replies
        .recv()
        .ok()
        .and_then(|r| r.result().ok().map(|s| text(&s.payload().to_bytes())))
        .unwrap_or_default()
}

#[test]
fn a_standard_zenoh_client_joins_when_the_robots_certificate_names_its_host() {
    let _machine = crate::shared_machine();
    let (_dir, keys) = keys_for(&["--host", "localhost", "--ip", "127.0.0.1"]);
    let robot = secured_robot(&keys, &["--duration", "12"]);
    std::thread::sleep(Duration::from_secs(1));
    let viewer = standard_client(&keys, "viewer", &robot.endpoint);
    let answer = speed(&viewer);
    assert!(
        answer.contains("speed_mps") || answer.contains("value"),
        "as a viewer: {answer:?}"
    );

    // The shipped keys before: the robot's certificate names only its role, and a
    // client that checks the name it dialled gets nothing.
    let (_old_dir, old_keys) = keys_for(&[]);
    let old_robot = secured_robot(&old_keys, &["--duration", "8"]);
    let refused = standard_client(&old_keys, "viewer", &old_robot.endpoint);
    assert_eq!(
        speed(&refused),
        "",
        "a name the certificate does not hold was taken"
    );
    drop((robot, old_robot));
}

#[test]
fn the_docs_python_program_joins_as_a_viewer() {
    let python_zenoh = std::process::Command::new("python3")
        .args(["-c", "import zenoh"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !python_zenoh {
        eprintln!("skipped: Python's zenoh is not installed here (pip install eclipse-zenoh)");
        return;
    }
    let _machine = crate::shared_machine();
    let (_dir, keys) = keys_for(&["--ip", "127.0.0.1"]);
    let robot = secured_robot(&keys, &["--duration", "12"]);
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/lab_client.py");
    let out = std::process::Command::new("timeout")
        .args(["20", "python3"])
        .arg(&script)
        .arg(keys.path())
        .args(["viewer", &robot.endpoint])
        .output()
        .unwrap();
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(
        said.contains("setting:") && said.contains("speed_mps"),
        "{said}"
    );
    assert!(said.contains("status: {\""), "{said}");
    drop(robot);
}

#[test]
fn the_docs_show_the_python_program_as_it_is() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let program = std::fs::read_to_string(root.join("docs/lab_client.py")).unwrap();
    let docs = std::fs::read_to_string(root.join("docs/bus.md")).unwrap();
    assert!(
        docs.contains(&format!("```python\n{program}```")),
        "docs/bus.md and docs/lab_client.py differ"
    );
}
