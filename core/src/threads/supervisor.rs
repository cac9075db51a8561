//! The supervisor thread: it owns the hardware, and runs the supervisor's tick
//! (supervisor/) at its rate, meeting the other threads only through its wires.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use mechweed_hw::{Hw, Outputs};

use crate::camlink::LinkStatus;
use crate::config::SteerSettings;
use crate::record::{Given, HwFailure, RecordTap};
use crate::rt::health::{self, PanicFlag, ThreadHealth, ThreadName};
use crate::rt::inject::{Fail, Injection};
use crate::rt::load::LoadGauge;
use crate::rt::{self, LoopSummary, Periodic};
use crate::state::modes::{Gains, Request};
use crate::state::request_channel::{Envelope, RequestReceiver};
use crate::state::status::Status;
use crate::state::{Latest, Mailbox, Reader, Writer};
use crate::steer::SteerCommand;
use crate::supervisor::Supervisor;

use super::{final_figures, publish_figures_now_and_then};

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
    /// The computer's load, read by a thread of its own (None: not read).
    pub load: Option<Arc<LoadGauge>>,
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
            load,
        } = wires;
        health::watch_this_thread(&panics, ThreadName::Supervisor);
        if let Some(warning) = rt::set_this_thread(priority, cpu) {
            tracing::warn!("supervisor thread: {warning}");
        }
        let mut hw = SafeOnDrop(hw);
        let mut periodic = Periodic::new(rate_hz);
        // Every object below is written by a thread of lower priority: read without
        // waiting (state/mod.rs), the busy locks counted.
        let (mut steer, mut link, mut gui_beat) =
            (Latest::new(steer), Latest::new(link), Latest::new(gui_beat));
        let mut paused = false;
        let mut figures_pending = false;
        let mut tuning_pending = false;
        while !stop.load(Ordering::Relaxed) {
            periodic.wait();
            let now_s = clock.elapsed().as_secs_f64();
            let lock_start = rt::monotonic_ns();
            tuning_pending = answer_requests(
                &mut core,
                &requests,
                now_s,
                &mut record,
                &steer_settings,
                &tuning,
                tuning_pending,
            );
            // The only meetings with other threads: copying their objects in and ours out.
            let busy = &mut periodic.stats.locks_busy;
            let (steer_now, link_now) = (steer.get(busy), link.get(busy));
            let gui_beat_s = gui_beat.get(busy);
            let mut lock_ns = rt::monotonic_ns() - lock_start;
            let health = ThreadHealth {
                gui_beat_s: (!gui_beat_s.is_nan()).then_some(gui_beat_s),
                panicked: panics.panicked(),
                supervisor_overruns: periodic.stats.overruns,
                cpu_load: load.as_ref().and_then(|gauge| gauge.now()),
            };
            let hw_failed =
                read_tick_write(&mut hw, &mut core, now_s, (&steer_now, &link_now), &health);
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
            fail_as_injected(inject, now_s, &mut paused);
            periodic.done();
            publish_figures_now_and_then(&mut periodic, &figures, &mut figures_pending);
        }
        (core, final_figures(&periodic, &figures))
    }
}

/// Every waiting request, answered in the order it came and recorded with the tick it
/// precedes; accepted steering-law settings posted to the steer thread, and the tuning
/// published when it changes. Returns whether the tuning still waits to be published
/// (a reader held it: it goes out at a next tick, never waiting).
fn answer_requests(
    core: &mut Supervisor,
    requests: &RequestReceiver,
    now_s: f64,
    record: &mut RecordTap,
    steer_settings: &Mailbox<SteerSettings>,
    tuning: &Writer<(Gains, SteerSettings)>,
    mut tuning_pending: bool,
) -> bool {
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
    tuning_pending
}

/// Read every input, tick, write every output. A card that fails is the fault
/// "hardware" and the safe outputs this tick; the failure is named for the record.
fn read_tick_write(
    hw: &mut SafeOnDrop,
    core: &mut Supervisor,
    now_s: f64,
    (steer, link): (&SteerCommand, &LinkStatus),
    health: &ThreadHealth,
) -> Option<HwFailure> {
    let mut hw_failed = None;
    let outputs = match hw.0.read() {
        Ok(inputs) => core.tick(now_s, &inputs, steer, link, health),
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
    hw_failed
}

/// Fail on purpose as the injection says, once its time has come (tests/runs/threads.rs).
fn fail_as_injected(inject: Option<Injection>, now_s: f64, paused: &mut bool) {
    if let Some(Injection {
        thread: ThreadName::Supervisor,
        at_s,
        action,
    }) = inject
        && now_s >= at_s
    {
        match action {
            Fail::Slow { ms } => std::thread::sleep(Duration::from_millis(ms)),
            Fail::Pause { ms } if !*paused => {
                *paused = true;
                std::thread::sleep(Duration::from_millis(ms));
            }
            _ => {}
        }
    }
}
