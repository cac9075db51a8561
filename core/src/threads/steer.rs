//! The steer thread: the steering law's tick (steer/) at its rate, and at once when
//! the camera link has a new usable estimate.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use crossbeam_channel::{Receiver, select};

use crate::camlink::LinkStatus;
use crate::config::SteerSettings;
use crate::gnss::GnssStatus;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::rt::inject::Injection;
use crate::rt::{self, LoopSummary, Periodic};
use crate::state::status::Status;
use crate::state::{Latest, Reader, Writer};
use crate::steer::{SteerCommand, SteerCore};

use super::{final_figures, publish_figures_now_and_then, publish_soon};

/// What the steer thread meets the other threads through.
pub struct SteerWires {
    /// The camera link's call: a new usable estimate.
    pub new_estimate: Receiver<()>,
    pub command: Writer<SteerCommand>,
    pub status: Reader<Status>,
    pub link: Reader<LinkStatus>,
    pub gnss: Reader<GnssStatus>,
    pub figures: Writer<LoopSummary>,
    /// New steering-law parameters, accepted by the supervisor in Halt.
    pub new_settings: Receiver<SteerSettings>,
    /// The steering-law parameters in use, for the GUI.
    pub settings: Writer<SteerSettings>,
    pub panics: Arc<PanicFlag>,
    pub stop: Arc<AtomicBool>,
}

/// What the steer thread owns: the steering law's state and its wires.
pub struct SteerThread {
    core: SteerCore,
    rate_hz: f64,
    clock: Instant,
    wires: SteerWires,
    /// SCHED_FIFO priority (0 = normal).
    priority: u8,
    inject: Option<Injection>,
}

impl SteerThread {
    /// The steer thread at `rate_hz`, at normal priority.
    pub fn new(core: SteerCore, rate_hz: f64, clock: Instant, wires: SteerWires) -> Self {
        SteerThread {
            core,
            rate_hz,
            clock,
            wires,
            priority: 0,
            inject: None,
        }
    }

    /// Run at this SCHED_FIFO priority (0 = normal).
    pub fn with_priority(self, priority: u8) -> SteerThread {
        SteerThread { priority, ..self }
    }

    /// Fail on purpose as `inject` says, if it names this thread.
    pub fn with_injection(self, inject: Option<Injection>) -> SteerThread {
        SteerThread { inject, ..self }
    }

    /// Ticks at its rate, and also as soon as the camera link has a new estimate.
    pub fn run(mut self) -> LoopSummary {
        health::watch_this_thread(&self.wires.panics, ThreadName::Steer);
        if let Some(warning) = rt::set_this_thread(self.priority, -1) {
            tracing::warn!("steer thread: {warning}");
        }
        let mut periodic = Periodic::new(self.rate_hz);
        let mut figures_pending = false;
        // Written by threads of normal priority (the camera link, GNSS) and read by
        // them (the bus, the GUI): never waited for, as the supervisor does not.
        let (mut status, mut link, mut gnss) = (
            Latest::new(self.wires.status.clone()),
            Latest::new(self.wires.link.clone()),
            Latest::new(self.wires.gnss.clone()),
        );
        while !self.wires.stop.load(Ordering::Relaxed) {
            let scheduled = select! {
                recv(self.wires.new_estimate) -> _ => false,
                default(periodic.until_deadline()) => true,
            };
            if scheduled {
                periodic.wait();
            } else {
                periodic.woke_now();
            }
            let now_s = self.clock.elapsed().as_secs_f64();
            let busy = &mut periodic.stats.locks_busy;
            if let Ok(new_settings) = self.wires.new_settings.try_recv() {
                self.core.set_law_settings(&new_settings);
                publish_soon(&self.wires.settings, &self.core.law_settings(), busy);
            }
            if let Some(injection) = self.inject
                && injection.thread == ThreadName::Steer
                && now_s >= injection.at_s
            {
                injection.strike(&self.wires.stop);
            }
            let (status_now, link_now, gnss_now) =
                (status.get(busy), link.get(busy), gnss.get(busy));
            let command = self.core.tick(now_s, &status_now, &link_now, &gnss_now);
            publish_soon(
                &self.wires.command,
                &command,
                &mut periodic.stats.locks_busy,
            );
            if scheduled {
                periodic.done();
            } else {
                periodic.done_unscheduled();
            }
            // After every tick, scheduled or woken by a camera frame: the figures go
            // out on the clock, not on a count of ticks that frames can step over.
            publish_figures_now_and_then(&mut periodic, &self.wires.figures, &mut figures_pending);
        }
        final_figures(&periodic, &self.wires.figures)
    }
}
