//! Every fault check of the supervisor, in one place, in the order they are checked.
//!
//! The supervisor calls `FaultChecks::check` once per tick with what it has just read;
//! the first cause found latches the Fault mode and safe outputs in that same tick.
//! Checks that must see a condition for some time (a battery sagging, an encoder not
//! counting) keep a timer here; their times are settings in robot.ini [faults].
//! `check` lists them all; the robot's motion checks are in motion.rs, and the
//! controller's own health (its threads beating, its ticks on time) in liveness.rs.

mod context;
mod liveness;
mod motion;

use mechweed_hw::{EncoderId, Inputs};

pub use context::CheckContext;
use context::held_for;

use crate::config::{CameraSettings, FaultSettings, RtSettings, Settings, SteerSource};
use crate::state::fault_cause::{FaultCause, JoystickAxis};
use crate::state::modes::Mode;
use crate::state::status::PowerState;
use crate::steer::{EndSwitchState, Steering};

/// Settings and the timers of the checks that need time to decide.
pub(crate) struct FaultChecks {
    s: FaultSettings,
    camera: CameraSettings,
    source: SteerSource,
    /// Since when the steer thread has had nothing to steer by (gnss or fused).
    no_row_since_s: Option<f64>,
    rt: RtSettings,
    power_up_timeout_s: f64,
    period_s: f64,
    joystick_axis_fault_v: f64,
    /// The drive wheels' feed-forward: the volts a speed needs, V per m/s.
    kff_v_per_mps: [f64; 2],
    /// Times of the most recent supervisor overruns (at most max_overruns + 1).
    overrun_times_s: std::collections::VecDeque<f64>,
    overruns_seen: u64,
    battery_low_since_s: Option<f64>,
    pot_disagree_since_s: Option<f64>,
    encoder_idle_since_s: [Option<f64>; 3],
    /// The potentiometer less the encoder (both filtered) when the steering encoder's idle time began, deg.
    steer_idle_pot_deg: f64,
    contactor_open_since_s: Option<f64>,
    /// Motor power has stayed on past the drop time with the relay open.
    contactor_welded: bool,
    /// Wrong-way, speed and uncommanded-motion checks (motion.rs).
    motion: motion::MotionChecks,
}

const ENCODERS: [EncoderId; 3] = [EncoderId::Left, EncoderId::Right, EncoderId::Steer];

/// A drive wheel asked to move slower than this may rightly stand (held on a slope by
/// its integrator), m/s.
const EXPECTED_MOTION_MPS: f64 = 0.05;
/// The potentiometer must show the steering turned at least this much while its encoder
/// stood still, deg: a wheel held by ground friction turns neither.
const STEER_TURNED_DEG: f64 = 1.0;

