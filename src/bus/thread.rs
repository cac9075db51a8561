//! The bus thread (normal priority): publishes the robot's status about ten times a
//! second, every Nth tick and every event, and answers requests and configuration
//! ports. It reads the protected objects and the tick queue the supervisor fills with
//! `try_send` (record::flow), so the supervisor never waits for it; its publishers drop
//! rather than queue when the network is slow, so a receiver on a slow link gets the
//! latest status, not a growing backlog.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{bounded, select};
use serde_json::json;
use zenoh::bytes::Encoding;
use zenoh::qos::CongestionControl;
use zenoh::query::Query;
use zenoh::{Session, Wait};

use super::payload::status_json;
use super::peers::Peers;
use super::queries::Queries;
use super::rows::RowCounts;
use super::{BusFigures, BusState};
use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerSettings};
use crate::modes::Gains;
use crate::record::{TickFlow, tick_json};
use crate::request_channel::SupervisorHandle;
use crate::rt::LoopSummary;
use crate::state::{Reader, Writer};
use crate::status::Status;
use crate::steer::SteerCommand;

/// How often ROBOT/status goes out: ten a second is what a person reads.
const STATUS_PERIOD: Duration = Duration::from_millis(100);
/// How often the bus thread fetches ticks and events from its queue.
const DRAIN_PERIOD: Duration = Duration::from_millis(20);
/// Queries waiting for the bus thread; more are dropped (the asker times out).
const QUEUE_QUERIES: usize = 16;

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
    // Requests and settings wait in queues of their own, requests served first: a
    // flood of settings never delays a HALT. A full queue drops the query (its asker
    // hears nothing and times out) and counts it.
    let dropped = Arc::new(AtomicU64::new(0));
    let queue = |key: String| -> zenoh::Result<_> {
        let (tx, rx) = bounded::<Query>(QUEUE_QUERIES);
        let dropped = Arc::clone(&dropped);
        let queryable = session
            .declare_queryable(key)
            .callback(move |q| {
                if tx.try_send(q).is_err() {
                    dropped.fetch_add(1, Ordering::Relaxed);
                }
            })
            .wait()?;
        Ok((queryable, rx))
    };
    let (_requests, requests) = queue(bus.key("request"))?;
    let (_config, configs) = queue(bus.key("config/**"))?;
    let own_token = bus.key("alive/controller");
    let _alive = session.liveliness().declare_token(&own_token).wait()?;
    let mut peers = Peers::watch(&session, &bus.key("alive/**"))?;
    let config_prefix = bus.key("config/");
    let mut answers = Queries::new(settings, w.supervisor, w.tuning);
    let mut figures = BusFigures {
        state: BusState::Running,
        ..BusFigures::default()
    };
    let mut json = String::with_capacity(4096);
    let mut next_status = Instant::now();
    while !w.stop.load(Ordering::Relaxed) {
        let wait = next_status
            .saturating_duration_since(Instant::now())
            .min(DRAIN_PERIOD);
        // Queries wake the thread; ticks and events are fetched on its own beat, so the
        // supervisor's try_send never has a sleeping reader to wake (a system call in
        // its tick).
        let next = match requests.try_recv() {
            Ok(query) => Some((true, query)),
            Err(_) => select! {
                recv(requests) -> q => q.ok().map(|q| (true, q)),
                recv(configs) -> q => q.ok().map(|q| (false, q)),
                default(wait) => None,
            },
        };
        if let Some((is_request, query)) = next {
            answers.serve(&query, is_request, &config_prefix, &mut figures);
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
            let status = status_json(
                &w.status.snapshot(),
                &w.link.snapshot(),
                &w.steer.snapshot(),
                &loops,
            );
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
            figures.queries_dropped = dropped.load(Ordering::Relaxed);
            w.figures.publish(&figures);
        }
    }
    figures.state = BusState::Closed;
    w.figures.publish(&figures);
    Ok(figures)
}
