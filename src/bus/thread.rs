//! The bus thread (normal priority): publishes the robot's status about ten times a
//! second, every Nth tick and every event, and answers requests and configuration
//! ports. It reads the protected objects and the tick queue the supervisor fills with
//! `try_send` (record::flow), so the supervisor never waits for it; its publishers drop
//! rather than queue when the network is slow, so a receiver on a slow link gets the
//! latest status, not a growing backlog.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{bounded, select};
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
use crate::config::Settings;
use crate::record::{TickFlow, tick_json};
use crate::request_channel::SupervisorHandle;
use crate::rt::LoopSummary;
use crate::state::{Reader, Writer};
use crate::status::Status;

/// How often ROBOT/status goes out: ten a second is what a person reads.
const STATUS_PERIOD: Duration = Duration::from_millis(100);
/// Queries waiting for the bus thread; more are dropped (the asker times out).
const QUEUE_QUERIES: usize = 16;

pub struct BusWires {
    pub status: Reader<Status>,
    pub link: Reader<LinkStatus>,
    pub loops: [Reader<LoopSummary>; 2],
    pub flow: TickFlow,
    pub supervisor: SupervisorHandle,
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
    let (query_tx, queries) = bounded::<(bool, Query)>(QUEUE_QUERIES);
    let tx = query_tx.clone();
    let _requests = session
        .declare_queryable(bus.key("request"))
        .callback(move |q| {
            let _ = tx.try_send((true, q));
        })
        .wait()?;
    let _config = session
        .declare_queryable(bus.key("config/**"))
        .callback(move |q| {
            let _ = query_tx.try_send((false, q));
        })
        .wait()?;
    let own_token = bus.key("alive/controller");
    let _alive = session.liveliness().declare_token(&own_token).wait()?;
    let peers = Peers::watch(&session, &bus.key("alive/**"))?;
    let config_prefix = bus.key("config/");
    let mut answers = Queries::new(settings, w.supervisor);
    let mut figures = BusFigures {
        state: BusState::Running,
        ..BusFigures::default()
    };
    let mut json = String::with_capacity(4096);
    let mut next_status = Instant::now();
    while !w.stop.load(Ordering::Relaxed) {
        let wait = next_status.saturating_duration_since(Instant::now());
        select! {
            recv(w.flow.ticks) -> tick => if let Ok(tick) = tick {
                tick_json(&tick, &mut json);
                if tick_pub.put(json.as_bytes()).wait().is_ok() {
                    figures.ticks_published += 1;
                }
            },
            recv(w.flow.events) -> event => if let Ok(event) = event {
                let text = event.to_json().to_string();
                if event_pub.put(text).wait().is_ok() {
                    figures.events_published += 1;
                }
            },
            recv(queries) -> query => if let Ok((is_request, query)) = query {
                let payload = query.payload().map(|p| p.to_bytes().into_owned());
                let answer = if is_request {
                    answers.request(payload.as_deref().unwrap_or_default())
                } else {
                    let key = query.key_expr().as_str();
                    let path = key.strip_prefix(&config_prefix).unwrap_or(key);
                    answers.config(path, payload.as_deref())
                };
                figures.queries_answered += 1;
                let sent = match answer {
                    Ok(reply) => query.reply(query.key_expr().clone(), reply.to_string()).wait(),
                    Err(why) => {
                        figures.queries_refused += 1;
                        query.reply_err(why).wait()
                    }
                };
                if let Err(e) = sent {
                    tracing::debug!("bus: the answer could not be sent: {e}");
                }
            },
            default(wait) => {}
        }
        if Instant::now() >= next_status {
            next_status += STATUS_PERIOD;
            let loops = [w.loops[0].snapshot(), w.loops[1].snapshot()];
            let status = status_json(&w.status.snapshot(), &w.link.snapshot(), &loops);
            if status_pub.put(status.to_string()).wait().is_ok() {
                figures.status_published += 1;
            }
            (figures.ticks_dropped, figures.events_dropped) = w.flow.dropped();
            figures.peers = peers.others(&own_token);
            figures.status_receivers = status_pub
                .matching_status()
                .wait()
                .is_ok_and(|m| m.matching());
            figures.rows_received = w.rows.received.load(Ordering::Relaxed);
            figures.rows_rejected = w.rows.rejected.load(Ordering::Relaxed);
            w.figures.publish(&figures);
        }
    }
    figures.state = BusState::Closed;
    w.figures.publish(&figures);
    Ok(figures)
}
