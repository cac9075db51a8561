//! Opening the Zenoh session: safe by default (only the endpoints robot.ini names,
//! no multicast scouting, no gossip, messages and sessions bounded), TLS with the
//! cluster's identities and access rules where its keys are given, and a clear error
//! that names the setting.

use zenoh::{Session, Wait};

use crate::bus::keys::Roster;
use crate::config::{BusSettings, TlsFiles, endpoint_address};

/// The largest message a program takes, bytes: a status or a plan is a few kilobytes.
/// Zenoh's own limit is a gigabyte, which a flood of large payloads would fill.
pub(crate) const MAX_MESSAGE_BYTES: usize = 128 * 1024;

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
    /// What the bus process said, in its own words (one of the above).
    #[error("{0}")]
    Process(String),
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
    /// `mechweed ros2` on the ROS machines' side: a client of their router, as ROS 2
    /// tools find it; fails after 3 s when the router is not there (the bridge tries
    /// again, saying so).
    RosClient { router: String },
}

/// Zenoh's error in words a user can act on: without the source file and line inside
/// zenoh that raised it ("at …/src/net/runtime/orchestrator.rs:388").
pub(crate) fn plain_words(error: &impl std::fmt::Display) -> String {
    let text = error.to_string();
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find(" at ") {
        let after = &rest[i + 4..];
        let end = after.find(char::is_whitespace).unwrap_or(after.len());
        if after[..end].contains(".rs:") {
            out.push_str(&rest[..i]);
        } else {
            out.push_str(&rest[..i + 4 + end]);
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out.trim().trim_end_matches('.').trim_end().to_string()
}

/// Open the session for `role`; with `tls`, TLS only, both ends showing a certificate
/// of the cluster's authority, under the access rules written from its roster.
pub fn open(role: Role, tls: Option<&TlsFiles>) -> Result<Session, BusError> {
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
        Role::RosClient { router } => (
            Vec::new(),
            vec![router.clone()],
            false,
            "[ros2] connect",
            false,
        ),
    };
    // Sessions at once: the robot's flows need a camera, a few views and recorders and
    // bus tools; the master one per launcher and status tool. A flood of sessions
    // finds the door shut instead of the memory full.
    let max_sessions = match role {
        Role::Robot(_) => 32,
        Role::Master { .. } => 64,
        Role::Tool { .. } | Role::RosClient { .. } => 8,
    };
    let mode = match role {
        Role::RosClient { .. } => "\"client\"",
        _ => "\"peer\"",
    };
    let mut config = zenoh::Config::default();
    let json = |items: &[String]| serde_json::to_string(items).expect("strings are JSON");
    let mut settings = vec![
        ("mode", mode.to_string()),
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
        (
            "transport/link/rx/max_message_size",
            MAX_MESSAGE_BYTES.to_string(),
        ),
        ("transport/unicast/max_sessions", max_sessions.to_string()),
        ("transport/unicast/accept_pending", "16".to_string()),
    ];
    if let Some(files) = tls {
        for (problem, fix) in crate::bus::keys::exposure(files) {
            tracing::warn!("bus: {problem}: {fix}");
        }
        settings.extend(secured(files).map_err(|why| BusError::Other { setting, why })?);
    }
    for (key, value) in settings {
        config
            .insert_json5(key, &value)
            .map_err(|e| BusError::Other {
                setting,
                why: format!("{key} = {value}: {e}"),
            })?;
    }
    zenoh::open(config)
        .wait()
        .map_err(|e| why_not_open(&e, &role, &listen, &connect, setting))
}

/// Why the session did not open, in words that name the setting to change: a port in
/// use, nothing answering where this program connects, or Zenoh's own words.
fn why_not_open(
    e: &zenoh::Error,
    role: &Role,
    listen: &[String],
    connect: &[String],
    setting: &'static str,
) -> BusError {
    let why = plain_words(e);
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
        // Zenoh's own words repeat the endpoints in its debug form.
        let why = if why.starts_with("Unable to connect") {
            "nothing answered within 3 s".to_string()
        } else {
            why
        };
        return BusError::Unreachable {
            endpoints: connect.join(", "),
            setting,
            why,
        };
    }
    BusError::Other { setting, why }
}

/// The TLS and access-control settings for `files`; an error names the file.
fn secured(files: &TlsFiles) -> Result<Vec<(&'static str, String)>, String> {
    let check = |path: &std::path::Path, holds: &str, what: &str| {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {what} {}: {e}", path.display()))?;
        if text.contains(holds) {
            Ok(())
        } else {
            Err(format!("{} is not {what}", path.display()))
        }
    };
    check(&files.ca, "CERTIFICATE", "the authority's certificate")?;
    check(&files.cert, "CERTIFICATE", "a certificate")?;
    check(&files.key, "PRIVATE KEY", "a private key")?;
    let roster = Roster::read(&files.roster())?;
    let path = |p: &std::path::Path| serde_json::to_string(&p.display().to_string()).expect("JSON");
    Ok(vec![
        // TLS only: no plain link is opened or accepted beside it.
        ("transport/link/protocols", r#"["tls"]"#.to_string()),
        ("transport/link/tls/root_ca_certificate", path(&files.ca)),
        ("transport/link/tls/listen_certificate", path(&files.cert)),
        ("transport/link/tls/listen_private_key", path(&files.key)),
        ("transport/link/tls/connect_certificate", path(&files.cert)),
        ("transport/link/tls/connect_private_key", path(&files.key)),
        ("transport/link/tls/enable_mtls", "true".to_string()),
        // Who a peer is comes from its certificate's name and the roster, not from
        // the address it was reached at (a field's addresses change).
        (
            "transport/link/tls/verify_name_on_connect",
            "false".to_string(),
        ),
        (
            "access_control",
            super::acl::access_control(&roster).to_string(),
        ),
    ])
}

/// Whether the roster of `tls` is for robot `robot`: its access rules cover that robot's
/// keys alone, and with another name every flow would be refused without a word.
pub(crate) fn check_robot(tls: Option<&TlsFiles>, robot: &str) -> Result<(), String> {
    let Some(tls) = tls else { return Ok(()) };
    let roster = Roster::read(&tls.roster())?;
    if roster.robot == robot {
        Ok(())
    } else {
        Err(format!(
            "{} is the roster of robot '{}', and this program is for robot '{robot}': its access rules would refuse every flow (make the keys with --robot {robot}, or set the robot's name to {})",
            tls.roster().display(),
            roster.robot,
            roster.robot
        ))
    }
}

/// The endpoint and port, if something else already listens on `endpoint`'s port.
fn in_use(endpoint: &str) -> Option<(String, u16)> {
    let (address, _) = endpoint_address(endpoint)?;
    let (_, port) = address.rsplit_once(':')?;
    let port: u16 = port.parse().ok()?;
    match std::net::TcpListener::bind(address) {
        Err(e) if e.kind() == std::io::ErrorKind::AddrInUse => Some((endpoint.to_string(), port)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn zenohs_source_paths_are_left_out_of_its_errors() {
        let zenoh = "Unable to connect to any of [tcp/127.0.0.1:7999]!  at /root/.cargo/registry/src/x/zenoh-1.10.2/src/net/runtime/orchestrator.rs:388.";
        assert_eq!(
            super::plain_words(&zenoh),
            "Unable to connect to any of [tcp/127.0.0.1:7999]!"
        );
        // " at " in ordinary words stays.
        assert_eq!(
            super::plain_words(&"nothing at port 7510"),
            "nothing at port 7510"
        );
    }
}
