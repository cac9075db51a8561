//! The robot's modes, the requests other threads send to the supervisor, and why a
//! request can be refused, in words an operator can act on.

use std::fmt;

use mechweed_hw::Outputs;

use crate::config::{PdSettings, PiSettings, SteerSettings};
use crate::faults::{FaultCause, PowerState};
use crate::supervisor::Status;

/// The three regulators' gains, as one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    pub left: PiSettings,
    pub right: PiSettings,
    pub steer: PdSettings,
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
    NotCalibrated,
    OnlyFromHalt(Mode),
    NotStanding,
    NotInTest,
    FaultIsNotAMode,
    AlreadyPowered,
    OnlyInHalt,
    NotStarted,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::FaultLatched(Some(c)) => {
                write!(f, "a fault is latched ({c}): power up to clear it")
            }
            Refusal::FaultLatched(None) => write!(f, "a fault is latched: power up to clear it"),
            Refusal::CauseStillActive(c) => write!(f, "cannot power up: {c}"),
            Refusal::NotPowered => write!(f, "motor power is off: press Power up first"),
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
            Refusal::NotStarted => write!(f, "the robot's inputs have not been read yet"),
            Refusal::OnlyInHalt => write!(
                f,
                "gains and steering-law parameters are changed only in halt, so that nothing jumps while moving"
            ),
        }
    }
}

/// Below this the robot counts as standing, m/s.
pub const STANDING_MPS: f64 = 0.01;

/// The supervisor's rule for a mode request: why it would refuse `wanted` now, or None.
/// The supervisor decides with it, and the GUI asks it to grey out a button and say why,
/// so that the two never disagree.
pub fn mode_refusal(wanted: Mode, st: &Status) -> Option<Refusal> {
    if st.tick == 0 {
        return Some(Refusal::NotStarted);
    }
    match wanted {
        Mode::Fault => Some(Refusal::FaultIsNotAMode),
        _ if st.mode == Mode::Fault => Some(Refusal::FaultLatched(st.fault.map(|f| f.cause))),
        Mode::Halt => None,
        Mode::Test if st.mode != Mode::Halt => Some(Refusal::OnlyFromHalt(st.mode)),
        Mode::Test if st.measured.speed_mps.abs() > STANDING_MPS => Some(Refusal::NotStanding),
        Mode::Test => None,
        // Joystick or Autonomous: from Halt, or switching between the two.
        _ if !(st.mode == Mode::Halt || st.mode.drives()) => Some(Refusal::OnlyFromHalt(st.mode)),
        _ if st.power != PowerState::On => Some(Refusal::NotPowered),
        _ if !st.measured.calibrated => Some(Refusal::NotCalibrated),
        _ => None,
    }
}

/// The supervisor's rule for `PowerUp`: why it would refuse now, or None.
pub fn power_up_refusal(st: &Status) -> Option<Refusal> {
    if st.tick == 0 {
        return Some(Refusal::NotStarted);
    }
    if let Some(cause) = st.standing_cause {
        return Some(Refusal::CauseStillActive(cause));
    }
    if st.mode != Mode::Fault && st.power != PowerState::Off {
        return Some(Refusal::AlreadyPowered);
    }
    None
}

/// Why the operator cannot have `wanted` now, in words; None if the supervisor would take it.
pub fn why_not(wanted: Mode, st: &Status) -> Option<String> {
    mode_refusal(wanted, st).map(|r| r.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn why_not_says_what_the_supervisor_would_refuse() {
        let mut st = Status::default();
        assert_eq!(mode_refusal(Mode::Halt, &st), Some(Refusal::NotStarted));
        assert_eq!(power_up_refusal(&st), Some(Refusal::NotStarted));
        st.tick = 1;
        assert_eq!(
            why_not(Mode::Autonomous, &st).as_deref(),
            Some("motor power is off: press Power up first")
        );
        assert_eq!(why_not(Mode::Test, &st), None, "test needs no power");
        assert_eq!(why_not(Mode::Halt, &st), None);
        st.power = PowerState::On;
        assert_eq!(
            why_not(Mode::Joystick, &st).as_deref(),
            Some("the steering is still being calibrated")
        );
        st.measured.calibrated = true;
        assert_eq!(why_not(Mode::Joystick, &st), None);
        assert_eq!(power_up_refusal(&st), Some(Refusal::AlreadyPowered));
        st.mode = Mode::Autonomous;
        st.measured.speed_mps = 0.5;
        assert_eq!(
            mode_refusal(Mode::Test, &st),
            Some(Refusal::OnlyFromHalt(Mode::Autonomous))
        );
        st.mode = Mode::Halt;
        assert_eq!(mode_refusal(Mode::Test, &st), Some(Refusal::NotStanding));
        st.mode = Mode::Fault;
        st.standing_cause = Some(FaultCause::EstopBack);
        assert_eq!(
            power_up_refusal(&st),
            Some(Refusal::CauseStillActive(FaultCause::EstopBack))
        );
        assert!(
            why_not(Mode::Halt, &st)
                .unwrap()
                .starts_with("a fault is latched")
        );
    }
}
