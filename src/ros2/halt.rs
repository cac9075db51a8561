//! The HALT service `/NAMESPACE/halt` (std_srvs/srv/Trigger), offered to ROS only with
//! `[ros2] halt_service = yes`: a call asks the robot for HALT on its bus, as
//! `mechweed bus request halt` does, and is answered with the robot's reply. It is
//! the one thing from ROS that reaches the robot, and it can only stop it.
//!
//! In rmw_zenoh's service format: a liveliness token (SS) for `ros2 service list`, and
//! a queryable on the service's key. A call is a query whose payload is the CDR request
//! and whose attachment is the client's (sequence number, time, GID); the reply carries
//! the CDR response and an attachment with the call's sequence number and the client's
//! GID, by which the client matches it to its call.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use zenoh::Wait;
use zenoh::liveliness::LivelinessToken;
use zenoh::query::{Query, Queryable};

use super::cdr::{decode, encode};
use super::msgs::{TriggerRequest, TriggerResponse};
use super::wire::{Node, attachment, read_attachment};

/// Asks the robot for HALT on its bus: the robot's answer, or why there is none.
pub type AskHalt = Arc<dyn Fn() -> Result<String, String> + Send + Sync>;

/// The service while it is offered: calls are answered on a thread of its own, so
/// that a robot slow to answer holds up no Zenoh thread.
pub struct HaltService {
    _token: LivelinessToken,
    _queryable: Queryable<()>,
    stop: Arc<AtomicBool>,
    answering: Option<JoinHandle<()>>,
}

impl HaltService {
    /// Offer the service on the ROS session; each call is answered through `ask`.
    pub fn offer(session: &zenoh::Session, node: &Node, ask: AskHalt) -> Result<Self, String> {
        let z = |e: zenoh::Error| crate::bus::session::plain_words(&e);
        let (tx, rx) = crossbeam_channel::bounded::<Query>(16);
        let queryable = session
            .declare_queryable(node.halt_key())
            .complete(true)
            .callback(move |query| {
                // A burst beyond 16 waiting calls is dropped: each of them asks the
                // same, and the robot is halting already.
                let _ = tx.try_send(query);
            })
            .wait()
            .map_err(z)?;
        let token = session
            .liveliness()
            .declare_token(node.halt_token())
            .wait()
            .map_err(z)?;
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let answering = std::thread::Builder::new()
            .name("ros2-halt".to_string())
            .spawn(move || {
                while !stopped.load(Ordering::Relaxed) {
                    if let Ok(query) = rx.recv_timeout(Duration::from_millis(100)) {
                        answer(&query, &ask);
                    }
                }
            })
            .map_err(|e| format!("cannot start the HALT service's thread: {e}"))?;
        Ok(HaltService {
            _token: token,
            _queryable: queryable,
            stop,
            answering: Some(answering),
        })
    }
}

impl Drop for HaltService {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.answering.take() {
            let _ = thread.join();
        }
    }
}

/// One call: checked, asked of the robot, answered. A call that is not a Trigger
/// request with rmw_zenoh's attachment is refused with why, and the robot not asked.
fn answer(query: &Query, ask: &AskHalt) {
    let call = query
        .attachment()
        .ok_or_else(|| "a call without rmw_zenoh's attachment".to_string())
        .and_then(|a| read_attachment(&a.to_bytes()))
        .and_then(|(sequence, _, gid)| {
            let payload = query.payload().map(|p| p.to_bytes().into_owned());
            decode::<TriggerRequest>(&payload.unwrap_or_default())
                .map(|_| (sequence, gid))
                .map_err(|why| format!("not a std_srvs/srv/Trigger request: {why}"))
        });
    let (sequence, gid) = match call {
        Ok(call) => call,
        Err(why) => {
            eprintln!("ros2: a HALT call refused: {why}");
            let _ = query.reply_err(why).wait();
            return;
        }
    };
    let response = match ask() {
        Ok(said) => TriggerResponse {
            success: true,
            message: said,
        },
        Err(why) => TriggerResponse {
            success: false,
            message: why,
        },
    };
    println!(
        "ros2: HALT asked from ROS: {}",
        if response.success { "done" } else { "not done" }
    );
    let now_ns = (crate::bus::payload::wall_s() * 1e9) as i64;
    let reply = attachment(sequence, now_ns, &gid).to_vec();
    match encode(&response) {
        Ok(bytes) => {
            let _ = query
                .reply(query.key_expr().clone(), bytes)
                .attachment(reply)
                .wait();
        }
        Err(why) => {
            let _ = query.reply_err(why).wait();
        }
    }
}
