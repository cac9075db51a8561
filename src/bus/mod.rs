//! The bus: mechweed's data flows to and from other programs and machines, on Zenoh.
//! One-way flows with any number of receivers (status, ticks, events out; row
//! estimates in), queries for requests and settings, and liveliness tokens for who is
//! there. The control loops never wait for it: the bus thread reads protected objects
//! and a queue that drops (thread.rs), and every publisher drops rather than queues.
//! The robot's session lives in a process of its own (gateway/), so that the network's
//! library cannot take the controller down.
//!
//! Keys (ROBOT = `[bus] robot`): ROBOT/status, ROBOT/tick, ROBOT/event, ROBOT/request,
//! ROBOT/config/SECTION/KEY, ROBOT/camera/row, ROBOT/alive/NAME. The bus is never a
//! safety channel: the e-stops are wired, and rows from the bus go through the camera
//! link's time-out and fault like a camera computer's.

pub mod acl;
pub mod asked_as;
pub mod gate;
pub mod gateway;
pub mod hearing;
pub mod identities;
pub mod inbox;
pub mod keys;
pub mod payload;
pub mod peers;
pub mod queries;
pub mod refusals;
pub mod row_clock;
pub mod rows;
pub mod session;
pub mod thread;

pub use session::{BusError, Role};

use crate::gamepad::Label;

/// The bus as the GUI and the report show it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BusState {
    /// `[bus] enabled = no`, or it could not start and is not required.
    #[default]
    Off,
    Running,
    /// The bus process ended; it is started again after a wait.
    Restarting,
    /// The run has ended.
    Closed,
}

/// What the bus has done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct BusFigures {
    pub state: BusState,
    /// Other programs present (their liveliness tokens).
    pub peers: u32,
    /// Someone subscribes to ROBOT/status now.
    pub status_receivers: bool,
    pub status_published: u64,
    pub ticks_published: u64,
    pub events_published: u64,
    /// Ticks and events the bus thread's queue had no room for.
    pub ticks_dropped: u64,
    pub events_dropped: u64,
    pub queries_answered: u64,
    /// Queries refused: bad input, not allowed, or refused by the supervisor.
    pub queries_refused: u64,
    /// Queries that found their queue full and got no answer.
    pub queries_dropped: u64,
    /// Row estimates received on ROBOT/camera/row, and those refused as impossible.
    pub rows_received: u64,
    pub rows_rejected: u64,
    /// Whether the bus is secured, and by which authority, in words.
    pub security: Label,
    /// The identities linked so far, and those refused (secured bus only).
    pub identities: Label,
    /// How often the bus process ended and was started again.
    pub process_restarts: u32,
}

/// The run's bus process, its session open: None when the bus is off, or when it could
/// not start and the run does not need it (a warning says why). An error when `[bus]
/// required = yes` or the camera's rows come from the bus.
pub(crate) fn open_for_run(
    s: &crate::config::Settings,
) -> Result<Option<gateway::supervise::Gateway>, BusError> {
    if !s.bus.enabled {
        return Ok(None);
    }
    session::check_robot(s.bus.tls.as_ref(), &s.bus.robot).map_err(|why| BusError::Other {
        setting: "[bus] robot and tls_ca",
        why,
    })?;
    match gateway::supervise::Gateway::start(s) {
        Ok(gateway) => {
            crate::say!(
                "bus: {}, keys {}/...; requests accepted: {}; {}",
                s.bus.endpoints(),
                s.bus.robot,
                match s.bus.accept_requests {
                    crate::config::AcceptRequests::Halt => "halt only",
                    crate::config::AcceptRequests::Operator => "halt, power up, modes, settings",
                },
                security_line(&s.bus)
            );
            let mut endpoints = s.bus.listen.iter().chain(&s.bus.connect);
            let open = endpoints.any(|e| !crate::config::is_loopback(e)) || s.bus.multicast;
            if s.bus.tls.is_none() && open {
                crate::say!(
                    "bus: OPEN TO ANYONE on the networks of {} ([bus] trusted_network = yes, no TLS): whoever reaches it may use the bus as this robot allows",
                    s.bus.endpoints()
                );
            }
            Ok(Some(gateway))
        }
        Err(why) if s.bus.required || s.camera_port == crate::config::CameraPort::Bus => {
            Err(BusError::Process(why))
        }
        Err(e) => {
            tracing::warn!("{e}; the robot runs without the bus ([bus] required = no)");
            Ok(None)
        }
    }
}

/// Whether the bus is secured, and by which authority, in words.
pub(crate) fn security_line(bus: &crate::config::BusSettings) -> String {
    match &bus.tls {
        Some(files) => format!(
            "secured: TLS, identities of the authority {}, rights from {}",
            files.authority(),
            files.roster().display()
        ),
        None => "not secured: plain TCP, no identities".to_string(),
    }
}

impl BusFigures {
    /// One line for the console, the report and the GUI.
    pub fn line(&self) -> String {
        if self.state == BusState::Off {
            return "bus: off".to_string();
        }
        let mut line = format!(
            "bus: {} status, {} ticks, {} events published ({} ticks, {} events dropped); {} queries answered ({} refused, {} dropped); {} other programs present{}",
            self.status_published,
            self.ticks_published,
            self.events_published,
            self.ticks_dropped,
            self.events_dropped,
            self.queries_answered,
            self.queries_refused,
            self.queries_dropped,
            self.peers,
            if self.status_receivers {
                ", status received"
            } else {
                ""
            },
        );
        if self.process_restarts > 0 {
            line += &format!(
                "; the bus process was started again {} times",
                self.process_restarts
            );
        }
        if self.state == BusState::Restarting {
            line += "; the bus process is away, starting again";
        }
        line += &format!("; {}", self.security.as_str());
        if !self.identities.as_str().is_empty() {
            line += &format!("; identities: {}", self.identities.as_str());
        }
        if self.rows_received > 0 {
            line += &format!(
                "; row estimates: {} received, {} refused",
                self.rows_received, self.rows_rejected
            );
        }
        line
    }
}
