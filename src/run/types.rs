//! What a run is given, what its operator interface holds while it runs, and what it
//! leaves behind.

use std::time::Instant;

use crossbeam_channel::Sender;
use mechweed_hw::sim::{CrossTrackSummary, SimControl, TruthHandle};

use crate::bus::BusFigures;
use crate::camlink::LinkStatus;
use crate::config::{Settings, SteerSettings};
use crate::gamepad::PadState;
use crate::record::RecordOutcome;
use crate::rt::LoopSummary;
use crate::rt::inject::Injection;
use crate::state::modes::Mode;
use crate::state::request_channel::SupervisorHandle;
use crate::state::status::{FaultRecord, Notice, Status};
use crate::state::{Reader, Writer};
use crate::steer::SteerCommand;

/// What an operator interface (the console or the GUI) reads and sends.
pub struct Handles {
    pub supervisor: SupervisorHandle,
    pub link: Reader<LinkStatus>,
    /// Loop figures of the supervisor and the steer thread, about once a second.
    pub loops: [Reader<LoopSummary>; 2],
    pub truth: TruthHandle,
    /// The simulated robot's buttons, joystick and faults (None on real hardware).
    pub sim: Option<SimControl>,
    /// Ask the camera link for a PING (its round trip shows in LinkStatus).
    pub ping: Sender<()>,
    /// The GUI's heartbeat, s since start: NaN until the GUI first beats; from then on
    /// the supervisor watches it (`ThreadHealth::gui_beat_s`).
    pub gui_beat: Writer<f64>,
    /// The steer thread's steering-law parameters as they are now.
    pub steer_settings: Reader<SteerSettings>,
    /// The steer thread's figures of the steering law (for plots).
    pub steer: Reader<SteerCommand>,
    pub clock: Instant,
    /// Said in the status line and the GUI's header while the real robot runs without
    /// real-time priorities.
    pub not_realtime: Option<String>,
    /// The bus's figures, about ten times a second (state Off without a bus).
    pub bus: Reader<BusFigures>,
    /// Where the bus listens and connects, for the GUI ("" without a bus).
    pub bus_endpoints: String,
    /// The gamepad ([joystick] source = gamepad), as the supervisor reads it.
    pub gamepad: Option<Reader<PadState>>,
    /// Whether the simulated field's cross-track means anything in this run.
    pub cross_track: crate::state::cross_track::CrossTrackMeaning,
}

pub struct RunOptions {
    pub settings: Settings,
    pub start_mode: Mode,
    pub duration_s: Option<f64>,
    /// Print a status line this often, s (0 = never).
    pub status_every_s: f64,
    /// For tests: make one thread fail on purpose.
    pub inject: Option<Injection>,
}

impl RunOptions {
    /// Standing in Halt until the operator asks, with no time limit and no status line:
    /// how the GUI starts (and restarts) a controller.
    pub fn in_halt(settings: Settings) -> RunOptions {
        RunOptions {
            settings,
            start_mode: Mode::Halt,
            duration_s: None,
            status_every_s: 0.0,
            inject: None,
        }
    }
}

/// Why a run could not start (nothing has started then).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The I/O cards could not be found or opened (every card's problem, one per line).
    #[error("{0}")]
    Cards(mechweed_hw::OpenError),
    #[error("cannot make a pseudo-terminal for the simulated camera computer: {0}")]
    SimulatedCameraWire(std::io::Error),
    #[error(
        "[camera] port = sim needs the simulated robot: set [camera] port to the camera computer's serial device (e.g. /dev/ttyS0) or tcp://HOST:PORT"
    )]
    SimulatedCameraOnRealRobot,
    #[error("{0}")]
    Bus(crate::bus::BusError),
    #[error("{0}")]
    Gnss(#[from] crate::gnss::run::GnssRunError),
}

/// What a run leaves behind for the report.
pub struct RunOutcome {
    /// The supervisor thread panicked (its safe outputs were written as it unwound): the
    /// run ended as badly as in a fault, whatever `final_status` says.
    pub supervisor_panicked: bool,
    pub final_status: Status,
    pub faults: Vec<FaultRecord>,
    pub notices: Vec<Notice>,
    pub supervisor_loop: LoopSummary,
    pub steer_loop: LoopSummary,
    pub link: LinkStatus,
    /// Warnings about real-time settings the system refused.
    pub rt_warnings: Vec<String>,
    /// The tool's cross-track figures (None on the real robot: nothing knows the row there).
    pub cross_track: Option<CrossTrackSummary>,
    /// The figures leave out the travel before this distance, m.
    pub cross_track_from_m: f64,
    /// The simulated robot with an outside camera: the field's cross-track is not
    /// meaningful, and `cross_track` is None.
    pub outside_camera: bool,
    pub record: RecordOutcome,
    /// What the bus did (state Off if there was none).
    pub bus: BusFigures,
    /// Where the bus listened and connected, in words.
    pub bus_endpoints: String,
    /// The steer thread's last command: which sensors steered, the row filter's figures.
    pub steer: crate::steer::SteerCommand,
    /// The GNSS link at the end (None without a receiver).
    pub gnss: Option<crate::gnss::GnssStatus>,
}
