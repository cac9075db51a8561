//! Joystick mode: speed and wheel angle straight from the two analog axes, and only
//! while the dead-man button is held.

use mechweed_hw::Inputs;

use crate::config::JoystickSettings;

/// Axis voltage -> -1..1, with a dead band around the centre so that a joystick
/// that does not quite return to 0 V does not creep.
fn deflection(volts: f64, s: &JoystickSettings) -> f64 {
    let beyond = (volts.abs() - s.deadband_v).max(0.0);
    let span = (s.full_scale_v - s.deadband_v).max(f64::EPSILON);
    (beyond / span).min(1.0) * volts.signum()
}

/// (speed m/s, wheel angle rad) asked for by the joystick. Without the dead-man button
/// the robot stands and the wheel stays where it is.
pub fn command(inputs: &Inputs, s: &JoystickSettings, wheel_angle_now_rad: f64) -> (f64, f64) {
    if !inputs.joystick_enable {
        return (0.0, wheel_angle_now_rad);
    }
    let speed_mps = deflection(inputs.joystick_speed_v, s) * s.max_speed_mps;
    // The steer axis reads positive to the right; angles are positive to the left.
    let angle_rad = -deflection(inputs.joystick_steer_v, s) * s.max_angle_deg.to_radians();
    (speed_mps, angle_rad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    #[test]
    fn full_forward_right_and_dead_man() {
        let s = Settings::shipped().joystick;
        let mut i = Inputs {
            joystick_speed_v: 4.0,
            joystick_steer_v: 4.0,
            joystick_enable: true,
            ..Inputs::default()
        };
        let (speed, angle) = command(&i, &s, 0.0);
        assert!((speed - s.max_speed_mps).abs() < 1e-9);
        assert!(
            (angle + s.max_angle_deg.to_radians()).abs() < 1e-9,
            "full right is negative"
        );
        i.joystick_speed_v = 0.1;
        assert_eq!(command(&i, &s, 0.0).0, 0.0, "inside the dead band");
        i.joystick_enable = false;
        i.joystick_speed_v = 4.0;
        assert_eq!(
            command(&i, &s, 0.2),
            (0.0, 0.2),
            "released dead-man stops and holds"
        );
    }
}
