//! The PCI-QUAD04: four LS7266R1 counter channels (two chips of two), each with a data
//! port and a control port, plus index routing (+8) and cascading (+9).
//!
//! Per channel: a 24-bit preset, counter and output latch, a byte pointer that steps
//! through the three bytes, flags, and the mode (CMR), input (IOR) and index (IDR)
//! registers. The encoder on the wires is a position in quadrature edges; the counter
//! counts them as the mode says (x4: every edge) while its inputs are enabled.

use std::io;
use std::sync::{Arc, Mutex};

use super::{lock, no_register};
use crate::cards::port::PortIo;

const WRAP: i64 = 1 << 24;
const MASK: u32 = 0xFF_FFFF;

/// Flag register bits.
const FLAG_BORROW: u8 = 0x01;
const FLAG_CARRY: u8 = 0x02;
const FLAG_SIGN: u8 = 0x08;
const FLAG_NOISE: u8 = 0x10;
const FLAG_UP: u8 = 0x20;

#[derive(Clone, Copy)]
struct Counter {
    preset: u32,
    count: u32,
    latch: u32,
    pointer: u8,
    flags: u8,
    cmr: u8,
    ior: u8,
    idr: u8,
    prescaler: u8,
    /// The encoder's position on the wires, quadrature edges.
    edges: i64,
    /// A broken counter: it no longer counts, whatever the encoder does.
    stopped: bool,
}

impl Counter {
    /// Nothing is documented at power-up: start from garbage that a driver must clear.
    fn powered_up() -> Counter {
        Counter {
            preset: 0x00A5_5A00,
            count: 0x005A_5A5A,
            latch: 0x00C3_C3C3,
            pointer: 2,
            flags: FLAG_NOISE,
            cmr: 0,
            ior: 0,
            idr: 0,
            prescaler: 0,
            edges: 0,
            stopped: false,
        }
    }

    /// Edges per count: x4 counts every edge, x2 every second, x1 every fourth; the
    /// non-quadrature mode (00) does not count quadrature signals at all.
    fn edges_per_count(&self) -> Option<i64> {
        match (self.cmr >> 3) & 0x03 {
            3 => Some(1),
            2 => Some(2),
            1 => Some(4),
            _ => None,
        }
    }

    fn move_to(&mut self, edges: i64) {
        let before = self.edges;
        self.edges = edges;
        let counting = self.ior & 0x01 != 0 && !self.stopped;
        let Some(per) = self.edges_per_count().filter(|_| counting) else {
            return;
        };
        let delta = edges.div_euclid(per) - before.div_euclid(per);
        if delta == 0 {
            return;
        }
        let unwrapped = i64::from(self.count) + delta;
        let wraps = unwrapped.div_euclid(WRAP);
        self.count = unwrapped.rem_euclid(WRAP) as u32;
        if wraps.rem_euclid(2) == 1 {
            self.flags ^= if delta > 0 { FLAG_CARRY } else { FLAG_BORROW };
        }
        if wraps > 0 {
            self.flags &= !FLAG_SIGN;
        } else if wraps < 0 {
            self.flags |= FLAG_SIGN;
        }
        if delta > 0 {
            self.flags |= FLAG_UP;
        } else {
            self.flags &= !FLAG_UP;
        }
    }

    /// A command on the control port: bits 6..5 choose RLD, CMR, IOR or IDR.
    fn command(&mut self, value: u8) {
        match (value >> 5) & 0x03 {
            0 => self.reset_load(value),
            1 => self.cmr = value & 0x1F,
            2 => self.ior = value & 0x1F,
            _ => self.idr = value & 0x1F,
        }
    }

    /// RLD: bit 0 resets the byte pointer; bits 2..1 reset the counter, the flags or
    /// the noise error; bits 4..3 move preset -> counter, counter -> latch, or the
    /// preset's low byte -> filter prescaler.
    fn reset_load(&mut self, value: u8) {
        if value & 0x01 != 0 {
            self.pointer = 0;
        }
        match (value >> 1) & 0x03 {
            1 => self.count = 0,
            2 => self.flags &= !(FLAG_BORROW | FLAG_CARRY | 0x04 | FLAG_SIGN),
            3 => self.flags &= !FLAG_NOISE,
            _ => {}
        }
        match (value >> 3) & 0x03 {
            1 => self.count = self.preset,
            2 => self.latch = self.count,
            3 => self.prescaler = self.preset as u8,
            _ => {}
        }
    }

    fn read_data(&mut self) -> u8 {
        let byte = (self.latch >> (8 * u32::from(self.pointer))) as u8;
        self.pointer = (self.pointer + 1) % 3;
        byte
    }

    fn write_data(&mut self, value: u8) {
        let shift = 8 * u32::from(self.pointer);
        self.preset = (self.preset & !(0xFF << shift) | u32::from(value) << shift) & MASK;
        self.pointer = (self.pointer + 1) % 3;
    }
}

struct Quad04Regs {
    channels: [Counter; 4],
    index_routing: u8,
    cascade: u8,
    dead: bool,
}

/// An emulated PCI-QUAD04; clones share the same card. Channels are numbered 1..4.
#[derive(Clone)]
pub struct EmulatedQuad04(Arc<Mutex<Quad04Regs>>);

impl Default for EmulatedQuad04 {
    fn default() -> Self {
        EmulatedQuad04::new()
    }
}

