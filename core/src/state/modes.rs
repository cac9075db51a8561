//! The robot's modes, the requests other threads send to the supervisor, and why a
//! request can be refused, in words an operator can act on.

use std::fmt;

use mechweed_hw::Outputs;

use crate::config::{PdSettings, PiSettings, SteerSettings};
use crate::state::commission::TestStep;
use crate::state::fault_cause::FaultCause;
use crate::state::sensor_down::SensorDown;

/// The three regulators' gains, as one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    pub left: PiSettings,
    pub right: PiSettings,
    pub steer: PdSettings,
}

impl Gains {
    /// The gains robot.ini gives.
    pub fn from_settings(s: &crate::config::Settings) -> Gains {
        Gains {
            left: s.pid_left,
            right: s.pid_right,
            steer: s.pid_steer,
        }
    }
}

/// What the robot is doing. Halt at start; every fault latches Fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    #[default]
    /// Standing: amplifiers 0 V, brakes on, tool off (motor power may be on).
    Halt,
    /// Driven from the joystick, dead-man button held.
    Joystick,
    /// Following the crop row from the camera.
    Autonomous,
    /// Hardware test panel: outputs set by hand.
    Test,
    /// Latched after a fault: safe outputs until the operator powers up again.
    Fault,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Halt => "halt",
            Mode::Joystick => "joystick",
            Mode::Autonomous => "autonomous",
            Mode::Test => "test",
            Mode::Fault => "fault",
        }
    }

    /// The mode of this name (as `name` writes it), or None.
    pub fn from_name(name: &str) -> Option<Mode> {
        [
            Mode::Halt,
            Mode::Joystick,
            Mode::Autonomous,
            Mode::Test,
            Mode::Fault,
        ]
        .into_iter()
        .find(|m| m.name() == name)
    }

    /// The robot may move in this mode.
    pub fn drives(self) -> bool {
        matches!(self, Mode::Joystick | Mode::Autonomous)
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What another thread (GUI, operator script, command line) asks of the supervisor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Request {
    /// Change mode (Halt is always accepted, except that a fault stays latched).
    Mode(Mode),
    /// Close the motor contactor; after a fault, also clears it if its cause is gone.
    PowerUp,
    /// Hardware test panel: the outputs to write while in Test.
    TestOutputs(Outputs),
    /// Hardware test panel: a person holds (true) or let go of (false) its Hold to run;
    /// a hold counts for supervisor::test_mode::PANEL_HOLD_S unless renewed.
    TestHold(bool),
    /// Hardware test panel: a commissioning step (state/commission.rs).
    TestStep(TestStep),
    /// New regulator gains; taken only in Halt, so that nothing jumps while moving.
    Gains(Gains),
    /// New gains and steering-law parameters together (the GUI's Apply): both are
    /// taken, or neither; only in Halt.
    Tuning(Gains, SteerSettings),
}

/// Why the supervisor said no.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refusal {
    /// A fault is latched (its cause, when the status carries it).
    FaultLatched(Option<FaultCause>),
    CauseStillActive(FaultCause),
    NotPowered,
    /// Power up was accepted and the contactor is still closing.
    PowerComingOn,
    NotCalibrated,
    OnlyFromHalt(Mode),
    NotStanding,
    NotInTest,
    FaultIsNotAMode,
    AlreadyPowered,
    /// In Test the panel's relay switch is the power switch.
    PanelHasThePower,
    /// The voltmeter step needs the contactor open.
    ContactorClosed,
    /// Another commissioning step is running.
    StepRunning,
    OnlyInHalt,
    NotStarted,
    /// A person drives in joystick mode, dead-man held: the bus may not take over.
    PersonAtTheRobot,
    /// Autonomous needs a sensor ([steer] source) that cannot be heard now.
    SensorDown(SensorDown),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::FaultLatched(Some(c)) => {
                write!(
                    f,
                    "a fault is latched ({c}): power up to clear it; what to check: {}",
                    c.what_to_check()
                )
            }
            Refusal::FaultLatched(None) => write!(f, "a fault is latched: power up to clear it"),
            Refusal::CauseStillActive(c) => write!(f, "cannot power up: {c}"),
            Refusal::NotPowered => write!(f, "motor power is off: press Power up first"),
            Refusal::PowerComingOn => write!(
                f,
                "motor power is still coming on (the contactor is closing): ask again when power shows on"
            ),
            Refusal::NotCalibrated => write!(f, "the steering is still being calibrated"),
            Refusal::OnlyFromHalt(m) => {
                write!(f, "this mode can only be entered from halt (now {m})")
            }
            Refusal::NotStanding => write!(f, "the robot is still moving"),
            Refusal::NotInTest => write!(f, "test outputs are only taken in test mode"),
            Refusal::FaultIsNotAMode => {
                write!(f, "fault is entered by the supervisor, not by request")
            }
            Refusal::AlreadyPowered => write!(f, "motor power is already on"),
            Refusal::PanelHasThePower => write!(
                f,
                "in test the panel's main power relay switch is the power switch"
            ),
            Refusal::ContactorClosed => write!(
                f,
                "the voltmeter step needs the contactor open: switch the panel's main power relay off, and wait until motor power shows off"
            ),
            Refusal::StepRunning => write!(f, "a commissioning step is running: stop it first"),
            Refusal::NotStarted => write!(f, "the robot's inputs have not been read yet"),
            Refusal::PersonAtTheRobot => write!(
                f,
                "a person at the robot holds the joystick's dead-man, or let go of it less than 2 s ago: a request over the bus never takes the robot from them into autonomous or test (rule: a person at the robot first)"
            ),
            Refusal::SensorDown(why) => write!(f, "autonomous needs its sensors: {why}"),
            Refusal::OnlyInHalt => write!(
                f,
                "gains and steering-law parameters are changed only in halt, so that nothing jumps while moving"
            ),
        }
    }
}
