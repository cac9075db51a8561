//! What a field technician checks after each fault, in the words of the fault table of
//! docs/function_spec.md (section 8, its last column): the GUI shows them under the
//! fault, the console's FAULT line and the report carry them, and the refusal of a mode
//! request in Fault repeats them. "Power up to clear it" alone sent the operator round
//! the same fault again.

use std::fmt;

use crate::state::fault_cause::FaultCause;

impl FaultCause {
    /// What to look at, and what to do then, before powering up again.
    pub fn what_to_check(&self) -> &'static str {
        match self {
            FaultCause::EstopFront => {
                "the front emergency stop: release it (or mend its wire), then Power up"
            }
            FaultCause::EstopBack => {
                "the back emergency stop: release it (or mend its wire), then Power up"
            }
            FaultCause::MotorPowerLost => {
                "why the contactor dropped (the fuse, the battery, the e-stop chain), then Power up"
            }
            FaultCause::PowerUpFailed => "the contactor and its relay, then Power up",
            FaultCause::ContactorWelded => {
                "the motor contactor: switch the battery off and replace it (Power up is refused while power stays on)"
            }
            FaultCause::BatteryLow { .. } => "the battery: charge or change it, then Power up",
            FaultCause::PotOutOfRange { .. } => {
                "the steering potentiometer's wire: mend it, then Power up (which calibrates the steering again, standing)"
            }
            FaultCause::PotDisagrees { .. } => {
                "the steering encoder's coupling, then Power up (the steering is calibrated again, standing)"
            }
            FaultCause::BothEndSwitches => {
                "the wiring of the steering end switches: mend it, then Power up"
            }
            FaultCause::EndSwitchUnhandled(_) => {
                "nothing at the robot: a program error; Power up, and report it"
            }
            FaultCause::EndSwitchStuck(_) => {
                "the steering and the end switch: free whichever is stuck, then Power up"
            }
            FaultCause::EncoderStuck(_) => "the encoder and its cable, then Power up",
            FaultCause::SteerWrongWay { .. } | FaultCause::EndSwitchNoBackOff { .. } => {
                "the steering amplifier's motor leads and the steering encoder's wires (docs/robot-pc.md, \"Commissioning\"), then Power up"
            }
            FaultCause::DriveWrongWay { .. } => {
                "that drive's amplifier leads and encoder wires (docs/robot-pc.md, \"Commissioning\"), then Power up"
            }
            FaultCause::DriveSpeed { .. } => {
                "that drive: its brake, its amplifier and [robot] enc_counts_per_m, then Power up"
            }
            FaultCause::UncommandedMotion { .. } => {
                "the amplifiers' offsets and the DDA06's range switches (Test's voltmeter step), then Power up"
            }
            FaultCause::CameraLinkLost { .. } => "the camera computer and its cable, then Power up",
            FaultCause::CameraSeesNoRow { .. } => {
                "where the robot stands: drive it back onto the row in Joystick, then Autonomous"
            }
            FaultCause::TwoRowSources => {
                "which programs send camera rows (the console names both): stop the one that is not the camera, then Power up"
            }
            FaultCause::NoRowSource { .. } => {
                "the camera and the GNSS receiver (docs/gnss.md), then Power up"
            }
            FaultCause::OffTheRow { .. } => {
                "where the robot stands: drive it back onto the row in Joystick, then Autonomous"
            }
            FaultCause::ThreadStopped { .. } => {
                "nothing at the robot (Power up clears it); if it repeats, restart the program"
            }
            FaultCause::ThreadPanicked { .. } => {
                "the log (a program error): restart the program and report it"
            }
            FaultCause::Overruns { .. } => {
                "what else runs on the computer: close other programs (docs/measurements.md, \"Real-time behaviour\"), then Power up"
            }
            FaultCause::LateTick { .. } => {
                "what else runs on the computer: close other programs, then Power up; if it repeats, the I/O cards (`mechweed probe`)"
            }
            FaultCause::JoystickAxis { .. } => {
                "the joystick's wiper and cable: mend them, then Power up"
            }
            FaultCause::Hardware { .. } => "the card (`mechweed probe`), then restart the program",
        }
    }
}

/// The words for a fault that came back this long after the power-up that cleared the
/// same cause, s: the power-up did not mend it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameBack {
    pub after_s: f64,
}

