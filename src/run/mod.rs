//! The product: the controller on real threads and real time. The supervisor thread
//! owns the hardware; the steer thread and the camera-link thread each own their own
//! state; they meet only through protected objects (state.rs) and bounded channels.

mod realtime;
mod robot;
mod types;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Instant;

use crossbeam_channel::bounded;
use mechweed_hw::Hw;
use mechweed_hw::sim::TruthHandle;

use crate::bus::BusFigures;
use crate::bus::rows::{BusRows, RowCounts};
use crate::bus::thread::BusWires;
use crate::camlink::thread::{LinkThread, LinkWires, READ_TIMEOUT};
use crate::camlink::{LinkCore, LinkStatus};
use crate::config::{Backend, JoystickSource, Settings};
use crate::config::{CameraPort, GnssPort};
use crate::gamepad::{self, PadHw, PadState};
use crate::record::{self, RecordTap, Recorder};
use crate::rt::LoopSummary;
use crate::rt::health::{self, PanicFlag, ThreadName};
use crate::state::cross_track::CrossTrackMeaning;
use crate::state::modes::Gains;
use crate::state::request_channel;
use crate::state::status::Status;
use crate::state::{self, Reader, shared};
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;
use realtime::rt_setup;
use robot::{camera_port, open_robot};

use crate::threads::{SteerThread, SteerWires, SupervisorThread, SupervisorWires};
pub use realtime::not_realtime;
pub use types::{Handles, RunError, RunOptions, RunOutcome};

fn spawn<T: Send + 'static>(name: &str, f: impl FnOnce() -> T + Send + 'static) -> JoinHandle<T> {
    std::thread::Builder::new()
        .name(name.to_string())
        .spawn(f)
        .unwrap_or_else(|e| panic!("cannot start the {name} thread: {e}"))
}

/// Ticks waiting for the bus thread: it publishes each as it comes, so a second's worth
/// is plenty; when full, ticks are dropped and counted.
const BUS_QUEUE_TICKS: usize = 64;

