//! Why the robot stopped: every fault cause, in words a field technician understands.
//! The checks that find them are in faults/mod.rs.

use std::fmt;

use mechweed_hw::{EncoderId, Side};

use crate::rt::health::ThreadName;
use crate::rt::load::CpuLoad;

/// Why the robot stopped, in words a field technician understands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaultCause {
    EstopFront,
    EstopBack,
    MotorPowerLost,
    PowerUpFailed,
    /// Motor power stayed on after the contactor was commanded open (welded contacts).
    ContactorWelded,
    BatteryLow {
        volts: f64,
    },
    PotOutOfRange {
        volts: f64,
    },
    PotDisagrees {
        pot_deg: f64,
        encoder_deg: f64,
    },
    BothEndSwitches,
    EndSwitchUnhandled(Side),
    EndSwitchStuck(Side),
    EncoderStuck(EncoderId),
    /// The steering turned against the way it was driven (faults/motion.rs).
    SteerWrongWay {
        /// Driven to the left (positive volts).
        driven_left: bool,
        /// How far the encoder saw it turn the wrong way, deg.
        turned_deg: f64,
        /// The potentiometer saw it turn the driven way: the encoder counts backwards.
        pot_driven_way: bool,
    },
    /// Driven off a closed end switch, the steering encoder showed no motion off it.
    EndSwitchNoBackOff {
        side: Side,
        moved_deg: f64,
    },
    /// A drive wheel turned against its speed reference.
    DriveWrongWay {
        wheel: Side,
        forwards: bool,
    },
    /// A drive wheel's speed stayed far from its reference.
    DriveSpeed {
        wheel: Side,
        speed_mps: f64,
        ref_mps: f64,
    },
    /// Something moved, standing with motor power on and 0 V commanded.
    UncommandedMotion {
        part: EncoderId,
        moved: f64,
    },
    CameraLinkLost {
        silent_s: f64,
    },
    CameraSeesNoRow {
        for_s: f64,
    },
    /// Rows from the bus: two programs with the camera's identity send them.
    TwoRowSources,
    /// [steer] source = gnss or fused: neither sensor gives a row to steer by.
    NoRowSource {
        camera_s: f64,
        gnss_s: f64,
    },
    /// [steer] source = gnss or fused: the row filter's row is this far from the robot.
    OffTheRow {
        offset_m: f64,
    },
    /// `started`: whether it had beaten at all (false: it never started).
    ThreadStopped {
        thread: ThreadName,
        for_s: f64,
        started: bool,
    },
    ThreadPanicked {
        thread: ThreadName,
    },
    /// The computer's load at the fault says whether other programs took the CPU.
    Overruns {
        count: u32,
        window_s: f64,
        load: Option<CpuLoad>,
    },
    /// One supervisor tick started this late after its deadline.
    LateTick {
        late_ms: f64,
        limit_ms: f64,
        load: Option<CpuLoad>,
    },
    /// A joystick axis read beyond what the joystick can give: a broken wiper.
    JoystickAxis {
        axis: JoystickAxis,
        volts: f64,
    },
    Hardware {
        card: &'static str,
    },
}

/// The joystick's two axes, for the fault that names one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JoystickAxis {
    Speed,
    Steer,
}

/// "; the computer's load was ...", where it was read.
fn say_load(f: &mut fmt::Formatter<'_>, load: Option<CpuLoad>) -> fmt::Result {
    match load {
        Some(load) => write!(f, "; {load}"),
        None => Ok(()),
    }
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::Left => "left",
        Side::Right => "right",
    }
}

