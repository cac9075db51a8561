//! Every fault check of the supervisor, in one place, in the order they are checked.
//!
//! The supervisor calls `FaultChecks::check` once per tick with what it has just read;
//! the first cause found latches the Fault mode and safe outputs in that same tick.
//! Checks that must see a condition for some time (a battery sagging, an encoder not
//! counting) keep a timer here; their times are settings in robot.ini [faults].

use std::fmt;

use mechweed_hw::Inputs;
use mechweed_hw::sim::{EncoderId, Side};

use crate::camlink::LinkStatus;
use crate::config::{CameraSettings, FaultSettings, RtSettings};
use crate::health::{ThreadHealth, ThreadName};
use crate::measure::Measured;
use crate::modes::Mode;
use crate::steer::{EndSwitchState, SteerCommand};

/// Why the robot stopped, in words a field technician understands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaultCause {
    EstopFront,
    EstopBack,
    MotorPowerLost,
    PowerUpFailed,
    BatteryLow { volts: f64 },
    PotOutOfRange { volts: f64 },
    PotDisagrees { pot_deg: f64, encoder_deg: f64 },
    BothEndSwitches,
    EndSwitchUnhandled(Side),
    EndSwitchStuck(Side),
    EncoderStuck(EncoderId),
    CameraLinkLost { silent_s: f64 },
    CameraSeesNoRow { for_s: f64 },
    ThreadStopped { thread: ThreadName, for_s: f64 },
    ThreadPanicked { thread: ThreadName },
    Overruns { count: u32, window_s: f64 },
    Hardware { card: &'static str },
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
            FaultCause::CameraLinkLost { silent_s } => {
                write!(f, "camera link lost: no row frame for {silent_s:.2} s")
            }
            FaultCause::CameraSeesNoRow { for_s } => {
                write!(f, "camera sees no row: no usable estimate for {for_s:.2} s")
            }
            FaultCause::ThreadStopped { thread, for_s } => {
                write!(
                    f,
                    "the {} thread stopped: no sign of life for {for_s:.2} s",
                    thread.label()
                )
            }
            FaultCause::ThreadPanicked { thread } => {
                write!(
                    f,
                    "the {} thread failed (a program error): see the log",
                    thread.label()
                )
            }
            FaultCause::Overruns { count, window_s } => write!(
                f,
                "the supervisor missed {count} deadlines within {window_s:.0} s: the computer is overloaded"
            ),
            FaultCause::Hardware { card } => write!(f, "I/O card {card} stopped answering"),
        }
    }
}

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

/// What the checks look at, gathered by the supervisor each tick.
pub struct CheckContext<'a> {
    pub now_s: f64,
    pub mode: Mode,
    /// When the current mode was entered, s.
    pub mode_since_s: f64,
    pub power: PowerState,
    pub inputs: &'a Inputs,
    pub measured: &'a Measured,
    /// Amplifier voltages written last tick: left, right, steering.
    pub driven_v: [f64; 3],
    /// Encoder counts moved since last tick: left, right, steering.
    pub counts_moved: [bool; 3],
    /// An end switch closed while driving, and when (latched by the supervisor).
    pub endswitch_hit: Option<(Side, f64)>,
    pub steer: &'a SteerCommand,
    pub link: &'a LinkStatus,
    pub health: &'a ThreadHealth,
}

/// Settings and the timers of the checks that need time to decide.
pub struct FaultChecks {
    s: FaultSettings,
    camera: CameraSettings,
    rt: RtSettings,
    power_up_timeout_s: f64,
    /// Times of the most recent supervisor overruns (at most max_overruns + 1).
    overrun_times_s: std::collections::VecDeque<f64>,
    overruns_seen: u64,
    battery_low_since_s: Option<f64>,
    pot_disagree_since_s: Option<f64>,
    encoder_idle_since_s: [Option<f64>; 3],
}

/// Starts a timer when `condition` becomes true; returns how long it has been true.
fn held_for(timer: &mut Option<f64>, condition: bool, now_s: f64) -> f64 {
    if !condition {
        *timer = None;
        return 0.0;
    }
    now_s - *timer.get_or_insert(now_s)
}

const ENCODERS: [EncoderId; 3] = [EncoderId::Left, EncoderId::Right, EncoderId::Steer];

impl FaultChecks {
    pub fn new(
        s: FaultSettings,
        camera: CameraSettings,
        rt: RtSettings,
        power_up_timeout_s: f64,
    ) -> FaultChecks {
        FaultChecks {
            s,
            camera,
            rt,
            power_up_timeout_s,
            overrun_times_s: std::collections::VecDeque::with_capacity(
                rt.max_overruns as usize + 1,
            ),
            overruns_seen: 0,
            battery_low_since_s: None,
            pot_disagree_since_s: None,
            encoder_idle_since_s: [None; 3],
        }
    }

    /// Conditions that hold right now whatever the mode; power-up is refused while one holds.
    pub fn standing_cause(&self, inputs: &Inputs) -> Option<FaultCause> {
        if !inputs.estop_front_released {
            return Some(FaultCause::EstopFront);
        }
        if !inputs.estop_back_released {
            return Some(FaultCause::EstopBack);
        }
        if inputs.battery_v < self.s.battery_min_v {
            return Some(FaultCause::BatteryLow {
                volts: inputs.battery_v,
            });
        }
        if !(self.s.pot_min_v..=self.s.pot_max_v).contains(&inputs.pot_v) {
            return Some(FaultCause::PotOutOfRange {
                volts: inputs.pot_v,
            });
        }
        if inputs.end_switch_left && inputs.end_switch_right {
            return Some(FaultCause::BothEndSwitches);
        }
        None
    }

