//! The [bus] section: the data flows between mechweed and other programs (src/bus/).

use std::path::{Path, PathBuf};

use super::reader::Reader;

/// Which requests other programs may make over the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AcceptRequests {
    /// HALT only: stopping the robot is always allowed, from anywhere.
    Halt,
    /// HALT, power up and modes, decided by the supervisor as for the GUI.
    Operator,
}

/// The files of one identity of the cluster (mechweed keys new makes them): with them
/// the bus speaks TLS only, both ends show a certificate of this authority, and the
/// access rules are written from the roster beside the authority's certificate.
/// The roster's file name in a keys folder (src/bus/keys/roster.rs reads and writes it).
pub const ROSTER_FILE: &str = "roles.ini";

#[derive(Debug, Clone, PartialEq)]
pub struct TlsFiles {
    /// The authority's certificate, ca.pem.
    pub ca: PathBuf,
    /// This program's certificate, NAME.pem.
    pub cert: PathBuf,
    /// This program's private key, NAME.key.
    pub key: PathBuf,
}

impl TlsFiles {
    /// The files of identity `name` in a keys folder (`--keys DIR --as NAME`).
    pub fn in_folder(dir: &Path, name: &str) -> TlsFiles {
        TlsFiles {
            ca: dir.join("ca.pem"),
            cert: dir.join(format!("{name}.pem")),
            key: dir.join(format!("{name}.key")),
        }
    }

    /// The keys folder: where the authority's certificate is.
    pub fn folder(&self) -> PathBuf {
        self.ca.parent().unwrap_or(Path::new(".")).to_path_buf()
    }

    /// The roster (who is who) beside the authority's certificate.
    pub fn roster(&self) -> PathBuf {
        self.folder().join(ROSTER_FILE)
    }

