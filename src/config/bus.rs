//! The [bus] section: the data flows between mechweed and other programs (src/bus/).

use super::reader::Reader;

/// Which requests other programs may make over the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AcceptRequests {
    /// HALT only: stopping the robot is always allowed, from anywhere.
    Halt,
    /// HALT, power up and modes, decided by the supervisor as for the GUI.
    Operator,
}

#[derive(Debug, Clone, PartialEq)]
pub struct BusSettings {
    pub enabled: bool,
    /// Without the bus the run goes on (a warning) unless this is set.
    pub required: bool,
    /// The first part of every key: ROBOT/status, ROBOT/request, ...
    pub robot: String,
    /// Zenoh endpoints this program listens on, e.g. tcp/127.0.0.1:7447.
    pub listen: Vec<String>,
    /// Zenoh endpoints this program connects to.
    pub connect: Vec<String>,
    /// Multicast scouting (finding peers on the network without an address).
    pub multicast: bool,
    /// Publish every Nth supervisor tick on ROBOT/tick.
    pub tick_every_n: u64,
    pub accept_requests: AcceptRequests,
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
    }
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

/// A comma-separated list of zenoh endpoints, `tcp/HOST:PORT`; `none` or empty for none.
pub fn parse_endpoints(text: &str) -> Result<Vec<String>, String> {
    if text.is_empty() || text == "none" {
        return Ok(Vec::new());
    }
    text.split(',')
        .map(|item| {
            let item = item.trim();
            let ok = item.strip_prefix("tcp/").is_some_and(|address| {
                address.rsplit_once(':').is_some_and(|(host, port)| {
                    !host.is_empty() && port.parse::<u16>().is_ok()
                })
            });
            if ok {
                Ok(item.to_string())
            } else {
                Err(format!(
                    "'{item}' is not an endpoint tcp/HOST:PORT (for example tcp/127.0.0.1:7447, or tcp/0.0.0.0:7447 for every network)"
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
            parse_endpoints("tcp/127.0.0.1:7447, tcp/[::1]:7448").unwrap(),
            ["tcp/127.0.0.1:7447", "tcp/[::1]:7448"]
        );
        assert!(parse_endpoints("none").unwrap().is_empty());
        let err = parse_endpoints("127.0.0.1:7447").unwrap_err();
        assert!(err.contains("tcp/HOST:PORT"), "{err}");
        assert!(parse_endpoints("udp/1.2.3.4:7447").is_err());
        assert!(parse_endpoints("tcp/host:port").is_err());
    }

    #[test]
    fn a_prefix_is_key_parts() {
        assert!(parse_prefix("farm/robot-2").is_ok());
        assert!(parse_prefix("a/*").is_err());
        assert!(parse_prefix("").is_err());
        assert!(parse_prefix("a//b").is_err());
    }
}
