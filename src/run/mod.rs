//! The product: the controller on real threads and real time. The supervisor thread
//! owns the hardware; the steer thread and the camera-link thread each own their own
//! state; they meet only through protected objects (core/src/state/mod.rs) and bounded channels.

mod realtime;
mod robot;
mod types;
mod wires;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Instant;

use mechweed_hw::Hw;
use mechweed_hw::sim::{SimControl, TruthHandle};

use crate::bus::BusFigures;
use crate::bus::gateway::supervise::Gateway;
use crate::bus::rows::BusRows;
use crate::bus::thread::BusWires;
use crate::camlink::thread::{LinkThread, READ_TIMEOUT};
use crate::camlink::{LinkCore, LinkStatus};
use crate::config::{Backend, JoystickSource, Settings};
use crate::config::{CameraPort, GnssPort};
use crate::gamepad::{self, PadHw, PadState};
use crate::record::{self, RecordTap, Recorder};
use crate::rt::LoopSummary;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::rt::load::{LoadGauge, sample_until};
use crate::state::Reader;
use crate::state::cross_track::CrossTrackMeaning;
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;
use realtime::rt_setup;
use robot::{camera_port, open_robot};
use wires::wire;

use crate::threads::{SteerThread, SupervisorThread};
pub use realtime::not_realtime;
pub use types::{Handles, RunError, RunOptions, RunOutcome};

fn spawn<T: Send + 'static>(name: &str, f: impl FnOnce() -> T + Send + 'static) -> JoinHandle<T> {
    std::thread::Builder::new()
        .name(name.to_string())
        .spawn(f)
        .unwrap_or_else(|e| panic!("cannot start the {name} thread: {e}"))
}

/// The controller's threads while they run; `finish` stops them and collects the outcome.
pub struct Running {
    threads: Threads,
    bus_figures: Reader<BusFigures>,
    gnss_status: Reader<crate::gnss::GnssStatus>,
    steer_command: Reader<SteerCommand>,
    link_status: Reader<LinkStatus>,
    truth: TruthHandle,
    settings: Settings,
    rt_warnings: Vec<String>,
    recorder: Recorder,
    panics: Arc<PanicFlag>,
    stop: Arc<AtomicBool>,
}

/// A run's threads, joined by `finish`.
struct Threads {
    supervisor: JoinHandle<(Supervisor, LoopSummary)>,
    steer: JoinHandle<LoopSummary>,
    link: JoinHandle<()>,
    bus: Option<JoinHandle<BusFigures>>,
    /// The simulated camera computer's end of its cable.
    cable: Option<JoinHandle<()>>,
    gamepad: Option<JoinHandle<()>>,
    gnss: Option<JoinHandle<()>>,
    gnss_cable: Option<JoinHandle<()>>,
    /// Reads the computer's load for the supervisor's timing faults.
    load: JoinHandle<()>,
}

/// What a run opens before any thread starts (steps 1 and 2 of `start`).
struct Opened {
    hw: Box<dyn Hw>,
    truth: TruthHandle,
    sim: Option<SimControl>,
    gnss: crate::gnss::run::GnssRun,
    camera_port: CameraPort,
    cable: Option<JoinHandle<()>>,
    clock: Instant,
    rt_warnings: Vec<String>,
    priorities_refused: Option<String>,
    panics: Arc<PanicFlag>,
    record_tap: RecordTap,
    recorder: Recorder,
    bus: Option<Gateway>,
}

/// Steps 1 and 2 of a run: each fails before any thread starts.
fn open(s: &Settings, stop: &Arc<AtomicBool>) -> Result<Opened, RunError> {
    // 1. The robot, the row map with the GNSS receiver's line, the camera's port.
    let robot = open_robot(s)?;
    let gnss = crate::gnss::run::prepare(s, robot.receiver, robot.planted, stop)?;
    let (camera_port, cable) = camera_port(s, robot.camera_line, stop)?;
    // 2. Real time, the panic watch, the record and the bus.
    let clock = Instant::now();
    let (rt_warnings, priorities_refused) = rt_setup(&s.rt);
    let panics = Arc::new(PanicFlag::default());
    health::watch_this_thread(&panics, ThreadName::Console);
    let (record_tap, recorder) = record::start_for_run(s, robot.truth.clone());
    let bus = crate::bus::open_for_run(s).map_err(RunError::Bus)?;
    Ok(Opened {
        hw: robot.hw,
        truth: robot.truth,
        sim: robot.sim,
        gnss,
        camera_port,
        cable,
        clock,
        rt_warnings,
        priorities_refused,
        panics,
        record_tap,
        recorder,
        bus,
    })
}

