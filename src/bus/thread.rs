//! The bus thread (normal priority): the controller's side of its bus process. It hands
//! the process the robot's status about ten times a second, every Nth tick and every
//! event, decides what other programs ask (gate.rs), and passes row estimates to the
//! camera link. It reads the protected objects and the tick queue the supervisor fills
//! with `try_send` (record::flow), so the supervisor never waits for it; what it hands
//! down drops rather than queues (gateway/supervise.rs).
//!
//! When the bus process ends, the thread says how, and starts it again after a wait that
//! grows while it keeps ending (1 s, doubling to 30 s; back to 1 s after a minute's
//! run). Meanwhile the robot drives on as a robot without a bus: nothing is published,
//! and no row estimate comes, so a robot steering by rows from the bus faults as for a
//! lost camera.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{RecvTimeoutError, Sender};
use serde_json::json;

use super::gate::Gate;
use super::gateway::supervise::Gateway;
use super::gateway::{Down, ProcessFigures, Up};
use super::payload::status_json;
use super::queries::Queries;
use super::rows::RowCounts;
use super::{BusFigures, BusState};
use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerSettings};
use crate::gamepad::Label;
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
/// The waits before a restart: the first, the longest, and a run long enough to start
/// again from the first.
const FIRST_RESTART: Duration = Duration::from_secs(1);
const LONGEST_RESTART: Duration = Duration::from_secs(30);
const STEADY_RUN: Duration = Duration::from_secs(60);

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
    /// Where row estimates go to the camera link (with `[camera] port = bus`), with
    /// their arrival, s since 1970.
    pub rows_to_link: Option<Sender<(Vec<u8>, f64)>>,
    pub stop: Arc<AtomicBool>,
}

/// Serve the run's flows through `first` and the bus processes after it, until `stop`;
/// returns the last figures.
pub fn run(first: Gateway, settings: &Settings, w: BusWires) -> BusFigures {
    let mut bus = Served {
        gate: Gate::new(),
        answers: Queries::new(settings, w.supervisor.clone(), w.tuning.clone()),
        figures: BusFigures {
            state: BusState::Running,
            security: Label::new(&super::security_line(&settings.bus)),
            ..BusFigures::default()
        },
        ended_lives: ProcessFigures::default(),
        this_life: ProcessFigures::default(),
        not_handed: (0, 0),
        json: String::with_capacity(4096),
        settings,
        w: &w,
    };
    let mut wait = FIRST_RESTART;
    let mut gateway = Some(first);
    while let Some(mut g) = gateway.take() {
        let started = Instant::now();
        let stopped = bus.serve(&g);
        let how = g.end();
        if stopped {
            break;
        }
        bus.lost();
        if started.elapsed() >= STEADY_RUN {
            wait = FIRST_RESTART;
        }
        crate::say!(
            "bus: the bus process ended ({how}): restarting in {} s",
            wait.as_secs()
        );
        gateway = bus.start_again(&mut wait);
    }
    bus.figures.state = BusState::Closed;
    w.figures.publish(&bus.figures);
    bus.figures
}

/// What the bus thread keeps across its bus processes.
struct Served<'a> {
    gate: Gate,
    answers: Queries,
    figures: BusFigures,
    /// The figures of the bus processes that have ended, added up, and of this one.
    ended_lives: ProcessFigures,
    this_life: ProcessFigures,
    /// Ticks and events not handed to a bus process (its queue full, or none running).
    not_handed: (u64, u64),
    json: String,
    settings: &'a Settings,
    w: &'a BusWires,
}

