//! What the panels draw and where their requests go. A panel sees one `View` (copies
//! of the controller's objects, all from the same instant) and never the controller
//! itself, so it draws the same from any source and can be tested from a `View` made
//! by hand.
//!
//! `ViewSource` is that source: the protected objects of the controller in this
//! process (`Handles`), or the robot's flows on the bus for the operator view on
//! another computer (`remote.rs`, `mechweed watch`), which fills the same `View` and
//! carries the requests the robot takes from the bus.

use std::time::Instant;

use crossbeam_channel::Sender;
use mechweed_hw::sim::Truth;

use crate::bus::BusFigures;
use crate::camlink::LinkStatus;
use crate::gamepad::{PadJoystick, PadState};
use crate::rt::LoopSummary;
use crate::run::Handles;
use crate::state::Reader;
use crate::state::cross_track::CrossTrackMeaning;
use crate::state::modes::Request;
use crate::state::request_channel::Answer;
use crate::state::status::Status;
use crate::steer::SteerCommand;

/// Copies of the controller's objects, taken once per pass: every panel draws the same
/// instant, and no lock is held while drawing.
#[derive(Debug, Clone, Default)]
pub struct View {
    /// Seconds since the controller started, on its clock (the status's `t_s` too).
    pub now_s: f64,
    pub status: Status,
    pub link: LinkStatus,
    pub steer: SteerCommand,
    /// Supervisor and steer loop figures.
    pub loops: [LoopSummary; 2],
    /// The simulated robot's true state.
    pub truth: Truth,
    /// The robot runs on the simulated plant (its panel and its truth are shown).
    pub simulated: bool,
    /// Said in the header while the real robot runs without real-time priorities.
    pub not_realtime: Option<String>,
    /// The bus: what it published and answered, who is there.
    pub bus: BusFigures,
    /// Where the bus listens and connects ([bus] listen and connect).
    pub bus_endpoints: String,
    /// Watching a robot over the bus (`mechweed watch`); None: the controller is here.
    pub remote: Option<RemoteLink>,
    /// The gamepad, when it is the joystick ([joystick] source = gamepad).
    pub gamepad: Option<GamepadView>,
    /// Whether the simulated field's cross-track means anything for this run.
    pub cross_track: CrossTrackMeaning,
}

/// The gamepad as its thread last published it, and its joystick as the supervisor
/// reads it at the view's instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GamepadView {
    pub state: PadState,
    pub joystick: PadJoystick,
}

/// What the operator view on another computer knows of its link to the robot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RemoteLink {
    /// The robot's name on the bus, and where it is reached.
    pub robot: String,
    pub endpoint: String,
    /// How long ago the newest status arrived, s; None: none yet.
    pub age_s: Option<f64>,
    /// How long the view has been waiting for the first status, s.
    pub waited_s: f64,
    /// With no status for this long the robot's mode is not known ([gui]
    /// remote_stale_s), s.
    pub unknown_after_s: f64,
    /// The robot takes power up and modes from the bus ([bus] accept_requests =
    /// operator), or only HALT; None: it has not said yet.
    pub operator: Option<bool>,
    /// The robot's fault and notice, in its words (the flows carry words, not causes).
    pub fault: Option<String>,
    pub notice: Option<String>,
    /// What to check for that fault, and how long after the power-up that cleared the
    /// same cause it came back, s (None from a robot that does not say).
    pub fault_check: Option<String>,
    pub fault_came_back_after_s: Option<f64>,
    /// A tick has come: the inputs (the e-stops) are the robot's, not the defaults.
    pub inputs_seen: bool,
    /// Messages on the flows that could not be read (the first few are logged).
    pub refused: u64,
    /// Messages under a key their subscriber was not for (not taken), and times the
    /// view's session was opened again (bus/hearing.rs).
    pub wrong_key: u64,
    pub reopened: u64,
}

/// Older than this, the robot's status is stale: what the window shows goes grey, s.
pub(crate) const REMOTE_FRESH_S: f64 = 1.0;

impl RemoteLink {
    /// The robot's status is older than a second: what the window shows is stale.
    pub fn stale(&self) -> bool {
        self.age_s.is_none_or(|age_s| age_s > REMOTE_FRESH_S)
    }

    /// No status has come yet: there is nothing to show but that.
    pub(crate) fn no_data(&self) -> bool {
        self.age_s.is_none()
    }

    /// Silent longer than [gui] remote_stale_s: the robot's mode is not known.
    pub(crate) fn mode_unknown(&self) -> bool {
        self.age_s.is_none_or(|age_s| age_s > self.unknown_after_s)
    }

    /// Whole seconds without a status while stale (or waited for the first), for the
    /// pacer: the counter the header shows moves once a second.
    pub(crate) fn silent_whole_s(&self) -> Option<u64> {
        match self.age_s {
            None => Some(self.waited_s as u64),
            Some(age_s) if age_s > REMOTE_FRESH_S => Some(age_s as u64),
            Some(_) => None,
        }
    }
}

/// Where the GUI's `View` comes from and where its requests go.
pub trait ViewSource {
    /// Everything the panels show, as one instant. The source reads its own clock:
    /// `now_s` must be on the clock of the status it delivers.
    fn view(&mut self) -> View;

    /// Queue `request` for the supervisor without waiting; its answer comes later on
    /// `reply`. An error says why it could not even be queued.
    fn send(&self, request: Request, reply: &Sender<Answer>) -> Result<(), String>;

    /// Ask the camera link for a round trip (PING); its result shows in the link status.
    fn ping_link(&self);

    /// Answers that come in words rather than as the supervisor's refusals (the robot's
    /// answers over the bus), each with its request.
    fn answers_in_words(&self) -> Vec<(Request, Result<(), String>)> {
        Vec::new()
    }
}

/// The controller in this process: its protected objects, read without waiting.
impl ViewSource for Handles {
    fn view(&mut self) -> View {
        let [supervisor_loop, steer_loop] = [&self.loops[0], &self.loops[1]].map(Reader::snapshot);
        View {
            now_s: self.clock.elapsed().as_secs_f64(),
            status: self.supervisor.status.snapshot(),
            link: self.link.snapshot(),
            steer: self.steer.snapshot(),
            loops: [supervisor_loop, steer_loop],
            truth: self.truth.truth(),
            simulated: self.sim.is_some(),
            not_realtime: self.not_realtime.clone(),
            bus: self.bus.snapshot(),
            bus_endpoints: self.bus_endpoints.clone(),
            remote: None,
            gamepad: self.gamepad.as_ref().map(|pad| {
                let state = pad.snapshot();
                let joystick = state.pad.joystick(Instant::now());
                GamepadView { state, joystick }
            }),
            cross_track: self.cross_track,
        }
    }

    fn send(&self, request: Request, reply: &Sender<Answer>) -> Result<(), String> {
        self.supervisor.send(request, reply)
    }

    fn ping_link(&self) {
        // One place: a second click before the link thread took the first is one ping.
        let _ = self.ping.try_send(());
    }
}