    /// Run every check; the first cause found is returned. Timers advance every tick.
    pub fn check(&mut self, c: &CheckContext) -> Option<FaultCause> {
        let mut found = None;
        let mut report = |cause: FaultCause| {
            found.get_or_insert(cause);
        };
        let now = c.now_s;
        let i = c.inputs;

        // Emergency stops: the hard-wired chain has already opened the contactor.
        if !i.estop_front_released {
            report(FaultCause::EstopFront);
        }
        if !i.estop_back_released {
            report(FaultCause::EstopBack);
        }

        // Power: the contactor must stay closed once it closed, and close in time.
        match c.power {
            PowerState::On if !i.motor_power_present => report(FaultCause::MotorPowerLost),
            PowerState::Closing { since_s } if now - since_s > self.power_up_timeout_s => {
                report(FaultCause::PowerUpFailed)
            }
            _ => {}
        }

        // Battery: sagging briefly under load is normal; staying low is not.
        let low = i.battery_v < self.s.battery_min_v;
        if held_for(&mut self.battery_low_since_s, low, now) >= self.s.battery_low_s && low {
            report(FaultCause::BatteryLow { volts: i.battery_v });
        }

        // Steering potentiometer: out of its band means a broken wire.
        if !(self.s.pot_min_v..=self.s.pot_max_v).contains(&i.pot_v) {
            report(FaultCause::PotOutOfRange { volts: i.pot_v });
        }
        // ... and once calibrated it must agree with the steering encoder.
        let m = c.measured;
        let pot_deg = m.pot_angle_filtered_rad.to_degrees();
        let encoder_deg = m.wheel_angle_filtered_rad.to_degrees();
        let disagree = m.calibrated && (pot_deg - encoder_deg).abs() > self.s.pot_disagree_deg;
        if held_for(&mut self.pot_disagree_since_s, disagree, now) >= self.s.pot_disagree_s
            && disagree
        {
            report(FaultCause::PotDisagrees {
                pot_deg,
                encoder_deg,
            });
        }

        // End switches: both at once is a wiring fault; one while driving must be taken
        // by the steer thread's end-switch procedure at once and cleared in time.
        if i.end_switch_left && i.end_switch_right {
            report(FaultCause::BothEndSwitches);
        }
        if let Some((side, since_s)) = c.endswitch_hit {
            let handled = matches!(c.steer.endswitch, EndSwitchState::Active { .. });
            let for_s = now - since_s;
            if !handled && for_s > self.s.endswitch_unhandled_s {
                report(FaultCause::EndSwitchUnhandled(side));
            } else if for_s > self.s.endswitch_timeout_s {
                report(FaultCause::EndSwitchStuck(side));
            }
        }

        // Encoders: a motor driven hard enough to move must make its encoder count.
        for (k, id) in ENCODERS.iter().enumerate() {
            let driven = c.driven_v[k].abs() > self.s.encoder_stuck_v && c.power == PowerState::On;
            let idle = driven && !c.counts_moved[k];
            if held_for(&mut self.encoder_idle_since_s[k], idle, now) >= self.s.encoder_stuck_s
                && idle
            {
                report(FaultCause::EncoderStuck(*id));
            }
        }

        // Autonomous driving needs the camera: frames, and frames that see the row.
        if c.mode == Mode::Autonomous {
            let since = |t: f64| now - t.max(c.mode_since_s);
            let silent_s = since(c.link.last_row_s);
            let blind_s = since(c.link.last_usable_s);
            if silent_s > self.camera.link_timeout_s {
                report(FaultCause::CameraLinkLost { silent_s });
            } else if blind_s > self.camera.link_timeout_s {
                report(FaultCause::CameraSeesNoRow { for_s: blind_s });
            }
        }

        // Threads: a panic anywhere, or a thread that stops beating, is a fault; the
        // steer thread beats with each command, the camera link with each status.
        if let Some(thread) = c.health.panicked {
            report(FaultCause::ThreadPanicked { thread });
        }
        let beats = [
            (ThreadName::Steer, Some(c.steer.t_s)),
            (ThreadName::CameraLink, Some(c.link.beat_s)),
            (ThreadName::Gui, c.health.gui_beat_s),
        ];
        for (thread, beat_s) in beats {
            // The GUI thread runs at normal priority and draws with the processor: it
            // gets its own, longer time-out.
            let timeout_s = if thread == ThreadName::Gui {
                self.rt.gui_heartbeat_timeout_s
            } else {
                self.rt.heartbeat_timeout_s
            };
            if let Some(beat_s) = beat_s {
                let for_s = now - beat_s;
                if for_s > timeout_s {
                    report(FaultCause::ThreadStopped { thread, for_s });
                }
            }
        }

        // Deadline overruns: a few are tolerated, a burst means an overloaded computer.
        let new_overruns = c
            .health
            .supervisor_overruns
            .saturating_sub(self.overruns_seen);
        self.overruns_seen = c.health.supervisor_overruns;
        for _ in 0..new_overruns.min(self.rt.max_overruns as u64 + 1) {
            if self.overrun_times_s.len() > self.rt.max_overruns as usize {
                self.overrun_times_s.pop_front();
            }
            self.overrun_times_s.push_back(now);
        }
        if self.overrun_times_s.len() > self.rt.max_overruns as usize
            && let Some(&oldest) = self.overrun_times_s.front()
            && now - oldest <= self.rt.overrun_window_s
        {
            report(FaultCause::Overruns {
                count: self.overrun_times_s.len() as u32,
                window_s: self.rt.overrun_window_s,
            });
        }
        found
    }
}

#[cfg(test)]
#[path = "faults_tests.rs"]
mod tests;
