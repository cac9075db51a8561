//! From a gamepad's events to the joystick the supervisor reads: the two axes as the
//! wired joystick's volts and the dead-man button as its enable. The dead band, the
//! limits and the ramp stay where they are (steer/joystick.rs, the supervisor); what is
//! new here is what a cable never does: the pad goes silent or goes away.
//!
//! The dead-man counts as released when:
//! - the pad is not connected;
//! - nothing came from it for `timeout_s` (a wireless pad out of range keeps its last
//!   values in the kernel, so silence is the only sign);
//! - it was connected, or came back after a silence, with the button held: the button
//!   must be released and pressed again, so a pad plugged in by someone holding it (or
//!   back in range) never starts the robot by itself;
//! - both sticks have not been seen in the middle (within the dead band) since the pad
//!   was connected: a stick held over, or an axis that rests at an end of its range (a
//!   trigger named by mistake), never starts the robot either.
//!
//! The kernel drops events when its buffer overflows; the thread therefore also gives
//! the kernel's own state of the sticks and button now and then (`reconcile`), so a
//! release that was dropped is not missed.

use std::time::Instant;

use evdev::{AbsoluteAxisCode, KeyCode};

use crate::config::{GamepadSettings, JoystickSettings};

/// What the mapping needs of the settings (Copy, so a `Pad` is too).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadMap {
    pub deadman: KeyCode,
    pub speed_axis: AbsoluteAxisCode,
    pub speed_sign: f64,
    pub steer_axis: AbsoluteAxisCode,
    pub steer_sign: f64,
    pub timeout_s: f64,
    /// The analog joystick's volts at full deflection: a pad's full deflection reads so.
    pub full_scale_v: f64,
    /// The analog joystick's dead band, V: a stick within it is in the middle.
    pub deadband_v: f64,
}

impl PadMap {
    pub fn new(pad: &GamepadSettings, joystick: &JoystickSettings) -> PadMap {
        let sign = |negative: bool| if negative { -1.0 } else { 1.0 };
        PadMap {
            deadman: pad.deadman_button,
            speed_axis: pad.speed_axis,
            speed_sign: sign(pad.speed_forward_negative),
            steer_axis: pad.steer_axis,
            steer_sign: sign(pad.steer_right_negative),
            timeout_s: pad.timeout_s,
            full_scale_v: joystick.full_scale_v,
            deadband_v: joystick.deadband_v,
        }
    }
}

/// An axis's range as the device reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisRange {
    pub min: i32,
    pub max: i32,
}

impl AxisRange {
    /// A reading -> -1..1 about the middle of the range.
    fn unit(&self, value: i32) -> f64 {
        let centre = (f64::from(self.min) + f64::from(self.max)) / 2.0;
        let half = ((f64::from(self.max) - f64::from(self.min)) / 2.0).max(1.0);
        ((f64::from(value) - centre) / half).clamp(-1.0, 1.0)
    }
}

/// The pad's state when it was opened.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Opened {
    pub speed: (AxisRange, i32),
    pub steer: (AxisRange, i32),
    pub deadman_held: bool,
}

/// Why the dead-man counts as released, or that it is held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DeadMan {
    Held,
    Released,
    NotConnected,
    /// Nothing from the pad for this long, s.
    Silent(f64),
    /// Held since the pad was connected or came back: release it and press again.
    ReleaseFirst,
    /// A stick has not been in the middle since the pad was connected.
    NotCentred,
}

impl DeadMan {
    pub fn words(&self) -> String {
        match self {
            DeadMan::Held => "held".into(),
            DeadMan::Released => "released".into(),
            DeadMan::NotConnected => "released (no gamepad)".into(),
            DeadMan::Silent(s) => format!("released (nothing from the gamepad for {s:.1} s)"),
            DeadMan::ReleaseFirst => "held, but must be released and pressed again".into(),
            DeadMan::NotCentred => {
                "held, but both sticks must first be let go to the middle".into()
            }
        }
    }
}

/// What the supervisor reads instead of the wired joystick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadJoystick {
    pub steer_v: f64,
    pub speed_v: f64,
    pub enable: bool,
    pub dead_man: DeadMan,
}

/// The gamepad as the mapping knows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pad {
    pub map: PadMap,
    pub connected: bool,
    speed: (AxisRange, i32),
    steer: (AxisRange, i32),
    deadman_held: bool,
    must_release: bool,
    /// Both sticks seen in the middle since the pad was connected.
    centred_seen: bool,
    last_event: Option<Instant>,
    /// Events taken since the program started, and times connected.
    pub events: u64,
    pub connections: u32,
}

