//! How the robot is wired to the cards (robot.ini [io], after docs/function_spec.md section 4a):
//! for each signal its card, channel or bit, polarity and scale; and the conversion of
//! card values into [`Inputs`] and of [`Outputs`] into card values.
//!
//! A signal is written in robot.ini as `CARD CHANNEL, OPTION`:
//!
//! | kind | places | option |
//! |---|---|---|
//! | analog input | `das08 ai N` (N 0..7) | `scale S`: signal volts per volt at the card |
//! | switch input | `das08 ip N` (1..3), `dda06 port X bit N` (X a, b, c; N 0..7) | `active high` or `active low` |
//! | encoder | `quad04 ch N` (1..4) | `scale 1` or `scale -1` (counts reversed) |
//! | analog output | `dda06 ao N` (0..5) | `scale S`: volts at the card per commanded volt |
//! | switched output | `das08 op N` (1..4), `dda06 port X bit N` | `active high` or `active low` |
//! | watchdog output | as a switched output, or `none` | `active high` or `active low` |
//!
//! `active high`: 1 at the card means true. The conversions run every tick and do not
//! allocate. The inverse conversions (what the wires carry for given physical signals,
//! what the card's outputs mean physically) serve the emulated robot in tests.

use std::fmt;

use crate::cards::dda06::PortDirections;
use crate::{Inputs, Outputs};

/// An analog input on the DAS08: signal = volts at the card x `scale`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogIn {
    pub channel: u8,
    pub scale: f64,
}

/// An analog output on the DDA06: volts at the card = signal x `scale`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogOut {
    pub channel: u8,
    pub scale: f64,
}

/// An encoder on the QUAD04: counts = card counts x `sign` (+1 or -1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoder {
    pub channel: u8,
    pub sign: i64,
}

/// One digital line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bit {
    /// DAS08 digital input IP1..IP3.
    Das08In(u8),
    /// DAS08 digital output OP1..OP4.
    Das08Out(u8),
    /// DDA06 8255 port (0 = A, 1 = B, 2 = C), bit 0..7.
    Dda06 { port: u8, bit: u8 },
}

/// A switch input or a switched output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Switch {
    pub bit: Bit,
    /// True: a 1 at the card means the signal is true.
    pub active_high: bool,
}

impl Switch {
    /// The signal from the line's level.
    pub fn signal(self, level: bool) -> bool {
        level == self.active_high
    }

    /// The line's level for a signal (the same mapping both ways).
    pub fn level(self, signal: bool) -> bool {
        signal == self.active_high
    }
}

/// Where one signal is wired, for checks and messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    Das08Ai(u8),
    Bit(Bit),
    Dda06Ao(u8),
    Quad04(u8),
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Place::Das08Ai(n) => write!(f, "das08 ai {n}"),
            Place::Bit(Bit::Das08In(n)) => write!(f, "das08 ip {n}"),
            Place::Bit(Bit::Das08Out(n)) => write!(f, "das08 op {n}"),
            Place::Bit(Bit::Dda06 { port, bit }) => {
                write!(
                    f,
                    "dda06 port {} bit {bit}",
                    ["a", "b", "c"][usize::from(port % 3)]
                )
            }
            Place::Dda06Ao(n) => write!(f, "dda06 ao {n}"),
            Place::Quad04(n) => write!(f, "quad04 ch {n}"),
        }
    }
}

/// The whole wiring: every input and output of the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wiring {
    pub pot_v: AnalogIn,
    pub joystick_steer_v: AnalogIn,
    pub joystick_speed_v: AnalogIn,
    pub battery_v: AnalogIn,
    pub estop_front_released: Switch,
    pub estop_back_released: Switch,
    pub motor_power_present: Switch,
    pub end_switch_left: Switch,
    pub end_switch_right: Switch,
    pub joystick_enable: Switch,
    /// The dead-man's second contact, if it has one: normally closed, true = let go.
    /// The dead-man is held only while its contacts disagree that way, so that a
    /// broken wire on either reads as let go (`inputs`).
    pub joystick_released: Option<Switch>,
    pub enc_left_counts: Encoder,
    pub enc_right_counts: Encoder,
    pub enc_steer_counts: Encoder,
    pub amp_left_v: AnalogOut,
    pub amp_right_v: AnalogOut,
    pub amp_steer_v: AnalogOut,
    pub main_power_on: Switch,
    pub brake_release_left: Switch,
    pub brake_release_right: Switch,
    pub tool_on: Switch,
    /// The charge-pump line for an external watchdog relay, if one is fitted; the
    /// cards' backend toggles it (watchdog.rs), it is no signal of [`Outputs`].
    pub watchdog: Option<Switch>,
}

