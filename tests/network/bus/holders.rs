//! One computer of the field network holding every session the robot takes: a revoked
//! laptop's certificate (of the cluster's authority, so Zenoh's TLS takes it, and the
//! access rules then give it nothing) opens session after session from a network
//! namespace, while a viewer on another computer asks for HALT. Without a limit the
//! holder got all 32 sessions and the HALT failed "nothing answered"; the package's
//! firewall rule (packaging/mechweed-bus.nft) lets one address hold at most 8 links.
//! Needs root, `ip` and `nft`; skips and says why where the machine lacks one.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use mechweed::bus::session::{Role, open};
use mechweed::config::TlsFiles;

use super::Robot;
use super::netns::{Netns, sh};
use super::secured::Keys;
use crate::common::{mechweed, text};

const HOLDER: &str = "MECHWEED_SESSION_HOLDER";
/// Sessions the holder tries to open: more than the robot takes.
const TRIES: usize = 40;

/// The shipped firewall rule for `port`, loaded as a table of this test's own; taken
/// out when dropped.
struct Firewall(String);

impl Firewall {
    fn load(port: u16) -> Result<Firewall, String> {
        let table = format!("mechweed_bus_test{}", std::process::id());
        let rules = std::fs::read_to_string("packaging/mechweed-bus.nft").unwrap();
        assert!(
            rules.contains("{ 7447, 7450 }"),
            "the ports moved in the file"
        );
        let rules = (rules.replace("{ 7447, 7450 }", &port.to_string()))
            .replace("table inet mechweed_bus ", &format!("table inet {table} "));
        let file = tempfile::NamedTempFile::new().unwrap();
        std::fs::write(file.path(), rules).unwrap();
        let loaded = Command::new("nft").arg("-f").arg(file.path()).output();
        match loaded {
            Ok(out) if out.status.success() => Ok(Firewall(table)),
            Ok(out) => Err(format!("nft refused the rules: {}", text(&out.stderr))),
            Err(e) => Err(format!("needs nft ({e})")),
        }
    }
}

impl Drop for Firewall {
    fn drop(&mut self) {
        sh(&["nft", "delete", "table", "inet", &self.0]);
    }
}

/// The holder process in `netns`: as `name`, TRIES sessions to `endpoint`, held.
fn holder(netns: &Netns, endpoint: &str, keys: &Keys, name: &str) -> Child {
    let exe = std::env::current_exe().unwrap();
    (netns.command(exe.to_str().unwrap()))
        .args([
            "--exact",
            "bus::holders::session_holder",
            "--ignored",
            "--nocapture",
        ])
        .env(
            HOLDER,
            format!("{endpoint} {} {name}", keys.path().display()),
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// Not a test: the holder process the test below starts (it does nothing without it).
#[test]
#[ignore = "a holder process of the session test"]
fn session_holder() {
    let Ok(spec) = std::env::var(HOLDER) else {
        return;
    };
    let words: Vec<&str> = spec.split(' ').collect();
    let [endpoint, keys, name] = words[..] else {
        panic!("{HOLDER}: {spec}");
    };
    let tls = TlsFiles::in_folder(std::path::Path::new(keys), name);
    let role = || Role::Tool {
        connect: vec![endpoint.to_string()],
        wait: false,
    };
    // All at once, as a flood would: each that cannot link fails within its 3 s.
    let tries: Vec<_> = (0..TRIES)
        .map(|_| {
            let (role, tls) = (role(), tls.clone());
            std::thread::spawn(move || open(role, Some(&tls)).ok())
        })
        .collect();
    let held: Vec<_> = tries
        .into_iter()
        .filter_map(|t| t.join().unwrap())
        .collect();
    println!("holder: {} {TRIES}", held.len());
    // Held until the test ends this process.
    std::thread::sleep(Duration::from_secs(60));
}

/// Two other computers (a stranger's and a viewer's) and the rule on a port of its
/// own, or why this machine cannot give them.
fn two_computers_and_the_rule() -> Result<(Netns, Netns, Firewall, u16), String> {
    let stranger = Netns::make(5, None)?;
    let viewer = Netns::make(6, None)?;
    let port = super::free_port();
    Ok((stranger, viewer, Firewall::load(port)?, port))
}

#[test]
fn one_computer_holding_sessions_leaves_room_for_another_computers_halt() {
    let _machine = crate::shared_machine();
    let (stranger, viewer, _rule, port) = match two_computers_and_the_rule() {
        Ok(ready) => ready,
        Err(why) => {
            eprintln!("skipped: one computer holding the robot's sessions: {why}");
            return;
        }
    };
    let keys = Keys::new();
    let dir = keys.path().display().to_string();
    let keys_cmd = |args: &[&str]| {
        let out = mechweed().arg("keys").args(args).output().unwrap();
        assert!(out.status.success(), "{}", text(&out.stderr));
    };
    keys_cmd(&["add", &dir, "operator", "laptop-2"]);
    keys_cmd(&["revoke", &dir, "laptop-2"]);
    let mut all = keys.robot_settings();
    all.extend(["--duration", "15"].map(String::from));
    let all: Vec<&str> = all.iter().map(String::as_str).collect();
    let mut robot = Robot::spawn(Some(format!("tls/0.0.0.0:{port}")), &all);
    // This computer's own tools come over lo, which the rule does not count.
    robot.endpoint = format!("tls/127.0.0.1:{port}");
    robot.tool_args = keys.as_("operator");
    robot.wait_until_answering();

    let mut held = holder(
        &stranger,
        &format!("tls/{}:{port}", stranger.host),
        &keys,
        "laptop-2",
    );
    let line = BufReader::new(held.stdout.take().unwrap())
        .lines()
        .map_while(Result::ok)
        .find(|l| l.starts_with("holder: "))
        .expect("the holder's count");
    let opened: usize = line.split(' ').nth(1).unwrap().parse().unwrap();

    let asked = Instant::now();
    let halt = (viewer.command(env!("CARGO_BIN_EXE_mechweed")))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("MECHWEED_SYSTEM_INI", "/nonexistent/robot.ini")
        .args(["bus", "request", "halt", "--connect"])
        .arg(format!("tls/{}:{port}", viewer.host))
        .args(keys.as_("viewer"))
        .output()
        .unwrap();
    let waited_s = asked.elapsed().as_secs_f64();
    let _ = held.kill();
    let _ = held.wait();
    println!(
        "one address held {opened} of the {TRIES} sessions it opened; a viewer on another computer asked HALT: {} in {waited_s:.1} s",
        if halt.status.success() {
            "answered"
        } else {
            "not answered"
        }
    );
    assert!(opened <= 8, "one address held {opened} sessions");
    assert!(
        halt.status.success(),
        "{}{}",
        text(&halt.stdout),
        text(&halt.stderr)
    );
    drop(robot.finish());
}
