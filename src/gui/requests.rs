//! The GUI's side of the conversation with the supervisor. Nothing in a frame waits:
//! panels only queue what the operator asked for; at the end of the pass `post` sends
//! it without waiting, and at the start of the next pass `take_answers` reads the
//! answers that have come back on the GUI's own bounded channel. The last of them is
//! the feedback line under the header ("halted", a refusal in the supervisor's words,
//! ...). A request that cannot even be queued is said at once.

use std::collections::VecDeque;

use crossbeam_channel::{Receiver, Sender, bounded};

use super::view::ViewSource;
use crate::state::modes::{Mode, Request};
use crate::state::request_channel::Answer;

/// Answers the GUI can hold between two passes. The supervisor never waits to answer
/// (a full channel loses the answer), and the GUI reads them every pass, every 50 ms at
/// least while one is awaited, while the supervisor takes at most a queue's worth (16)
/// each tick.
const ANSWER_PLACES: usize = 64;

/// What a view says of an answer that came but said neither yes nor why not (an
/// error with no words, a body it cannot read); shown as no answer, never a refusal.
pub const NO_ANSWER: &str = "no answer";
/// The supervisor answers within a tick; this long without an answer, it has stopped
/// (the console's blocking request waits as long), s.
pub(crate) const ANSWER_WAIT_S: f64 = 1.0;

/// The supervisor's last answer to something the operator did, shown in the header.
#[derive(Debug, Clone, PartialEq)]
pub struct Feedback {
    pub text: String,
    pub refused: bool,
    /// When the operator asked, s on the controller's clock.
    pub at_s: f64,
}

/// Which request: to know whether its answer has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AskId(u64);

struct Ask {
    id: AskId,
    request: Request,
    /// Said when the supervisor takes it (None: nothing, as for the test outputs).
    done: Option<String>,
    /// When it was sent, s.
    at_s: f64,
}

pub struct Requests {
    reply: Sender<Answer>,
    answers: Receiver<Answer>,
    /// Asked for in this pass, sent by `post`.
    queued: Vec<Ask>,
    ping: bool,
    /// Sent, the answer not yet here; oldest first.
    pending: VecDeque<Ask>,
    next_id: u64,
    feedback: Option<Feedback>,
    /// The time of the last `post`, s: when a late answer's ask is no longer known.
    last_post_s: f64,
}

impl Default for Requests {
    fn default() -> Self {
        let (reply, answers) = bounded(ANSWER_PLACES);
        Requests {
            reply,
            answers,
            queued: Vec::new(),
            ping: false,
            pending: VecDeque::new(),
            next_id: 0,
            feedback: None,
            last_post_s: 0.0,
        }
    }
}

/// The words for a request that nothing answered, or whose answer could not be read:
/// not a refusal. A HALT may well have been taken (the robot's status says).
pub fn no_answer_text(request: &Request) -> String {
    match request {
        Request::Mode(Mode::Halt) => {
            "HALT: no answer (the robot may have halted: look at its status)".to_string()
        }
        _ => "no answer (the robot may have taken it: look at its status)".to_string(),
    }
}

/// The words for a refusal (or a request that could not be sent) of `request`.
fn refused_text(request: &Request, why: &str) -> String {
    match request {
        Request::TestOutputs(_) => format!("test outputs refused: {why}"),
        Request::TestHold(_) => format!("hold to run refused: {why}"),
        Request::TestStep(step) => format!("{} step refused: {why}", step.name()),
        _ => format!("refused: {why}"),
    }
}

impl Requests {
    /// Ask the supervisor for `request`; `done` is said when it is taken.
    pub fn ask(&mut self, request: Request, done: &str) -> AskId {
        self.queue(request, Some(done.to_string()))
    }

    /// Ask, and say nothing when it is taken (only a refusal): the test panel's stream
    /// of outputs.
    pub(crate) fn ask_quietly(&mut self, request: Request) -> AskId {
        self.queue(request, None)
    }

    fn queue(&mut self, request: Request, done: Option<String>) -> AskId {
        let id = AskId(self.next_id);
        self.next_id += 1;
        self.queued.push(Ask {
            id,
            request,
            done,
            at_s: f64::NAN,
        });
        id
    }

    /// Ask the camera link for a round trip.
    pub fn ping_link(&mut self) {
        self.ping = true;
    }

    /// Say something in the feedback line now (what the GUI itself knows: a save, a
    /// value out of range, ...).
    pub fn say(&mut self, text: impl Into<String>, refused: bool, at_s: f64) {
        self.feedback = Some(Feedback {
            text: text.into(),
            refused,
            at_s,
        });
    }

    /// The feedback line: the last answer or message.
    pub fn feedback(&self) -> Option<&Feedback> {
        self.feedback.as_ref()
    }

    /// Some answer has not come yet (the GUI passes until it has).
    pub(crate) fn awaiting(&self) -> bool {
        !self.queued.is_empty() || !self.pending.is_empty()
    }

    /// The request is queued or sent and its answer has not come yet.
    pub fn is_open(&self, id: AskId) -> bool {
        self.queued.iter().chain(&self.pending).any(|a| a.id == id)
    }

    /// End of a pass: send what was asked for, without waiting (a request that cannot
    /// be queued is said at once), and give up on answers overdue by `ANSWER_WAIT_S`.
    pub fn post(&mut self, source: &dyn ViewSource, now_s: f64) {
        self.last_post_s = now_s;
        if std::mem::take(&mut self.ping) {
            source.ping_link();
        }
        for mut ask in std::mem::take(&mut self.queued) {
            ask.at_s = now_s;
            match source.send(ask.request, &self.reply) {
                Ok(()) => self.pending.push_back(ask),
                Err(why) => self.say(refused_text(&ask.request, &why), true, now_s),
            }
        }
        // An answer that came during this pass is not overdue.
        self.take_answers();
        while let Some(ask) = self.pending.front()
            && now_s - ask.at_s > ANSWER_WAIT_S
        {
            let text = no_answer_text(&ask.request);
            let at_s = ask.at_s;
            self.pending.pop_front();
            self.say(text, true, at_s);
        }
    }

    /// Start of a pass: the answers that have come, in order; each one's words become
    /// the feedback line.
    pub fn take_answers(&mut self) {
        while let Ok((request, answer)) = self.answers.try_recv() {
            self.answered(request, answer.map_err(|refusal| refusal.to_string()));
        }
    }

    /// Answers in words (the robot's, over the bus): said as the supervisor's are.
    pub(crate) fn take_answers_in_words(&mut self, answers: Vec<(Request, Result<(), String>)>) {
        for (request, answer) in answers {
            self.answered(request, answer);
        }
    }

    fn answered(&mut self, request: Request, answer: Result<(), String>) {
        // Answers come in the order asked; one may be lost (a full channel), so the
        // oldest open ask of the same request is the one answered.
        let ask = self
            .pending
            .iter()
            .position(|a| a.request == request)
            .and_then(|k| self.pending.remove(k));
        let (done, at_s) = match ask {
            Some(ask) => (ask.done, ask.at_s),
            None => (None, self.last_post_s),
        };
        match (answer, done) {
            (Ok(()), Some(done)) => self.say(done, false, at_s),
            (Ok(()), None) => {}
            (Err(why), _) if why == NO_ANSWER => self.say(no_answer_text(&request), true, at_s),
            (Err(why), _) => self.say(refused_text(&request, &why), true, at_s),
        }
    }

    /// The controller was restarted: what the old one was asked will not be answered.
    pub(crate) fn forget_open(&mut self) {
        self.queued.clear();
        self.pending.clear();
        while self.answers.try_recv().is_ok() {}
    }
}