/// What the cards gave in one tick, in card units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CardInputs {
    /// DAS08 analog inputs 0..7, volts at the card.
    pub das08_ai_v: [f64; 8],
    /// DAS08 IP1..IP3 levels in bits 0..2.
    pub das08_ip: u8,
    /// DDA06 8255 ports A, B, C as read.
    pub dda06_ports: [u8; 3],
    /// QUAD04 channels 1..4 (index 0..3), counts.
    pub quad04_counts: [i64; 4],
}

/// What to write to the cards in one tick, in card units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct CardOutputs {
    /// DDA06 analog outputs 0..5, volts at the card.
    pub dda06_ao_v: [f64; 6],
    /// DAS08 OP1..OP4 levels in bits 0..3.
    pub das08_op: u8,
    /// DDA06 8255 ports A, B, C (only output bits matter).
    pub dda06_ports: [u8; 3],
}

impl CardOutputs {
    /// Set one output line to `level`.
    pub(crate) fn set_line(&mut self, bit: Bit, level: bool) {
        set_level(bit, level, &mut self.das08_op, &mut self.dda06_ports);
    }
}

/// One line's level: from `das08` (the IP or the OP byte) or the DDA06 `ports`.
fn get_level(bit: Bit, das08: u8, ports: &[u8; 3]) -> bool {
    match bit {
        Bit::Das08In(n) | Bit::Das08Out(n) => das08 >> (n.clamp(1, 4) - 1) & 1 != 0,
        Bit::Dda06 { port, bit } => ports[usize::from(port % 3)] >> (bit % 8) & 1 != 0,
    }
}

/// Set one line's level in a byte of levels.
fn set(byte: &mut u8, bit: u8, level: bool) {
    if level {
        *byte |= 1 << bit;
    } else {
        *byte &= !(1 << bit);
    }
}

/// Set one line's level: in `das08` (the IP or the OP byte, as the line is an input
/// or an output) or in the DDA06 `ports`.
fn set_level(bit: Bit, level: bool, das08: &mut u8, ports: &mut [u8; 3]) {
    match bit {
        Bit::Das08In(n) | Bit::Das08Out(n) => set(das08, n.clamp(1, 4) - 1, level),
        Bit::Dda06 { port, bit } => set(&mut ports[usize::from(port % 3)], bit % 8, level),
    }
}