impl fmt::Display for CameBack {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "came back {:.1} s after power-up: its cause is still there, check again",
            self.after_s
        )
    }
}

#[cfg(test)]
mod tests {
    use mechweed_hw::{EncoderId, Side};

    use super::*;
    use crate::rt::health::ThreadName;
    use crate::state::fault_cause::JoystickAxis as Axis;

    const SPEC: &str = include_str!("../../../docs/function_spec.md");

    /// One cause of every kind.
    fn every_cause() -> Vec<FaultCause> {
        use FaultCause::*;
        // A new kind of cause stops this from compiling until it is in the list below.
        let _in_the_list = |c: FaultCause| match c {
            EstopFront | EstopBack | MotorPowerLost | PowerUpFailed | ContactorWelded => (),
            BatteryLow { .. } | PotOutOfRange { .. } | PotDisagrees { .. } => (),
            BothEndSwitches | EndSwitchUnhandled(_) | EndSwitchStuck(_) | EncoderStuck(_) => (),
            SteerWrongWay { .. } | EndSwitchNoBackOff { .. } | DriveWrongWay { .. } => (),
            DriveSpeed { .. } | UncommandedMotion { .. } => (),
            CameraLinkLost { .. } | CameraSeesNoRow { .. } | TwoRowSources => (),
            NoRowSource { .. } | OffTheRow { .. } => (),
            ThreadStopped { .. } | ThreadPanicked { .. } | Overruns { .. } | LateTick { .. } => (),
            JoystickAxis { .. } | Hardware { .. } => (),
        };
        vec![
            EstopFront,
            EstopBack,
            MotorPowerLost,
            PowerUpFailed,
            ContactorWelded,
            BatteryLow { volts: 19.0 },
            PotOutOfRange { volts: 0.1 },
            PotDisagrees {
                pot_deg: 1.0,
                encoder_deg: 9.0,
            },
            BothEndSwitches,
            EndSwitchUnhandled(Side::Left),
            EndSwitchStuck(Side::Right),
            EncoderStuck(EncoderId::Left),
            SteerWrongWay {
                driven_left: true,
                turned_deg: 2.5,
                pot_driven_way: false,
            },
            EndSwitchNoBackOff {
                side: Side::Left,
                moved_deg: 0.0,
            },
            DriveWrongWay {
                wheel: Side::Left,
                forwards: true,
            },
            DriveSpeed {
                wheel: Side::Right,
                speed_mps: 0.9,
                ref_mps: 0.5,
            },
            UncommandedMotion {
                part: EncoderId::Steer,
                moved: 1.5,
            },
            CameraLinkLost { silent_s: 0.5 },
            CameraSeesNoRow { for_s: 0.5 },
            TwoRowSources,
            NoRowSource {
                camera_s: 1.0,
                gnss_s: 1.0,
            },
            OffTheRow { offset_m: 0.3 },
            ThreadStopped {
                thread: ThreadName::Steer,
                for_s: 1.0,
                started: true,
            },
            ThreadPanicked {
                thread: ThreadName::Steer,
            },
            Overruns {
                count: 10,
                window_s: 10.0,
                load: None,
            },
            LateTick {
                late_ms: 300.0,
                limit_ms: 200.0,
                load: None,
            },
            JoystickAxis {
                axis: Axis::Speed,
                volts: 9.0,
            },
            Hardware { card: "PCI-QUAD04" },
        ]
    }

    #[test]
    fn every_cause_says_what_to_check_in_the_words_of_the_function_spec() {
        // The spec's fault table is where a technician looks it up: the words shown
        // with a fault must be the table's, not a second version of them.
        let table: Vec<&str> = SPEC
            .lines()
            .skip_while(|l| !l.starts_with("## 8."))
            .take_while(|l| !l.starts_with("**Refusals**"))
            .filter(|l| l.starts_with('|'))
            .collect();
        for cause in every_cause() {
            let check = cause.what_to_check();
            let row = format!("| {check} |");
            assert!(
                table.iter().any(|l| l.ends_with(&row)),
                "{cause}: \"{check}\" is not the last column of a row of the fault table"
            );
        }
    }

    #[test]
    fn a_fault_that_came_back_says_when_and_to_check_again() {
        let words = CameBack { after_s: 0.62 }.to_string();
        assert_eq!(
            words,
            "came back 0.6 s after power-up: its cause is still there, check again"
        );
    }
}
