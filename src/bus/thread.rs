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
use zenoh::qos::CongestionControl;
use zenoh::{Session, Wait};

use super::identities::Identities;
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
    let mut request_limit = PerRequester::new(REQUESTS_PER_S);
    let mut setting_limit = PerRequester::new(SETTINGS_PER_S);
    let mut all_limit = RateLimit::new(ALL_PER_S, Instant::now());
    let mut refusals = Refusals::default();
    let own_token = bus.key("alive/controller");
    let _alive = session.liveliness().declare_token(&own_token).wait()?;
    let mut peers = Peers::watch(&session, &bus.key("alive/**"))?;
    let mut answers = Queries::new(settings, w.supervisor, w.tuning);
    let mut figures = BusFigures {
        state: BusState::Running,
        security: crate::gamepad::Label::new(&super::security_line(bus)),
        ..BusFigures::default()
    };
    // The roster was read when the session opened: it is there.
    let mut identities = bus
        .tls
        .as_ref()
        .and_then(|tls| crate::bus::keys::Roster::read(&tls.roster()).ok())
        .map(Identities::new);
    let (link_changes, _links) = super::identities::watch_links(&session)?;
    let mut rivals_said = false;
    let mut json = String::with_capacity(4096);
    let mut next_status = Instant::now();
    while !w.stop.load(Ordering::Relaxed) {
        let wait = next_status
            .saturating_duration_since(Instant::now())
            .min(DRAIN_PERIOD);
        // Queries wake the thread; ticks and events are fetched on its own beat, so the
        // supervisor's try_send never has a sleeping reader to wake (a system call in
        // its tick).
        let next = inbox.next(wait);
        if let Some((port, query, halt)) = next {
            let now = Instant::now();
            let limit = match port {
                Port::Get | Port::Set => &mut setting_limit,
                _ => &mut request_limit,
            };
            let asker = requester(&query);
            let refused = if halt || (limit.take(&asker, now) && all_limit.take(now)) {
                answers.serve(&query, port, &mut figures)
            } else {
                let why = format!(
                    "too many requests: the bus takes {REQUESTS_PER_S} requests and {SETTINGS_PER_S} settings a second from each program, {ALL_PER_S} from all, at most (HALT always)"
                );
                Queries::refuse(&query, &why, &mut figures);
                Some(format!("{}: {why}", query.key_expr()))
            };
            // Said with who asked, where the bus tells it.
            let who = identities
                .as_ref()
                .and_then(|ids| ids.name_of(&asker))
                .map_or(String::new(), |name| format!(" (asked by {name})"));
            let refused = refused.map(|why| format!("{why}{who}"));
            if let Some(line) = refused.and_then(|why| refusals.refused(why, now)) {
                tracing::warn!("{line}");
            }
        }
        if let Some(line) = refusals.due(Instant::now()) {
            tracing::warn!("{line}");
        }
        while let Ok(tick) = w.flow.ticks.try_recv() {
            tick_json(&tick, &mut json);
            if tick_pub.put(json.as_bytes()).wait().is_ok() {
                figures.ticks_published += 1;
            }
        }
        while let Ok(event) = w.flow.events.try_recv() {
            if event_pub.put(event.to_json().to_string()).wait().is_ok() {
                figures.events_published += 1;
            }
        }
        let now = Instant::now();
        if now >= next_status {
            // After a long answer (a request waits for the supervisor), one status now,
            // not a burst of the ones missed.
            next_status += STATUS_PERIOD;
            if next_status < now {
                next_status = now + STATUS_PERIOD;
            }
            let loops = [w.loops[0].snapshot(), w.loops[1].snapshot()];
            let mut status = status_json(
                &w.status.snapshot(),
                &w.link.snapshot(),
                &w.steer.snapshot(),
                &loops,
            );
            // One rule for what cross-track means, on the bus as everywhere.
            status["cross_track"] = json!(CrossTrackMeaning::of(settings).word());
            // Whoever watches sees whether this bus is secured, and who came.
            status["bus"] = json!({
                "secured": bus.tls.is_some(),
                "security": figures.security.as_str(),
                "identities": figures.identities.as_str(),
            });
            if status_pub.put(status.to_string()).wait().is_ok() {
                figures.status_published += 1;
            }
            let (ticks_dropped, events_dropped) = w.flow.dropped();
            if ticks_dropped > figures.ticks_dropped {
                // Said on the event flow too, as the record says its own gaps.
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
            figures.peers = peers.others(&own_token);
            figures.status_receivers = status_pub
                .matching_status()
                .wait()
                .is_ok_and(|m| m.matching());
            figures.rows_received = w.rows.received.load(Ordering::Relaxed);
            figures.rows_rejected = w.rows.rejected.load(Ordering::Relaxed);
            figures.queries_dropped = inbox.dropped();
            if let Some(ids) = &mut identities {
                let look = ids.take(link_changes.try_iter());
                for name in &look.newly_refused {
                    tracing::warn!(
                        "bus: {name} linked with a certificate of this authority, but the roster gives it no rights (revoked, or never in it): it may do nothing"
                    );
                }
                let rivals = !look.rival_cameras.is_empty();
                if rivals && !rivals_said {
                    tracing::warn!(
                        "bus: two programs send camera rows: {}; the rows of neither are taken",
                        look.rival_cameras.join(" and ")
                    );
                }
                rivals_said = rivals;
                w.rows.rivals.store(rivals, Ordering::Relaxed);
                figures.identities = crate::gamepad::Label::new(&ids.summary());
            }
            w.figures.publish(&figures);
        }
    }
    figures.state = BusState::Closed;
    w.figures.publish(&figures);
    Ok(figures)
}
