//! Test mode, as the supervisor runs it: the hardware test panel sets the outputs by
//! hand, and the supervisor still decides what reaches the robot.
//!
//! Power and Test go together like this: Test keeps the contactor as it was (entered
//! after Power up, the relay stays closed; without it, open), and the panel's relay
//! switch is the way to close or open it. The supervisor's power state follows that
//! switch, so the checks that watch driving (motor power lost, power-up failed, an
//! encoder that does not count) watch Test too, with or without a Power up first.
//! Leaving Test restores the safe outputs with the contactor open: to drive after
//! Test, power up again.
//!
//! Hold-to-run: what the panel sets moves the robot only while a person holds a control
//! (the panel's Hold to run, or the joystick's dead-man on the cards), as a manual mode
//! of a machine must (IEC 60204-1). Not held, every amplifier gets 0 V, in the tick the
//! hold ends; and a brake stays on where its wheel's amplifier is asked for a voltage,
//! since a released brake would let that voltage drive the wheel as soon as anyone
//! holds. [test]'s drive voltage and wheel speed limits hold while held.

use mechweed_hw::Outputs;

use crate::config::{PiSettings, TestSettings};
use crate::state::measure::Measured;
use crate::state::status::PowerState;

/// The amplifiers take -10..+10 V: whatever the test panel asks, never more.
pub(crate) const AMPLIFIER_MAX_V: f64 = 10.0;

/// The outputs Test starts with: everything safe, the relay as the power state has it.
pub(crate) fn first_outputs(power: PowerState) -> Outputs {
    Outputs {
        main_power_on: power != PowerState::Off,
        ..Outputs::SAFE
    }
}

/// The power state after the panel's relay switch: opening it is switching power off
/// (no fault); closing it is a power-up, which must see motor power in time.
pub(crate) fn power_after_panel(relay_closed: bool, power: PowerState, now_s: f64) -> PowerState {
    match (relay_closed, power) {
        (false, _) => PowerState::Off,
        (true, PowerState::Off) => PowerState::Closing { since_s: now_s },
        (true, other) => other,
    }
}

/// The panel's outputs with every amplifier within its range.
pub(crate) fn limit_amplifiers(mut outputs: Outputs) -> Outputs {
    for v in [
        &mut outputs.amp_left_v,
        &mut outputs.amp_right_v,
        &mut outputs.amp_steer_v,
    ] {
        // NaN (from a broken sender) becomes 0 V, not a pass-through.
        *v = if v.is_finite() {
            v.clamp(-AMPLIFIER_MAX_V, AMPLIFIER_MAX_V)
        } else {
            0.0
        };
    }
    outputs
}

/// A hold from the panel counts for this long unless renewed, s: the GUI renews it
/// every 0.1 s while the button or key is held and ends it when let go, so a GUI that
/// stops with the button down still lets go within this time.
pub(crate) const PANEL_HOLD_S: f64 = 0.25;

/// Who holds a control in Test: the panel's hold, until a time, and whether every
/// control has been let go since Test began. A control already held as Test is entered
/// (a dead-man taped down, a key that sticks) is no hold until it is let go once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hold {
    panel_until_s: f64,
    armed: bool,
}

impl Hold {
    /// Nobody holds, and nothing is armed: entering or leaving Test, a fault.
    pub(crate) const RELEASED: Hold = Hold {
        panel_until_s: f64::NEG_INFINITY,
        armed: false,
    };

    /// The panel's Hold to run held (renewed) or let go at `now_s`.
    pub(crate) fn panel(&mut self, held: bool, now_s: f64) {
        self.panel_until_s = if held {
            now_s + PANEL_HOLD_S
        } else {
            f64::NEG_INFINITY
        };
    }

    /// Held in this tick at `now_s`, with the dead-man input `deadman`.
    pub(crate) fn held(&mut self, deadman: bool, now_s: f64) -> bool {
        let any = deadman || now_s < self.panel_until_s;
        self.armed |= !any;
        self.armed && any
    }
}

/// The panel's outputs as they may reach the robot: all amplifiers at 0 V and the tool
/// off unless `held`, brakes on where their wheel is asked for a voltage unless `held`,
/// and while held the
/// drives within [test] drive_limit_v, a drive whose wheel turns faster than [test]
/// max_speed_mps at 0 V.
pub(crate) fn hold_to_run(
    mut outputs: Outputs,
    held: bool,
    limits: &TestSettings,
    measured: &Measured,
) -> Outputs {
    if !held {
        outputs.brake_release_left &= outputs.amp_left_v == 0.0;
        outputs.brake_release_right &= outputs.amp_right_v == 0.0;
        outputs.amp_left_v = 0.0;
        outputs.amp_right_v = 0.0;
        outputs.amp_steer_v = 0.0;
        // The weeding tool's motor moves too.
        outputs.tool_on = false;
        return outputs;
    }
    for (volts, speed_mps) in [
        (&mut outputs.amp_left_v, measured.v_left_mps),
        (&mut outputs.amp_right_v, measured.v_right_mps),
    ] {
        // A speed that is not a number is no speed within the limit.
        *volts = if speed_mps.is_nan() || speed_mps.abs() > limits.max_speed_mps {
            0.0
        } else {
            volts.clamp(-limits.drive_limit_v, limits.drive_limit_v)
        };
    }
    outputs
}

