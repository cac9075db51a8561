//! Where the robot program listens, and a slow link between machines.

use std::process::{Command, Stdio};
use std::time::Duration;

use super::Robot;

/// The inodes of the sockets process `pid` holds.
fn socket_inodes(pid: u32) -> Vec<String> {
    let Ok(fds) = std::fs::read_dir(format!("/proc/{pid}/fd")) else {
        return Vec::new();
    };
    fds.filter_map(|fd| std::fs::read_link(fd.ok()?.path()).ok())
        .filter_map(|target| {
            let t = target.to_string_lossy().to_string();
            Some(t.strip_prefix("socket:[")?.strip_suffix(']')?.to_string())
        })
        .collect()
}

/// Local addresses (hex, as /proc/net/* writes them) of the sockets among `inodes` that
/// can be reached from outside: listening TCP sockets, and every UDP socket (multicast
/// scouting would be one, bound to every network).
fn listening(inodes: &[String]) -> Vec<String> {
    let mut found = Vec::new();
    for (table, tcp) in [
        ("/proc/net/tcp", true),
        ("/proc/net/tcp6", true),
        ("/proc/net/udp", false),
        ("/proc/net/udp6", false),
    ] {
        let Ok(text) = std::fs::read_to_string(table) else {
            continue;
        };
        for line in text.lines().skip(1) {
            let f: Vec<&str> = line.split_whitespace().collect();
            // local_address is field 1, st field 3 (0A = LISTEN), inode field 9.
            let open = !tcp || f.get(3) == Some(&"0A");
            if f.len() > 9 && open && inodes.iter().any(|i| i == f[9]) {
                found.push(format!("{} {}", if tcp { "tcp" } else { "udp" }, f[1]));
            }
        }
    }
    found
}

/// 127.0.0.1 or ::1, as /proc/net/tcp* writes them.
fn is_loopback(socket: &str) -> bool {
    let hex = socket.split(' ').nth(1).unwrap_or("");
    let address = hex.split(':').next().unwrap_or("");
    address == "0100007F" || address == "00000000000000000000000001000000"
}

#[test]
fn with_the_shipped_settings_nothing_listens_but_loopback() {
    let _machine = crate::shared_machine();
    // The shipped [bus] (the tests' settings turn it off; this one turns it back on).
    let robot = Robot::spawn(None, &["--duration", "5"]);
    let mut sockets = Vec::new();
    for _ in 0..40 {
        std::thread::sleep(Duration::from_millis(100));
        // The robot program and its bus process, which holds the session.
        let processes = [vec![robot.pid()], super::process::children_of(robot.pid())].concat();
        sockets = listening(
            &processes
                .into_iter()
                .flat_map(socket_inodes)
                .collect::<Vec<_>>(),
        );
        if !sockets.is_empty() {
            break;
        }
    }
    let (stdout, _, _) = robot.finish();
    let listen = super::shipped_listen();
    assert!(
        stdout.contains(&format!("bus: listening on {listen}")),
        "the shipped bus did not start ({listen} taken by another program?)\n{stdout}"
    );
    assert!(!sockets.is_empty(), "no listening socket found");
    for address in &sockets {
        assert!(is_loopback(address), "listens on {address}: {sockets:?}");
    }
}

/// Runs `args` as root tools do; false if it fails.
fn sh(args: &[&str]) -> bool {
    Command::new(args[0])
        .args(&args[1..])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// A network namespace joined to this one by a veth pair with 200 ms and 256 kbit/s
/// each way, or why the machine cannot make one. Taken down when dropped.
struct SlowLink {
    netns: String,
    host_veth: String,
}

impl SlowLink {
    fn make() -> Result<SlowLink, String> {
        if unsafe { libc::geteuid() } != 0 {
            return Err("needs root".into());
        }
        if !sh(&["ip", "-V"]) {
            return Err("needs the ip command".into());
        }
        let id = std::process::id() % 10_000;
        let link = SlowLink {
            netns: format!("mwbus{id}"),
            host_veth: format!("mwh{id}"),
        };
        let peer = format!("mwp{id}");
        let ns = link.netns.as_str();
        let steps: [&[&str]; 7] = [
            &["ip", "netns", "add", ns],
            &[
                "ip",
                "link",
                "add",
                &link.host_veth,
                "type",
                "veth",
                "peer",
                "name",
                &peer,
            ],
            &["ip", "link", "set", &peer, "netns", ns],
            &["ip", "addr", "add", "10.231.0.1/24", "dev", &link.host_veth],
            &["ip", "link", "set", &link.host_veth, "up"],
            &[
                "ip",
                "netns",
                "exec",
                ns,
                "ip",
                "addr",
                "add",
                "10.231.0.2/24",
                "dev",
                &peer,
            ],
            &["ip", "netns", "exec", ns, "ip", "link", "set", &peer, "up"],
        ];
        for step in steps {
            if !sh(step) {
                return Err(format!(
                    "`{}` failed (no network namespaces here?)",
                    step.join(" ")
                ));
            }
        }
        let netem = ["netem", "delay", "200ms", "rate", "256kbit"];
        let host: Vec<&str> = ["tc", "qdisc", "add", "dev", &link.host_veth, "root"].into();
        let far: Vec<&str> = [
            "ip", "netns", "exec", ns, "tc", "qdisc", "add", "dev", &peer, "root",
        ]
        .into();
        for mut cmd in [host, far] {
            cmd.extend(netem);
            if !sh(&cmd) {
                return Err("tc netem is not available (the kernel lacks sch_netem)".into());
            }
        }
        sh(&["ip", "netns", "exec", ns, "ip", "link", "set", "lo", "up"]);
        Ok(link)
    }
}

impl Drop for SlowLink {
    fn drop(&mut self) {
        sh(&["ip", "link", "del", &self.host_veth]);
        sh(&["ip", "netns", "del", &self.netns]);
    }
}

#[test]
fn over_a_slow_link_the_receiver_s_newest_status_is_never_a_second_old() {
    let _machine = crate::shared_machine();
    let link = match SlowLink::make() {
        Ok(link) => link,
        Err(why) => {
            eprintln!("skipped: a 200 ms, 256 kbit/s link between namespaces: {why}");
            return;
        }
    };
    let port = super::free_port();
    let listen = format!("tcp/10.231.0.1:{port}");
    let robot = Robot::spawn(
        Some(listen.clone()),
        &["--mode", "autonomous", "--duration", "20"],
    );
    std::thread::sleep(Duration::from_secs(2));
    // The laptop at the field's edge, across the slow link; it drops what it cannot take.
    let receiver = Command::new("ip")
        .args(["netns", "exec", &link.netns, env!("CARGO_BIN_EXE_mechweed")])
        .args([
            "bus",
            "echo",
            "status",
            "--seconds",
            "15",
            "--connect",
            &listen,
        ])
        .output()
        .unwrap();
    let lines = super::json_lines(&receiver);
    assert!(
        lines.len() > 20,
        "{} status messages over the slow link",
        lines.len()
    );
    // The first seconds fill the link; after them, every status is fresh.
    for line in lines.iter().skip(10) {
        let age_s =
            line["received_s"].as_f64().unwrap() - line["payload"]["wall_s"].as_f64().unwrap();
        assert!(age_s < 1.0, "a status {age_s:.2} s old");
    }
    let (stdout, _, _) = robot.finish();
    assert!(stdout.contains("faults: none"), "{stdout}");
}
