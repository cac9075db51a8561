//! [joystick]: the wired analog joystick's scale and limits, and where the joystick
//! comes from: the analog one on the DAS08, or a gamepad read from Linux's input events.

use std::path::PathBuf;

use evdev::{AbsoluteAxisCode, KeyCode};

use super::Reader;

/// Which joystick drives in joystick mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JoystickSource {
    /// The analog joystick wired to the DAS08 ([io] joystick_*).
    Analog,
    /// A USB or wireless gamepad ([joystick] gamepad_*).
    Gamepad,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JoystickSettings {
    pub source: JoystickSource,
    pub full_scale_v: f64,
    pub deadband_v: f64,
    pub max_speed_mps: f64,
    pub max_angle_deg: f64,
    pub axis_fault_v: f64,
}

/// Which input event device is the gamepad.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GamepadDevice {
    /// The first device (by event number) that looks like a gamepad and has the
    /// configured axes and button.
    Auto,
    /// This device file, e.g. /dev/input/by-id/usb-...-event-joystick.
    Path(PathBuf),
}

/// The gamepad's buttons and axes, by their Linux names.
#[derive(Debug, Clone, PartialEq)]
pub struct GamepadSettings {
    pub device: GamepadDevice,
    pub deadman_button: KeyCode,
    pub speed_axis: AbsoluteAxisCode,
    /// The speed axis reads negative with the stick pushed forward (most pads do).
    pub speed_forward_negative: bool,
    pub steer_axis: AbsoluteAxisCode,
    /// The steer axis reads negative with the stick pushed right.
    pub steer_right_negative: bool,
    /// No event from the pad for this long counts as the dead-man released, s.
    pub timeout_s: f64,
}

pub(super) fn load(r: &mut Reader) -> JoystickSettings {
    let s = "joystick";
    JoystickSettings {
        source: [JoystickSource::Analog, JoystickSource::Gamepad]
            [r.choice(s, "source", &["analog", "gamepad"])],
        full_scale_v: r.f64(s, "full_scale_v", 0.1, 10.0),
        deadband_v: r.f64(s, "deadband_v", 0.0, 5.0),
        max_speed_mps: r.f64(s, "max_speed_mps", 0.0, 3.0),
        max_angle_deg: r.f64(s, "max_angle_deg", 0.0, 45.0),
        // The A/D reads at most 5 V: a limit at or above it could never trip.
        axis_fault_v: r.f64(s, "axis_fault_v", 0.1, 4.95),
    }
}

pub(super) fn gamepad(r: &mut Reader) -> GamepadSettings {
    let s = "joystick";
    let device = r
        .parsed(s, "gamepad_device", |text| match text {
            "auto" => Ok(GamepadDevice::Auto),
            path if path.starts_with('/') => Ok(GamepadDevice::Path(path.into())),
            _ => Err(format!(
                "'{text}' is neither auto nor a device file such as /dev/input/event5"
            )),
        })
        .unwrap_or(GamepadDevice::Auto);
    let sign = ["positive", "negative"];
    GamepadSettings {
        device,
        deadman_button: r
            .parsed(s, "gamepad_deadman_button", button)
            .unwrap_or(KeyCode::BTN_TL),
        speed_axis: r
            .parsed(s, "gamepad_speed_axis", axis)
            .unwrap_or(AbsoluteAxisCode::ABS_Y),
        speed_forward_negative: r.choice(s, "gamepad_speed_forward", &sign) == 1,
        steer_axis: r
            .parsed(s, "gamepad_steer_axis", axis)
            .unwrap_or(AbsoluteAxisCode::ABS_X),
        steer_right_negative: r.choice(s, "gamepad_steer_right", &sign) == 1,
        // A wireless pad out of range keeps its last values: the robot must not drive on
        // them for more than a few seconds.
        timeout_s: r.f64(s, "gamepad_timeout_s", 0.1, 5.0),
    }
}

fn button(text: &str) -> Result<KeyCode, String> {
    match text.parse::<KeyCode>() {
        Ok(code) if text.starts_with("BTN_") => Ok(code),
        _ => Err(format!(
            "'{text}' is not a button's Linux name such as BTN_TL, BTN_TR or BTN_SOUTH (mechweed probe lists a pad's buttons)"
        )),
    }
}

fn axis(text: &str) -> Result<AbsoluteAxisCode, String> {
    text.parse::<AbsoluteAxisCode>().map_err(|_| {
        format!("'{text}' is not an axis's Linux name such as ABS_X, ABS_Y, ABS_RX or ABS_RY (mechweed probe lists a pad's axes)")
    })
}

#[cfg(test)]
mod tests {
    use crate::config::{GamepadDevice, JoystickSource, Settings};

    fn errors(set: &[&str]) -> String {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        let errors = Settings::parse("robot.ini", super::super::DEFAULT_INI, &set).unwrap_err();
        errors.iter().map(|e| format!("{e}\n")).collect()
    }

    #[test]
    fn the_shipped_joystick_is_the_analog_one_and_a_gamepad_is_named_by_linux_names() {
        let s = Settings::shipped();
        assert_eq!(s.joystick.source, JoystickSource::Analog);
        assert_eq!(s.gamepad.device, GamepadDevice::Auto);
        let set = [
            "joystick.source=gamepad".to_string(),
            "joystick.gamepad_device=/dev/input/by-id/usb-pad-event-joystick".to_string(),
            "joystick.gamepad_steer_axis=ABS_RX".to_string(),
        ];
        let s = Settings::parse("robot.ini", super::super::DEFAULT_INI, &set).unwrap();
        assert_eq!(s.joystick.source, JoystickSource::Gamepad);
        let path = "/dev/input/by-id/usb-pad-event-joystick";
        assert_eq!(s.gamepad.device, GamepadDevice::Path(path.into()));
        assert_eq!(s.gamepad.steer_axis, evdev::AbsoluteAxisCode::ABS_RX);
    }

    #[test]
    fn a_wrong_button_axis_device_or_time_out_is_named_with_its_key() {
        let all = errors(&[
            "joystick.gamepad_deadman_button=KEY_A",
            "joystick.gamepad_speed_axis=Y",
            "joystick.gamepad_device=event5",
            "joystick.gamepad_timeout_s=0",
        ]);
        assert!(
            all.contains("gamepad_deadman_button: 'KEY_A' is not a button's Linux name"),
            "{all}"
        );
        assert!(
            all.contains("gamepad_speed_axis: 'Y' is not an axis's Linux name"),
            "{all}"
        );
        assert!(
            all.contains("gamepad_device: 'event5' is neither auto nor a device file"),
            "{all}"
        );
        assert!(all.contains("gamepad_timeout_s"), "{all}");
        let same = errors(&["joystick.gamepad_steer_axis=ABS_Y"]);
        assert!(same.contains("gamepad_steer_axis are both ABS_Y"), "{same}");
    }
}