impl Pad {
    pub fn new(map: PadMap) -> Pad {
        let idle = (AxisRange { min: -1, max: 1 }, 0);
        Pad {
            map,
            connected: false,
            speed: idle,
            steer: idle,
            deadman_held: false,
            must_release: false,
            centred_seen: false,
            last_event: None,
            events: 0,
            connections: 0,
        }
    }

    /// The pad was opened (at start or plugged back in).
    pub fn connect(&mut self, opened: Opened, now: Instant) {
        self.connected = true;
        self.speed = opened.speed;
        self.steer = opened.steer;
        self.deadman_held = opened.deadman_held;
        self.must_release = opened.deadman_held;
        self.centred_seen = false;
        self.look_for_centre();
        self.last_event = Some(now);
        self.connections += 1;
    }

    /// The kernel's state of the sticks and button now, in case an event was dropped. A
    /// release, or a stick's place, is taken at once; it is no sign of life (a pad out
    /// of range keeps its last state in the kernel).
    pub(crate) fn reconcile(&mut self, now: Opened) {
        self.speed.1 = now.speed.1;
        self.steer.1 = now.steer.1;
        self.look_for_centre();
        if !now.deadman_held {
            self.deadman_held = false;
            self.must_release = false;
        }
    }

    /// The dead-man button is down (as far as the pad has said).
    pub(crate) fn deadman_down(&self) -> bool {
        self.connected && self.deadman_held
    }

    fn look_for_centre(&mut self) {
        let (steer, speed) = self.deflection();
        let band = self.map.deadband_v / self.map.full_scale_v;
        self.centred_seen |= steer.abs() <= band && speed.abs() <= band;
    }

    /// The pad went away (unplugged, out of a wireless receiver's reach, or unreadable).
    pub(crate) fn disconnect(&mut self) {
        self.connected = false;
        self.deadman_held = false;
    }

    /// One event from the pad: an axis (EV_ABS), a button (EV_KEY) or anything else,
    /// which counts only as a sign of life.
    pub fn event(&mut self, kind: evdev::EventType, code: u16, value: i32, now: Instant) {
        if self.deadman_held && self.silent_s(now).is_some() {
            self.must_release = true;
        }
        self.last_event = Some(now);
        self.events += 1;
        if kind == evdev::EventType::ABSOLUTE {
            if code == self.map.speed_axis.0 {
                self.speed.1 = value;
            }
            if code == self.map.steer_axis.0 {
                self.steer.1 = value;
            }
            self.look_for_centre();
        } else if kind == evdev::EventType::KEY && code == self.map.deadman.code() {
            // 1 pressed, 2 the kernel's auto-repeat while held, 0 released.
            self.deadman_held = value != 0;
            if !self.deadman_held {
                self.must_release = false;
            }
        }
    }

    /// How long the pad has been silent beyond the time-out, or None.
    fn silent_s(&self, now: Instant) -> Option<f64> {
        let quiet_s = now
            .saturating_duration_since(self.last_event?)
            .as_secs_f64();
        (quiet_s > self.map.timeout_s).then_some(quiet_s)
    }

    /// The axes in unit deflection, right and forward positive.
    pub fn deflection(&self) -> (f64, f64) {
        (
            self.map.steer_sign * self.steer.0.unit(self.steer.1),
            self.map.speed_sign * self.speed.0.unit(self.speed.1),
        )
    }

    /// The joystick as the supervisor reads it now.
    pub fn joystick(&self, now: Instant) -> PadJoystick {
        let dead_man = if !self.connected {
            DeadMan::NotConnected
        } else if !self.deadman_held {
            DeadMan::Released
        } else if let Some(quiet_s) = self.silent_s(now) {
            DeadMan::Silent(quiet_s)
        } else if self.must_release {
            DeadMan::ReleaseFirst
        } else if !self.centred_seen {
            DeadMan::NotCentred
        } else {
            DeadMan::Held
        };
        let (steer, speed) = if self.connected {
            self.deflection()
        } else {
            (0.0, 0.0)
        };
        PadJoystick {
            steer_v: steer * self.map.full_scale_v,
            speed_v: speed * self.map.full_scale_v,
            enable: dead_man == DeadMan::Held,
            dead_man,
        }
    }
}

#[cfg(test)]
#[path = "mapping_tests.rs"]
mod tests;