/// The controller's threads while they run; `finish` stops them and collects the outcome.
pub struct Running {
    supervisor: JoinHandle<(Supervisor, LoopSummary)>,
    steer: JoinHandle<LoopSummary>,
    link: JoinHandle<()>,
    bus: Option<JoinHandle<BusFigures>>,
    bus_figures: Reader<BusFigures>,
    cable: Option<JoinHandle<()>>,
    gamepad: Option<JoinHandle<()>>,
    gnss: Option<JoinHandle<()>>,
    gnss_cable: Option<JoinHandle<()>>,
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

/// Start the controller's threads; the caller is the operator interface (console or
/// GUI) and calls `Running::finish` at the end. The steps that can fail come first and
/// start nothing a failure would leave behind; the threads start last.
pub fn start(opts: &RunOptions, stop: Arc<AtomicBool>) -> Result<(Handles, Running), RunError> {
    let s = &opts.settings;
    // 1. The robot, the row map with the GNSS receiver's line, the camera's port.
    let robot = open_robot(s)?;
    let mut gnss = crate::gnss::run::prepare(s, robot.receiver, robot.planted, &stop)?;
    let (camera_port, cable) = camera_port(s, robot.camera_line, &stop)?;
    let truth = robot.truth;

    // 2. Real time, the panic watch, the record and the bus.
    let clock = Instant::now();
    let (rt_warnings, priorities_refused) = rt_setup(&s.rt);
    let priority = |p: u8| if priorities_refused.is_some() { 0 } else { p };
    let panics = Arc::new(PanicFlag::default());
    health::watch_this_thread(&panics, ThreadName::Console);
    let (record_tap, recorder) = record::start_for_run(s, truth.clone());
    let bus_session = crate::bus::open_for_run(s).map_err(RunError::Bus)?;

    // 3. What the threads meet through: protected objects and bounded channels.
    let (status_w, status_r) = shared(Status::default());
    let (steer_w, steer_r) = shared(SteerCommand::default());
    let (link_w, link_r) = shared(LinkStatus::default());
    let (gui_beat_w, gui_beat_r) = shared(f64::NAN);
    let (steer_settings_w, steer_settings_r) = shared(s.steer);
    let (tuning_w, tuning_r) = shared((Gains::from_settings(s), s.steer));
    let (estimate_tx, estimate_rx) = bounded(1);
    let (ping_tx, ping_rx) = bounded(1);
    let (new_steer_settings_tx, new_steer_settings_rx) = state::mailbox();
    let (supervisor_figures_w, supervisor_figures) = shared(LoopSummary::default());
    let (steer_figures_w, steer_figures) = shared(LoopSummary::default());
    let (handle, request_rx) = request_channel::channel(status_r.clone());
    let (bus_figures_w, bus_figures) = shared(BusFigures::default());
    let row_counts = Arc::new(RowCounts::default());
    let (bus_tap, bus_flow) = match &bus_session {
        Some(_) => {
            let (tap, flow) = record::flow(s.bus.tick_every_n, BUS_QUEUE_TICKS, truth.clone());
            (tap, Some(flow))
        }
        None => (RecordTap::off(), None),
    };

    // 4. Each thread with its wires. The camera link is the last step that can fail
    //    (rows from the bus); the gamepad thread starts after it.
    let steer = SteerThread::new(
        SteerCore::with_map(s, gnss.place.take()),
        s.steer.rate_hz,
        clock,
        SteerWires {
            new_estimate: estimate_rx,
            command: steer_w,
            status: status_r.clone(),
            link: link_r.clone(),
            gnss: gnss.status.clone(),
            figures: steer_figures_w,
            new_settings: new_steer_settings_rx,
            settings: steer_settings_w,
            panics: panics.clone(),
            stop: stop.clone(),
        },
    )
    .with_priority(priority(s.rt.steer_priority))
    .with_injection(opts.inject);
    let link_wires = LinkWires {
        new_estimate: estimate_tx,
        ping_requests: ping_rx,
        status: link_w,
        robot: status_r.clone(),
        panics: panics.clone(),
        stop: stop.clone(),
    };
    let link = LinkThread::new(LinkCore::new(&s.camera), camera_port, clock, link_wires)
        .with_priority(priority(s.rt.camlink_priority))
        .with_injection(opts.inject);
    let link = with_rows_from_the_bus(link, s, bus_session.as_ref(), &row_counts)?;
    let (hw, gamepad, gamepad_thread) = with_gamepad(robot.hw, s, &panics, &stop);
    let supervisor_wires = SupervisorWires {
        requests: request_rx,
        status: status_w,
        steer: steer_r.clone(),
        link: link_r.clone(),
        gui_beat: gui_beat_r,
        steer_settings: new_steer_settings_tx,
        tuning: tuning_w,
        figures: supervisor_figures_w,
        record: record_tap,
        bus: bus_tap,
        panics: panics.clone(),
        stop: stop.clone(),
    };
    let supervisor = SupervisorThread::new(
        hw,
        Supervisor::new(s),
        s.supervisor.rate_hz,
        clock,
        supervisor_wires,
    )
    .with_priority(priority(s.rt.supervisor_priority), s.rt.supervisor_cpu)
    .with_injection(opts.inject);

    // 5. Start them.
    let bus = bus_session.zip(bus_flow).map(|(session, flow)| {
        let wires = BusWires {
            status: status_r.clone(),
            link: link_r.clone(),
            steer: steer_r.clone(),
            loops: [supervisor_figures.clone(), steer_figures.clone()],
            flow,
            supervisor: handle.clone(),
            tuning: tuning_r,
            figures: bus_figures_w,
            rows: row_counts,
            stop: stop.clone(),
        };
        start_bus(session, s.clone(), wires, panics.clone())
    });
    let supervisor = spawn("supervisor", move || supervisor.run());
    let steer = spawn("steer", move || steer.run());
    let link = spawn("camlink", move || link.run());
    let gnss_thread = gnss.start(clock, panics.clone(), stop.clone());

    // 6. What the operator interface reads, and what `finish` stops.
    let handles = Handles {
        supervisor: handle,
        link: link_r.clone(),
        loops: [supervisor_figures, steer_figures],
        truth: truth.clone(),
        sim: robot.sim,
        ping: ping_tx,
        gui_beat: gui_beat_w,
        steer_settings: steer_settings_r,
        steer: steer_r.clone(),
        clock,
        not_realtime: not_realtime(s.backend, &s.rt, priorities_refused.as_deref()),
        bus: bus_figures.clone(),
        bus_endpoints: s.bus.endpoints(),
        gamepad,
        cross_track: CrossTrackMeaning::of(s),
    };
    let running = Running {
        supervisor,
        steer,
        link,
        bus,
        bus_figures,
        cable,
        gamepad: gamepad_thread,
        gnss_status: gnss.status.clone(),
        steer_command: steer_r,
        gnss: gnss_thread,
        gnss_cable: gnss.cable.take(),
        link_status: link_r,
        truth,
        settings: s.clone(),
        rt_warnings,
        recorder,
        panics,
        stop,
    };
    Ok((handles, running))
}

/// With `[camera] port = bus`, the camera link reads its rows from the bus instead of a
/// port; a subscription that fails is the run's error.
fn with_rows_from_the_bus(
    link: LinkThread,
    s: &Settings,
    session: Option<&zenoh::Session>,
    row_counts: &Arc<RowCounts>,
) -> Result<LinkThread, RunError> {
    let (CameraPort::Bus, Some(session)) = (&s.camera_port, session) else {
        return Ok(link);
    };
    let rows = BusRows::subscribe(
        session,
        &s.bus.key("camera/row"),
        READ_TIMEOUT,
        s.camera.link_timeout_s,
        row_counts.clone(),
    )
    .map_err(|e| RunError::BusRows(e.to_string()))?;
    Ok(link.with_stream(Box::new(rows), row_counts.rivals.clone()))
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

/// The bus thread; a bus that stops with an error is said, and its figures are zero.
fn start_bus(
    session: zenoh::Session,
    settings: Settings,
    wires: BusWires,
    panics: Arc<PanicFlag>,
) -> JoinHandle<BusFigures> {
    spawn("bus", move || {
        health::watch_this_thread(&panics, ThreadName::Bus);
        crate::bus::thread::run(session, &settings, wires).unwrap_or_else(|e| {
            tracing::error!("the bus stopped: {e}");
            BusFigures::default()
        })
    })
}

impl Running {
    /// Name the calling thread in this run's panic reports (the main thread is the
    /// console unless it says otherwise, e.g. the GUI).
    pub fn watch_this_thread_as(&self, name: ThreadName) {
        health::watch_this_thread(&self.panics, name);
    }

    /// A controller thread has ended although the run was not stopped.
    pub fn any_thread_ended(&self) -> bool {
        self.supervisor.is_finished() || self.steer.is_finished() || self.link.is_finished()
    }

    /// Stop the threads (the supervisor writes the safe outputs) and collect the outcome.
    pub fn finish(self) -> RunOutcome {
        self.stop.store(true, Ordering::Relaxed);
        let link_ok = self.link.join().is_ok();
        let steer_loop = self.steer.join().unwrap_or_default();
        let (supervisor, supervisor_loop) = match self.supervisor.join() {
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
        if let Some(cable) = self.cable {
            let _ = cable.join();
        }
        if let Some(Err(_)) = self.gamepad.map(JoinHandle::join) {
            tracing::error!("the gamepad thread panicked");
        }
        if let Some(Err(_)) = self.gnss.map(JoinHandle::join) {
            tracing::error!("the GNSS link thread panicked");
        }
        if let Some(cable) = self.gnss_cable {
            let _ = cable.join();
        }
        let bus = match self.bus.map(JoinHandle::join) {
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
            final_status: *supervisor.status(),
            faults: supervisor.faults().to_vec(),
            notices: supervisor.notices().to_vec(),
            supervisor_loop,
            steer_loop,
            link: self.link_status.snapshot(),
            rt_warnings: self.rt_warnings,
            cross_track: (self.settings.backend == Backend::Sim && !outside_camera)
                .then(|| self.truth.cross_track().summary()),
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
