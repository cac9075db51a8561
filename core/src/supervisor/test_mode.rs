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

use mechweed_hw::Outputs;

use crate::config::PiSettings;
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