impl EmulatedQuad04 {
    pub fn new() -> EmulatedQuad04 {
        EmulatedQuad04(Arc::new(Mutex::new(Quad04Regs {
            channels: [Counter::powered_up(); 4],
            index_routing: 0xFF,
            cascade: 0xFF,
            dead: false,
        })))
    }

    /// Move the encoder on channel `ch` (1..4) to `edges` quadrature edges.
    pub fn set_encoder_edges(&self, ch: usize, edges: i64) {
        if let Some(c) = lock(&self.0).channels.get_mut(ch.wrapping_sub(1)) {
            c.move_to(edges);
        }
    }

    /// Channel `ch`'s counter stops counting (a broken chip or filter).
    pub fn stop_counter(&self, ch: usize) {
        if let Some(c) = lock(&self.0).channels.get_mut(ch.wrapping_sub(1)) {
            c.stopped = true;
        }
    }

    /// The card reads 0xFF at every register and ignores writes.
    pub fn set_dead(&self, dead: bool) {
        lock(&self.0).dead = dead;
    }

    /// Channel `ch`'s 24-bit counter, its filter prescaler and mode (CMR), for tests.
    pub fn counter(&self, ch: usize) -> (u32, u8, u8) {
        let r = lock(&self.0);
        let c = r.channels[ch.clamp(1, 4) - 1];
        (c.count, c.prescaler, c.cmr)
    }

    /// Index routing (+8) and cascading (+9) as last written.
    pub fn board_registers(&self) -> (u8, u8) {
        let r = lock(&self.0);
        (r.index_routing, r.cascade)
    }
}

impl PortIo for EmulatedQuad04 {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        let mut r = lock(&self.0);
        if offset > 9 {
            return Err(no_register("PCI-QUAD04", offset));
        }
        if r.dead {
            return Ok(0xFF);
        }
        let Some(c) = r.channels.get_mut(usize::from(offset / 2)) else {
            // +8 and +9 read back is not documented.
            return Ok(0);
        };
        Ok(if offset.is_multiple_of(2) {
            c.read_data()
        } else {
            c.flags
        })
    }

    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        let mut r = lock(&self.0);
        if offset > 9 {
            return Err(no_register("PCI-QUAD04", offset));
        }
        if r.dead {
            return Ok(());
        }
        let n = usize::from(offset / 2);
        match offset {
            8 => r.index_routing = value,
            9 => r.cascade = value,
            _ if offset.is_multiple_of(2) => r.channels[n].write_data(value),
            // Bit 7: the command goes to both counters of this channel's chip.
            _ if value & 0x80 != 0 => {
                let first = n & !1;
                r.channels[first].command(value & 0x7F);
                r.channels[first + 1].command(value & 0x7F);
            }
            _ => r.channels[n].command(value),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Latch and read channel 1's count as the card's manual says.
    fn read_count(card: &mut EmulatedQuad04) -> u32 {
        card.write_u8(1, 0x11).unwrap();
        let bytes = [0, 0, 0].map(|_| card.read_u8(0).unwrap());
        u32::from_le_bytes([bytes[0], bytes[1], bytes[2], 0])
    }

    #[test]
    fn counts_only_once_enabled_and_in_a_quadrature_mode() {
        let mut card = EmulatedQuad04::new();
        card.set_encoder_edges(1, 100);
        assert_eq!(card.counter(1).0, 0x5A5A5A, "powers up not counting");
        card.write_u8(1, 0x02).unwrap(); // reset counter
        card.write_u8(1, 0x38).unwrap(); // x4
        card.write_u8(1, 0x41).unwrap(); // enable A/B
        card.set_encoder_edges(1, 130);
        assert_eq!(read_count(&mut card), 30);
        card.write_u8(1, 0x28).unwrap(); // x1: every fourth edge
        card.set_encoder_edges(1, 170);
        assert_eq!(read_count(&mut card), 40);
    }

    #[test]
    fn wraps_at_24_bits_both_ways_and_toggles_carry_and_borrow() {
        let mut card = EmulatedQuad04::new();
        card.write_u8(1, 0x38).unwrap();
        card.write_u8(1, 0x41).unwrap();
        card.write_u8(1, 0x06).unwrap(); // clear the noise flag
        card.write_u8(1, 0x04).unwrap();
        card.write_u8(1, 0x01).unwrap(); // byte pointer to the low byte
        for byte in [0xFE, 0xFF, 0xFF] {
            card.write_u8(0, byte).unwrap(); // preset 0xFFFFFE
        }
        card.write_u8(1, 0x08).unwrap(); // preset -> counter
        card.set_encoder_edges(1, 5);
        assert_eq!(read_count(&mut card), 3);
        assert_eq!(
            card.read_u8(1).unwrap() & (FLAG_CARRY | FLAG_UP),
            FLAG_CARRY | FLAG_UP
        );
        card.set_encoder_edges(1, -5);
        assert_eq!(read_count(&mut card), 0xFF_FFF9);
        assert_eq!(card.read_u8(1).unwrap() & FLAG_BORROW, FLAG_BORROW);
    }

    #[test]
    fn bit_7_commands_both_counters_of_a_chip() {
        let mut card = EmulatedQuad04::new();
        card.write_u8(3, 0x80 | 0x38).unwrap();
        assert_eq!(card.counter(1).2, 0x18);
        assert_eq!(card.counter(2).2, 0x18);
        assert_eq!(card.counter(3).2, 0, "the other chip is untouched");
    }
}
