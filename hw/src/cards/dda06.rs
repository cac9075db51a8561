//! Driver of the PCIM-DDA06/16 (docs/function_spec.md, section 4a): six 16-bit DACs and an 8255 with
//! 24 digital lines in three ports.
//!
//! A DAC takes its low byte, then its high byte, which updates the output. Each DAC's
//! range is a switch on the card that software cannot read, so it is a setting; the
//! bipolar ranges are offset binary (0x8000 = 0 V), so "off" is 0x8000, never 0x0000.
//! The 8255 is configured once, at open: every port group that carries an output is
//! an output, every other one an input (the power-up state). Its control word clears
//! the output latches, so outputs are written after it.
//!
//! Nothing in the documented registers reads back from this card, so a DDA06 that
//! stopped answering cannot be told from one that answers; with the robot's wiring a
//! card that reads 0xFF shows both end switches closed, itself a fault.

use crate::cards::port::PortIo;
use crate::{CardFault, HwError};

/// The card's name in every message.
pub const NAME: &str = "PCIM-DDA06/16";

/// The six DACs.
pub const DACS: usize = 6;
const PORT_A: u16 = 0x0C;
const CONTROL_8255: u16 = 0x0F;

/// One DAC's output range, set by a switch on the card.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DacRange {
    Bipolar10,
    Bipolar5,
    Unipolar10,
    Unipolar5,
}

impl DacRange {
    pub const ALL: [DacRange; 4] = [
        DacRange::Bipolar10,
        DacRange::Bipolar5,
        DacRange::Unipolar10,
        DacRange::Unipolar5,
    ];

    /// As written in robot.ini.
    pub fn name(self) -> &'static str {
        match self {
            DacRange::Bipolar10 => "+-10",
            DacRange::Bipolar5 => "+-5",
            DacRange::Unipolar10 => "0..10",
            DacRange::Unipolar5 => "0..5",
        }
    }

    pub fn parse(text: &str) -> Result<DacRange, String> {
        DacRange::ALL
            .into_iter()
            .find(|r| r.name() == text.trim())
            .ok_or_else(|| format!("'{}' is not one of: +-10, +-5, 0..10, 0..5", text.trim()))
    }

    pub fn full_scale_v(self) -> f64 {
        match self {
            DacRange::Bipolar10 | DacRange::Unipolar10 => 10.0,
            DacRange::Bipolar5 | DacRange::Unipolar5 => 5.0,
        }
    }

    pub fn bipolar(self) -> bool {
        matches!(self, DacRange::Bipolar10 | DacRange::Bipolar5)
    }

    /// The code for 0 V: 0x8000 on a bipolar range, 0 on a unipolar one.
    pub(crate) fn zero_code(self) -> u16 {
        if self.bipolar() { 0x8000 } else { 0 }
    }

    /// The code for `volts`, clamped to the range; anything not a number is 0 V.
    pub fn code(self, volts: f64) -> u16 {
        if !volts.is_finite() {
            return self.zero_code();
        }
        let steps = volts / self.full_scale_v() * if self.bipolar() { 32768.0 } else { 65536.0 };
        let code = steps.round() + f64::from(self.zero_code());
        code.clamp(0.0, 65535.0) as u16
    }

    /// What a DAC whose switch is at this range puts out for `code`, V: offset binary
    /// when bipolar. A code written for one range and put out at another is how a
    /// switch that differs from robot.ini shows on a voltmeter.
    pub fn volts(self, code: u16) -> f64 {
        let fs = self.full_scale_v();
        if self.bipolar() {
            (f64::from(code) - 32768.0) / 32768.0 * fs
        } else {
            f64::from(code) / 65536.0 * fs
        }
    }

    /// The unipolar range of the same full scale: a switch set one position off.
    pub fn unipolar(self) -> DacRange {
        match self {
            DacRange::Bipolar10 | DacRange::Unipolar10 => DacRange::Unipolar10,
            DacRange::Bipolar5 | DacRange::Unipolar5 => DacRange::Unipolar5,
        }
    }
}

/// Which bits of the 8255's ports A, B and C are wired as outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PortDirections {
    pub output_bits: [u8; 3],
}

impl PortDirections {
    /// Mode 0; a group without outputs is an input: 0x10 A, 0x08 upper C, 0x02 B,
    /// 0x01 lower C.
    pub(crate) fn control_word(self) -> u8 {
        let [a, b, c] = self.output_bits;
        let input = |bits: u8, flag: u8| if bits == 0 { flag } else { 0 };
        0x80 | input(a, 0x10) | input(c & 0xF0, 0x08) | input(b, 0x02) | input(c & 0x0F, 0x01)
    }
}

pub struct Dda06 {
    port: Box<dyn PortIo>,
    ranges: [DacRange; DACS],
}

fn failed(register: u16, fault: CardFault) -> HwError {
    HwError::CardNotAnswering {
        card: NAME,
        register,
        fault,
    }
}

impl Dda06 {
    /// Take the card: every DAC to 0 V first, then the 8255 (which clears its output
    /// latches), then `safe_ports` on the ports that have outputs.
    pub fn open(
        port: Box<dyn PortIo>,
        ranges: [DacRange; DACS],
        directions: PortDirections,
        safe_ports: [u8; 3],
    ) -> Result<Dda06, HwError> {
        let mut card = Dda06 { port, ranges };
        card.write_all_zero()?;
        card.write(CONTROL_8255, directions.control_word())?;
        for (p, &bits) in directions.output_bits.iter().enumerate() {
            if bits != 0 {
                card.write_port(p, safe_ports[p])?;
            }
        }
        Ok(card)
    }

    fn write(&mut self, offset: u16, value: u8) -> Result<(), HwError> {
        self.port
            .write_u8(offset, value)
            .map_err(|e| failed(offset, CardFault::WriteFailed(e.kind())))
    }

    /// Every DAC to its 0 V code.
    pub(crate) fn write_all_zero(&mut self) -> Result<(), HwError> {
        for n in 0..DACS {
            self.write_code(n, self.ranges[n].zero_code())?;
        }
        Ok(())
    }

    /// DAC `n` (0..5): low byte, then high byte, which updates the output.
    pub(crate) fn write_code(&mut self, n: usize, code: u16) -> Result<(), HwError> {
        let offset = 2 * (n.min(DACS - 1) as u16);
        let [low, high] = code.to_le_bytes();
        self.write(offset, low)?;
        self.write(offset + 1, high)
    }

    /// DAC `n` to `volts`, clamped to its range; returns the code written.
    pub(crate) fn write_volts(&mut self, n: usize, volts: f64) -> Result<u16, HwError> {
        let code = self.ranges[n.min(DACS - 1)].code(volts);
        self.write_code(n, code)?;
        Ok(code)
    }

    /// 8255 port `p` (0 = A, 1 = B, 2 = C).
    pub fn read_port(&mut self, p: usize) -> Result<u8, HwError> {
        let offset = PORT_A + p.min(2) as u16;
        self.port
            .read_u8(offset)
            .map_err(|e| failed(offset, CardFault::ReadFailed(e.kind())))
    }

    pub(crate) fn write_port(&mut self, p: usize, value: u8) -> Result<(), HwError> {
        self.write(PORT_A + p.min(2) as u16, value)
    }
}

/// "A", "B" or "C".
pub fn port_name(p: usize) -> &'static str {
    ["A", "B", "C"][p.min(2)]
}

#[cfg(test)]
#[path = "dda06_tests.rs"]
mod tests;