impl FaultChecks {
    pub fn new(settings: &Settings) -> FaultChecks {
        let rt = settings.rt;
        FaultChecks {
            s: settings.faults.clone(),
            camera: settings.camera,
            source: settings.sources.source,
            no_row_since_s: None,
            rt,
            power_up_timeout_s: settings.supervisor.power_up_timeout_s,
            period_s: 1.0 / settings.supervisor.rate_hz,
            joystick_axis_fault_v: settings.joystick.axis_fault_v,
            kff_v_per_mps: [settings.pid_left.kff, settings.pid_right.kff],
            overrun_times_s: std::collections::VecDeque::with_capacity(
                rt.max_overruns as usize + 1,
            ),
            overruns_seen: 0,
            battery_low_since_s: None,
            pot_disagree_since_s: None,
            encoder_idle_since_s: [None; 3],
            steer_idle_pot_deg: 0.0,
            contactor_open_since_s: None,
            contactor_welded: false,
            motion: motion::MotionChecks::new(settings),
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
        if self.contactor_welded && inputs.motor_power_present {
            return Some(FaultCause::ContactorWelded);
        }
        None
    }

    /// Run every check; the first cause found is returned. Every group runs each tick, in
    /// this order, so that the timers advance.
    pub fn check(&mut self, c: &CheckContext) -> Option<FaultCause> {
        let mut found = None;
        let mut report = |cause: FaultCause| {
            found.get_or_insert(cause);
        };
        self.estops_and_power(c, &mut report);
        self.battery_and_potentiometer(c, &mut report);
        self.end_switches(c, &mut report);
        self.encoders(c, &mut report);
        self.motion.check(c, &mut report);
        self.joystick(c, &mut report);
        self.row_sources(c, &mut report);
        self.camera(c, &mut report);
        self.threads(c, &mut report);
        self.timing(c, &mut report);
        found
    }

    /// Emergency stops, and the contactor: closed in time, closed while on, open when commanded.
    fn estops_and_power(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
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
        // ... and open when commanded: power that stays on is a welded contactor, which
        // no software can switch off (the e-stop chain may not either).
        let stays_on = !c.relay_closed && i.motor_power_present;
        self.contactor_welded = held_for(&mut self.contactor_open_since_s, stays_on, now)
            >= self.s.contactor_drop_s
            && stays_on;
        if self.contactor_welded {
            report(FaultCause::ContactorWelded);
        }
    }

    /// The battery, and the steering potentiometer: in its band, and agreeing with the encoder.
    fn battery_and_potentiometer(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        let i = c.inputs;
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
    }

    /// The end switches: never both; one while driving handled at once and cleared in time.
    fn end_switches(&self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        let i = c.inputs;
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
    }

    /// The encoders: each counts while its motor should be moving.
    fn encoders(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        // Encoders: an encoder that does not count while its motor should be moving.
        // Not the voltage alone: standing on a slope, a wheel's integrator rightly holds
        // a voltage while the wheel stands, and ground friction can hold the steering.
        for (k, id) in ENCODERS.iter().enumerate() {
            let driven = c.driven_v[k].abs() > self.s.encoder_stuck_v && c.power == PowerState::On;
            let idle = driven && !c.counts_moved[k];
            let was_idle = self.encoder_idle_since_s[k].is_some();
            let idle_s = held_for(&mut self.encoder_idle_since_s[k], idle, now);
            let should_move = match id {
                // A drive wheel asked to move, pushed in that direction: at a speed
                // that shows, or at a creep with far more voltage than the creep needs
                // (an integrator winding up behind a dead encoder).
                EncoderId::Left | EncoderId::Right => {
                    let (expected_mps, driven_v) = (c.expected_mps[k], c.driven_v[k]);
                    let needed_v = self.kff_v_per_mps[k] * expected_mps.abs();
                    expected_mps * driven_v > 0.0
                        && (expected_mps.abs() > EXPECTED_MOTION_MPS
                            || driven_v.abs() > needed_v + self.s.encoder_stuck_v)
                }
                // The steering: the potentiometer saw it turn while the encoder stood.
                // Against the encoder through the same filter, so that the filter's
                // lag after a jump both saw (a stone's kick) is not a turn.
                EncoderId::Steer => {
                    let m = c.measured;
                    let pot_deg =
                        (m.pot_angle_filtered_rad - m.wheel_angle_filtered_rad).to_degrees();
                    if !was_idle {
                        self.steer_idle_pot_deg = pot_deg;
                    }
                    (pot_deg - self.steer_idle_pot_deg).abs() > STEER_TURNED_DEG
                }
            };
            if idle && should_move && idle_s >= self.s.encoder_stuck_s {
                report(FaultCause::EncoderStuck(*id));
            }
        }
    }

    /// The joystick: no axis beyond what the joystick can give.
    fn joystick(&self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let i = c.inputs;
        // Joystick: an axis beyond what the joystick can give is a broken wiper, which
        // would otherwise read as full deflection.
        if c.mode == Mode::Joystick {
            let axes = [
                (JoystickAxis::Speed, i.joystick_speed_v),
                (JoystickAxis::Steer, i.joystick_steer_v),
            ];
            for (axis, volts) in axes {
                if volts.is_nan() || volts.abs() > self.joystick_axis_fault_v {
                    report(FaultCause::JoystickAxis { axis, volts });
                }
            }
        }
    }

    /// Autonomous by GNSS or the fused row: something to steer by, and the robot on the row.
    fn row_sources(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        // Autonomous driving by GNSS or the fused row needs one of them: the steer
        // thread says which steers, and since when each has been lost.
        let nothing = c.mode == Mode::Autonomous
            && c.steer.mode == Mode::Autonomous
            && c.steer.sources.steering == Steering::Nothing;
        let nothing_s = held_for(&mut self.no_row_since_s, nothing, now);
        if self.source != SteerSource::Camera && nothing_s > self.camera.link_timeout_s {
            let lost_s = |t: f64| now - t.max(c.mode_since_s);
            report(FaultCause::NoRowSource {
                camera_s: lost_s(c.steer.sources.camera_good_s),
                gnss_s: lost_s(c.steer.sources.gnss_good_s),
            });
        }

        // Steering by GNSS or the fused row, nothing loses the row the way a camera
        // does: a robot far from the filter's row has left it (a steering that swings).
        let offset_m = c.steer.sources.row_offset_m;
        let by_filter = c.mode == Mode::Autonomous && c.steer.mode == Mode::Autonomous;
        if self.source != SteerSource::Camera && by_filter && offset_m.abs() > self.s.off_row_m {
            report(FaultCause::OffTheRow { offset_m });
        }
    }

    /// Autonomous by the camera: frames, and frames that see the row; one source of rows.
    fn camera(&self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let now = c.now_s;
        // Autonomous driving by the camera needs it: frames, and frames that see the row
        // (an old image's estimate repeated sees it only for [camera] gap_hold_m: the steer
        // thread says, as of its last tick, since when the camera has had a row it steers
        // by; a steer thread that stalls is its own fault, not the camera's).
        // Two programs sending rows: neither's are taken, and the robot stops until one
        // is gone (a rogue's rows, or a second camera program started by mistake).
        if c.link.rival_sources {
            report(FaultCause::TwoRowSources);
        }
        if c.mode == Mode::Autonomous && self.source == SteerSource::Camera {
            let since = |t: f64| now - t.max(c.mode_since_s);
            let silent_s = since(c.link.last_row_s);
            let held_too_long_s = c.steer.t_s - c.steer.sources.camera_good_s.max(c.mode_since_s);
            let blind_s = since(c.link.last_usable_s).max(held_too_long_s);
            // While the steer thread looks for the first plants (within [camera]
            // first_row_m, it says), a camera that sees no row is what it expects.
            let looking = c.steer.sources.searching;
            if silent_s > self.camera.link_timeout_s {
                report(FaultCause::CameraLinkLost { silent_s });
            } else if blind_s > self.camera.link_timeout_s && !looking {
                report(FaultCause::CameraSeesNoRow { for_s: blind_s });
            }
        }
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod tests_others;
