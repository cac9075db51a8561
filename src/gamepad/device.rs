//! Linux input event devices (/dev/input/event*): which ones look like gamepads, and
//! opening the one robot.ini names with the axes and button it needs.

use std::path::{Path, PathBuf};

use std::os::fd::AsRawFd;
use std::time::Duration;

use evdev::{AbsoluteAxisCode, Device, EventType, KeyCode};

use super::mapping::{AxisRange, Opened, PadMap};
use super::pin::{Pin, choose};
use super::thread::PadSource;
use crate::config::GamepadDevice;

/// Where Linux puts the input event devices.
pub(crate) const INPUT_DIR: &str = "/dev/input";

/// One input device as `mechweed probe` lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    pub path: PathBuf,
    pub name: String,
    /// Joysticks' and gamepads' buttons (BTN_SOUTH, BTN_TL, ...), by Linux name.
    pub buttons: Vec<String>,
    /// Absolute axes (ABS_X, ABS_Y, ...), by Linux name.
    pub axes: Vec<String>,
    /// Where it is plugged in (the kernel's physical path, e.g. usb-0000:00:14.0-2/input0),
    /// empty if the kernel does not say: with the name, which pad it is across a replug.
    pub phys: String,
}

impl Found {
    /// Two axes and a joystick's or gamepad's button: keyboards, mice and touchpads have
    /// no such buttons.
    pub(crate) fn looks_like_gamepad(&self) -> bool {
        self.axes.iter().any(|a| a == "ABS_X")
            && self.axes.iter().any(|a| a == "ABS_Y")
            && !self.buttons.is_empty()
    }
}

/// A joystick's or gamepad's buttons: BTN_JOYSTICK (0x120) up to BTN_THUMBR (0x13e).
fn is_pad_button(code: KeyCode) -> bool {
    (0x120..=0x13e).contains(&code.code())
}

fn describe(path: &Path, device: &Device) -> Found {
    let buttons = device
        .supported_keys()
        .map(|keys| {
            keys.iter()
                .filter(|k| is_pad_button(*k))
                .map(|k| format!("{k:?}"))
                .collect()
        })
        .unwrap_or_default();
    let axes = device
        .supported_absolute_axes()
        .map(|axes| axes.iter().map(|a| format!("{a:?}")).collect())
        .unwrap_or_default();
    Found {
        path: path.to_path_buf(),
        name: device.name().unwrap_or("(no name)").to_string(),
        buttons,
        axes,
        phys: device.physical_path().unwrap_or("").to_string(),
    }
}

/// The devices opened, each with what it is; and the lines of those that could not be.
pub(crate) type Listed = (Vec<(Found, Device)>, Vec<String>);

/// The event devices in `dir` in the kernel's order (event0, event1, ... event10), and
/// what could not be opened (e.g. permission denied), one line each; or why the folder
/// cannot be listed.
pub fn list(dir: &Path) -> Result<Listed, String> {
    let mut paths: Vec<(u32, PathBuf)> = match std::fs::read_dir(dir) {
        Ok(entries) => entries
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().to_string();
                let n = name.strip_prefix("event")?.parse().ok()?;
                Some((n, e.path()))
            })
            .collect(),
        Err(e) => return Err(format!("cannot list {}: {e}", dir.display())),
    };
    paths.sort();
    let mut found = Vec::new();
    let mut refused = Vec::new();
    for (_, path) in paths {
        match Device::open(&path) {
            Ok(device) => found.push((describe(&path, &device), device)),
            Err(e) => refused.push(format!("{}: {e}", path.display())),
        }
    }
    Ok((found, refused))
}

/// An opened gamepad.
pub struct OpenPad {
    pub device: Device,
    pub found: Found,
    pub opened: Opened,
}

