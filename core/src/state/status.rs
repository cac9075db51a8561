//! What the supervisor publishes every tick for the other threads (the protected
//! object `Status`), and the faults and notices it keeps for the report.

use mechweed_hw::{Inputs, Outputs, Side};

use crate::state::commission::{MeterReading, StepReport};
use crate::state::fault_cause::FaultCause;
use crate::state::measure::Measured;
use crate::state::modes::Mode;
use crate::state::sensor_down::SensorDown;
use crate::state::steering::Steering;

/// The motor contactor as the supervisor commands it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum PowerState {
    Off,
    /// Relay commanded closed at this time; waiting for motor power to appear.
    Closing {
        since_s: f64,
    },
    On,
}

/// One fault, as the report lists it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultRecord {
    pub cause: FaultCause,
    pub t_s: f64,
    /// Tick that first saw the cause.
    pub tick_seen: u64,
    /// Tick that wrote the safe outputs.
    pub tick_safe: u64,
    /// The same kind of cause latched this soon after the power-up that cleared it, s:
    /// the power-up did not mend it. None: it did not come back.
    pub came_back_after_s: Option<f64>,
}

/// Something the operator should know that is not a fault.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Notice {
    /// The end-switch procedure stopped the robot and steered back off this switch.
    EndSwitchRecovered { side: Side, t_s: f64 },
    /// The tool passed the end of the row: the robot stopped in Halt. Driven in
    /// Autonomous along this row, m.
    RowEnded { driven_m: f64, t_s: f64 },
    /// Test entered: the robot must be on its stand, and nothing moves unless held.
    TestOnStand { t_s: f64 },
    /// A commissioning step in Test ended: what the encoder and potentiometer saw.
    StepDone { report: StepReport, t_s: f64 },
    /// The voltmeter step began: what the meter must read.
    Voltmeter { reading: MeterReading, t_s: f64 },
    /// Autonomous by GNSS or the fused row: these sensors steer from now on.
    /// The sensors that steer changed; `why` names what the others lack.
    Steering {
        steering: Steering,
        why: Option<&'static str>,
        t_s: f64,
    },
}

impl Notice {
    /// When it happened, s since the start of the run.
    pub fn t_s(&self) -> f64 {
        match self {
            Notice::EndSwitchRecovered { t_s, .. }
            | Notice::RowEnded { t_s, .. }
            | Notice::TestOnStand { t_s }
            | Notice::StepDone { t_s, .. }
            | Notice::Voltmeter { t_s, .. }
            | Notice::Steering { t_s, .. } => *t_s,
        }
    }
}

impl std::fmt::Display for Notice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Notice::EndSwitchRecovered { side, .. } => {
                let side = match side {
                    Side::Left => "left",
                    Side::Right => "right",
                };
                write!(
                    f,
                    "the steering hit the {side} end switch: robot stopped, steering moved back off it, now in halt"
                )
            }
            Notice::RowEnded { driven_m, .. } => write!(
                f,
                "end of row after {driven_m:.1} m: the tool passed the row's end, robot stopped, now in halt"
            ),
            Notice::TestOnStand { .. } => write!(
                f,
                "test mode: the robot must be on its stand with the drive wheels off the ground; an amplifier gets the panel's voltage only while Hold to run (or the dead-man) is held"
            ),
            Notice::StepDone { report, .. } => write!(f, "{report}"),
            Notice::Voltmeter { reading, .. } => write!(f, "{reading}"),
            Notice::Steering { steering, why, .. } => {
                write!(f, "steering by {}", steering.words())?;
                match why {
                    Some(why) => write!(f, ": {why}"),
                    None => Ok(()),
                }
            }
        }
    }
}

/// What the supervisor publishes every tick for the other threads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Status {
    pub t_s: f64,
    pub tick: u64,
    pub mode: Mode,
    pub fault: Option<FaultRecord>,
    pub power: PowerState,
    pub inputs: Inputs,
    pub outputs: Outputs,
    pub measured: Measured,
    pub speed_ref_mps: f64,
    pub v_left_ref_mps: f64,
    pub v_right_ref_mps: f64,
    pub wheel_angle_ref_rad: f64,
    /// An end switch closed while driving: latched until the steer thread's
    /// end-switch procedure reports done.
    pub endswitch_hit: Option<Side>,
    pub notice: Option<Notice>,
    /// A fault cause that holds now whatever the mode (an e-stop pressed, ...): power-up
    /// is refused while there is one.
    pub standing_cause: Option<FaultCause>,
    /// A sensor that autonomous mode needs by [steer] source and cannot hear now:
    /// Autonomous is refused while there is one.
    pub sensor_down: Option<SensorDown>,
}

impl Default for Status {
    fn default() -> Self {
        Status {
            t_s: 0.0,
            tick: 0,
            mode: Mode::Halt,
            fault: None,
            power: PowerState::Off,
            inputs: Inputs::default(),
            outputs: Outputs::SAFE,
            measured: Measured::default(),
            speed_ref_mps: 0.0,
            v_left_ref_mps: 0.0,
            v_right_ref_mps: 0.0,
            wheel_angle_ref_rad: 0.0,
            endswitch_hit: None,
            notice: None,
            standing_cause: None,
            sensor_down: None,
        }
    }
}
