//! `mechweed bus ...`: small programs for a person at another computer (or a script):
//! watch a flow, send a request, get or set a setting, see who is there. Each opens its
//! own session that connects to the robot program and listens on nothing.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use zenoh::{Session, Wait};

use crate::bus::payload::wall_s;
use crate::bus::session::{Role, open, plain_words};
use crate::config::TlsFiles;

/// Where the robot program listens with the shipped settings ([bus] listen), the tools'
/// --connect when none is given (a test in programs/bus/mod.rs keeps the two equal).
pub(crate) const DEFAULT_ENDPOINT: &str = "tcp/127.0.0.1:7510";
/// How long a tool waits for the robot program to answer.
const ANSWER_WAIT: Duration = Duration::from_secs(3);

/// The flows a robot program publishes or takes, as `bus echo` names them.
pub(crate) const FLOWS: [&str; 4] = ["status", "tick", "event", "camera/row"];

/// Key prefixes under which other programs publish (the cluster's master and
/// launchers, the programs' tokens): taken as given.
const OTHER_PROGRAMS: [&str; 2] = ["cluster/", "alive/"];

/// Refuse a flow name the robot does not have (a typo waits for ever otherwise). Keys
/// taken whole (`/farm/robot2/status`), patterns (`*`) and the other programs' keys are
/// taken as given.
pub(crate) fn check_flow(key: &str) -> Result<(), String> {
    let others = OTHER_PROGRAMS.iter().any(|p| key.starts_with(p));
    if key.starts_with('/') || key.contains('*') || others || FLOWS.contains(&key) {
        return Ok(());
    }
    Err(format!(
        "'{key}' is not a flow of the robot: its flows are {} (the cluster's: cluster/...; another robot's: /NAME/status; a pattern: '*')",
        FLOWS.join(", ")
    ))
}

/// A tool's connection to one robot's flows.
pub struct Tool {
    session: Session,
    robot: String,
    endpoint: String,
    /// TLS with the cluster's identities: the rules allow only named flows.
    secured: bool,
    /// This program's identity and its role in the roster, on a secured bus.
    identity: String,
    /// Its certificate's name, on a secured bus: it asks under ROBOT/as/NAME.
    name: Option<String>,
}

impl Tool {
    /// Connect to `endpoint`, to the flows of robot `robot` (the key prefix).
    /// `wait`: keep trying until the robot program is there (camsim may start first).
    /// `tls`: this program's identity in the cluster; None, plain TCP.
    pub fn connect(
        endpoint: &str,
        robot: &str,
        wait: bool,
        tls: Option<&TlsFiles>,
    ) -> Result<Tool, String> {
        let role = Role::Tool {
            connect: vec![endpoint.to_string()],
            wait,
        };
        crate::bus::session::check_robot(tls, robot)?;
        let session = open(role, tls).map_err(|e| plain_words(&e))?;
        Ok(Tool {
            session,
            robot: robot.to_string(),
            endpoint: endpoint.to_string(),
            secured: tls.is_some(),
            identity: tls.map(identity_of).unwrap_or_default(),
            name: tls.map(TlsFiles::name),
        })
    }

    /// The session, for a program that subscribes itself (the off-board recorder).
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// `ROBOT/KEY`; a key that starts with `/` is taken whole, without it (another
    /// robot's flows: /farm/robot2/status).
    pub fn key(&self, key: &str) -> String {
        match key.strip_prefix('/') {
            Some(whole) => whole.to_string(),
            None => format!("{}/{key}", self.robot),
        }
    }

