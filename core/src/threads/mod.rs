//! The bodies of the two periodic threads a run starts: the supervisor thread (it owns
//! the hardware) and the steer thread. Each owns its state and meets the others only
//! through protected objects and channels; run.rs starts them and collects them.

pub mod backend;
pub mod lockstep;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, select};
use mechweed_hw::{Hw, Outputs};

use crate::camlink::LinkStatus;
use crate::config::SteerSettings;
use crate::gnss::GnssStatus;
use crate::record::{Given, HwFailure, RecordTap};
use crate::rt::health::{self, PanicFlag, ThreadHealth, ThreadName};
use crate::rt::inject::{Fail, Injection};
use crate::rt::{self, LoopSummary, Periodic};
use crate::state::modes::{Gains, Request};
use crate::state::request_channel::{Envelope, RequestReceiver};
use crate::state::status::Status;
use crate::state::{Latest, Mailbox, Reader, Writer};
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;

/// Writes the safe outputs when dropped: at the end of the supervisor thread, and
/// also if it unwinds from a panic, so that no exit leaves a frozen last command.
pub struct SafeOnDrop(Box<dyn Hw>);

impl Drop for SafeOnDrop {
    fn drop(&mut self) {
        if let Err(e) = self.0.write(&Outputs::SAFE) {
            tracing::error!("could not write the safe outputs at exit: {e}");
        }
    }
}

/// What the supervisor thread meets the other threads through.
pub struct SupervisorWires {
    pub requests: RequestReceiver,
    pub status: Writer<Status>,
    pub steer: Reader<SteerCommand>,
    pub link: Reader<LinkStatus>,
    pub gui_beat: Reader<f64>,
    /// Steering-law parameters the supervisor accepted (in Halt), for the steer thread.
    pub steer_settings: Mailbox<SteerSettings>,
    /// The gains and steering law in force, published when a request changes them.
    pub tuning: Writer<(Gains, SteerSettings)>,
    pub figures: Writer<LoopSummary>,
    /// Hands each tick to the recorder thread; never blocks.
    pub record: RecordTap,
    /// The same for the bus thread (off when the bus is).
    pub bus: RecordTap,
    pub panics: Arc<PanicFlag>,
    pub stop: Arc<AtomicBool>,
}

/// What the supervisor thread owns: the hardware, the supervisor, its wires.
pub struct SupervisorThread {
    hw: Box<dyn Hw>,
    core: Supervisor,
    rate_hz: f64,
    clock: Instant,
    wires: SupervisorWires,
    /// SCHED_FIFO priority (0 = normal) and CPU (-1 = any).
    priority: u8,
    cpu: i32,
    inject: Option<Injection>,
}

impl SupervisorThread {
    /// The supervisor on `hw` at `rate_hz`, at normal priority on any CPU.
    pub fn new(
        hw: Box<dyn Hw>,
        core: Supervisor,
        rate_hz: f64,
        clock: Instant,
        wires: SupervisorWires,
    ) -> SupervisorThread {
        SupervisorThread {
            hw,
            core,
            rate_hz,
            clock,
            wires,
            priority: 0,
            cpu: -1,
            inject: None,
        }
    }

    /// Run at this SCHED_FIFO priority (0 = normal), on this CPU (-1 = any).
    pub fn with_priority(self, priority: u8, cpu: i32) -> SupervisorThread {
        SupervisorThread {
            priority,
            cpu,
            ..self
        }
    }

    /// Fail on purpose as `inject` says, if it names this thread.
    pub fn with_injection(self, inject: Option<Injection>) -> SupervisorThread {
        SupervisorThread { inject, ..self }
    }

