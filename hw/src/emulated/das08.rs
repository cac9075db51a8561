//! The PCI-DAS08's eight registers: a 12-bit A/D with an 8-channel multiplexer and an
//! end-of-conversion flag, three digital inputs and four write-only digital outputs.

use std::io;
use std::sync::{Arc, Mutex};

use super::{lock, no_register};
use crate::cards::port::PortIo;

/// Status reads that show "busy" after a conversion starts, unless told otherwise.
/// A real conversion takes about 10 us, a few port reads.
const DEFAULT_BUSY_READS: u32 = 3;

struct Das08Regs {
    /// Volts on each analog input's wire.
    ai_volts: [f64; 8],
    /// Levels on IP1..IP3, in bits 0..2.
    inputs: u8,
    /// The last control byte: outputs OP4..OP1 in bits 7..4, interrupt enable 3, mux 2..0.
    control: u8,
    /// The last conversion's result, 12 bits.
    code: u16,
    /// Status reads left that show busy.
    busy_reads_left: u32,
    busy_reads: u32,
    eoc_stuck: bool,
    dead: bool,
}

/// An emulated PCI-DAS08; clones share the same card.
#[derive(Clone)]
pub struct EmulatedDas08(Arc<Mutex<Das08Regs>>);

impl Default for EmulatedDas08 {
    fn default() -> Self {
        EmulatedDas08::new()
    }
}

/// The card's A/D transfer: -5 V .. +5 V onto 0 .. 4095, 2.441 mV per step.
fn convert(volts: f64) -> u16 {
    let code = ((volts + 5.0) / 10.0 * 4096.0).round();
    if code.is_nan() {
        0
    } else {
        code.clamp(0.0, 4095.0) as u16
    }
}

impl EmulatedDas08 {
    /// A card just powered up: every output on (the power-up state is not documented,
    /// so assume the worst), inputs at 0 V and low.
    pub fn new() -> EmulatedDas08 {
        EmulatedDas08(Arc::new(Mutex::new(Das08Regs {
            ai_volts: [0.0; 8],
            inputs: 0,
            control: 0xF0,
            code: 0,
            busy_reads_left: 0,
            busy_reads: DEFAULT_BUSY_READS,
            eoc_stuck: false,
            dead: false,
        })))
    }

    /// Volts on analog input `channel` (0..7; others are ignored).
    pub fn set_ai_volts(&self, channel: usize, volts: f64) {
        if let Some(v) = lock(&self.0).ai_volts.get_mut(channel) {
            *v = volts;
        }
    }

    /// Level on digital input IP`n` (1..3; others are ignored).
    pub fn set_input(&self, n: usize, high: bool) {
        if (1..=3).contains(&n) {
            let mut r = lock(&self.0);
            let bit = 1 << (n - 1);
            r.inputs = if high {
                r.inputs | bit
            } else {
                r.inputs & !bit
            };
        }
    }

    /// Level the card drives on digital output OP`n` (1..4).
    pub fn output(&self, n: usize) -> bool {
        (1..=4).contains(&n) && lock(&self.0).control & (0x10 << (n - 1)) != 0
    }

    /// Status reads that show busy after each conversion start.
    pub fn set_busy_reads(&self, reads: u32) {
        lock(&self.0).busy_reads = reads;
    }

    /// The end-of-conversion flag stays busy for ever (a broken A/D).
    pub fn set_eoc_stuck(&self, stuck: bool) {
        lock(&self.0).eoc_stuck = stuck;
    }

    /// The card reads 0xFF at every register and ignores writes.
    pub fn set_dead(&self, dead: bool) {
        lock(&self.0).dead = dead;
    }
}

impl PortIo for EmulatedDas08 {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        let mut r = lock(&self.0);
        if offset > 7 {
            return Err(no_register("PCI-DAS08", offset));
        }
        if r.dead {
            return Ok(0xFF);
        }
        Ok(match offset {
            0 => ((r.code & 0x0F) << 4) as u8,
            1 => (r.code >> 4) as u8,
            2 => {
                let busy = r.eoc_stuck || r.busy_reads_left > 0;
                r.busy_reads_left = r.busy_reads_left.saturating_sub(1);
                let eoc = if busy { 0x80 } else { 0 };
                // The outputs are not in the status: they cannot be read back.
                eoc | (r.inputs & 0x07) << 4 | (r.control & 0x07)
            }
            // The 8254 counters are not used by mechweed and not emulated.
            _ => 0,
        })
    }

    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        let mut r = lock(&self.0);
        if offset > 7 {
            return Err(no_register("PCI-DAS08", offset));
        }
        if r.dead {
            return Ok(());
        }
        match offset {
            // +0 starts an 8-bit conversion: the low nibble reads 0.
            0 | 1 => {
                let code = convert(r.ai_volts[usize::from(r.control & 0x07)]);
                r.code = if offset == 0 { code & 0xFF0 } else { code };
                r.busy_reads_left = r.busy_reads;
            }
            2 => r.control = value,
            _ => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transfer_function_is_the_cards() {
        assert_eq!(convert(-5.0), 0);
        assert_eq!(convert(0.0), 2048);
        assert_eq!(convert(4.9976), 4095);
        assert_eq!(convert(9.0), 4095);
        assert_eq!(convert(-9.0), 0);
        assert_eq!(convert(f64::NAN), 0);
    }

    #[test]
    fn a_conversion_is_busy_for_some_status_reads_then_gives_its_code() {
        let mut card = EmulatedDas08::new();
        card.set_ai_volts(3, 2.4);
        card.write_u8(2, 0x03).unwrap();
        card.write_u8(1, 0).unwrap();
        let status: Vec<u8> = (0..4).map(|_| card.read_u8(2).unwrap()).collect();
        assert_eq!(status, [0x83, 0x83, 0x83, 0x03]);
        let high = card.read_u8(1).unwrap();
        let low = card.read_u8(0).unwrap();
        assert_eq!(u16::from(high) * 16 + u16::from(low >> 4), convert(2.4));
    }

    #[test]
    fn outputs_follow_the_control_byte_but_are_not_readable() {
        let mut card = EmulatedDas08::new();
        assert!((1..=4).all(|n| card.output(n)), "powers up with outputs on");
        card.write_u8(2, 0xA0).unwrap();
        let outputs: Vec<bool> = (1..=4).map(|n| card.output(n)).collect();
        assert_eq!(outputs, [false, true, false, true]);
        card.set_input(1, true);
        card.set_input(3, true);
        assert_eq!(card.read_u8(2).unwrap(), 0x50);
    }
}
