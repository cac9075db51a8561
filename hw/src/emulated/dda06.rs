//! The PCIM-DDA06/16's sixteen registers: six 16-bit DACs (low byte, then high byte,
//! which updates the output) and an 8255 with three 8-bit ports.

use std::io;
use std::sync::{Arc, Mutex};

use super::{lock, no_register};
use crate::cards::dda06::DacRange;
use crate::cards::port::PortIo;

struct Dda06Regs {
    /// The range switches on the card, which software cannot read.
    ranges: [DacRange; 6],
    /// Low bytes written, waiting for their high byte.
    low: [u8; 6],
    /// The code each DAC outputs.
    codes: [u16; 6],
    /// 8255 control word; power-up: every line an input.
    control: u8,
    /// 8255 output latches of ports A, B, C.
    latches: [u8; 3],
    /// Levels driven onto the 8255's pins from outside (switches), ports A, B, C.
    pins_in: [u8; 3],
    dead: bool,
}

impl Dda06Regs {
    /// Bits of port `p` (0 = A, 1 = B, 2 = C) that the 8255 drives as outputs.
    fn output_mask(&self, p: usize) -> u8 {
        let c = self.control;
        match p {
            0 if c & 0x10 == 0 => 0xFF,
            1 if c & 0x02 == 0 => 0xFF,
            2 => (if c & 0x08 == 0 { 0xF0 } else { 0 }) | (if c & 0x01 == 0 { 0x0F } else { 0 }),
            _ => 0,
        }
    }

    /// What the pins of port `p` carry: the latch on output bits, the wire on inputs.
    fn pins(&self, p: usize) -> u8 {
        let out = self.output_mask(p);
        (self.latches[p] & out) | (self.pins_in[p] & !out)
    }
}

/// An emulated PCIM-DDA06/16; clones share the same card.
#[derive(Clone)]
pub struct EmulatedDda06(Arc<Mutex<Dda06Regs>>);

impl EmulatedDda06 {
    /// A card just powered up, its range switches set to `ranges`: every DAC at 0 V,
    /// every 8255 line an input.
    pub fn new(ranges: [DacRange; 6]) -> EmulatedDda06 {
        let codes = ranges.map(|r| if r.bipolar() { 0x8000 } else { 0 });
        EmulatedDda06(Arc::new(Mutex::new(Dda06Regs {
            ranges,
            low: [0; 6],
            codes,
            // Mode 0, all four groups inputs.
            control: 0x9B,
            latches: [0; 3],
            pins_in: [0; 3],
            dead: false,
        })))
    }

    /// Volts on DAC output `n` (0..5).
    pub(crate) fn dac_volts(&self, n: usize) -> f64 {
        let r = lock(&self.0);
        match (r.ranges.get(n), r.codes.get(n)) {
            (Some(&range), Some(&code)) => range.volts(code),
            _ => 0.0,
        }
    }

    /// Someone sets DAC `n`'s range switch to `range` (the card keeps its code).
    pub fn set_range_switch(&self, n: usize, range: DacRange) {
        if let Some(switch) = lock(&self.0).ranges.get_mut(n) {
            *switch = range;
        }
    }

    /// The code DAC `n` outputs.
    pub fn dac_code(&self, n: usize) -> u16 {
        lock(&self.0).codes.get(n).copied().unwrap_or(0)
    }

    /// Drive the level of `bit` (0..7) of 8255 port `p` (0 = A, 1 = B, 2 = C) from outside.
    pub(crate) fn set_pin(&self, p: usize, bit: u8, high: bool) {
        let mut r = lock(&self.0);
        if let Some(pins) = r.pins_in.get_mut(p) {
            let mask = 1u8.checked_shl(u32::from(bit)).unwrap_or(0);
            *pins = if high { *pins | mask } else { *pins & !mask };
        }
    }

    /// The level on `bit` of port `p` as the robot sees it (output latch or input wire).
    pub fn pin(&self, p: usize, bit: u8) -> bool {
        let r = lock(&self.0);
        p < 3 && bit < 8 && r.pins(p) & (1 << bit) != 0
    }

    /// The card reads 0xFF at every register and ignores writes.
    pub fn set_dead(&self, dead: bool) {
        lock(&self.0).dead = dead;
    }
}

impl PortIo for EmulatedDda06 {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        let r = lock(&self.0);
        if offset > 0x0F {
            return Err(no_register("PCIM-DDA06/16", offset));
        }
        if r.dead {
            return Ok(0xFF);
        }
        Ok(match offset {
            // Reading a DAC register updates all six at once (simultaneous mode); in
            // this emulation the outputs already follow each high byte. The value read
            // is not documented.
            0x00..=0x0B => 0,
            0x0C..=0x0E => r.pins(usize::from(offset - 0x0C)),
            _ => 0,
        })
    }

    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        let mut r = lock(&self.0);
        if offset > 0x0F {
            return Err(no_register("PCIM-DDA06/16", offset));
        }
        if r.dead {
            return Ok(());
        }
        let n = usize::from(offset / 2);
        match offset {
            0x00..=0x0B if offset.is_multiple_of(2) => r.low[n] = value,
            0x00..=0x0B => r.codes[n] = u16::from(value) << 8 | u16::from(r.low[n]),
            0x0C..=0x0E => r.latches[usize::from(offset - 0x0C)] = value,
            _ if value & 0x80 != 0 => {
                // A mode word sets the directions and clears every output latch.
                r.control = value;
                r.latches = [0; 3];
            }
            _ => {
                // Bit set/reset of one port C line: bits 3..1 the line, bit 0 the level.
                let bit = 1u8 << ((value >> 1) & 0x07);
                r.latches[2] = if value & 1 != 0 {
                    r.latches[2] | bit
                } else {
                    r.latches[2] & !bit
                };
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use DacRange::*;

    fn card() -> EmulatedDda06 {
        EmulatedDda06::new([
            Bipolar10, Bipolar5, Unipolar10, Unipolar5, Bipolar5, Bipolar5,
        ])
    }

    #[test]
    fn dacs_power_up_at_zero_volts_and_change_on_the_high_byte() {
        let mut card = card();
        assert!((0..6).all(|n| card.dac_volts(n) == 0.0));
        assert_eq!(card.dac_code(0), 0x8000);
        assert_eq!(card.dac_code(2), 0);
        card.write_u8(0, 0x00).unwrap();
        assert_eq!(card.dac_volts(0), 0.0, "the low byte alone changes nothing");
        card.write_u8(1, 0xC0).unwrap();
        assert_eq!(card.dac_volts(0), 5.0);
        card.write_u8(2, 0x00).unwrap();
        card.write_u8(3, 0x00).unwrap();
        assert_eq!(card.dac_volts(1), -5.0);
        card.write_u8(4, 0x00).unwrap();
        card.write_u8(5, 0x80).unwrap();
        assert_eq!(card.dac_volts(2), 5.0);
    }

    #[test]
    fn the_8255_control_word_sets_directions_and_clears_output_latches() {
        let mut card = card();
        card.set_pin(0, 1, true);
        card.write_u8(0x0F, 0x90).unwrap(); // A in, B and C out
        card.write_u8(0x0D, 0x81).unwrap();
        assert!(card.pin(1, 0) && card.pin(1, 7) && !card.pin(1, 1));
        assert_eq!(card.read_u8(0x0C).unwrap(), 0x02, "port A reads its pins");
        card.write_u8(0x0F, 0x90).unwrap();
        assert!(!card.pin(1, 0), "a control word clears the latches");
        card.write_u8(0x0F, 0x07).unwrap(); // port C bit 3 set
        assert!(card.pin(2, 3));
    }
}
