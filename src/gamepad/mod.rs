//! A gamepad as the joystick ([joystick] source = gamepad): a thread of its own reads
//! the pad's Linux input events (device.rs, thread.rs), the mapping turns them into the
//! wired joystick's volts and dead-man (mapping.rs), and the supervisor reads them in
//! place of the analog joystick (hw.rs). The steer thread and the supervisor do not know
//! the difference: the same dead band, limits, ramp and dead-man rule.

pub mod device;
mod hw;
pub mod mapping;
pub mod pin;
mod thread;

pub use hw::PadHw;
pub use mapping::{DeadMan, Pad, PadJoystick, PadMap};
pub use thread::start;

/// Short text that fits in a protected object (which holds only `Copy` values).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Label {
    bytes: [u8; 120],
    len: u8,
}

impl Label {
    pub(crate) const EMPTY: Label = Label {
        bytes: [0; 120],
        len: 0,
    };

    /// The text, cut at a character's boundary if longer than 120 bytes.
    pub fn new(text: &str) -> Label {
        let mut end = text.len().min(120);
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let mut label = Label::EMPTY;
        label.bytes[..end].copy_from_slice(&text.as_bytes()[..end]);
        label.len = end as u8;
        label
    }

    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..usize::from(self.len)]).unwrap_or("")
    }
}

impl Default for Label {
    fn default() -> Label {
        Label::EMPTY
    }
}

impl serde::Serialize for Label {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

impl std::fmt::Debug for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

/// The gamepad as the GUI and the supervisor see it (one protected object, written by
/// the gamepad thread).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadState {
    pub pad: Pad,
    /// The device's name ("Logitech Gamepad F310") and file, while or since connected.
    pub name: Label,
    pub place: Label,
    /// Why no pad is connected ("no input device looks like a gamepad"), if none is.
    pub problem: Label,
}

impl PadState {
    pub fn new(map: PadMap) -> PadState {
        PadState {
            pad: Pad::new(map),
            name: Label::EMPTY,
            place: Label::EMPTY,
            problem: Label::new("not looked for yet"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Label;

    #[test]
    fn a_label_keeps_short_text_and_cuts_long_text_at_a_character() {
        assert_eq!(
            Label::new("Logitech Gamepad F310").as_str(),
            "Logitech Gamepad F310"
        );
        let long = "é".repeat(100);
        let cut = Label::new(&long);
        assert_eq!(cut.as_str(), "é".repeat(60));
    }
}