impl Wiring {
    /// Every signal with its robot.ini key and place, inputs first.
    pub fn places(&self) -> [(&'static str, Place); 20] {
        let ai = |a: AnalogIn| Place::Das08Ai(a.channel);
        let sw = |s: Switch| Place::Bit(s.bit);
        let enc = |e: Encoder| Place::Quad04(e.channel);
        let ao = |a: AnalogOut| Place::Dda06Ao(a.channel);
        [
            ("pot_v", ai(self.pot_v)),
            ("joystick_steer_v", ai(self.joystick_steer_v)),
            ("joystick_speed_v", ai(self.joystick_speed_v)),
            ("battery_v", ai(self.battery_v)),
            ("estop_front_released", sw(self.estop_front_released)),
            ("estop_back_released", sw(self.estop_back_released)),
            ("motor_power_present", sw(self.motor_power_present)),
            ("end_switch_left", sw(self.end_switch_left)),
            ("end_switch_right", sw(self.end_switch_right)),
            ("joystick_enable", sw(self.joystick_enable)),
            ("enc_left_counts", enc(self.enc_left_counts)),
            ("enc_right_counts", enc(self.enc_right_counts)),
            ("enc_steer_counts", enc(self.enc_steer_counts)),
            ("amp_left_v", ao(self.amp_left_v)),
            ("amp_right_v", ao(self.amp_right_v)),
            ("amp_steer_v", ao(self.amp_steer_v)),
            ("main_power_on", sw(self.main_power_on)),
            ("brake_release_left", sw(self.brake_release_left)),
            ("brake_release_right", sw(self.brake_release_right)),
            ("tool_on", sw(self.tool_on)),
        ]
    }

    /// The switch inputs, with their robot.ini keys: six, and the dead-man's second
    /// contact where it has one.
    pub(crate) fn switch_inputs(&self) -> impl Iterator<Item = (&'static str, Switch)> {
        let released = self.joystick_released.map(|s| ("joystick_released", s));
        [
            ("estop_front_released", self.estop_front_released),
            ("estop_back_released", self.estop_back_released),
            ("motor_power_present", self.motor_power_present),
            ("end_switch_left", self.end_switch_left),
            ("end_switch_right", self.end_switch_right),
            ("joystick_enable", self.joystick_enable),
        ]
        .into_iter()
        .chain(released)
    }

    /// The four switched outputs, with their robot.ini keys.
    pub(crate) fn switch_outputs(&self) -> [(&'static str, Switch); 4] {
        [
            ("main_power_on", self.main_power_on),
            ("brake_release_left", self.brake_release_left),
            ("brake_release_right", self.brake_release_right),
            ("tool_on", self.tool_on),
        ]
    }

    /// Every line the cards drive, with its key: the switched outputs and the watchdog.
    pub(crate) fn driven_lines(&self) -> impl Iterator<Item = (&'static str, Switch)> {
        let watchdog = self.watchdog.map(|w| ("watchdog", w));
        self.switch_outputs().into_iter().chain(watchdog)
    }

    pub(crate) fn analog_inputs(&self) -> [AnalogIn; 4] {
        [
            self.pot_v,
            self.joystick_steer_v,
            self.joystick_speed_v,
            self.battery_v,
        ]
    }

    pub fn encoders(&self) -> [Encoder; 3] {
        [
            self.enc_left_counts,
            self.enc_right_counts,
            self.enc_steer_counts,
        ]
    }

    pub(crate) fn analog_outputs(&self) -> [AnalogOut; 3] {
        [self.amp_left_v, self.amp_right_v, self.amp_steer_v]
    }

    /// True if a switch input is on the DAS08 (then its status must be read).
    pub(crate) fn reads_das08_inputs(&self) -> bool {
        let on_das08 = |(_, s): &(&str, Switch)| matches!(s.bit, Bit::Das08In(_));
        self.switch_inputs().any(|input| on_das08(&input))
    }

    /// The 8255 directions: every bit that carries a switched output or the watchdog.
    pub(crate) fn dda06_directions(&self) -> PortDirections {
        let mut output_bits = [0u8; 3];
        for (_, s) in self.driven_lines() {
            if let Bit::Dda06 { port, bit } = s.bit {
                output_bits[usize::from(port % 3)] |= 1 << (bit % 8);
            }
        }
        PortDirections { output_bits }
    }

    /// The 8255 ports that carry a switch input and must be read.
    pub(crate) fn dda06_input_ports(&self) -> [bool; 3] {
        let mut read = [false; 3];
        for (_, s) in self.switch_inputs() {
            if let Bit::Dda06 { port, .. } = s.bit {
                read[usize::from(port % 3)] = true;
            }
        }
        read
    }

    /// Physical inputs from what the cards read.
    pub fn inputs(&self, c: &CardInputs) -> Inputs {
        let volts = |a: AnalogIn| c.das08_ai_v[usize::from(a.channel % 8)] * a.scale;
        let on = |s: Switch| s.signal(get_level(s.bit, c.das08_ip, &c.dda06_ports));
        let counts = |e: Encoder| c.quad04_counts[usize::from(e.channel.clamp(1, 4) - 1)] * e.sign;
        Inputs {
            pot_v: volts(self.pot_v),
            joystick_steer_v: volts(self.joystick_steer_v),
            joystick_speed_v: volts(self.joystick_speed_v),
            battery_v: volts(self.battery_v),
            estop_front_released: on(self.estop_front_released),
            estop_back_released: on(self.estop_back_released),
            motor_power_present: on(self.motor_power_present),
            end_switch_left: on(self.end_switch_left),
            end_switch_right: on(self.end_switch_right),
            // Held: its open contact closed and, on a two-contact button, its closed
            // contact open.
            joystick_enable: on(self.joystick_enable) && !self.joystick_released.is_some_and(on),
            enc_left_counts: counts(self.enc_left_counts),
            enc_right_counts: counts(self.enc_right_counts),
            enc_steer_counts: counts(self.enc_steer_counts),
        }
    }

    /// Card values for the outputs. Unwired DACs stay at 0 V.
    pub(crate) fn card_outputs(&self, o: &Outputs) -> CardOutputs {
        let mut c = CardOutputs::default();
        let volts = [o.amp_left_v, o.amp_right_v, o.amp_steer_v];
        for (a, v) in self.analog_outputs().into_iter().zip(volts) {
            c.dda06_ao_v[usize::from(a.channel % 6)] = v * a.scale;
        }
        let on = [
            o.main_power_on,
            o.brake_release_left,
            o.brake_release_right,
            o.tool_on,
        ];
        for ((_, s), signal) in self.switch_outputs().into_iter().zip(on) {
            set_level(s.bit, s.level(signal), &mut c.das08_op, &mut c.dda06_ports);
        }
        c
    }
}

mod emulated;
mod parse;
pub use parse::{
    check, parse_analog_in, parse_analog_out, parse_encoder, parse_second_contact, parse_switch_in,
    parse_switch_out, parse_watchdog,
};

#[cfg(test)]
pub(crate) mod tests;