/// Open the gamepad robot.ini names (or the first that fits, or with `pin` the pad
/// chosen before), or say why none is usable.
pub fn open(
    which: &GamepadDevice,
    map: &PadMap,
    dir: &Path,
    pin: Option<&Pin>,
) -> Result<OpenPad, String> {
    match which {
        GamepadDevice::Path(path) => {
            let device = Device::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
            let found = describe(path, &device);
            if let Some(missing) = lacks(&found, map) {
                return Err(format!(
                    "{} ({}) has no {missing}",
                    found.name,
                    path.display()
                ));
            }
            ready(device, found, map)
        }
        GamepadDevice::Auto => {
            let (devices, refused) = list(dir)?;
            let mut unfit = Vec::new();
            let mut fitting = Vec::new();
            for (found, device) in devices.into_iter().filter(|(f, _)| f.looks_like_gamepad()) {
                match lacks(&found, map) {
                    None => fitting.push((found, device)),
                    Some(missing) => unfit.push(format!("{} has no {missing}", found.name)),
                }
            }
            let found: Vec<Found> = fitting.iter().map(|(f, _)| f.clone()).collect();
            match choose(&found, pin) {
                Ok(i) => {
                    let (found, device) = fitting.swap_remove(i);
                    return ready(device, found, map);
                }
                Err(why) if pin.is_some() => return Err(why),
                Err(_) => {}
            }
            let mut why = format!("no input device in {} looks like a gamepad", dir.display());
            if !unfit.is_empty() {
                why = format!(
                    "no gamepad has the axes and button of [joystick]: {}",
                    unfit.join("; ")
                );
            }
            if !refused.is_empty() {
                why += &format!("; not readable: {}", refused.join(", "));
            }
            Err(why)
        }
    }
}

/// The first of the axes and button robot.ini names that the device does not have.
pub fn lacks(found: &Found, map: &PadMap) -> Option<String> {
    let axis = |code: AbsoluteAxisCode| format!("{code:?}");
    let button = format!("{:?}", map.deadman);
    [axis(map.speed_axis), axis(map.steer_axis)]
        .into_iter()
        .find(|a| !found.axes.contains(a))
        .map(|a| format!("axis {a}"))
        .or_else(|| (!found.buttons.contains(&button)).then(|| format!("button {button}")))
}

/// The axes' ranges and readings and the dead-man's state now, as the kernel has them.
fn kernel_state(device: &Device, map: &PadMap) -> Result<Opened, String> {
    let mut speed = None;
    let mut steer = None;
    for (code, info) in device.get_absinfo().map_err(|e| e.to_string())? {
        let reading = (
            AxisRange {
                min: info.minimum(),
                max: info.maximum(),
            },
            info.value(),
        );
        if code == map.speed_axis {
            speed = Some(reading);
        }
        if code == map.steer_axis {
            steer = Some(reading);
        }
    }
    let keys = device.get_key_state().map_err(|e| e.to_string())?;
    let missing = || "the kernel gave no range for the axes".to_string();
    Ok(Opened {
        speed: speed.ok_or_else(missing)?,
        steer: steer.ok_or_else(missing)?,
        deadman_held: keys.contains(map.deadman),
    })
}

fn ready(device: Device, found: Found, map: &PadMap) -> Result<OpenPad, String> {
    let place = found.path.display().to_string();
    let opened = kernel_state(&device, map).map_err(|e| format!("{place}: {e}"))?;
    // Read without waiting: the thread looks for the stop flag and the time-out between.
    (device.set_nonblocking(true)).map_err(|e| format!("{place}: {e}"))?;
    Ok(OpenPad {
        opened,
        device,
        found,
    })
}

/// The kernel's input devices as the gamepad thread's source.
pub(crate) struct InputDevices {
    pub which: GamepadDevice,
    pub dir: PathBuf,
    open: Option<Device>,
    /// With `auto`: the pad chosen first, the only one taken from then on.
    pin: Option<Pin>,
}

impl InputDevices {
    pub fn new(which: GamepadDevice, dir: &Path) -> InputDevices {
        InputDevices {
            which,
            dir: dir.to_path_buf(),
            open: None,
            pin: None,
        }
    }
}

