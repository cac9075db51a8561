//! The bus thread (normal priority): publishes the robot's status about ten times a
//! second, every Nth tick and every event, and answers requests and configuration
//! ports. It reads the protected objects and the tick queue the supervisor fills with
//! `try_send` (record::flow), so the supervisor never waits for it; its publishers drop
//! rather than queue when the network is slow, so a receiver on a slow link gets the
//! latest status, not a growing backlog.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde_json::json;
use zenoh::bytes::Encoding;
use zenoh::pubsub::Publisher;
use zenoh::qos::CongestionControl;
use zenoh::query::Query;
use zenoh::{Session, Wait};

use super::identities::{Identities, LinkChange};
use super::inbox::{Inbox, requester};
use super::payload::status_json;
use super::peers::Peers;
use super::queries::{Port, Queries};
use super::refusals::{PerRequester, RateLimit, Refusals};
use super::rows::RowCounts;
use super::{BusFigures, BusState};
use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerSettings};
use crate::record::{TickFlow, tick_json};
use crate::rt::LoopSummary;
use crate::state::cross_track::CrossTrackMeaning;
use crate::state::modes::Gains;
use crate::state::request_channel::SupervisorHandle;
use crate::state::status::Status;
use crate::state::{Reader, Writer};
use crate::steer::SteerCommand;

/// How often ROBOT/status goes out: ten a second is what a person reads.
const STATUS_PERIOD: Duration = Duration::from_millis(100);
/// How often the bus thread fetches ticks and events from its queue.
const DRAIN_PERIOD: Duration = Duration::from_millis(20);
/// Requests other than HALT taken a second from each program, and settings asked a
/// second: more are refused at once, so that nobody's flood keeps the supervisor busy.
const REQUESTS_PER_S: f64 = 5.0;
const SETTINGS_PER_S: f64 = 20.0;
/// All programs together: a flood that names a new requester on every query still
/// finds the door shut.
const ALL_PER_S: f64 = 20.0;

pub struct BusWires {
    pub status: Reader<Status>,
    pub link: Reader<LinkStatus>,
    pub steer: Reader<SteerCommand>,
    pub loops: [Reader<LoopSummary>; 2],
    pub flow: TickFlow,
    pub supervisor: SupervisorHandle,
    /// The gains and steering law in force (a set changes one value of them).
    pub tuning: Reader<(Gains, SteerSettings)>,
    pub figures: Writer<BusFigures>,
    pub rows: Arc<RowCounts>,
    pub stop: Arc<AtomicBool>,
}

/// Declare the flows on `session` and serve them until `stop`; returns the last figures.
pub fn run(session: Session, settings: &Settings, w: BusWires) -> zenoh::Result<BusFigures> {
    let bus = &settings.bus;
    let publisher = |what: &str| {
        session
            .declare_publisher(bus.key(what))
            .congestion_control(CongestionControl::Drop)
            .encoding(Encoding::APPLICATION_JSON)
            .wait()
    };
    let (status_pub, tick_pub, event_pub) = (
        publisher("status")?,
        publisher("tick")?,
        publisher("event")?,
    );
    let inbox = Inbox::declare(&session, bus)?;
    let mut gate = Gate::new();
    let own_token = bus.key("alive/controller");
    let _alive = session.liveliness().declare_token(&own_token).wait()?;
    let mut peers = Peers::watch(&session, &bus.key("alive/**"))?;
    let mut answers = Queries::new(settings, w.supervisor.clone(), w.tuning.clone());
    let mut figures = BusFigures {
        state: BusState::Running,
        security: crate::gamepad::Label::new(&super::security_line(bus)),
        ..BusFigures::default()
    };
    // The roster was read when the session opened: it is there.
    let mut identities = (bus.tls.as_ref())
        .and_then(|tls| crate::bus::keys::Roster::read(&tls.roster()).ok())
        .map(|roster| Watched::new(Identities::new(roster)));
    let (link_changes, _links) = super::identities::watch_links(&session)?;
    let mut json = String::with_capacity(4096);
    let mut next_status = Instant::now();
    while !w.stop.load(Ordering::Relaxed) {
        let wait = next_status
            .saturating_duration_since(Instant::now())
            .min(DRAIN_PERIOD);
        // Queries wake the thread; ticks and events are fetched on its own beat, so the
        // supervisor's try_send never has a sleeping reader to wake (a system call in
        // its tick).
        if let Some((port, query, halt)) = inbox.next(wait) {
            let ids = identities.as_ref().map(|watched| &watched.ids);
            gate.serve(&query, (port, halt), &mut answers, &mut figures, ids);
        }
        gate.say_refusals();
        publish_flows(&w, (&tick_pub, &event_pub), &mut json, &mut figures);
        let now = Instant::now();
        if now < next_status {
            continue;
        }
        // After a long answer (a request waits for the supervisor), one status now, not
        // a burst of the ones missed.
        next_status += STATUS_PERIOD;
        if next_status < now {
            next_status = now + STATUS_PERIOD;
        }
        if status_pub
            .put(status_message(&w, settings, &figures).to_string())
            .wait()
            .is_ok()
        {
            figures.status_published += 1;
        }
        say_dropped(&w, &event_pub, &mut figures);
        figures.peers = peers.others(&own_token);
        figures.status_receivers = status_pub
            .matching_status()
            .wait()
            .is_ok_and(|m| m.matching());
        figures.rows_received = w.rows.received.load(Ordering::Relaxed);
        figures.rows_rejected = w.rows.rejected.load(Ordering::Relaxed);
        figures.queries_dropped = inbox.dropped();
        if let Some(watched) = &mut identities {
            watched.follow(link_changes.try_iter(), &w.rows, &mut figures);
        }
        w.figures.publish(&figures);
    }
    figures.state = BusState::Closed;
    w.figures.publish(&figures);
    Ok(figures)
}