impl fmt::Display for FaultCause {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FaultCause::EstopFront => {
                write!(f, "front emergency stop pressed (or its wire is broken)")
            }
            FaultCause::EstopBack => {
                write!(f, "back emergency stop pressed (or its wire is broken)")
            }
            FaultCause::MotorPowerLost => write!(f, "motor power lost: the motor contactor opened"),
            FaultCause::PowerUpFailed => write!(f, "motor power did not come on after power-up"),
            FaultCause::ContactorWelded => write!(
                f,
                "the motor contactor did not open: motor power stays on although it was switched off (welded contacts?); the watchdog line stops while it does, so a watchdog relay ([io] watchdog) cuts the contactor's coil"
            ),
            FaultCause::BatteryLow { volts } => write!(f, "battery low: {volts:.1} V"),
            FaultCause::PotOutOfRange { volts } => {
                write!(
                    f,
                    "steering potentiometer reads {volts:.2} V: wire broken or loose?"
                )
            }
            FaultCause::PotDisagrees {
                pot_deg,
                encoder_deg,
            } => write!(
                f,
                "steering potentiometer ({pot_deg:.1} deg) and steering encoder ({encoder_deg:.1} deg) disagree"
            ),
            FaultCause::BothEndSwitches => {
                write!(
                    f,
                    "both steering end switches closed at once: check their wiring"
                )
            }
            FaultCause::EndSwitchUnhandled(s) => {
                write!(
                    f,
                    "{} steering end switch closed and the steer thread did not react",
                    side_name(s)
                )
            }
            FaultCause::EndSwitchStuck(s) => write!(
                f,
                "could not steer off the {} end switch: steering jammed or switch stuck",
                side_name(s)
            ),
            FaultCause::EncoderStuck(e) => {
                let which = match e {
                    EncoderId::Left => "left wheel",
                    EncoderId::Right => "right wheel",
                    EncoderId::Steer => "steering",
                };
                write!(
                    f,
                    "{which} encoder does not count while its motor is driven"
                )
            }
            FaultCause::SteerWrongWay {
                driven_left,
                turned_deg,
                pot_driven_way,
            } => {
                let (driven, other) = if driven_left {
                    ("left", "right")
                } else {
                    ("right", "left")
                };
                if pot_driven_way {
                    write!(
                        f,
                        "the steering encoder counts the wrong way: driven {driven}, the potentiometer saw the steering turn {driven} but the encoder {turned_deg:.1} deg {other}: its A and B wires may be swapped"
                    )
                } else {
                    write!(
                        f,
                        "the steering turns the wrong way: driven {driven}, it turned {turned_deg:.1} deg {other}: the steering amplifier's motor leads may be swapped"
                    )
                }
            }
            FaultCause::EndSwitchNoBackOff { side, moved_deg } => write!(
                f,
                "driven off the {} end switch, the steering encoder saw it move {moved_deg:.1} deg off: the steering amplifier's or encoder's wires may be swapped, or the steering is jammed",
                side_name(side)
            ),
            FaultCause::DriveWrongWay { wheel, forwards } => {
                let (driven, turns) = if forwards {
                    ("forwards", "backwards")
                } else {
                    ("backwards", "forwards")
                };
                write!(
                    f,
                    "the {} drive turns {turns} when driven {driven}: its amplifier's or its encoder's wires may be swapped",
                    side_name(wheel)
                )
            }
            FaultCause::DriveSpeed {
                wheel,
                speed_mps,
                ref_mps,
            } => {
                let why = if speed_mps.abs() > ref_mps.abs() {
                    "too fast: its encoder counts too few ([robot] enc_counts_per_m?) or its amplifier gives too much"
                } else {
                    "too slow: a brake still on, the wheel jammed, or its amplifier limited"
                };
                write!(
                    f,
                    "the {} drive turns at {speed_mps:.2} m/s, asked for {ref_mps:.2} m/s: {why}",
                    side_name(wheel)
                )
            }
            FaultCause::UncommandedMotion { part, moved } => {
                let what = match part {
                    EncoderId::Left => format!("the left wheel moved {:.0} mm", moved * 1e3),
                    EncoderId::Right => format!("the right wheel moved {:.0} mm", moved * 1e3),
                    EncoderId::Steer => format!("the steering turned {moved:.1} deg"),
                };
                write!(
                    f,
                    "uncommanded motion: {what} with motor power on and 0 V commanded: an amplifier's offset, or a DDA06 range switch that differs from [hw] dda06_ranges_v"
                )
            }
            FaultCause::CameraLinkLost { silent_s } => {
                write!(f, "camera link lost: no row frame for {silent_s:.2} s")
            }
            FaultCause::CameraSeesNoRow { for_s } => {
                write!(f, "camera sees no row: no usable estimate for {for_s:.2} s")
            }
            FaultCause::TwoRowSources => write!(
                f,
                "two programs send camera rows (the console names both): the rows of neither are taken"
            ),
            FaultCause::OffTheRow { offset_m } => write!(
                f,
                "the robot is off its row: the row is {:.0} cm to its {} (steering by GNSS or the fused row)",
                offset_m.abs() * 100.0,
                if offset_m > 0.0 { "left" } else { "right" }
            ),
            FaultCause::NoRowSource { camera_s, gnss_s } => write!(
                f,
                "no row to steer by: the camera has given no usable row for {camera_s:.2} s and GNSS no fix it may steer by for {gnss_s:.2} s (the notice before says why)"
            ),
            FaultCause::ThreadStopped {
                thread,
                for_s,
                started: true,
            } => write!(
                f,
                "the {} thread stopped: no sign of life for {for_s:.2} s",
                thread.label()
            ),
            FaultCause::ThreadStopped {
                thread,
                for_s,
                started: false,
            } => write!(
                f,
                "the {} thread did not start: no sign of life {for_s:.2} s after the controller started",
                thread.label()
            ),
            FaultCause::ThreadPanicked { thread } => {
                write!(
                    f,
                    "the {} thread failed (a program error): see the log",
                    thread.label()
                )
            }
            FaultCause::Overruns {
                count,
                window_s,
                load,
            } => {
                write!(
                    f,
                    "the supervisor missed {count} deadlines within {window_s:.0} s"
                )?;
                say_load(f, load)
            }
            FaultCause::LateTick {
                late_ms,
                limit_ms,
                load,
            } => {
                write!(
                    f,
                    "the supervisor stalled: one tick started {late_ms:.0} ms late (limit {limit_ms:.0} ms)"
                )?;
                say_load(f, load)
            }
            FaultCause::JoystickAxis { axis, volts } => {
                let which = match axis {
                    JoystickAxis::Speed => "speed",
                    JoystickAxis::Steer => "steer",
                };
                write!(
                    f,
                    "joystick {which} axis reads {volts:.2} V, beyond its full scale: wiper broken or loose?"
                )
            }
            FaultCause::Hardware { card } => write!(f, "I/O card {card} stopped answering"),
        }
    }
}