impl PadSource for InputDevices {
    fn open(&mut self, map: &PadMap) -> Result<(Found, Opened), String> {
        let pad = open(&self.which, map, &self.dir, self.pin.as_ref())?;
        if self.which == GamepadDevice::Auto && self.pin.is_none() {
            self.pin = Some(Pin::of(&pad.found));
        }
        self.open = Some(pad.device);
        Ok((pad.found, pad.opened))
    }

    fn events(
        &mut self,
        wait: Duration,
        out: &mut Vec<(EventType, u16, i32)>,
    ) -> Result<(), String> {
        let Some(device) = self.open.as_mut() else {
            return Err("not open".into());
        };
        let mut poll = libc::pollfd {
            fd: device.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        // SAFETY: one valid pollfd for the duration of the call. An interrupted or failed
        // poll only means the read below finds nothing or the error.
        unsafe { libc::poll(&mut poll, 1, wait.as_millis() as i32) };
        let result = match device.fetch_events() {
            Ok(events) => {
                out.extend(events.map(|e| (e.event_type(), e.code(), e.value())));
                Ok(())
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Ok(()),
            // Unplugged: "No such device" (ENODEV).
            Err(e) => Err(e.to_string()),
        };
        if result.is_err() {
            self.open = None;
        }
        result
    }

    fn state(&mut self, map: &PadMap) -> Result<Opened, String> {
        match self.open.as_ref() {
            Some(device) => kernel_state(device, map),
            None => Err("not open".into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    #[test]
    fn files_that_are_not_input_devices_are_named_in_the_kernels_order_with_the_reason() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["event10", "event2", "mouse0", "js0"] {
            std::fs::write(dir.path().join(name), "").unwrap();
        }
        let (found, refused) = list(dir.path()).unwrap();
        assert!(found.is_empty());
        assert_eq!(refused.len(), 2, "{refused:?}");
        assert!(
            refused[0].contains("event2:") && refused[1].contains("event10:"),
            "{refused:?}"
        );
        let s = Settings::shipped();
        let map = PadMap::new(&s.gamepad, &s.joystick);
        let why = open(&GamepadDevice::Auto, &map, dir.path(), None)
            .err()
            .unwrap();
        assert!(
            why.contains("looks like a gamepad") && why.contains("not readable"),
            "{why}"
        );
        let missing = dir.path().join("none");
        assert!(list(&missing).unwrap_err().contains("cannot list"));
        let named = GamepadDevice::Path(dir.path().join("event2"));
        assert!(
            open(&named, &map, dir.path(), None)
                .err()
                .unwrap()
                .contains("event2")
        );
    }

    #[test]
    fn a_pad_fits_only_with_both_axes_and_the_dead_man_button() {
        let s = Settings::shipped();
        let map = PadMap::new(&s.gamepad, &s.joystick);
        let mut pad = Found {
            path: "/dev/input/event5".into(),
            name: "pad".into(),
            buttons: vec!["BTN_SOUTH".into(), "BTN_TL".into()],
            axes: vec!["ABS_X".into(), "ABS_Y".into(), "ABS_RX".into()],
            phys: String::new(),
        };
        assert!(pad.looks_like_gamepad());
        assert_eq!(lacks(&pad, &map), None);
        pad.buttons.retain(|b| b != "BTN_TL");
        assert_eq!(lacks(&pad, &map).as_deref(), Some("button BTN_TL"));
        pad.axes.retain(|a| a != "ABS_Y");
        assert_eq!(lacks(&pad, &map).as_deref(), Some("axis ABS_Y"));
        assert!(!pad.looks_like_gamepad());
        // A keyboard's keys are not a gamepad's buttons.
        let keyboard = Found {
            buttons: vec![],
            ..pad
        };
        assert!(!keyboard.looks_like_gamepad());
    }
}
