//! How other threads talk to the supervisor: requests on one bounded channel, each
//! with the channel its answer goes back on. The supervisor takes every waiting request
//! at the start of its tick and never waits to answer (a full answer channel loses the
//! answer, not a tick).
//!
//! Two ways to ask: `SupervisorHandle::request` waits (at most a second each way) for
//! the answer, for the console and scripts; `SupervisorHandle::send` returns at once and
//! the answer arrives later on the sender's own channel, for the GUI, which must never
//! wait inside a frame.

use std::time::Duration;

use crossbeam_channel::{Receiver, Sender, TrySendError, bounded};

use crate::state::Reader;
use crate::state::modes::{Refusal, Request};
use crate::state::status::Status;

/// The supervisor's answer to one request, with the request it answers.
pub type Answer = (Request, Result<(), Refusal>);

/// A request and where to send the supervisor's answer.
pub struct Envelope {
    pub request: Request,
    pub reply: Sender<Answer>,
    /// Asked by another program over the bus: a person at the robot comes first.
    pub from_bus: bool,
}

/// Requests waiting for the supervisor at most; more is a program that floods it.
pub const QUEUE_PLACES: usize = 16;

/// The supervisor's end: the requests to take, at the start of each tick.
pub type RequestReceiver = Receiver<Envelope>;

/// How other threads (the operator script, the console, the GUI) talk to the supervisor.
#[derive(Clone)]
pub struct SupervisorHandle {
    requests: Sender<Envelope>,
    pub status: Reader<Status>,
}

/// A new request channel: the handle for the askers, the receiver for the supervisor.
pub fn channel(status: Reader<Status>) -> (SupervisorHandle, RequestReceiver) {
    let (requests, receiver) = bounded(QUEUE_PLACES);
    (SupervisorHandle { requests, status }, receiver)
}

impl SupervisorHandle {
    /// Ask, and wait (at most a second) for the answer.
    pub fn request(&self, request: Request) -> Result<(), String> {
        self.ask(request, false)
    }

    /// Ask for another program on the bus, and wait (at most a second) for the answer.
    pub fn request_from_bus(&self, request: Request) -> Result<(), String> {
        self.ask(request, true)
    }

    fn ask(&self, request: Request, from_bus: bool) -> Result<(), String> {
        let (reply, answers) = bounded(1);
        let envelope = Envelope {
            request,
            reply,
            from_bus,
        };
        self.requests
            .send_timeout(envelope, Duration::from_secs(1))
            .map_err(|_| "the supervisor is not taking requests".to_string())?;
        match answers.recv_timeout(Duration::from_secs(1)) {
            Ok((_, answer)) => answer.map_err(|refusal| refusal.to_string()),
            Err(_) => Err("the supervisor did not answer".to_string()),
        }
    }

    /// Ask without waiting: the answer comes later on `reply`. An error says why the
    /// request could not even be queued.
    pub fn send(&self, request: Request, reply: &Sender<Answer>) -> Result<(), String> {
        let envelope = Envelope {
            request,
            reply: reply.clone(),
            from_bus: false,
        };
        self.requests.try_send(envelope).map_err(|e| match e {
            TrySendError::Full(_) => "the supervisor has too many requests waiting".to_string(),
            TrySendError::Disconnected(_) => "the supervisor is not taking requests".to_string(),
        })
    }
}