impl Served<'_> {
    /// Serve through `g` until it ends (false) or the run stops (true).
    fn serve(&mut self, g: &Gateway) -> bool {
        let mut next_status = Instant::now();
        loop {
            if self.w.stop.load(Ordering::Relaxed) {
                return true;
            }
            let wait = next_status
                .saturating_duration_since(Instant::now())
                .min(DRAIN_PERIOD);
            // Queries wake the thread; ticks and events are fetched on its own beat, so
            // the supervisor's try_send never has a sleeping reader to wake (a system
            // call in its tick).
            match g.from.recv_timeout(wait) {
                Ok(Up::Query(q)) => {
                    let answer = self.gate.serve(&q, &mut self.answers, &mut self.figures);
                    g.answer(Down::Answer { id: q.id, answer });
                }
                Ok(Up::Row { payload, arrived_s }) => {
                    if let Some(link) = &self.w.rows_to_link {
                        let _ = link.try_send((payload, arrived_s));
                    }
                }
                Ok(Up::Figures(f)) => {
                    self.w.rows.rivals.store(f.rivals, Ordering::Relaxed);
                    self.this_life = f;
                    // In the next status at once: who is linked.
                    self.merge_figures();
                }
                Ok(Up::Ready | Up::Failed { .. }) | Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => return false,
            }
            self.gate.say_refusals();
            self.hand_flows(Some(g));
            let now = Instant::now();
            if now < next_status {
                continue;
            }
            // After a long answer (a request waits for the supervisor), one status now,
            // not a burst of the ones missed.
            next_status += STATUS_PERIOD;
            if next_status < now {
                next_status = now + STATUS_PERIOD;
            }
            g.send(Down::Status {
                json: self.status_message().to_string(),
            });
            self.say_dropped(Some(g));
            self.publish_figures();
        }
    }

    /// The bus process has ended: its counts are kept, its presence is not.
    fn lost(&mut self) {
        let (ended, life) = (&mut self.ended_lives, std::mem::take(&mut self.this_life));
        ended.status_published += life.status_published;
        ended.ticks_published += life.ticks_published;
        ended.events_published += life.events_published;
        ended.queries_dropped += life.queries_dropped;
        self.w.rows.rivals.store(false, Ordering::Relaxed);
        self.figures.state = BusState::Restarting;
        self.publish_figures();
    }

    /// Wait `wait` (ticks and events not published meanwhile), then start a bus process;
    /// each failure waits twice as long. None when the run stops first.
    fn start_again(&mut self, wait: &mut Duration) -> Option<Gateway> {
        loop {
            let until = Instant::now() + *wait;
            while Instant::now() < until {
                if self.w.stop.load(Ordering::Relaxed) {
                    return None;
                }
                std::thread::sleep(DRAIN_PERIOD);
                self.hand_flows(None);
                self.publish_figures();
            }
            *wait = (*wait * 2).min(LONGEST_RESTART);
            match Gateway::start(self.settings) {
                Ok(g) => {
                    self.figures.process_restarts += 1;
                    self.figures.state = BusState::Running;
                    crate::say!(
                        "bus: the bus process runs again (restart {}, process {})",
                        self.figures.process_restarts,
                        g.pid()
                    );
                    return Some(g);
                }
                Err(why) => crate::say!(
                    "bus: the bus process could not start: {why}: trying again in {} s",
                    wait.as_secs()
                ),
            }
        }
    }

    /// Every tick and event waiting in the supervisor's queue, handed to `g` (or, with
    /// none running, counted as not published).
    fn hand_flows(&mut self, g: Option<&Gateway>) {
        let w = self.w;
        while let Ok(tick) = w.flow.ticks.try_recv() {
            tick_json(&tick, &mut self.json);
            let json = self.json.clone();
            if !g.is_some_and(|g| g.send(Down::Tick { json })) {
                self.not_handed.0 += 1;
            }
        }
        while let Ok(event) = w.flow.events.try_recv() {
            let json = event.to_json().to_string();
            if !g.is_some_and(|g| g.send(Down::Event { json })) {
                self.not_handed.1 += 1;
            }
        }
    }

    /// ROBOT/status: the supervisor's status with the link's, the steering's and the
    /// loops', what cross-track means, and whether this bus is secured and who came.
    fn status_message(&self) -> serde_json::Value {
        let w = self.w;
        let loops = [w.loops[0].snapshot(), w.loops[1].snapshot()];
        let mut status = status_json(
            &w.status.snapshot(),
            &w.link.snapshot(),
            &w.steer.snapshot(),
            &loops,
        );
        // One rule for what cross-track means, on the bus as everywhere.
        status["cross_track"] = json!(CrossTrackMeaning::of(self.settings).word());
        status["bus"] = json!({
            "secured": self.settings.bus.tls.is_some(),
            "security": self.figures.security.as_str(),
            "identities": self.figures.identities.as_str(),
            "present": self.this_life.present,
            "receivers": self.this_life.receivers,
        });
        status
    }

    /// Ticks not published since the last look, said on the event flow too, as the
    /// record says its own gaps.
    fn say_dropped(&mut self, g: Option<&Gateway>) {
        let (in_queue, events_in_queue) = self.w.flow.dropped();
        let (ticks_dropped, events_dropped) = (
            in_queue + self.not_handed.0,
            events_in_queue + self.not_handed.1,
        );
        let f = &mut self.figures;
        if ticks_dropped > f.ticks_dropped
            && let Some(g) = g
        {
            let now = self.w.status.snapshot();
            let event = json!({
                "t_s": now.t_s,
                "tick": now.tick,
                "kind": "dropped",
                "text": format!(
                    "{} ticks not published: the bus thread fell behind, or the bus process was away",
                    ticks_dropped - f.ticks_dropped
                ),
            });
            g.send(Down::Event {
                json: event.to_string(),
            });
        }
        (f.ticks_dropped, f.events_dropped) = (ticks_dropped, events_dropped);
    }

    /// The figures as the GUI and the report read them: the processes' counts added up.
    fn publish_figures(&mut self) {
        self.merge_figures();
        if self.figures.state == BusState::Restarting {
            self.say_dropped(None);
        }
        self.w.figures.publish(&self.figures);
    }

    /// The processes' counts added up into the figures.
    fn merge_figures(&mut self) {
        let (ended, life, f) = (&self.ended_lives, &self.this_life, &mut self.figures);
        f.status_published = ended.status_published + life.status_published;
        f.ticks_published = ended.ticks_published + life.ticks_published;
        f.events_published = ended.events_published + life.events_published;
        f.queries_dropped = ended.queries_dropped + life.queries_dropped;
        f.peers = life.peers;
        f.status_receivers = life.status_receivers;
        if !life.identities.is_empty() {
            f.identities = Label::new(&life.identities);
        }
        f.rows_received = self.w.rows.received.load(Ordering::Relaxed);
        f.rows_rejected = self.w.rows.rejected.load(Ordering::Relaxed);
    }
}
