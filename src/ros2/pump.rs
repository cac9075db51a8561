//! The robot's flows in, ROS 2 messages out: what the bridge and the ROS 2 recorder
//! share. The robot's tick, status and event flows are heard on its bus (a tool's
//! session; a viewer's identity when it is secured) and queued; each is made into
//! messages (flows.rs), and /diagnostics once a second, for `send` to put on the ROS
//! router or into a bag.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use zenoh::Wait;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::Subscriber;

use super::flows::{Converter, Counts, Outgoing};
use crate::bus::session::{self, Role};
use crate::config::TlsFiles;

/// Messages waiting for the loop; beyond this they are dropped here and counted.
const QUEUE: usize = 1024;
/// Bad messages are counted; the first few are also said.
const SAY_BAD: u64 = 5;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Flow {
    Tick,
    Status,
    Event,
}

/// The robot's flows, heard.
pub struct Robot {
    /// The robot's name on its bus.
    pub name: String,
    /// Each flow's message and when it arrived.
    rx: crossbeam_channel::Receiver<(Flow, Vec<u8>, Instant)>,
    dropped_here: Arc<AtomicU64>,
    _subscribers: Vec<Subscriber<()>>,
    _alive: LivelinessToken,
    /// Last: dropped after what it declared.
    _session: zenoh::Session,
}

/// What a pump did.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pumped {
    pub counts: Counts,
    /// Messages `send` took, and refused.
    pub sent: u64,
    pub failed: u64,
    /// Flows the queue had no room for.
    pub dropped_here: u64,
}

impl Pumped {
    /// One line for the end: what came and what went.
    pub fn line(&self, robot: &str, what: &str) -> String {
        let c = self.counts;
        format!(
            "{} ticks, {} statuses and {} events of {robot} made {} {what} ({} not taken, {} dropped on this computer, {} refused)",
            c.ticks, c.statuses, c.events, self.sent, self.failed, self.dropped_here, c.bad
        )
    }
}

impl Robot {
    /// Connect to the robot's bus at `endpoint` (waiting for the robot program) and
    /// hear its flows; `who` names this program's liveliness token (alive/WHO-PID).
    pub fn hear(
        endpoint: &str,
        name: &str,
        tls: Option<&TlsFiles>,
        who: &str,
    ) -> Result<Robot, String> {
        // A tool's session: it connects to the robot program and listens on nothing.
        session::check_robot(tls, name)?;
        let role = Role::Tool {
            connect: vec![endpoint.to_string()],
            wait: true,
        };
        let zenoh = session::open(role, tls).map_err(|e| session::plain_words(&e))?;
        let key = |what: &str| format!("{name}/{what}");
        let (tx, rx) = crossbeam_channel::bounded(QUEUE);
        let dropped_here = Arc::new(AtomicU64::new(0));
        let mut subscribers = Vec::new();
        for (flow, what) in [
            (Flow::Tick, "tick"),
            (Flow::Status, "status"),
            (Flow::Event, "event"),
        ] {
            let (tx, dropped) = (tx.clone(), dropped_here.clone());
            let subscriber = zenoh
                .declare_subscriber(key(what))
                .callback(move |sample| {
                    let bytes = sample.payload().to_bytes().into_owned();
                    if tx.try_send((flow, bytes, Instant::now())).is_err() {
                        dropped.fetch_add(1, Ordering::Relaxed);
                    }
                })
                .wait()
                .map_err(|e| e.to_string())?;
            subscribers.push(subscriber);
        }
        let alive = zenoh
            .liveliness()
            .declare_token(key(&format!("alive/{who}-{}", std::process::id())))
            .wait()
            .map_err(|e| e.to_string())?;
        Ok(Robot {
            name: name.to_string(),
            _session: zenoh,
            rx,
            dropped_here,
            _subscribers: subscribers,
            _alive: alive,
        })
    }

    /// Make messages of the flows and give each to `send` (true: taken) until `stop`
    /// or `end`. `say` prefixes the program's lines.
    pub fn pump(
        &self,
        wheel_radius_m: f64,
        stop: &AtomicBool,
        end: Option<Instant>,
        say: &str,
        mut send: impl FnMut(&Outgoing) -> bool,
    ) -> Pumped {
        let mut converter = Converter::new(&self.name, wheel_radius_m);
        let mut pumped = Pumped::default();
        let mut next_diagnostics = Instant::now();
        let mut heard = false;
        while !stop.load(Ordering::Relaxed) && end.is_none_or(|end| Instant::now() < end) {
            let mut made = Vec::new();
            let now = Instant::now();
            if now >= next_diagnostics {
                next_diagnostics = now + Duration::from_secs(1);
                let figures = format!(
                    "{} messages sent, {} refused",
                    pumped.sent, converter.counts.bad
                );
                made.push(converter.diagnostics(now, &figures).map(|m| vec![m]));
            }
            if let Ok((flow, bytes, arrived)) = self.rx.recv_timeout(Duration::from_millis(50)) {
                made.push(match flow {
                    Flow::Tick => converter.tick(&bytes),
                    Flow::Status => converter.status(&bytes, arrived),
                    Flow::Event => converter.event(&bytes),
                });
                if !heard {
                    heard = true;
                    println!("{say}: the robot's flows are coming");
                }
            }
            for messages in made {
                match messages {
                    Ok(messages) => {
                        for m in &messages {
                            if send(m) {
                                pumped.sent += 1;
                            } else {
                                pumped.failed += 1;
                            }
                        }
                    }
                    Err(why) => {
                        converter.counts.bad += 1;
                        if converter.counts.bad <= SAY_BAD {
                            eprintln!(
                                "{say}: a message of the robot that cannot be made a ROS message: {why}"
                            );
                        }
                    }
                }
            }
        }
        pumped.counts = converter.counts;
        pumped.dropped_here = self.dropped_here.load(Ordering::Relaxed);
        pumped
    }
}
