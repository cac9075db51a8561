//! The bodies of the two periodic threads a run starts: the supervisor thread (it owns
//! the hardware) and the steer thread. Each owns its state and meets the others only
//! through protected objects and channels; run.rs starts them and collects them.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, Sender, select};
use mechweed_hw::{Hw, Outputs};

use crate::camlink::LinkStatus;
use crate::config::SteerSettings;
use crate::health::{self, PanicFlag, ThreadHealth, ThreadName};
use crate::inject::{Fail, Injection};
use crate::record::RecordTap;
use crate::request_channel::{Envelope, RequestReceiver};
use crate::rt::{self, LoopSummary, Periodic};
use crate::state::{Latest, Reader, Writer};
use crate::status::Status;
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;

/// Writes the safe outputs when dropped: at the end of the supervisor thread, and
/// also if it unwinds from a panic, so that no exit leaves a frozen last command.
pub(crate) struct SafeOnDrop(Box<dyn Hw>);

impl Drop for SafeOnDrop {
    fn drop(&mut self) {
        if let Err(e) = self.0.write(&Outputs::SAFE) {
            tracing::error!("could not write the safe outputs at exit: {e}");
        }
    }
}

/// What the supervisor thread owns: the hardware, the supervisor, its object's writer.
pub(crate) struct SupervisorThread {
    pub(crate) hw: Box<dyn Hw>,
    pub(crate) core: Supervisor,
    pub(crate) rate_hz: f64,
    pub(crate) clock: Instant,
    pub(crate) requests: RequestReceiver,
    pub(crate) status: Writer<Status>,
    pub(crate) steer: Reader<SteerCommand>,
    pub(crate) link: Reader<LinkStatus>,
    pub(crate) panics: Arc<PanicFlag>,
    pub(crate) priority: u8,
    pub(crate) cpu: i32,
    pub(crate) inject: Option<Injection>,
    pub(crate) figures: Writer<LoopSummary>,
    pub(crate) gui_beat: Reader<f64>,
    /// Steering-law parameters the supervisor accepted (in Halt), for the steer thread.
    pub(crate) steer_settings: Sender<SteerSettings>,
    pub(crate) stop: Arc<AtomicBool>,
    /// Hands each tick to the recorder thread; never blocks.
    pub(crate) record: RecordTap,
}

impl SupervisorThread {
    pub(crate) fn run(self) -> (Supervisor, LoopSummary) {
        let SupervisorThread {
            hw,
            mut core,
            rate_hz,
            clock,
            requests,
            status,
            steer,
            link,
            panics,
            priority,
            cpu,
            inject,
            figures,
            gui_beat,
            steer_settings,
            stop,
            mut record,
        } = self;
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
        while !stop.load(Ordering::Relaxed) {
            periodic.wait();
            let now_s = clock.elapsed().as_secs_f64();
            let lock_start = rt::monotonic_ns();
            while let Ok(Envelope { request, reply }) = requests.try_recv() {
                let _ = reply.try_send((request, core.handle(request)));
                if let Some(accepted) = core.take_steer_settings() {
                    // One place, bounded: a newer set replaces one not yet taken.
                    let _ = steer_settings.try_send(accepted);
                }
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
            let outputs = match hw.0.read() {
                Ok(inputs) => core.tick(now_s, &inputs, &steer_now, &link_now, &health),
                Err(e) => {
                    tracing::error!("{e}");
                    core.hardware_failed(now_s, e.card())
                }
            };
            if let Err(e) = hw.0.write(&outputs) {
                tracing::error!("{e}");
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
            record.after_tick(core.status(), &steer_now, &link_now);
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
            publish_figures_now_and_then(&periodic, &figures);
        }
        (core, periodic.stats.summary())
    }
}

/// What the steer thread owns: the steering law's state and the command's writer.
pub(crate) struct SteerThread {
    pub(crate) core: SteerCore,
    pub(crate) rate_hz: f64,
    pub(crate) clock: Instant,
    pub(crate) new_estimate: Receiver<()>,
    pub(crate) command: Writer<SteerCommand>,
    pub(crate) status: Reader<Status>,
    pub(crate) link: Reader<LinkStatus>,
    pub(crate) panics: Arc<PanicFlag>,
    pub(crate) priority: u8,
    pub(crate) inject: Option<Injection>,
    pub(crate) figures: Writer<LoopSummary>,
    /// New steering-law parameters, accepted by the supervisor in Halt.
    pub(crate) new_settings: Receiver<SteerSettings>,
    pub(crate) settings: Writer<SteerSettings>,
    pub(crate) stop: Arc<AtomicBool>,
}

impl SteerThread {
    /// Ticks at its rate, and also as soon as the camera link has a new estimate.
    pub(crate) fn run(mut self) -> LoopSummary {
        health::watch_this_thread(&self.panics, ThreadName::Steer);
        if let Some(warning) = rt::set_this_thread(self.priority, -1) {
            tracing::warn!("steer thread: {warning}");
        }
        let mut periodic = Periodic::new(self.rate_hz);
        while !self.stop.load(Ordering::Relaxed) {
            let scheduled = select! {
                recv(self.new_estimate) -> _ => false,
                default(periodic.until_deadline()) => true,
            };
            if scheduled {
                periodic.wait();
            } else {
                periodic.woke_now();
            }
            let now_s = self.clock.elapsed().as_secs_f64();
            if let Ok(new_settings) = self.new_settings.try_recv() {
                self.core.set_law_settings(&new_settings);
                self.settings.publish(&self.core.law_settings());
            }
            if let Some(injection) = self.inject
                && injection.thread == ThreadName::Steer
                && now_s >= injection.at_s
            {
                injection.strike(&self.stop);
            }
            let command = self
                .core
                .tick(now_s, &self.status.snapshot(), &self.link.snapshot());
            self.command.publish(&command);
            if scheduled {
                periodic.done();
                publish_figures_now_and_then(&periodic, &self.figures);
            } else {
                periodic.done_unscheduled();
            }
        }
        periodic.stats.summary()
    }
}

/// Publish a loop's figures about once a second (percentiles cost a few microseconds).
fn publish_figures_now_and_then(periodic: &Periodic, figures: &Writer<LoopSummary>) {
    let ticks_per_second = periodic.stats.rate_hz().round().max(1.0) as u64;
    if periodic.stats.ticks.is_multiple_of(ticks_per_second) {
        figures.publish(&periodic.stats.summary());
    }
}