    /// This identity's name: its certificate's file name, NAME.pem.
    pub fn name(&self) -> String {
        self.cert
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned())
    }

    /// The authority's name as its certificate's file says it, for the start line.
    pub fn authority(&self) -> String {
        self.ca.display().to_string()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct BusSettings {
    pub enabled: bool,
    /// Without the bus the run goes on (a warning) unless this is set.
    pub required: bool,
    /// The first part of every key: ROBOT/status, ROBOT/request, ...
    pub robot: String,
    /// Zenoh endpoints this program listens on, e.g. tcp/127.0.0.1:7510.
    pub listen: Vec<String>,
    /// Zenoh endpoints this program connects to.
    pub connect: Vec<String>,
    /// Multicast scouting (finding peers on the network without an address).
    pub multicast: bool,
    /// Publish every Nth supervisor tick on ROBOT/tick.
    pub tick_every_n: u64,
    pub accept_requests: AcceptRequests,
    /// TLS with the cluster's identities; None: plain TCP (loopback only, unless
    /// `trusted_network`).
    pub tls: Option<TlsFiles>,
    /// Plain TCP beyond loopback is allowed: whoever is on the network may use the bus.
    pub trusted_network: bool,
    /// On the real robot, a power-up asked over the bus is taken (shipped no).
    pub remote_power_up: bool,
}

impl BusSettings {
    /// A key of this robot's flows: `ROBOT/what`.
    pub fn key(&self, what: &str) -> String {
        format!("{}/{what}", self.robot)
    }

    /// Where the bus listens and connects, in words (the start line, the GUI, the report).
    pub fn endpoints(&self) -> String {
        let list = |endpoints: &[String]| match endpoints {
            [] => "nothing".to_string(),
            _ => endpoints.join(", "),
        };
        format!(
            "listening on {}, connecting to {}",
            list(&self.listen),
            list(&self.connect)
        )
    }
}

pub(super) fn load(r: &mut Reader) -> BusSettings {
    let s = "bus";
    let yes_no = ["yes", "no"];
    BusSettings {
        enabled: r.choice(s, "enabled", &yes_no) == 0,
        required: r.choice(s, "required", &yes_no) == 0,
        robot: r.parsed(s, "robot", parse_prefix).unwrap_or_default(),
        listen: r.parsed(s, "listen", parse_endpoints).unwrap_or_default(),
        connect: r.parsed(s, "connect", parse_endpoints).unwrap_or_default(),
        multicast: r.choice(s, "multicast", &yes_no) == 0,
        tick_every_n: r.u64(s, "tick_every_n", 1, 10_000),
        accept_requests: [AcceptRequests::Halt, AcceptRequests::Operator]
            [r.choice(s, "accept_requests", &["halt", "operator"])],
        tls: tls_files(r, s, true),
        // Settings files from before these keys: the safe meaning when missing.
        trusted_network: optional_yes(r, s, "trusted_network"),
        remote_power_up: optional_yes(r, s, "remote_power_up"),
    }
}

/// yes or no, no when the key is not in the file.
pub fn optional_yes(r: &mut Reader, section: &str, key: &str) -> bool {
    match r.optional(section, key).as_deref() {
        None | Some("no") => false,
        Some("yes") => true,
        Some(other) => {
            r.error_at(section, key, format!("'{other}' is neither yes nor no"));
            false
        }
    }
}

/// `tls_ca`, `tls_cert`, `tls_key`: all three files, or none of them (`none`).
/// `here`: the files are on this computer, and a missing one is an error now (a graph
/// names the master's files, on the master's computer).
pub fn tls_files(r: &mut Reader, section: &str, here: bool) -> Option<TlsFiles> {
    let keys = ["tls_ca", "tls_cert", "tls_key"];
    let [ca, cert, key] = keys.map(|k| {
        r.optional(section, k)
            .filter(|v| !v.is_empty() && v != "none")
            .map(PathBuf::from)
    });
    match (ca, cert, key) {
        (None, None, None) => None,
        (Some(ca), Some(cert), Some(key)) => {
            for (k, path) in keys.iter().zip([&ca, &cert, &key]) {
                if here && !path.is_file() {
                    r.error_at(
                        section,
                        k,
                        format!(
                            "{} is not a file (mechweed keys new DIR makes the cluster's keys)",
                            path.display()
                        ),
                    );
                }
            }
            Some(TlsFiles { ca, cert, key })
        }
        _ => {
            r.error_at(
                section,
                "tls_ca",
                format!(
                    "[{section}] tls_ca, tls_cert and tls_key go together: set all three (the authority's certificate, this program's certificate and its key) or none"
                ),
            );
            None
        }
    }
}

/// The address of an endpoint, `tcp/HOST:PORT` or `tls/HOST:PORT`, and whether it is TLS.
pub fn endpoint_address(endpoint: &str) -> Option<(&str, bool)> {
    if let Some(address) = endpoint.strip_prefix("tls/") {
        Some((address, true))
    } else {
        endpoint.strip_prefix("tcp/").map(|a| (a, false))
    }
}

/// Whether an endpoint's host is this computer only (127.x.x.x, ::1, localhost).
pub fn is_loopback(endpoint: &str) -> bool {
    let Some((address, _)) = endpoint_address(endpoint) else {
        return false;
    };
    let host = address.rsplit_once(':').map_or(address, |(h, _)| h);
    let host = host.trim_start_matches('[').trim_end_matches(']');
    host == "localhost"
        || host
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback())
}

/// Why `listen` may not be used as it is: plain TCP beyond loopback without
/// `trusted_network`, or a plain endpoint while TLS is on. `setting` names the key.
pub fn listen_refusal(
    listen: &[String],
    tls: bool,
    trusted_network: bool,
    setting: &str,
) -> Option<String> {
    if tls {
        let plain = listen.iter().find(|e| e.starts_with("tcp/"))?;
        return Some(format!(
            "{setting} = {plain}: with the cluster's keys set (tls_ca, tls_cert, tls_key) every endpoint is tls/HOST:PORT"
        ));
    }
    let open = listen.iter().find(|e| !is_loopback(e))?;
    if trusted_network {
        return None;
    }
    Some(format!(
        "{setting} = {open} opens the bus beyond this computer without TLS: anyone on that network could drive the robot. \
         Make the cluster's keys (mechweed keys new keys) and set tls_ca, tls_cert and tls_key with a tls/HOST:PORT endpoint, \
         or, only on a network you trust, set trusted_network = yes"
    ))
}

/// A key prefix: letters, digits, `_` and `-`, in parts joined by `/`.
pub fn parse_prefix(text: &str) -> Result<String, String> {
    let part_ok = |part: &str| {
        !part.is_empty()
            && part
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    };
    if text.split('/').all(part_ok) {
        Ok(text.to_string())
    } else {
        Err(format!(
            "'{text}' is not a key prefix: letters, digits, _ and -, parts joined by / (for example mechweed or farm/robot2)"
        ))
    }
}

