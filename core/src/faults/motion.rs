//! The checks that see the robot move the wrong way, too fast, or with no command:
//! how wiring mistakes show at a first power-up. A steering amplifier with its motor
//! leads swapped would otherwise swing the wheel to the opposite end switch at full
//! rate; a drive wheel reversed (amplifier or encoder) makes its speed regulator run
//! away to full volts; a DDA06 range switch that differs from robot.ini turns "0 V"
//! into half of full scale in every safe state, where nothing else looks.
//!
//! Each check reads the encoders, which count what truly moved (the steering's
//! potentiometer only says which of its amplifier and its encoder is reversed), and
//! the volts written last tick. Its limits are [faults] settings (config/motion_faults.rs
//! says why each shipped value is what it is).

use mechweed_hw::{EncoderId, Side};

use super::context::{CheckContext, held_for};
use crate::config::{MotionFaultSettings, Settings};
use crate::state::fault_cause::FaultCause;
use crate::state::modes::Mode;
use crate::state::status::PowerState;

/// Below this the steering is not being driven either way, V: its motor barely turns
/// (6 deg/s on the simulated robot) and the PD regulator crosses it near its target.
const STEER_DRIVEN_V: f64 = 1.0;
/// A drive wheel slower than this, or asked for less, has no direction to be wrong
/// about, m/s (the encoder check's own creep threshold).
const MOVING_MPS: f64 = 0.05;

/// The steering driven one way, since when, and where it was once its motor had had
/// time to respond (encoder, potentiometer; deg).
#[derive(Debug, Clone, Copy)]
struct Episode {
    sign: f64,
    since_s: f64,
    anchor_deg: Option<(f64, f64)>,
}

impl Episode {
    /// The episode for volts of `sign` now: this one if it goes on, else a new one.
    fn follow(last: Option<Episode>, sign: f64, now_s: f64) -> Episode {
        match last {
            Some(e) if e.sign == sign => e,
            _ => Episode {
                sign,
                since_s: now_s,
                anchor_deg: None,
            },
        }
    }
}

pub(crate) struct MotionChecks {
    s: MotionFaultSettings,
    counts_per_m: f64,
    counts_per_deg: f64,
    steer: Option<Episode>,
    backoff: Option<Episode>,
    wrong_way_since_s: [Option<f64>; 2],
    speed_error_since_s: [Option<f64>; 2],
    /// The last tick that commanded motion (a mode other than Halt, or volts), s.
    commanded_s: f64,
    /// The encoders' counts where standing uncommanded began: left, right, steering.
    standing_counts: Option<[i64; 3]>,
}

impl MotionChecks {
    pub fn new(settings: &Settings) -> MotionChecks {
        MotionChecks {
            s: settings.faults.motion,
            counts_per_m: settings.robot.enc_counts_per_m,
            counts_per_deg: settings.robot.steer_counts_per_deg,
            steer: None,
            backoff: None,
            wrong_way_since_s: [None; 2],
            speed_error_since_s: [None; 2],
            commanded_s: f64::NEG_INFINITY,
            standing_counts: None,
        }
    }

    /// Every motion check, each tick, so that each keeps its own time.
    pub fn check(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let driving = c.mode.drives() && c.power == PowerState::On;
        self.steering(c, driving, report);
        self.endswitch_backoff(c, driving, report);
        self.drives(c, driving, report);
        self.standing(c, report);
    }

    /// The steering, driven one way, must not turn the other way (away from the end
    /// switches: at one, `endswitch_backoff` looks instead).
    fn steering(&mut self, c: &CheckContext, driving: bool, report: &mut impl FnMut(FaultCause)) {
        let sign = volts_sign(c.driven_v[2]);
        if !driving || sign == 0.0 || c.endswitch_hit.is_some() {
            self.steer = None;
            return;
        }
        let (encoder_deg, pot_deg) = self.steer_deg(c);
        let episode = self
            .steer
            .insert(Episode::follow(self.steer, sign, c.now_s));
        // A wheel still coasting the old way after its volts changed sign is not wrong.
        if c.now_s - episode.since_s < self.s.steer_response_s {
            return;
        }
        let (encoder_0, pot_0) = *episode.anchor_deg.get_or_insert((encoder_deg, pot_deg));
        let against_deg = -(encoder_deg - encoder_0) * sign;
        if against_deg > self.s.steer_wrong_way_deg {
            // The potentiometer turning the driven way while the encoder turns the
            // other: the encoder counts backwards; both the other way: the motor does.
            let pot_driven_way = (pot_deg - pot_0) * sign > 0.5 * self.s.steer_wrong_way_deg;
            report(FaultCause::SteerWrongWay {
                driven_left: sign > 0.0,
                turned_deg: against_deg,
                pot_driven_way,
            });
        }
    }