    /// Wait (at most ANSWER_WAIT) until the robot program's token is seen, so that a
    /// query right after connecting finds its queryables.
    fn wait_for_controller(&self) -> Result<(), String> {
        let key = self.key("alive/controller");
        let end = Instant::now() + ANSWER_WAIT;
        while Instant::now() < end {
            let replies = self
                .session
                .liveliness()
                .get(&key)
                .timeout(Duration::from_millis(500))
                .wait()
                .map_err(|e| plain_words(&e))?;
            if replies.recv().is_ok() {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        Err(format!(
            "no mechweed robot program '{}' answers at {} (is it running, with [bus] enabled = yes and this listen endpoint?)",
            self.robot, self.endpoint
        ))
    }

    /// Whether the robot program's token answers within `wait` (one look).
    fn controller_answers(&self, wait: Duration) -> bool {
        let key = self.key("alive/controller");
        let replies = self.session.liveliness().get(&key).timeout(wait).wait();
        replies.is_ok_and(|replies| replies.recv().is_ok())
    }

    /// Ask `key` with `payload`; the first answer as text, or the error's text.
    /// On a secured bus it asks under its own name, so that the robot counts what it
    /// asks by its certificate and no other identity's flood is counted with it.
    pub fn ask(&self, key: &str, payload: Option<String>) -> Result<String, String> {
        self.wait_for_controller()?;
        // A whole key (another robot's, /farm/robot2/...) is asked as it is.
        let key = if key.starts_with('/') {
            self.key(key)
        } else {
            crate::bus::asked_as::key(&self.robot, self.name.as_deref(), key)
        };
        // Named, so that the robot limits this program's requests apart from others'.
        let mut get = self
            .session
            .get(&key)
            .attachment(self.session.zid().to_string())
            .timeout(ANSWER_WAIT);
        if let Some(payload) = payload {
            get = get.payload(payload);
        }
        let replies = get.wait().map_err(|e| plain_words(&e))?;
        let reply = replies.recv().map_err(|_| {
            let mut why = format!("no answer from {key} within {} s", ANSWER_WAIT.as_secs());
            if self.secured {
                // The robot's access rules drop what an identity may not ask, unanswered.
                why += &format!(
                    ": the robot may be busy or gone, or its access rules dropped the question unanswered (on a secured bus only an operator's identity may ask for more than HALT or set a setting; this program is {})",
                    self.identity
                );
            }
            why
        })?;
        match reply.result() {
            Ok(sample) => Ok(text(&sample.payload().to_bytes())),
            // {"error": WHY}: the reason, as the robot program says it.
            Err(error) => {
                let body = text(&error.payload().to_bytes());
                let json: serde_json::Value = serde_json::from_str(&body).unwrap_or_default();
                Err(json["error"].as_str().map_or(body, str::to_string))
            }
        }
    }

    /// Print each message on `key` as one line of JSON, `{"key", "received_s",
    /// "payload"}`, until `count` messages or `seconds` have passed (None: for ever).
    /// `slow_s`: take this long over each message (a slow receiver, for tests and
    /// measurements). Returns each message's age on arrival, s, where its payload says
    /// when it was sent (`wall_s`).
    pub fn echo(
        &self,
        key: &str,
        count: Option<u64>,
        seconds: Option<f64>,
        slow_s: f64,
    ) -> Result<Vec<f64>, String> {
        let key = self.key(key);
        // A receiver that falls behind drops the oldest messages, never the sender's
        // pace: of a status only the newest counts; of other flows the newest 256 wait.
        let keep = if key.ends_with("/status") { 1 } else { 256 };
        let subscriber = self
            .session
            .declare_subscriber(&key)
            .with(zenoh::handlers::RingChannel::new(keep))
            .wait()
            .map_err(|e| plain_words(&e))?;
        // Seen by the robot program as a receiver (its status and the GUI count them).
        let _alive = self
            .session
            .liveliness()
            .declare_token(self.key(&format!("alive/echo-{}", std::process::id())))
            .wait()
            .map_err(|e| plain_words(&e))?;
        let end = seconds.map(|s| Instant::now() + Duration::from_secs_f64(s));
        // Said once, a few seconds in, when nothing came and no robot program is there:
        // a subscriber waits for the robot, but not silently.
        let mut absence_said = false;
        let asked_at = Instant::now();
        let mut printed = 0;
        let mut ages_s = Vec::new();
        while count.is_none_or(|n| printed < n) {
            let wait = end.map_or(Duration::from_millis(200), |end| {
                end.saturating_duration_since(Instant::now())
            });
            if end.is_some_and(|end| Instant::now() >= end) {
                break;
            }
            let Ok(Some(sample)) = subscriber.recv_timeout(wait.min(Duration::from_millis(200)))
            else {
                if printed == 0 && !absence_said && asked_at.elapsed() >= ANSWER_WAIT {
                    absence_said = true;
                    if !self.controller_answers(Duration::from_millis(500)) {
                        eprintln!(
                            "bus echo: nothing yet on {key}: no mechweed robot program '{}' answers at {} (is it running, with [bus] enabled = yes and this endpoint?); still waiting, Ctrl-C to stop",
                            self.robot, self.endpoint
                        );
                    }
                }
                continue;
            };
            let payload = text(&sample.payload().to_bytes());
            // A JSON payload stays JSON; anything else is quoted.
            let payload: serde_json::Value =
                serde_json::from_str(&payload).unwrap_or(serde_json::Value::String(payload));
            let received_s = wall_s();
            if let Some(sent_s) = payload.get("wall_s").and_then(serde_json::Value::as_f64) {
                ages_s.push(received_s - sent_s);
            }
            let line = serde_json::json!({
                "key": sample.key_expr().as_str(),
                "received_s": received_s,
                "payload": payload,
            });
            println!("{line}");
            printed += 1;
            if slow_s > 0.0 {
                std::thread::sleep(Duration::from_secs_f64(slow_s));
            }
        }
        Ok(ages_s)
    }

    /// What the robot's status says of its bus: secured and by whom, who came; and the
    /// programs' tokens the robot sees.
    fn robot_says_of_its_bus(&self) -> Option<(String, Vec<String>)> {
        let subscriber = self
            .session
            .declare_subscriber(self.key("status"))
            .wait()
            .ok()?;
        let sample = subscriber.recv_timeout(ANSWER_WAIT).ok()??;
        let status: serde_json::Value =
            serde_json::from_slice(&sample.payload().to_bytes()).ok()?;
        let bus = &status["bus"];
        let mut line = bus["security"].as_str()?.to_string();
        if let Some(ids) = bus["identities"].as_str().filter(|i| !i.is_empty()) {
            line += &format!("; identities: {ids}");
        }
        let present = (bus["present"].as_array().into_iter().flatten())
            .filter_map(|name| Some(name.as_str()?.to_string()))
            .collect();
        Some((line, present))
    }

    /// Who is present (liveliness tokens) and which flows carry messages, with their
    /// rates over `seconds`.
    pub fn list(&self, seconds: f64) -> Result<String, String> {
        let alive = self.key("alive/**");
        let replies = self
            .session
            .liveliness()
            .get(&alive)
            .timeout(ANSWER_WAIT)
            .wait()
            .map_err(|e| plain_words(&e))?;
        let robot_says = self.robot_says_of_its_bus();
        let mut out = match &robot_says {
            Some((line, _)) => format!("the robot's bus: {line}\n"),
            None => "the robot's bus: no status within 3 s\n".to_string(),
        };
        out += &format!(
            "this program: {}\n",
            if self.secured {
                format!("TLS, as {}", self.identity)
            } else {
                "plain TCP, no identity".to_string()
            }
        );
        out += "present:\n";
        // The robot's session does not pass the other programs' tokens on to this one:
        // the robot's status names those it sees.
        let mut present = robot_says.map(|(_, present)| present).unwrap_or_default();
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result() {
                present.push(sample.key_expr().as_str().to_string());
            }
        }
        present.sort();
        present.dedup();
        if present.is_empty() {
            out += "  nobody\n";
        }
        for name in present {
            out += &format!("  {name}\n");
        }
        // On a secured bus a rule allows named flows, not all of ROBOT/** at once.
        let keys: Vec<String> = if self.secured {
            ["status", "tick", "event"].map(|k| self.key(k)).to_vec()
        } else {
            vec![self.key("**")]
        };
        let (tx, samples) = crossbeam_channel::bounded::<String>(1024);
        let mut subscribers = Vec::new();
        for key in keys {
            let tx = tx.clone();
            let subscriber = self
                .session
                .declare_subscriber(key)
                .callback(move |sample| {
                    let _ = tx.try_send(sample.key_expr().as_str().to_string());
                })
                .wait()
                .map_err(|e| plain_words(&e))?;
            subscribers.push(subscriber);
        }
        let start = Instant::now();
        let mut counts: BTreeMap<String, u64> = BTreeMap::new();
        while start.elapsed().as_secs_f64() < seconds {
            if let Ok(key) = samples.recv_timeout(Duration::from_millis(50)) {
                *counts.entry(key).or_default() += 1;
            }
        }
        drop(subscribers);
        out += &format!("flows over {seconds:.0} s:\n");
        if counts.is_empty() {
            out += "  none\n";
        }
        for (key, n) in counts {
            out += &format!(
                "  {key:<32} {:6.1} messages/s\n",
                n as f64 / seconds.max(1e-3)
            );
        }
        Ok(out)
    }
}

/// "NAME (ROLE)" for the identity in `files`, as the roster beside its authority says.
fn identity_of(files: &TlsFiles) -> String {
    let name = files.name();
    let role = crate::bus::keys::Roster::read(&files.roster())
        .ok()
        .and_then(|r| r.role_of(&name))
        .map_or("not in the roster".to_string(), |r| r.to_string());
    format!("{name} ({role})")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
