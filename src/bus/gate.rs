//! The controller's door for what other programs ask: each query from the bus process
//! is taken only within its asker's rate and everyone's together (HALT always), then
//! answered by queries.rs with the supervisor's rules. The bus process only sorted the
//! queries; whether one is a HALT is read again here from its own payload, so that a bus
//! process that says otherwise gains nothing.

use std::time::Instant;

use super::BusFigures;
use super::gateway::QueryIn;
use super::payload::parse_request;
use super::queries::{Answer, Port, Queries};
use super::refusals::{PerRequester, RateLimit, Refusals};
use crate::state::modes::{Mode, Request};

/// Requests other than HALT taken a second from each program, and settings asked a
/// second: more are refused at once, so that nobody's flood keeps the supervisor busy.
const REQUESTS_PER_S: f64 = 5.0;
const SETTINGS_PER_S: f64 = 20.0;
/// All programs together: a flood that names a new requester on every query still
/// finds the door shut.
const ALL_PER_S: f64 = 20.0;

/// The limits on requests and settings, and the refusals said about once a second.
pub(crate) struct Gate {
    request_limit: PerRequester,
    setting_limit: PerRequester,
    all_limit: RateLimit,
    refusals: Refusals,
}

impl Gate {
    pub fn new() -> Gate {
        Gate {
            request_limit: PerRequester::new(REQUESTS_PER_S),
            setting_limit: PerRequester::new(SETTINGS_PER_S),
            all_limit: RateLimit::new(ALL_PER_S, Instant::now()),
            refusals: Refusals::default(),
        }
    }

    /// Answer one query, or refuse it when its program (or all of them) asked too often;
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
        let limit = match q.port {
            Port::Get | Port::Set => &mut self.setting_limit,
            _ => &mut self.request_limit,
        };
        let answer = if halt || (limit.take(&q.asker, now) && self.all_limit.take(now)) {
            let asker = q.asker_name.as_deref();
            answers.answer(&q.key, q.payload.as_deref(), q.port, asker)
        } else {
            Queries::refused(format!(
                "too many requests: the bus takes {REQUESTS_PER_S} requests and {SETTINGS_PER_S} settings a second from each program, {ALL_PER_S} from all, at most (HALT always)"
            ))
        };
        let who =
            (q.asker_name.as_ref()).map_or(String::new(), |name| format!(" (asked by {name})"));
        let refused = Queries::count(&answer, figures).map(|why| format!("{}: {why}{who}", q.key));
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
