//! The product: the controller on real threads and real time. The supervisor thread
//! owns the hardware; the steer thread and the camera-link thread each own their own
//! state; they meet only through protected objects (state.rs) and bounded channels.

mod realtime;
mod types;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Instant;

use crossbeam_channel::bounded;
use mechweed_hw::Hw;
use mechweed_hw::sim::{SimControl, SimHw, SimRobot, TruthHandle, byte_pipe};

use crate::bus::BusFigures;
use crate::bus::rows::{BusRows, RowCounts};
use crate::bus::thread::BusWires;
use crate::camlink::thread::{LinkThread, LinkWires, READ_TIMEOUT};
use crate::camlink::{LinkCore, LinkStatus, simwire};
use crate::config::{Backend, JoystickSource, Settings};
use crate::config::{CameraPort, GnssPort};
use crate::cross_track::CrossTrackMeaning;
use crate::gamepad::{self, PadHw};
use crate::health::{self, PanicFlag, ThreadName};
use crate::modes::Gains;
use crate::record::{self, RecordTap, Recorder};
use crate::request_channel;
use crate::rt::LoopSummary;
use crate::state::{self, Reader, shared};
use crate::status::Status;
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;
use realtime::rt_setup;

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

/// Start the controller's threads on the simulated robot; the caller is the operator
/// interface (console or GUI) and calls `Running::finish` at the end.
pub fn start(opts: &RunOptions, stop: Arc<AtomicBool>) -> Result<(Handles, Running), RunError> {
    let s = &opts.settings;
    let (camera_end, robot_end) = byte_pipe(4096);
    let (mut receiver, mut planted) = (None, None);
    let (hw, truth, sim_control): (Box<dyn Hw>, TruthHandle, Option<SimControl>) = match s.backend {
        Backend::Sim => {
            let mut receiver_end = None;
            if s.gnss.port == GnssPort::Link(CameraPort::Sim) {
                let (robot_end, program_end) = byte_pipe(8192);
                receiver_end = Some(robot_end);
                receiver = Some(program_end);
            }
            let robot = SimRobot::with_gnss(&s.sim, camera_end, receiver_end);
            if s.gnss.port != GnssPort::None {
                planted = Some(robot.planted_map());
            }
            let sim = SimHw::new(robot);
            let (truth, control) = (sim.truth_handle(), sim.control());
            (Box::new(sim), truth, Some(control))
        }
        // No simulated camera computer, no truth and no simulator panel on the real robot.
        Backend::Cards => (
            crate::backend::open_hw(s).map_err(RunError::Cards)?,
            TruthHandle::none(),
            None,
        ),
    };
    // The row map and the GNSS receiver's line, before anything starts that an error
    // here would leave behind (the record).
    let mut gnss = crate::gnss::run::prepare(s, receiver, planted, &stop)?;
    // The simulated camera computer speaks through a pseudo-terminal, unless robot.ini
    // names a real port: then it stays unplugged and the port's camera computer is used.
    let (camera_port, cable) = match (&s.camera_port, s.backend) {
        (CameraPort::Sim, Backend::Sim) => {
            let (path, cable) =
                simwire::start(robot_end, stop.clone()).map_err(RunError::SimulatedCameraWire)?;
            (CameraPort::Serial { path, baud: 115200 }, Some(cable))
        }
        (CameraPort::Sim, Backend::Cards) => {
            return Err(RunError::SimulatedCameraOnRealRobot);
        }
        (port, _) => (port.clone(), None),
    };
    let clock = Instant::now();
    let (rt_warnings, priorities_refused) = rt_setup(&s.rt);
    let priority = |p: u8| if priorities_refused.is_some() { 0 } else { p };
    let panics = Arc::new(PanicFlag::default());
    health::watch_this_thread(&panics, ThreadName::Console);
    let (record_tap, recorder) = record::start_for_run(s, truth.clone());
    let bus_session = crate::bus::open_for_run(s).map_err(RunError::Bus)?;

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

    let wires = SupervisorWires {
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
    let supervisor_wires = wires;
    let wires = SteerWires {
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
    };
    let steer = SteerThread::new(
        SteerCore::with_map(s, gnss.place.take()),
        s.steer.rate_hz,
        clock,
        wires,
    )
    .with_priority(priority(s.rt.steer_priority))
    .with_injection(opts.inject);
    let wires = LinkWires {
        new_estimate: estimate_tx,
        ping_requests: ping_rx,
        status: link_w,
        robot: status_r.clone(),
        panics: panics.clone(),
        stop: stop.clone(),
    };
    let mut link = LinkThread::new(LinkCore::new(&s.camera), camera_port, clock, wires)
        .with_priority(priority(s.rt.camlink_priority))
        .with_injection(opts.inject);
    if let (CameraPort::Bus, Some(session)) = (&s.camera_port, &bus_session) {
        let rows = BusRows::subscribe(
            session,
            &s.bus.key("camera/row"),
            READ_TIMEOUT,
            s.camera.link_timeout_s,
            row_counts.clone(),
        )
        .map_err(|e| RunError::BusRows(e.to_string()))?;
        link = link.with_stream(Box::new(rows), row_counts.rivals.clone());
    }
    // A gamepad in place of the wired joystick: the supervisor reads it with the inputs.
    // Started after the last step that can fail, so that no error leaves it running.
    let (hw, gamepad, gamepad_thread) = match s.joystick.source {
        JoystickSource::Analog => (hw, None, None),
        JoystickSource::Gamepad => {
            let (pad, thread) = gamepad::start(s, panics.clone(), stop.clone());
            let hw: Box<dyn Hw> = Box::new(PadHw::new(hw, pad.clone()));
            (hw, Some(pad), Some(thread))
        }
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
    let bus = match (bus_session, bus_flow) {
        (Some(session), Some(flow)) => {
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
            let settings = s.clone();
            let panics = panics.clone();
            Some(spawn("bus", move || {
                health::watch_this_thread(&panics, ThreadName::Bus);
                crate::bus::thread::run(session, &settings, wires).unwrap_or_else(|e| {
                    tracing::error!("the bus stopped: {e}");
                    BusFigures::default()
                })
            }))
        }
        _ => None,
    };
    let supervisor = spawn("supervisor", move || supervisor.run());
    let steer = spawn("steer", move || steer.run());
    let link = spawn("camlink", move || link.run());
    let gnss_thread = gnss.start(clock, panics.clone(), stop.clone());

    let handles = Handles {
        supervisor: handle,
        link: link_r.clone(),
        loops: [supervisor_figures, steer_figures],
        truth: truth.clone(),
        sim: sim_control,
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
        steer_command: steer_r.clone(),
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