    /// Driven off a closed end switch, only motion the encoder confirms is off it goes
    /// on: the steering must not turn into the switch once its motor has responded,
    /// and must have turned off it by `steer_wrong_way_deg` within `endswitch_backoff_s`.
    fn endswitch_backoff(
        &mut self,
        c: &CheckContext,
        driving: bool,
        report: &mut impl FnMut(FaultCause),
    ) {
        let Some((side, _)) = c.endswitch_hit.filter(|_| driving) else {
            self.backoff = None;
            return;
        };
        // Off the left switch is to the right (negative volts), and the other way round.
        let off_sign = if side == Side::Left { -1.0 } else { 1.0 };
        if volts_sign(c.driven_v[2]) != off_sign {
            self.backoff = None;
            return;
        }
        let (encoder_deg, _) = self.steer_deg(c);
        let episode = self
            .backoff
            .insert(Episode::follow(self.backoff, off_sign, c.now_s));
        let (encoder_0, _) = *episode.anchor_deg.get_or_insert((encoder_deg, 0.0));
        let moved_deg = (encoder_deg - encoder_0) * off_sign;
        let for_s = c.now_s - episode.since_s;
        let into_switch =
            for_s >= self.s.steer_response_s && moved_deg < -self.s.steer_wrong_way_deg;
        let not_off = for_s >= self.s.endswitch_backoff_s && moved_deg < self.s.steer_wrong_way_deg;
        if into_switch || not_off {
            report(FaultCause::EndSwitchNoBackOff { side, moved_deg });
        }
    }

    /// Each drive wheel turns the way its reference asks, near its speed.
    fn drives(&mut self, c: &CheckContext, driving: bool, report: &mut impl FnMut(FaultCause)) {
        let m = c.measured;
        let speeds_mps = [m.v_left_mps, m.v_right_mps];
        for (k, wheel) in [Side::Left, Side::Right].into_iter().enumerate() {
            let (speed_mps, ref_mps) = (speeds_mps[k], c.expected_mps[k]);
            let wrong_way = driving
                && ref_mps.abs() > MOVING_MPS
                && speed_mps.abs() > MOVING_MPS
                && speed_mps * ref_mps < 0.0;
            let wrong_s = held_for(&mut self.wrong_way_since_s[k], wrong_way, c.now_s);
            if wrong_way && wrong_s >= self.s.drive_wrong_way_s {
                report(FaultCause::DriveWrongWay {
                    wheel,
                    forwards: ref_mps > 0.0,
                });
            }
            let far = driving && (speed_mps - ref_mps).abs() > self.s.speed_error_mps;
            let far_s = held_for(&mut self.speed_error_since_s[k], far, c.now_s);
            if far && far_s >= self.s.speed_error_s {
                report(FaultCause::DriveSpeed {
                    wheel,
                    speed_mps,
                    ref_mps,
                });
            }
        }
    }

    /// Standing in Halt, or in Test with nothing held, with motor power on and 0 V on
    /// every amplifier, nothing moves once the last motion has had time to stop: not
    /// the steering, and not a wheel whose brake is on (in Test a person may turn a
    /// wheel whose brake the panel released).
    fn standing(&mut self, c: &CheckContext, report: &mut impl FnMut(FaultCause)) {
        let volts = c.driven_v.iter().any(|v| *v != 0.0);
        if !matches!(c.mode, Mode::Halt | Mode::Test) || volts {
            self.commanded_s = c.now_s;
        }
        // Without motor power no amplifier can move anything: motion then is a
        // person's hands, not the wiring.
        let settled = c.now_s - self.commanded_s >= self.s.uncommanded_settle_s;
        if !(settled && c.inputs.motor_power_present) {
            self.standing_counts = None;
            return;
        }
        let i = c.inputs;
        let counts = [i.enc_left_counts, i.enc_right_counts, i.enc_steer_counts];
        let start = *self.standing_counts.get_or_insert(counts);
        let moved = |k: usize| counts[k].abs_diff(start[k]) as f64;
        let parts = [
            (
                EncoderId::Left,
                moved(0) / self.counts_per_m,
                self.s.uncommanded_m,
            ),
            (
                EncoderId::Right,
                moved(1) / self.counts_per_m,
                self.s.uncommanded_m,
            ),
            (
                EncoderId::Steer,
                moved(2) / self.counts_per_deg,
                self.s.uncommanded_deg,
            ),
        ];
        for (k, (part, moved, limit)) in parts.into_iter().enumerate() {
            let free_wheel = k < 2 && c.brakes_released[k];
            if moved > limit && !free_wheel {
                report(FaultCause::UncommandedMotion { part, moved });
            }
        }
    }

    /// The steering's angle since the encoder's count 0, and the potentiometer's, deg.
    fn steer_deg(&self, c: &CheckContext) -> (f64, f64) {
        let encoder_deg = c.inputs.enc_steer_counts as f64 / self.counts_per_deg;
        (encoder_deg, c.measured.pot_angle_filtered_rad.to_degrees())
    }
}

/// +1 or -1 for volts that drive the steering, 0 for volts that do not.
fn volts_sign(volts: f64) -> f64 {
    if volts > STEER_DRIVEN_V {
        1.0
    } else if volts < -STEER_DRIVEN_V {
        -1.0
    } else {
        0.0
    }
}
