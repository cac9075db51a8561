//! Where the robot's queryables put what other programs ask: each kind in a bounded
//! queue of its own, taken in order of importance. HALT first, every one waiting, then
//! requests, then settings changed, then settings read; so no flood of one kind delays
//! another, and a HALT waits at most for the one answer being given. On a secured bus
//! the settings an operator's identity reads under its own name (ROBOT/as/NAME/config,
//! bus/asked_as.rs) wait apart from everyone else's, and a request other than HALT on
//! ROBOT/request (which every role that may stop the robot may ask) waits apart and
//! last: a viewer's flood of either never starves the operator.
//!
//! Zenoh's callbacks only sort and hand each query on; a full queue drops the query (its
//! asker hears nothing and times out) and counts it.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use crossbeam_channel::{Receiver, Sender, bounded};
use zenoh::query::{Query, Queryable};
use zenoh::{Session, Wait};

use super::asked_as;
use super::payload::parse_request;
use super::queries::Port;
use crate::config::BusSettings;
use crate::state::modes::{Mode, Request};

/// Places in each queue: HALTs, requests, settings changed, settings read by an
/// operator's identity, settings read by others, and requests other than HALT on
/// ROBOT/request of a secured bus.
const PLACES: [usize; 6] = [64, 4, 4, 4, 8, 4];

pub(crate) struct Inbox {
    /// In the order they are served.
    queues: [Receiver<(Port, Query)>; 6],
    dropped: Arc<AtomicU64>,
    robot: String,
    _queryables: Vec<Queryable<()>>,
}

impl Inbox {
    /// Declare the robot's queryables on `session`; `operators`: the names of the
    /// roster's operators, on a secured bus.
    pub(crate) fn declare(
        session: &Session,
        bus: &BusSettings,
        operators: Vec<String>,
    ) -> zenoh::Result<Inbox> {
        let (senders, queues): (Vec<Sender<(Port, Query)>>, Vec<_>) =
            PLACES.iter().map(|&n| bounded(n)).unzip();
        let dropped = Arc::new(AtomicU64::new(0));
        let secured = bus.tls.is_some();
        let operators = Arc::new(operators);
        let mut queryables = Vec::new();
        let ports = [
            ("request", Port::Halt),
            ("request/operator", Port::Operator),
            ("set/**", Port::Set),
            ("config/**", Port::Get),
        ];
        let named = ports.map(|(what, port)| (format!("as/*/{what}"), port));
        for (what, port) in ports
            .map(|(what, port)| (what.to_string(), port))
            .into_iter()
            .chain(named)
        {
            let (senders, dropped) = (senders.clone(), Arc::clone(&dropped));
            let operators = Arc::clone(&operators);
            let robot = bus.robot.clone();
            let queryable = session
                .declare_queryable(bus.key(&what))
                .callback(move |q| {
                    let asked_as = || asked_as::split(&robot, q.key_expr().as_str()).1;
                    let queue = match port {
                        // Payloads are small (the session's message limit): telling a
                        // HALT from the rest here keeps the two apart from the start.
                        Port::Halt if is_halt(&q) => 0,
                        Port::Halt if secured => 5,
                        Port::Halt | Port::Operator => 1,
                        Port::Set => 2,
                        Port::Get if asked_as().is_some_and(|n| operators.contains(&n)) => 3,
                        Port::Get => 4,
                    };
                    if senders[queue].try_send((port, q)).is_err() {
                        dropped.fetch_add(1, Ordering::Relaxed);
                    }
                })
                .wait()?;
            queryables.push(queryable);
        }
        let queues: [Receiver<(Port, Query)>; 6] = queues
            .try_into()
            .unwrap_or_else(|_| unreachable!("one receiver per queue"));
        Ok(Inbox {
            queues,
            dropped,
            robot: bus.robot.clone(),
            _queryables: queryables,
        })
    }

    /// The most important query waiting.
    pub fn try_next(&self) -> Option<(Port, Query)> {
        self.queues.iter().find_map(|queue| queue.try_recv().ok())
    }

    /// `query`'s key as the robot answers it, and the name it was asked as.
    pub fn asked_as(&self, query: &Query) -> (String, Option<String>) {
        asked_as::split(&self.robot, query.key_expr().as_str())
    }

    /// The queues, for a wait on them and on something else (gateway/child.rs).
    pub fn queues(&self) -> &[Receiver<(Port, Query)>] {
        &self.queues
    }

    /// Queries dropped because their queue was full.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// Whether a query on ROBOT/request asks for HALT.
fn is_halt(query: &Query) -> bool {
    let payload = query.payload().map(|p| p.to_bytes());
    parse_request(payload.as_deref().unwrap_or_default()) == Ok(Request::Mode(Mode::Halt))
}

/// Who asked `query`: the Zenoh session its attachment names (mechweed's tools name
/// theirs), or "" for one that names none.
pub(crate) fn requester(query: &Query) -> String {
    query
        .attachment()
        .and_then(|a| String::from_utf8(a.to_bytes().into_owned()).ok())
        .filter(|a| a.len() <= 64)
        .unwrap_or_default()
}
