//! The operator view on another computer (`mechweed watch`): a `ViewSource` fed by the
//! robot's flows on the bus instead of the protected objects. Zenoh's callbacks only
//! hand each message to a channel; the pacer's look reads the newest status and tick
//! from it. Requests go out as bus queries without waiting: HALT always, power up and
//! modes only where the robot takes them from the bus (`[bus] accept_requests =
//! operator`, asked of the robot every few seconds).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Sender, bounded};
use serde_json::{Value, json};
use zenoh::{Session, Wait};

use crate::bus::asked_as;
use crate::bus::hearing::{Ear, Hearing};

use super::remote_view::{fill_from_status, fill_from_tick};
use super::requests::NO_ANSWER;
use super::view::{RemoteLink, View, ViewSource};
use crate::record::received::parse_tick;
use crate::state::modes::{Mode, Request};
use crate::state::request_channel::Answer;

/// Messages waiting for the next look; beyond, the oldest are not needed (only the
/// newest status and tick are drawn) and new ones are dropped.
const QUEUE: usize = 256;
/// Bad messages are counted; the first few are also said.
const SAY_BAD: u64 = 5;
/// How often the robot is asked whether it takes operator requests from the bus.
const ASK_OPERATOR_EVERY: Duration = Duration::from_secs(5);
const ANSWER_WAIT: Duration = Duration::from_secs(3);

/// The flows the view reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    Status,
    Tick,
}

type Said = (Request, Result<(), String>);

pub struct RemoteView {
    robot: String,
    endpoint: String,
    /// This program's identity on a secured bus: it asks under ROBOT/as/NAME, which
    /// the robot counts by its certificate (no other identity's flood is counted with it).
    name: Option<String>,
    /// None: fed by hand (`feed`), as the tests do.
    hearing: Option<Hearing<Flow>>,
    arrived: Receiver<(Flow, Vec<u8>, Instant)>,
    arrive: Sender<(Flow, Vec<u8>, Instant)>,
    /// What the robot said of `[bus] accept_requests`: `UNKNOWN` until it answers.
    operator: Arc<AtomicU8>,
    answers: Receiver<Said>,
    answer: Sender<Said>,
    /// The request payloads a view fed by hand would have sent.
    pub sent: parking_lot::Mutex<Vec<String>>,
    view: View,
    status_at: Option<Instant>,
    /// When the view began waiting for the robot.
    opened: Instant,
    quit: Arc<AtomicBool>,
}

/// The robot's answer about operator requests over the bus, kept in an atomic.
const UNKNOWN: u8 = 0;
const HALT_ONLY: u8 = 1;
const OPERATOR: u8 = 2;

fn operator_of(value: u8) -> Option<bool> {
    match value {
        HALT_ONLY => Some(false),
        OPERATOR => Some(true),
        _ => None,
    }
}

impl Drop for RemoteView {
    fn drop(&mut self) {
        self.quit.store(true, Ordering::Relaxed);
    }
}

impl RemoteView {
    /// A view fed by hand (`feed`), with no network: for tests.
    pub fn offline(robot: &str, endpoint: &str) -> RemoteView {
        let (arrive, arrived) = bounded(QUEUE);
        let (answer, answers) = bounded(QUEUE);
        let view = View {
            bus_endpoints: format!("watching over the bus, connected to {endpoint}"),
            remote: Some(RemoteLink {
                robot: robot.to_string(),
                endpoint: endpoint.to_string(),
                unknown_after_s: crate::config::Settings::shipped().gui.remote_stale_s,
                ..RemoteLink::default()
            }),
            ..View::default()
        };
        RemoteView {
            robot: robot.to_string(),
            endpoint: endpoint.to_string(),
            name: None,
            hearing: None,
            arrived,
            arrive,
            operator: Arc::new(AtomicU8::new(UNKNOWN)),
            answers,
            answer,
            sent: parking_lot::Mutex::default(),
            view,
            status_at: None,
            opened: Instant::now(),
            quit: Arc::default(),
        }
    }

