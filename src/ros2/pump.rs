//! The robot's flows in, ROS 2 messages out: what the bridge and the ROS 2 recorder
//! share. The robot's tick, status and event flows are heard on its bus (a tool's
//! session; a viewer's identity when it is secured) and queued; each is made into
//! messages (flows.rs), and /diagnostics once a second, for `send` to put on the ROS
//! router or into a bag.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::flows::{Converter, Counts, Outgoing};
use super::model::RobotModel;
use crate::bus::hearing::{Ear, Hearing};
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
    /// Each flow's message and when it arrived, from a session that mends itself.
    hearing: Hearing<Flow>,
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
    /// Messages under a wrong key (not taken), and times the session was opened again.
    pub wrong_key: u64,
    pub reopened: u64,
}

impl Pumped {
    /// One message given to the ROS side: taken, or not.
    fn count(&mut self, taken: bool) {
        if taken {
            self.sent += 1;
        } else {
            self.failed += 1;
        }
    }

    /// One line for the end: what came and what went.
    pub fn line(&self, robot: &str, what: &str) -> String {
        let c = self.counts;
        format!(
            "{} ticks, {} statuses and {} events of {robot} made {} {what} ({} not taken, {} dropped on this computer, {} refused, {} under the wrong key; the session opened again {} times)",
            c.ticks,
            c.statuses,
            c.events,
            self.sent,
            self.failed,
            self.dropped_here,
            c.bad,
            self.wrong_key,
            self.reopened
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
        let hearing = Hearing::start(Ear {
            endpoint: endpoint.to_string(),
            robot: name.to_string(),
            tls: tls.cloned(),
            token: format!("alive/{who}-{}", std::process::id()),
            flows: vec![
                (Flow::Tick, "tick"),
                (Flow::Status, "status"),
                (Flow::Event, "event"),
            ],
            program: "ros2",
            queue: QUEUE,
        })?;
        Ok(Robot {
            name: name.to_string(),
            hearing,
        })
    }

    /// Make messages of the flows and give each to `send` (true: taken) until `stop`
    /// or `end`. `say` prefixes the program's lines.
    pub fn pump(
        &self,
        ros: &crate::config::Ros2Settings,
        model: &RobotModel,
        stop: &AtomicBool,
        end: Option<Instant>,
        say: &str,
        mut send: impl FnMut(&Outgoing) -> bool,
    ) -> Pumped {
        let mut converter =
            Converter::new(&self.name, model.clone()).with_frame_prefix(&ros.frame_prefix);
        let mut pumped = Pumped::default();
        match converter.latched() {
            Ok(latched) => latched.iter().for_each(|m| pumped.count(send(m))),
            Err(why) => eprintln!("{say}: the robot's model cannot be made a ROS message: {why}"),
        }
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
                made.push(
                    converter
                        .diagnostics(now, &figures)
                        .map(|m| m.into_iter().collect()),
                );
            }
            if let Ok((flow, bytes, arrived)) =
                self.hearing.rx.recv_timeout(Duration::from_millis(50))
            {
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
                            pumped.count(send(m));
                        }
                    }
                    Err(why) => {
                        converter.counts.bad += 1;
                        self.hearing.unreadable();
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
        let counts = &self.hearing.counts;
        pumped.dropped_here = counts.dropped_here.load(Ordering::Relaxed);
        pumped.wrong_key = counts.wrong_key.load(Ordering::Relaxed);
        pumped.reopened = counts.reopened.load(Ordering::Relaxed);
        pumped
    }
}