/// Start the controller's threads; the caller is the operator interface (console or
/// GUI) and calls `Running::finish` at the end. The steps that can fail come first and
/// start nothing a failure would leave behind; the threads start last.
pub fn start(opts: &RunOptions, stop: Arc<AtomicBool>) -> Result<(Handles, Running), RunError> {
    let s = &opts.settings;
    let mut o = open(s, &stop)?;
    let priority = |p: u8| if o.priorities_refused.is_some() { 0 } else { p };

    // 3. What the threads meet through: protected objects and bounded channels.
    let gnss_status = o.gnss.status.clone();
    let mut w = wire(
        s,
        &o.truth,
        o.bus.is_some(),
        gnss_status,
        o.record_tap,
        &o.panics,
        &stop,
    );

    // 4. Each thread with its wires. The camera link is the last step that can fail
    //    (rows from the bus); the gamepad thread starts after it.
    let steer_core = SteerCore::with_map(s, o.gnss.place.take());
    let steer = SteerThread::new(steer_core, s.steer.rate_hz, o.clock, w.steer)
        .with_priority(priority(s.rt.steer_priority))
        .with_injection(opts.inject);
    let link = LinkThread::new(LinkCore::new(&s.camera), o.camera_port, o.clock, w.link)
        .with_priority(priority(s.rt.camlink_priority))
        .with_injection(opts.inject);
    let link = with_rows_from_the_bus(link, s, w.bus.as_mut());
    let (hw, gamepad, gamepad_thread) = with_gamepad(o.hw, s, &o.panics, &stop);
    let rate_hz = s.supervisor.rate_hz;
    let gauge = Arc::new(LoadGauge::default());
    w.supervisor.load = Some(gauge.clone());
    let supervisor = SupervisorThread::new(hw, Supervisor::new(s), rate_hz, o.clock, w.supervisor)
        .with_priority(priority(s.rt.supervisor_priority), s.rt.supervisor_cpu)
        .with_injection(opts.inject);

    // 5. Start them.
    let threads = Threads {
        bus: (o.bus.zip(w.bus))
            .map(|(gateway, wires)| start_bus(gateway, s.clone(), wires, o.panics.clone())),
        supervisor: spawn("supervisor", move || supervisor.run()),
        steer: spawn("steer", move || steer.run()),
        link: spawn("camlink", move || link.run()),
        gnss: o.gnss.start(o.clock, o.panics.clone(), stop.clone()),
        cable: o.cable,
        gamepad: gamepad_thread,
        gnss_cable: o.gnss.cable.take(),
        load: spawn("load", {
            let stop = stop.clone();
            move || sample_until(&gauge, &stop)
        }),
    };

    // 6. What the operator interface reads, and what `finish` stops.
    let handles = Handles {
        supervisor: w.requests,
        link: w.link_status.clone(),
        loops: w.loops,
        truth: o.truth.clone(),
        sim: o.sim,
        ping: w.ping,
        gui_beat: w.gui_beat,
        steer_settings: w.steer_settings,
        steer: w.steer_command.clone(),
        clock: o.clock,
        not_realtime: not_realtime(s.backend, &s.rt, o.priorities_refused.as_deref()),
        bus: w.bus_figures.clone(),
        bus_endpoints: s.bus.endpoints(),
        gamepad,
        cross_track: CrossTrackMeaning::of(s),
    };
    let running = Running {
        threads,
        bus_figures: w.bus_figures,
        gnss_status: o.gnss.status.clone(),
        steer_command: w.steer_command,
        link_status: w.link_status,
        truth: o.truth,
        settings: s.clone(),
        rt_warnings: o.rt_warnings,
        recorder: o.recorder,
        panics: o.panics,
        stop,
    };
    Ok((handles, running))
}

/// With `[camera] port = bus`, the camera link reads its rows from the bus instead of a
/// port: the bus thread hands them on as the bus process receives them.
fn with_rows_from_the_bus(
    link: LinkThread,
    s: &Settings,
    bus: Option<&mut BusWires>,
) -> LinkThread {
    let (CameraPort::Bus, Some(bus)) = (&s.camera_port, bus) else {
        return link;
    };
    let (rows, to_link) = BusRows::new(
        &s.bus.key("camera/row"),
        READ_TIMEOUT,
        s.camera.link_timeout_s,
        bus.rows.clone(),
    );
    bus.rows_to_link = Some(to_link);
    link.with_stream(Box::new(rows), bus.rows.rivals.clone())
}