/// A comma-separated list of zenoh endpoints, `tcp/HOST:PORT` or `tls/HOST:PORT`;
/// `none` or empty for none.
pub fn parse_endpoints(text: &str) -> Result<Vec<String>, String> {
    if text.is_empty() || text == "none" {
        return Ok(Vec::new());
    }
    text.split(',')
        .map(|item| {
            let item = item.trim();
            let ok = endpoint_address(item).is_some_and(|(address, _)| {
                address.rsplit_once(':').is_some_and(|(host, port)| {
                    !host.is_empty() && port.parse::<u16>().is_ok()
                })
            });
            if ok {
                Ok(item.to_string())
            } else {
                Err(format!(
                    "'{item}' is not an endpoint tcp/HOST:PORT or tls/HOST:PORT (for example tcp/127.0.0.1:7510, or tls/0.0.0.0:7510 for every network, with the cluster's keys)"
                ))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_are_tcp_host_port_lists() {
        assert_eq!(
            parse_endpoints("tcp/127.0.0.1:7510, tcp/[::1]:7511").unwrap(),
            ["tcp/127.0.0.1:7510", "tcp/[::1]:7511"]
        );
        assert!(parse_endpoints("none").unwrap().is_empty());
        let err = parse_endpoints("127.0.0.1:7510").unwrap_err();
        assert!(err.contains("tcp/HOST:PORT"), "{err}");
        assert!(parse_endpoints("udp/1.2.3.4:7510").is_err());
        assert_eq!(
            parse_endpoints("tls/0.0.0.0:7510").unwrap(),
            ["tls/0.0.0.0:7510"]
        );
        assert!(parse_endpoints("tcp/host:port").is_err());
    }

    /// The port of each endpoint in `listen`.
    fn ports(listen: &[String]) -> Vec<u16> {
        let port = |e: &String| {
            let (address, _) = endpoint_address(e)?;
            address.rsplit_once(':')?.1.parse().ok()
        };
        listen.iter().map(|e| port(e).expect(e)).collect()
    }

    #[test]
    fn the_shipped_bus_is_not_on_a_zenoh_routers_port() {
        // 7447 is the TCP port of zenohd and of rmw_zenohd (ROS 2's router), 7446
        // Zenoh's UDP scouting port: a robot listening there does not start its bus on
        // a ROS machine or beside a Zenoh router.
        let listen = crate::config::Settings::shipped().bus.listen;
        assert!(!listen.is_empty(), "the shipped bus listens nowhere");
        for port in ports(&listen) {
            assert!(![7447, 7446].contains(&port), "{listen:?}");
        }
    }

    #[test]
    fn an_older_robot_ini_on_7447_is_read_as_it_says() {
        // Files from before the bus had a port of its own listen on 7447: still an
        // endpoint like any other.
        let ini = crate::config::DEFAULT_INI;
        let older = ini.replace("listen = tcp/127.0.0.1:7510", "listen = tcp/127.0.0.1:7447");
        assert_ne!(older, ini, "the shipped [bus] listen has moved");
        let s = crate::config::Settings::parse("robot.ini", &older, &[]).unwrap();
        assert_eq!(s.bus.listen, ["tcp/127.0.0.1:7447"]);
    }

    #[test]
    fn plain_tcp_beyond_loopback_is_refused_unless_trusted() {
        let open = ["tcp/0.0.0.0:7510".to_string()];
        let why = listen_refusal(&open, false, false, "[bus] listen").unwrap();
        assert!(why.contains("[bus] listen = tcp/0.0.0.0:7510"), "{why}");
        assert!(why.contains("trusted_network"), "{why}");
        assert_eq!(listen_refusal(&open, false, true, "[bus] listen"), None);
        for local in ["tcp/127.0.0.1:7510", "tcp/[::1]:7510", "tcp/localhost:7510"] {
            assert_eq!(
                listen_refusal(&[local.to_string()], false, false, "x"),
                None
            );
        }
        let secured = ["tls/0.0.0.0:7510".to_string()];
        assert_eq!(listen_refusal(&secured, true, false, "x"), None);
        assert!(
            listen_refusal(&open, true, true, "x").is_some(),
            "plain beside TLS"
        );
    }

    #[test]
    fn a_prefix_is_key_parts() {
        assert!(parse_prefix("farm/robot-2").is_ok());
        assert!(parse_prefix("a/*").is_err());
        assert!(parse_prefix("").is_err());
        assert!(parse_prefix("a//b").is_err());
    }
}