    /// Watch robot `robot` at `endpoint` (it may start later: the session waits), as
    /// the identity `tls` names on a secured bus.
    pub fn connect(
        endpoint: &str,
        robot: &str,
        tls: Option<&crate::config::TlsFiles>,
    ) -> Result<RemoteView, String> {
        let mut remote = RemoteView::offline(robot, endpoint);
        remote.name = tls.map(crate::config::TlsFiles::name);
        let hearing = Hearing::start(Ear {
            endpoint: endpoint.to_string(),
            robot: robot.to_string(),
            tls: tls.cloned(),
            token: format!("alive/watch-{}", std::process::id()),
            flows: vec![(Flow::Status, "status"), (Flow::Tick, "tick")],
            program: "watch",
            queue: QUEUE,
        })?;
        remote.arrived = hearing.rx.clone();
        let (sessions, operator, quit) = (
            hearing.sessions(),
            remote.operator.clone(),
            remote.quit.clone(),
        );
        let key = asked_as::key(robot, remote.name.as_deref(), "config/bus/accept_requests");
        std::thread::Builder::new()
            .name("watch-operator".into())
            .spawn(move || {
                while !quit.load(Ordering::Relaxed) {
                    if let Some(taken) = accepts_operator(&sessions.lock().clone(), &key) {
                        let value = if taken { OPERATOR } else { HALT_ONLY };
                        operator.store(value, Ordering::Relaxed);
                    }
                    std::thread::sleep(ASK_OPERATOR_EVERY);
                }
            })
            .map_err(|e| format!("cannot start a thread: {e}"))?;
        remote.hearing = Some(hearing);
        Ok(remote)
    }

    /// Hand a message of `flow` over, as zenoh's callback does.
    pub fn feed(&self, flow: Flow, bytes: &[u8], at: Instant) {
        let _ = self.arrive.try_send((flow, bytes.to_vec(), at));
    }

    /// As if the robot had answered `request` so, as the query's callback hands it over.
    pub fn answer_by_hand(&self, request: Request, said: Result<(), String>) {
        let _ = self.answer.try_send((request, said));
    }

    /// As if the robot took (true) or refused (false) operator requests from the bus.
    pub fn set_operator(&self, taken: bool) {
        let value = if taken { OPERATOR } else { HALT_ONLY };
        self.operator.store(value, Ordering::Relaxed);
    }

    /// With no status for `seconds` the robot's mode is shown as unknown ([gui]
    /// remote_stale_s).
    pub(crate) fn unknown_after(mut self, seconds: f64) -> RemoteView {
        if let Some(link) = &mut self.view.remote {
            link.unknown_after_s = seconds;
        }
        self
    }

    /// As if the view had been opened `ago` before now (tests of a long wait).
    pub fn opened_ago(mut self, ago: std::time::Duration) -> RemoteView {
        self.opened = Instant::now() - ago;
        self
    }

    /// The view at `now`: every message that arrived, the newest last.
    pub fn view_at(&mut self, now: Instant) -> View {
        while let Ok((flow, bytes, at)) = self.arrived.try_recv() {
            let read = match flow {
                Flow::Status => serde_json::from_slice::<Value>(&bytes)
                    .map_err(|e| format!("not JSON ({e})"))
                    .and_then(|json| self.take_status(&json, at)),
                // Checked as the off-board recorder checks it: every column of a record.
                Flow::Tick => parse_tick(&bytes).map(|tick| {
                    let json = serde_json::from_str(&tick.json).unwrap_or_default();
                    fill_from_tick(&mut self.view, &json);
                    self.view.remote.get_or_insert_default().inputs_seen = true;
                }),
            };
            if let Err(why) = read {
                if let Some(hearing) = &self.hearing {
                    hearing.unreadable();
                }
                let link = self.view.remote.get_or_insert_default();
                link.refused += 1;
                if link.refused <= SAY_BAD {
                    eprintln!("watch: a {flow:?} message of {} refused: {why}", self.robot);
                }
            }
        }
        let age_s = self
            .status_at
            .map(|at| now.saturating_duration_since(at).as_secs_f64());
        let mut view = self.view.clone();
        // The robot's clock, running on since its newest status.
        view.now_s = view.status.t_s + age_s.unwrap_or(0.0);
        if let Some(link) = &mut view.remote {
            link.age_s = age_s;
            link.waited_s = now.saturating_duration_since(self.opened).as_secs_f64();
            link.operator = operator_of(self.operator.load(Ordering::Relaxed));
            if let Some(hearing) = &self.hearing {
                link.wrong_key = hearing.counts.wrong_key.load(Ordering::Relaxed);
                link.reopened = hearing.counts.reopened.load(Ordering::Relaxed);
            }
        }
        view
    }

    fn take_status(&mut self, json: &Value, at: Instant) -> Result<(), String> {
        if self.status_at.is_some_and(|seen| at < seen) {
            return Ok(()); // an older one, overtaken
        }
        fill_from_status(&mut self.view, json)?;
        self.status_at = Some(at);
        if let Some(link) = &mut self.view.remote {
            link.fault = json["fault"].as_str().map(str::to_string);
            link.notice = json["notice"].as_str().map(str::to_string);
            // A robot of before these fields has none: nothing more is said then.
            link.fault_check = json["fault_check"].as_str().map(str::to_string);
            link.fault_came_back_after_s = json["fault_came_back_after_s"].as_f64();
        }
        Ok(())
    }
}

