//! Opening the Zenoh session: safe by default (only the endpoints robot.ini names,
//! no multicast scouting, no gossip), and a clear error that names the setting.

use zenoh::{Session, Wait};

use crate::config::BusSettings;

/// Why the bus could not start.
#[derive(Debug, thiserror::Error)]
pub enum BusError {
    #[error(
        "cannot listen on {endpoint} ({setting}): port {port} is already in use (another mechweed running? choose another port{advice})"
    )]
    PortInUse {
        endpoint: String,
        port: u16,
        setting: &'static str,
        advice: &'static str,
    },
    #[error("cannot reach {endpoints} ({setting}): {why} (is the robot program running there?)")]
    Unreachable {
        endpoints: String,
        setting: &'static str,
        why: String,
    },
    #[error("the bus could not start ({setting}): {why}")]
    Other { setting: &'static str, why: String },
}

/// Who opens the session.
pub enum Role<'a> {
    /// The robot program: listens and connects as [bus] says; a connect endpoint that
    /// is not there yet is tried again in the background.
    Robot(&'a BusSettings),
    /// A tool (`bus echo`, `camsim --bus`, ...) that connects to the robot program and
    /// listens on nothing. `wait`: keep trying to connect instead of failing.
    Tool { connect: Vec<String>, wait: bool },
    /// The cluster's master: listens where the graph says, for the launchers.
    Master { listen: String },
}

/// Open the session for `role`.
pub fn open(role: Role) -> Result<Session, BusError> {
    let (listen, connect, multicast, setting, wait) = match &role {
        Role::Robot(s) => (
            s.listen.clone(),
            s.connect.clone(),
            s.multicast,
            "[bus] listen and connect",
            true,
        ),
        Role::Tool { connect, wait } => (Vec::new(), connect.clone(), false, "--connect", *wait),
        Role::Master { listen } => (
            vec![listen.clone()],
            Vec::new(),
            false,
            "[cluster] master",
            true,
        ),
    };
    let mut config = zenoh::Config::default();
    let json = |items: &[String]| serde_json::to_string(items).expect("strings are JSON");
    let settings = [
        ("mode", "\"peer\"".to_string()),
        // Explicit, also when empty: a peer's default listens on every network.
        ("listen/endpoints", json(&listen)),
        ("connect/endpoints", json(&connect)),
        ("scouting/multicast/enabled", multicast.to_string()),
        ("scouting/gossip/enabled", multicast.to_string()),
        ("connect/exit_on_failure", (!wait).to_string()),
        (
            "connect/timeout_ms",
            if wait { "-1" } else { "3000" }.to_string(),
        ),
        // A program waiting for another (camsim for the controller, a launcher for
        // the master) finds it within a second of its start, not four.
        (
            "connect/retry",
            r#"{"period_init_ms": 250, "period_max_ms": 1000, "period_increase_factor": 2}"#
                .to_string(),
        ),
    ];
    for (key, value) in settings {
        config
            .insert_json5(key, &value)
            .map_err(|e| BusError::Other {
                setting,
                why: format!("{key} = {value}: {e}"),
            })?;
    }
    zenoh::open(config).wait().map_err(|e| {
        let why = e.to_string();
        if let Some((endpoint, port)) = listen.iter().find_map(|ep| in_use(ep)) {
            let advice = match role {
                Role::Master { .. } => "",
                _ => " with --set bus.listen=tcp/127.0.0.1:PORT",
            };
            let setting = match role {
                Role::Master { .. } => "[cluster] master",
                _ => "[bus] listen",
            };
            return BusError::PortInUse {
                endpoint,
                port,
                setting,
                advice,
            };
        }
        if !connect.is_empty() && listen.is_empty() {
            return BusError::Unreachable {
                endpoints: connect.join(", "),
                setting,
                why,
            };
        }
        BusError::Other { setting, why }
    })
}

/// The endpoint and port, if something else already listens on `endpoint`'s port.
fn in_use(endpoint: &str) -> Option<(String, u16)> {
    let address = endpoint.strip_prefix("tcp/")?;
    let (_, port) = address.rsplit_once(':')?;
    let port: u16 = port.parse().ok()?;
    match std::net::TcpListener::bind(address) {
        Err(e) if e.kind() == std::io::ErrorKind::AddrInUse => Some((endpoint.to_string(), port)),
        _ => None,
    }
}