/// The limits on requests and settings, and the refusals said about once a second.
struct Gate {
    request_limit: PerRequester,
    setting_limit: PerRequester,
    all_limit: RateLimit,
    refusals: Refusals,
}

impl Gate {
    fn new() -> Gate {
        Gate {
            request_limit: PerRequester::new(REQUESTS_PER_S),
            setting_limit: PerRequester::new(SETTINGS_PER_S),
            all_limit: RateLimit::new(ALL_PER_S, Instant::now()),
            refusals: Refusals::default(),
        }
    }

    /// Answer one query, or refuse it when its program (or all of them) asked too often;
    /// HALT always goes through. A refusal is said with who asked, where the bus tells it.
    fn serve(
        &mut self,
        query: &Query,
        (port, halt): (Port, bool),
        answers: &mut Queries,
        figures: &mut BusFigures,
        identities: Option<&Identities>,
    ) {
        let now = Instant::now();
        let limit = match port {
            Port::Get | Port::Set => &mut self.setting_limit,
            _ => &mut self.request_limit,
        };
        let asker = requester(query);
        let refused = if halt || (limit.take(&asker, now) && self.all_limit.take(now)) {
            answers.serve(query, port, figures)
        } else {
            let why = format!(
                "too many requests: the bus takes {REQUESTS_PER_S} requests and {SETTINGS_PER_S} settings a second from each program, {ALL_PER_S} from all, at most (HALT always)"
            );
            Queries::refuse(query, &why, figures);
            Some(format!("{}: {why}", query.key_expr()))
        };
        let who = identities
            .and_then(|ids| ids.name_of(&asker))
            .map_or(String::new(), |name| format!(" (asked by {name})"));
        let refused = refused.map(|why| format!("{why}{who}"));
        if let Some(line) = refused.and_then(|why| self.refusals.refused(why, now)) {
            tracing::warn!("{line}");
        }
    }

    /// The refusals counted since they were last said, when it is time to say them.
    fn say_refusals(&mut self) {
        if let Some(line) = self.refusals.due(Instant::now()) {
            tracing::warn!("{line}");
        }
    }
}

/// Every tick and event waiting in the supervisor's queue, published.
fn publish_flows(
    w: &BusWires,
    (tick_pub, event_pub): (&Publisher<'_>, &Publisher<'_>),
    json: &mut String,
    figures: &mut BusFigures,
) {
    while let Ok(tick) = w.flow.ticks.try_recv() {
        tick_json(&tick, json);
        if tick_pub.put(json.as_bytes()).wait().is_ok() {
            figures.ticks_published += 1;
        }
    }
    while let Ok(event) = w.flow.events.try_recv() {
        if event_pub.put(event.to_json().to_string()).wait().is_ok() {
            figures.events_published += 1;
        }
    }
}

/// ROBOT/status: the supervisor's status with the link's, the steering's and the
/// loops', what cross-track means, and whether this bus is secured and who came.
fn status_message(w: &BusWires, settings: &Settings, figures: &BusFigures) -> serde_json::Value {
    let loops = [w.loops[0].snapshot(), w.loops[1].snapshot()];
    let mut status = status_json(
        &w.status.snapshot(),
        &w.link.snapshot(),
        &w.steer.snapshot(),
        &loops,
    );
    // One rule for what cross-track means, on the bus as everywhere.
    status["cross_track"] = json!(CrossTrackMeaning::of(settings).word());
    status["bus"] = json!({
        "secured": settings.bus.tls.is_some(),
        "security": figures.security.as_str(),
        "identities": figures.identities.as_str(),
    });
    status
}

/// Ticks the bus thread fell behind on, said on the event flow too, as the record says
/// its own gaps.
fn say_dropped(w: &BusWires, event_pub: &Publisher<'_>, figures: &mut BusFigures) {
    let (ticks_dropped, events_dropped) = w.flow.dropped();
    if ticks_dropped > figures.ticks_dropped {
        let now = w.status.snapshot();
        let event = json!({
            "t_s": now.t_s,
            "tick": now.tick,
            "kind": "dropped",
            "text": format!(
                "{} ticks not published: the bus thread fell behind",
                ticks_dropped - figures.ticks_dropped
            ),
        });
        if event_pub.put(event.to_string()).wait().is_ok() {
            figures.events_published += 1;
        }
    }
    (figures.ticks_dropped, figures.events_dropped) = (ticks_dropped, events_dropped);
}

/// Who is linked, by the cluster's roster: said when one has no rights, and when two
/// programs send camera rows (the rows of neither are taken then).
struct Watched {
    ids: Identities,
    rivals_said: bool,
}

impl Watched {
    fn new(ids: Identities) -> Watched {
        Watched {
            ids,
            rivals_said: false,
        }
    }

    fn follow(
        &mut self,
        changes: impl IntoIterator<Item = LinkChange>,
        rows: &RowCounts,
        figures: &mut BusFigures,
    ) {
        let look = self.ids.take(changes);
        for name in &look.newly_refused {
            tracing::warn!(
                "bus: {name} linked with a certificate of this authority, but the roster gives it no rights (revoked, or never in it): it may do nothing"
            );
        }
        let rivals = !look.rival_cameras.is_empty();
        if rivals && !self.rivals_said {
            tracing::warn!(
                "bus: two programs send camera rows: {}; the rows of neither are taken",
                look.rival_cameras.join(" and ")
            );
        }
        self.rivals_said = rivals;
        rows.rivals.store(rivals, Ordering::Relaxed);
        figures.identities = crate::gamepad::Label::new(&self.ids.summary());
    }
}