/// A gamepad in place of the wired joystick ([joystick] source = gamepad): its thread
/// started, and the hardware with the pad's values in the joystick's inputs, which the
/// supervisor reads with the rest.
#[allow(clippy::type_complexity)]
fn with_gamepad(
    hw: Box<dyn Hw>,
    s: &Settings,
    panics: &Arc<PanicFlag>,
    stop: &Arc<AtomicBool>,
) -> (
    Box<dyn Hw>,
    Option<Reader<PadState>>,
    Option<JoinHandle<()>>,
) {
    match s.joystick.source {
        JoystickSource::Analog => (hw, None, None),
        JoystickSource::Gamepad => {
            let (pad, thread) = gamepad::start(s, panics.clone(), stop.clone());
            let hw: Box<dyn Hw> = Box::new(PadHw::new(hw, pad.clone()));
            (hw, Some(pad), Some(thread))
        }
    }
}

/// The bus thread, with the run's first bus process.
fn start_bus(
    gateway: Gateway,
    settings: Settings,
    wires: BusWires,
    panics: Arc<PanicFlag>,
) -> JoinHandle<BusFigures> {
    spawn("bus", move || {
        health::watch_this_thread(&panics, ThreadName::Bus);
        crate::bus::thread::run(gateway, &settings, wires)
    })
}

impl Running {
    /// Name the calling thread in this run's panic reports (the main thread is the
    /// console unless it says otherwise, e.g. the GUI).
    pub(crate) fn watch_this_thread_as(&self, name: ThreadName) {
        health::watch_this_thread(&self.panics, name);
    }

    /// A controller thread has ended although the run was not stopped.
    pub(crate) fn any_thread_ended(&self) -> bool {
        let t = &self.threads;
        t.supervisor.is_finished() || t.steer.is_finished() || t.link.is_finished()
    }

    /// Stop the threads (the supervisor writes the safe outputs) and collect the outcome.
    pub fn finish(self) -> RunOutcome {
        self.stop.store(true, Ordering::Relaxed);
        let link_ok = self.threads.link.join().is_ok();
        let steer_loop = self.threads.steer.join().unwrap_or_default();
        let supervisor_joined = self.threads.supervisor.join();
        let supervisor_panicked = supervisor_joined.is_err();
        let (supervisor, supervisor_loop) = match supervisor_joined {
            Ok(result) => result,
            Err(_) => {
                tracing::error!(
                    "the supervisor thread panicked; safe outputs were written as it unwound"
                );
                (Supervisor::new(&self.settings), LoopSummary::default())
            }
        };
        if !link_ok {
            tracing::error!("the camera link thread panicked");
        }
        if let Some(cable) = self.threads.cable {
            let _ = cable.join();
        }
        if let Some(Err(_)) = self.threads.gamepad.map(JoinHandle::join) {
            tracing::error!("the gamepad thread panicked");
        }
        if let Some(Err(_)) = self.threads.gnss.map(JoinHandle::join) {
            tracing::error!("the GNSS link thread panicked");
        }
        let _ = self.threads.load.join();
        if let Some(cable) = self.threads.gnss_cable {
            let _ = cable.join();
        }
        let bus = match self.threads.bus.map(JoinHandle::join) {
            Some(Ok(figures)) => figures,
            Some(Err(_)) => {
                tracing::error!("the bus thread panicked");
                self.bus_figures.snapshot()
            }
            None => BusFigures::default(),
        };
        // The supervisor thread has ended and dropped its tap: the recorder closes the files.
        let record = self.recorder.finish();
        let outside_camera =
            CrossTrackMeaning::of(&self.settings) == CrossTrackMeaning::OutsideCamera;
        RunOutcome {
            supervisor_panicked,
            final_status: *supervisor.status(),
            faults: supervisor.faults().to_vec(),
            notices: supervisor.notices().to_vec(),
            supervisor_loop,
            steer_loop,
            link: self.link_status.snapshot(),
            rt_warnings: self.rt_warnings,
            cross_track: (self.settings.backend == Backend::Sim && !outside_camera)
                .then(|| self.truth.cross_track_summary()),
            cross_track_from_m: self.settings.sim.cross_track_from_m,
            outside_camera,
            record,
            bus,
            bus_endpoints: self.settings.bus.endpoints(),
            steer: self.steer_command.snapshot(),
            gnss: (self.settings.gnss.port != GnssPort::None).then(|| self.gnss_status.snapshot()),
        }
    }
}