    pub fn run(self) -> (Supervisor, LoopSummary) {
        let SupervisorThread {
            hw,
            mut core,
            rate_hz,
            clock,
            wires,
            priority,
            cpu,
            inject,
        } = self;
        let SupervisorWires {
            requests,
            status,
            steer,
            link,
            gui_beat,
            steer_settings,
            tuning,
            figures,
            mut record,
            mut bus,
            panics,
            stop,
        } = wires;
        health::watch_this_thread(&panics, ThreadName::Supervisor);
        if let Some(warning) = rt::set_this_thread(priority, cpu) {
            tracing::warn!("supervisor thread: {warning}");
        }
        let mut hw = SafeOnDrop(hw);
        let mut periodic = Periodic::new(rate_hz);
        // Every object below is written by a thread of lower priority: read without
        // waiting (state.rs), the busy locks counted.
        let (mut steer, mut link, mut gui_beat) =
            (Latest::new(steer), Latest::new(link), Latest::new(gui_beat));
        let mut paused = false;
        let mut figures_pending = false;
        let mut tuning_pending = false;
        while !stop.load(Ordering::Relaxed) {
            periodic.wait();
            let now_s = clock.elapsed().as_secs_f64();
            let lock_start = rt::monotonic_ns();
            while let Ok(Envelope {
                request,
                reply,
                from_bus,
            }) = requests.try_recv()
            {
                let answer = core.handle_from(request, from_bus);
                // Recorded with the tick it precedes, so that a replay gives it there.
                record.requested(now_s, core.status().tick + 1, request, answer);
                if let Some(accepted) = core.take_steer_settings() {
                    // A newer set replaces one the steer thread has not taken yet, so
                    // that it ends on the law that goes with the gains in use.
                    steer_settings.post(accepted);
                }
                // Published before the answer, so that whoever asked reads the new values;
                // never waiting: a reader holding it now gets them at a next tick.
                tuning_pending |=
                    answer.is_ok() && matches!(request, Request::Gains(_) | Request::Tuning(..));
                if tuning_pending {
                    tuning_pending = !tuning.try_publish(&core.tuning());
                }
                let _ = reply.try_send((request, answer));
            }
            if tuning_pending {
                tuning_pending = !tuning.try_publish(&core.tuning());
            }
            // The only meetings with other threads: copying their objects in and ours out.
            let busy = &mut periodic.stats.locks_busy;
            let (steer_now, link_now) = (steer.get(busy), link.get(busy));
            let gui_beat_s = gui_beat.get(busy);
            let mut lock_ns = rt::monotonic_ns() - lock_start;
            let health = ThreadHealth {
                gui_beat_s: (!gui_beat_s.is_nan()).then_some(gui_beat_s),
                panicked: panics.panicked(),
                supervisor_overruns: periodic.stats.overruns,
            };
            let mut hw_failed = None;
            let outputs = match hw.0.read() {
                Ok(inputs) => core.tick(now_s, &inputs, &steer_now, &link_now, &health),
                Err(e) => {
                    tracing::error!("{e}");
                    hw_failed = Some(HwFailure {
                        during: "read",
                        card: e.card(),
                    });
                    core.hardware_failed(now_s, e.card())
                }
            };
            if let Err(e) = hw.0.write(&outputs) {
                tracing::error!("{e}");
                hw_failed = Some(HwFailure {
                    during: "write",
                    card: e.card(),
                });
                core.hardware_failed(now_s, e.card());
                let _ = hw.0.write(&Outputs::SAFE);
            }
            if health.panicked.is_some() && core.status().outputs.is_safe() {
                panics.safe_outputs_written();
            }
            let publish_start = rt::monotonic_ns();
            if !status.try_publish(core.status()) {
                // A reader holds it: the next tick publishes a newer status anyway.
                periodic.stats.locks_busy += 1;
            }
            lock_ns = lock_ns.max(rt::monotonic_ns() - publish_start);
            periodic.stats.worst_lock_us = periodic.stats.worst_lock_us.max(lock_ns / 1000);
            let given = Given { health, hw_failed };
            record.after_tick(&mut bus, core.status(), &steer_now, &link_now, &given);
            if let Some(Injection {
                thread: ThreadName::Supervisor,
                at_s,
                action,
            }) = inject
                && now_s >= at_s
            {
                match action {
                    Fail::Slow { ms } => std::thread::sleep(Duration::from_millis(ms)),
                    Fail::Pause { ms } if !paused => {
                        paused = true;
                        std::thread::sleep(Duration::from_millis(ms));
                    }
                    _ => {}
                }
            }
            periodic.done();
            publish_figures_now_and_then(&mut periodic, &figures, &mut figures_pending);
        }
        (core, periodic.stats.summary())
    }
}

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
        periodic.stats.summary()
    }
}

/// Publish `value` without blocking on a reader of lower priority that holds the lock:
/// tried again after a short sleep (the reader then runs and lets go), for at most a
/// millisecond; a value still not published is replaced by the next tick's.
fn publish_soon<T: Copy>(writer: &Writer<T>, value: &T, busy: &mut u64) {
    for _ in 0..10 {
        if writer.try_publish(value) {
            return;
        }
        *busy += 1;
        std::thread::sleep(Duration::from_micros(100));
    }
}

/// Publish a loop's figures four times a second of the monotonic clock (percentiles
/// cost a few microseconds), never waiting for a reader (the GUI, the console) that holds the
/// lock: then they go out at the next tick.
fn publish_figures_now_and_then(
    periodic: &mut Periodic,
    figures: &Writer<LoopSummary>,
    pending: &mut bool,
) {
    if periodic.figures_due() || *pending {
        *pending = !figures.try_publish(&periodic.stats.summary());
        if *pending {
            periodic.stats.locks_busy += 1;
        }
    }
}
