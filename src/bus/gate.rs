//! The controller's door for what other programs ask: each query from the bus process
//! is taken only within its asker's rate and its kind's together (HALT always), then
//! answered by queries.rs with the supervisor's rules. The bus process only sorted the
//! queries; whether one is a HALT is read again here from its own payload, so that a bus
//! process that says otherwise gains nothing.
//!
//! Two allowances that nothing shares: the operator's (requests and settings changed,
//! on keys that only an operator's identity may ask on a secured bus), and everyone
//! else's (settings read, and requests on the HALT key that are not HALT). A recorder or
//! a viewer reading the settings as fast as it can uses up the readers' allowance, never
//! the operator's.
//!
//! Within each, an identity that asks under its own name (ROBOT/as/NAME, which only its
//! certificate may ask on: bus/asked_as.rs) has an allowance of its own, counted by its
//! link's certificate; no other identity's flood can use it, however it names itself.
//! What is asked on the keys that name no one is counted by what the query says, and
//! all of it together within one allowance.

use std::time::Instant;

use super::BusFigures;
use super::gateway::QueryIn;
use super::identities::shown_name;
use super::payload::parse_request;
use super::queries::{Answer, Port, Queries};
use super::refusals::{PerRequester, RateLimit, Refusals};
use crate::state::modes::{Mode, Request};

/// The operator's requests and settings changed, a second from each program and from
/// all of them together.
const OPERATOR_PER_S: f64 = 5.0;
const OPERATOR_ALL_PER_S: f64 = 20.0;
/// Settings read (and requests on the HALT key that are not HALT), a second from each
/// program and from all together: a flood that names a new asker on every query still
/// finds the door shut.
const READS_PER_S: f64 = 20.0;
const READS_ALL_PER_S: f64 = 20.0;
/// Settings read by one identity under its own name, a second.
const NAMED_READS_PER_S: f64 = 10.0;

/// One allowance: per identity by its link; and per asker by what it says, and for
/// all those askers together.
struct Allowance {
    named: PerRequester,
    each: PerRequester,
    all: RateLimit,
}

impl Allowance {
    fn new(named_per_s: f64, each_per_s: f64, all_per_s: f64) -> Allowance {
        Allowance {
            named: PerRequester::new(named_per_s),
            each: PerRequester::new(each_per_s),
            all: RateLimit::new(all_per_s, Instant::now()),
        }
    }

    fn take(&mut self, q: &QueryIn, asker: &str, now: Instant) -> bool {
        if q.from_link {
            self.named.take(asker, now)
        } else {
            self.each.take(asker, now) && self.all.take(now)
        }
    }
}

/// The allowances, and the refusals said about once a second.
pub(crate) struct Gate {
    operator: Allowance,
    reads: Allowance,
    refusals: Refusals,
}

impl Gate {
    pub fn new() -> Gate {
        Gate {
            operator: Allowance::new(OPERATOR_PER_S, OPERATOR_PER_S, OPERATOR_ALL_PER_S),
            reads: Allowance::new(NAMED_READS_PER_S, READS_PER_S, READS_ALL_PER_S),
            refusals: Refusals::default(),
        }
    }

    /// Answer one query, or refuse it when its asker (or its kind) asked too often;
    /// HALT always goes through. A refusal is said with who asked, where the bus tells it.
    pub fn serve(
        &mut self,
        q: &QueryIn,
        answers: &mut Queries,
        figures: &mut BusFigures,
    ) -> Answer {
        let now = Instant::now();
        let halt = q.port == Port::Halt
            && parse_request(q.payload.as_deref().unwrap_or_default())
                == Ok(Request::Mode(Mode::Halt));
        // An identity's name where the roster gives one, else the session it names.
        let asker = q.asker_name.as_deref().unwrap_or(&q.asker);
        let (allowance, kind) = match q.port {
            Port::Operator | Port::Set => (&mut self.operator, "the operator's requests"),
            Port::Get | Port::Halt => (&mut self.reads, "reads"),
        };
        let answer = if halt || allowance.take(q, asker, now) {
            let asker = q.asker_name.as_deref();
            answers.answer(&q.key, q.payload.as_deref(), q.port, asker)
        } else {
            Queries::refused(format!(
                "too many requests ({kind}): the bus takes {OPERATOR_PER_S} requests and settings changed and {NAMED_READS_PER_S} reads a second from each identity asking under its own name, and {OPERATOR_ALL_PER_S} and {READS_ALL_PER_S} from all others together; HALT always"
            ))
        };
        let by_link = if q.from_link {
            ", by its certificate"
        } else {
            ""
        };
        let who = (q.asker_name.as_ref()).map_or(String::new(), |name| {
            format!(" (asked by {}{by_link})", shown_name(name))
        });
        let refused = Queries::count(&answer, figures).map(|why| format!("{}{who}: {why}", q.key));
        if let Some(line) = refused.and_then(|why| self.refusals.refused(why, now)) {
            tracing::warn!("{line}");
        }
        answer
    }

    /// The refusals counted since they were last said, when it is time to say them.
    pub fn say_refusals(&mut self) {
        if let Some(line) = self.refusals.due(Instant::now()) {
            tracing::warn!("{line}");
        }
    }
}