/// A request on its way. Zenoh lets go of a query's callback when the query is over: one
/// that no answer reached (nothing answered within the wait, or no robot was there to
/// ask) is then said as no answer, never as a refusal and never as nothing.
struct Unanswered {
    to: Sender<Said>,
    request: Request,
    answered: AtomicBool,
}

impl Drop for Unanswered {
    fn drop(&mut self) {
        if !self.answered.load(Ordering::Relaxed) {
            let _ = self.to.try_send((self.request, Err(NO_ANSWER.to_string())));
        }
    }
}

/// Whether the robot takes operator requests from the bus; None: no answer.
fn accepts_operator(session: &Session, key: &str) -> Option<bool> {
    let replies = session.get(key).timeout(ANSWER_WAIT).wait().ok()?;
    let reply = replies.recv().ok()?;
    let sample = reply.result().ok()?;
    let json: Value = serde_json::from_slice(&sample.payload().to_bytes()).ok()?;
    Some(json["value"].as_str()? == "operator")
}

/// The robot's answer to a request, in its words; an answer that says neither yes nor
/// why not is no answer (`NO_ANSWER`), never "refused".
fn answer_of(body: &[u8], ok: bool) -> Result<(), String> {
    let json: Value = serde_json::from_slice(body).unwrap_or_default();
    let why = |key: &str| {
        json[key]
            .as_str()
            .map_or(NO_ANSWER.to_string(), str::to_string)
    };
    match (ok, json["accepted"].as_bool()) {
        (true, Some(true)) => Ok(()),
        (true, Some(false)) => Err(why("reason")),
        (true, None) => Err(NO_ANSWER.to_string()),
        (false, _) => Err(why("error")),
    }
}

impl ViewSource for RemoteView {
    fn view(&mut self) -> View {
        self.view_at(Instant::now())
    }

    fn send(
        &self,
        request: Request,
        _reply: &crossbeam_channel::Sender<Answer>,
    ) -> Result<(), String> {
        let operator = operator_of(self.operator.load(Ordering::Relaxed));
        let payload = match request {
            Request::Mode(Mode::Halt) => json!({"request": "halt"}),
            _ if operator.is_none() => {
                return Err(
                    "the robot has not yet said whether it takes requests from the bus: only HALT until it does".into(),
                );
            }
            _ if operator == Some(false) => {
                return Err(
                    "the robot takes only HALT from the bus ([bus] accept_requests = halt)".into(),
                );
            }
            Request::PowerUp => json!({"request": "power_up"}),
            Request::Mode(mode) => json!({"request": "mode", "mode": mode.name()}),
            _ => {
                return Err(
                    "from another computer only HALT, power up and modes (a gain: mechweed bus set)"
                        .into(),
                );
            }
        };
        let Some(session) = self.hearing.as_ref().map(Hearing::session) else {
            // Fed by hand: nothing to send it to; the tests read what would have gone.
            self.sent.lock().push(payload.to_string());
            return Ok(());
        };
        let answer = Unanswered {
            to: self.answer.clone(),
            request,
            answered: AtomicBool::new(false),
        };
        // HALT on the key every identity that may stop the robot may ask; the others on
        // the operator's own (bus/acl.rs).
        let rest = match request {
            Request::Mode(Mode::Halt) => "request",
            _ => "request/operator",
        };
        let key = asked_as::key(&self.robot, self.name.as_deref(), rest);
        session
            .get(key)
            .attachment(session.zid().to_string())
            .payload(payload.to_string())
            .timeout(ANSWER_WAIT)
            .callback(move |reply| {
                let said = match reply.result() {
                    Ok(sample) => answer_of(&sample.payload().to_bytes(), true),
                    Err(error) => answer_of(&error.payload().to_bytes(), false),
                };
                answer.answered.store(true, Ordering::Relaxed);
                let _ = answer.to.try_send((request, said));
            })
            .wait()
            .map_err(|e| format!("cannot ask {} at {}: {e}", self.robot, self.endpoint))
    }

    fn ping_link(&self) {}

    fn answers_in_words(&self) -> Vec<(Request, Result<(), String>)> {
        self.answers.try_iter().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_answer_that_says_neither_yes_nor_why_not_is_no_answer_not_a_refusal() {
        assert_eq!(answer_of(br#"{"accepted": true}"#, true), Ok(()));
        let refused = answer_of(
            br#"{"accepted": false, "reason": "a fault is latched"}"#,
            true,
        );
        assert_eq!(refused, Err("a fault is latched".to_string()));
        // Before: each of these read "refused".
        for (body, ok) in [
            (&b"garbage"[..], true),
            (&b"{}"[..], true),
            (&b""[..], false),
        ] {
            assert_eq!(answer_of(body, ok), Err(NO_ANSWER.to_string()), "{body:?}");
        }
        assert_eq!(
            answer_of(br#"{"error": "not allowed"}"#, false),
            Err("not allowed".to_string())
        );
    }
}
