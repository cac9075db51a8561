//! Which gamepad is the joystick across a replug: with `gamepad_device = auto` the pad
//! chosen first is pinned, and a pad that comes back is taken only if it is the same
//! one (its name and the port it is plugged into), never silently another.

use super::device::Found;

/// The pad `gamepad_device = auto` chose first: a pad that comes back is taken only if
/// it is the same one, so that a replug never switches silently to another pad.
#[derive(Debug, Clone, PartialEq)]
pub struct Pin {
    pub name: String,
    pub phys: String,
}

impl Pin {
    pub fn of(found: &Found) -> Pin {
        Pin {
            name: found.name.clone(),
            phys: found.phys.clone(),
        }
    }

    pub fn matches(&self, found: &Found) -> bool {
        self.name == found.name && self.phys == found.phys
    }
}

/// Of the pads that fit, the one to take: the pinned one if there is a pin; else the
/// first. An error says why none is taken, naming the pads left alone.
pub(crate) fn choose(fitting: &[Found], pin: Option<&Pin>) -> Result<usize, String> {
    let Some(pin) = pin else {
        return if fitting.is_empty() {
            Err("no pad fits".into())
        } else {
            Ok(0)
        };
    };
    if let Some(i) = fitting.iter().position(|f| pin.matches(f)) {
        return Ok(i);
    }
    let others: Vec<String> = fitting
        .iter()
        .map(|f| format!("{} ({})", f.name, f.path.display()))
        .collect();
    Err(format!(
        "the gamepad chosen at start, {} at {}, is not there{}; it stays the joystick for this run (set [joystick] gamepad_device to a device path to choose another)",
        pin.name,
        if pin.phys.is_empty() { "?" } else { &pin.phys },
        if others.is_empty() {
            String::new()
        } else {
            format!("; not taking {}", others.join(", "))
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn a_replug_takes_the_pad_chosen_at_start_not_another() {
        let pad = |name: &str, port: &str| Found {
            path: PathBuf::from(format!("/dev/input/event{}", port.len())),
            name: name.into(),
            buttons: vec!["BTN_SOUTH".into()],
            axes: vec!["ABS_X".into(), "ABS_Y".into()],
            phys: port.into(),
        };
        let (first, second) = (pad("Pad A", "usb-1"), pad("Pad A", "usb-22"));
        assert_eq!(choose(&[first.clone(), second.clone()], None), Ok(0));
        let pin = Pin::of(&first);
        // The chosen pad unplugged: the other one is not taken, and named.
        let why = choose(std::slice::from_ref(&second), Some(&pin)).unwrap_err();
        assert!(why.contains("is not there"), "{why}");
        assert!(
            why.contains("not taking Pad A (/dev/input/event6)"),
            "{why}"
        );
        // Back in the kernel's list after the other: still the chosen one.
        assert_eq!(choose(&[second, first], Some(&pin)), Ok(1));
    }
}
