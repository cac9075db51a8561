//! Where the robot program listens, and a slow link between machines.

use std::time::Duration;

use super::Robot;
use super::netns::Netns;

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

#[test]
fn over_a_slow_link_the_receiver_s_newest_status_is_never_a_second_old() {
    let _machine = crate::shared_machine();
    let link = match Netns::make(2, Some(&["netem", "delay", "200ms", "rate", "256kbit"])) {
        Ok(link) => link,
        Err(why) => {
            eprintln!("skipped: a 200 ms, 256 kbit/s link between namespaces: {why}");
            return;
        }
    };
    let port = super::free_port();
    let listen = format!("tcp/{}:{port}", link.host);
    let robot = Robot::spawn(
        Some(listen.clone()),
        &["--mode", "autonomous", "--duration", "20"],
    );
    std::thread::sleep(Duration::from_secs(2));
    // The laptop at the field's edge, across the slow link; it drops what it cannot take.
    let receiver = link
        .command(env!("CARGO_BIN_EXE_mechweed"))
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