/// How fast each drive wheel should turn under the panel's voltages, m/s: the
/// feed-forward's motor model (kff volts per m/s), or 0 with the brake on. The
/// encoder check compares the encoders against this.
pub(crate) fn expected_mps(outputs: &Outputs, left: &PiSettings, right: &PiSettings) -> [f64; 2] {
    let wheel = |volts: f64, released: bool, pi: &PiSettings| {
        if !released {
            0.0
        } else if pi.kff > 0.0 {
            volts / pi.kff
        } else {
            // No motor model: any voltage above the check's threshold should move it.
            volts.signum()
        }
    };
    [
        wheel(outputs.amp_left_v, outputs.brake_release_left, left),
        wheel(outputs.amp_right_v, outputs.brake_release_right, right),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_relay_switch_is_the_power_switch_in_test() {
        assert_eq!(
            power_after_panel(true, PowerState::Off, 2.0),
            PowerState::Closing { since_s: 2.0 }
        );
        assert_eq!(power_after_panel(true, PowerState::On, 2.0), PowerState::On);
        assert_eq!(
            power_after_panel(false, PowerState::On, 2.0),
            PowerState::Off
        );
        assert!(first_outputs(PowerState::On).main_power_on);
        assert!(!first_outputs(PowerState::Off).main_power_on);
    }

    #[test]
    fn nothing_moves_unless_held_and_held_only_within_the_test_limits() {
        let limits = TestSettings::shipped();
        // The unsafe state: the panel asks 6 V on the left drive and -3 V on the
        // steering, the tool on, both brakes released.
        let asked = Outputs {
            amp_left_v: 6.0,
            amp_right_v: 0.0,
            amp_steer_v: -3.0,
            brake_release_left: true,
            brake_release_right: true,
            main_power_on: true,
            tool_on: true,
        };
        let still = Measured::default();
        let out = hold_to_run(asked, false, &limits, &still);
        assert_eq!(
            (out.amp_left_v, out.amp_right_v, out.amp_steer_v),
            (0.0, 0.0, 0.0)
        );
        assert!(
            !out.brake_release_left,
            "a driven wheel's brake needs the hold"
        );
        assert!(
            out.brake_release_right,
            "a wheel at 0 V may have its brake off"
        );
        assert!(out.main_power_on, "the relay switch is no motion");
        assert!(!out.tool_on, "the tool's motor needs the hold");
        let out = hold_to_run(asked, true, &limits, &still);
        assert_eq!(out.amp_left_v, limits.drive_limit_v);
        assert_eq!(
            out.amp_steer_v, -3.0,
            "the steering keeps the amplifier's limit"
        );
        assert!(out.brake_release_left);
        let fast = Measured {
            v_left_mps: limits.max_speed_mps + 0.01,
            ..Measured::default()
        };
        assert_eq!(hold_to_run(asked, true, &limits, &fast).amp_left_v, 0.0);
        let broken = Measured {
            v_left_mps: f64::NAN,
            ..Measured::default()
        };
        assert_eq!(hold_to_run(asked, true, &limits, &broken).amp_left_v, 0.0);
    }

    #[test]
    fn a_control_held_as_test_begins_is_no_hold_until_let_go_once() {
        let mut hold = Hold::RELEASED;
        assert!(!hold.held(true, 1.0), "the dead-man was down as Test began");
        assert!(!hold.held(true, 1.01));
        assert!(!hold.held(false, 1.02), "let go");
        assert!(hold.held(true, 1.03), "pressed again: held");
        hold.panel(true, 1.04);
        assert!(
            hold.held(false, 1.04 + PANEL_HOLD_S - 0.01),
            "the panel's hold lasts"
        );
        assert!(!hold.held(false, 1.04 + PANEL_HOLD_S + 0.01), "and lapses");
        hold.panel(true, 2.0);
        hold.panel(false, 2.05);
        assert!(!hold.held(false, 2.05), "let go ends it at once");
    }

    #[test]
    fn a_braked_wheel_is_not_expected_to_move() {
        let pi = crate::config::Settings::shipped().pid_left;
        let mut out = Outputs {
            amp_left_v: 4.0,
            amp_right_v: -4.0,
            brake_release_left: true,
            ..Outputs::SAFE
        };
        let [left, right] = expected_mps(&out, &pi, &pi);
        assert!((left - 4.0 / pi.kff).abs() < 1e-12);
        assert_eq!(right, 0.0);
        out.amp_left_v = f64::NAN;
        assert_eq!(limit_amplifiers(out).amp_left_v, 0.0);
    }
}
