//! A second computer for the bus's tests: a network namespace joined to this one by a
//! veth pair, addresses from 198.18.0.0/15 (the range kept for such tests), made with
//! the `ip` command as root. Where the machine cannot make one the test says why and
//! skips.

use std::process::{Command, Stdio};

/// Runs `args` as root tools do; false if it fails.
pub fn sh(args: &[&str]) -> bool {
    Command::new(args[0])
        .args(&args[1..])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// The namespace and its link, taken down when dropped.
pub struct Netns {
    pub netns: String,
    pub host_veth: String,
    /// This computer's address on the link, and the namespace's.
    pub host: String,
    pub far: String,
}

impl Netns {
    /// A namespace on 198.18.`subnet`.0/24, with `netem` (tc's words, e.g. "delay
    /// 200ms") on both ends of its link, or why the machine cannot make one.
    pub fn make(subnet: u8, netem: Option<&[&str]>) -> Result<Netns, String> {
        if unsafe { libc::geteuid() } != 0 {
            return Err("needs root".into());
        }
        if !sh(&["ip", "-V"]) {
            return Err("needs the ip command".into());
        }
        let id = format!("{}{subnet}", std::process::id() % 10_000);
        let link = Netns {
            netns: format!("mwbus{id}"),
            host_veth: format!("mwh{id}"),
            host: format!("198.18.{subnet}.1"),
            far: format!("198.18.{subnet}.2"),
        };
        let peer = format!("mwp{id}");
        let (ns, veth) = (link.netns.as_str(), link.host_veth.as_str());
        let (host, far) = (format!("{}/24", link.host), format!("{}/24", link.far));
        let inside = |cmd: &[&'static str]| -> Vec<String> {
            let mut all = vec!["ip".to_string(), "netns".into(), "exec".into(), ns.into()];
            all.extend(cmd.iter().map(|s| s.to_string()));
            all
        };
        let steps: Vec<Vec<String>> = vec![
            vec!["ip".into(), "netns".into(), "add".into(), ns.into()],
            [
                "ip", "link", "add", veth, "type", "veth", "peer", "name", &peer,
            ]
            .map(String::from)
            .to_vec(),
            ["ip", "link", "set", &peer, "netns", ns]
                .map(String::from)
                .to_vec(),
            ["ip", "addr", "add", &host, "dev", veth]
                .map(String::from)
                .to_vec(),
            ["ip", "link", "set", veth, "up"].map(String::from).to_vec(),
            [
                inside(&["ip", "addr", "add"]),
                vec![far, "dev".into(), peer.clone()],
            ]
            .concat(),
            [
                inside(&["ip", "link", "set"]),
                vec![peer.clone(), "up".into()],
            ]
            .concat(),
            inside(&["ip", "link", "set", "lo", "up"]),
        ];
        for step in steps {
            let step: Vec<&str> = step.iter().map(String::as_str).collect();
            if !sh(&step) {
                return Err(format!(
                    "`{}` failed (no network namespaces here?)",
                    step.join(" ")
                ));
            }
        }
        if let Some(netem) = netem {
            let host: Vec<&str> = ["tc", "qdisc", "add", "dev", veth, "root"].into();
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
        }
        Ok(link)
    }

    /// Cut (false) or restore (true) the link, as a pulled cable does.
    pub fn carrier(&self, up: bool) {
        assert!(sh(&[
            "ip",
            "link",
            "set",
            &self.host_veth,
            if up { "up" } else { "down" }
        ]));
    }

    /// A command run inside the namespace.
    pub fn command(&self, program: &str) -> Command {
        let mut cmd = Command::new("ip");
        cmd.args(["netns", "exec", &self.netns, program]);
        cmd
    }
}

impl Drop for Netns {
    fn drop(&mut self) {
        sh(&["ip", "link", "del", &self.host_veth]);
        sh(&["ip", "netns", "del", &self.netns]);
    }
}
