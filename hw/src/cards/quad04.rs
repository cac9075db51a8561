//! Driver of the PCI-QUAD04 (docs/function_spec.md section 4a): four quadrature counters on two
//! LS7266R1 chips, channel n (1..4) with its data port at 2(n-1) and its control
//! port at 2(n-1)+1.
//!
//! Nothing is documented at power-up, so every channel is initialised at open, in the
//! order function_spec.md section 4a gives, for x4 counting. A count is latched and read as three
//! bytes of the same port (low, middle, high). The chip counts in 24 bits and wraps;
//! the driver extends each change between two reads to a signed step and adds it to
//! an i64 position, which therefore survives any number of wraps in either direction
//! (as long as an encoder moves less than 2^23 counts between two reads: 800 m of
//! wheel travel at 10 000 counts/m).

use crate::cards::port::PortIo;
use crate::{CardFault, HwError};

/// The card's name in every message.
pub const NAME: &str = "PCI-QUAD04";

pub const CHANNELS: usize = 4;
const MASK_24: u32 = 0xFF_FFFF;
/// Index/interrupt routing (+8) and cascading (+9): four independent 24-bit counters.
const INDEX_ROUTING: u16 = 8;
const CASCADE: u16 = 9;

/// The filter prescaler: filter clock 10 MHz / (1 + 1) = 5 MHz, good for edge rates up
/// to 625 kHz (at least 8x the highest A/B edge rate), far above the robot's encoders.
const PRESCALER: u8 = 1;

/// Initialisation of one channel, after function_spec.md section 4a: what goes to the control port
/// (`true`) or the data port (`false`), in order.
const INIT: [(bool, u8); 10] = [
    (true, 0x02),       // RLD: reset the counter
    (true, 0x04),       // RLD: reset the flags
    (true, 0x06),       // RLD: reset the noise error
    (true, 0x01),       // RLD: reset the byte pointer
    (false, PRESCALER), // preset low byte
    (true, 0x18),       // RLD: preset low byte -> filter prescaler
    (true, 0x01),       // RLD: reset the byte pointer
    (true, 0x38),       // CMR: x4 quadrature, normal counting
    (true, 0x41),       // IOR: enable the A/B inputs
    (true, 0x60),       // IDR: index off
];
/// RLD: reset the counter.
const RESET_COUNTER: u8 = 0x02;
/// RLD: counter -> output latch, and reset the byte pointer.
const LATCH: u8 = 0x11;

fn data_port(ch: usize) -> u16 {
    2 * (ch.clamp(1, CHANNELS) as u16 - 1)
}

fn control_port(ch: usize) -> u16 {
    data_port(ch) + 1
}

/// A 24-bit count difference as a signed step (two's complement in 24 bits).
pub(crate) fn step_24(from: u32, to: u32) -> i64 {
    let diff = to.wrapping_sub(from) & MASK_24;
    i64::from(((diff << 8) as i32) >> 8)
}

fn failed(register: u16, fault: CardFault) -> HwError {
    HwError::CardNotAnswering {
        card: NAME,
        register,
        fault,
    }
}

pub struct Quad04 {
    port: Box<dyn PortIo>,
    /// The 24-bit count at the last read, per channel.
    last_raw: [u32; CHANNELS],
    /// The unwrapped position, counts, per channel.
    position: [i64; CHANNELS],
}

impl Quad04 {
    /// Take the card: initialise all four channels, set the board to four independent
    /// counters, reset every counter, and check that the card answers.
    pub fn open(port: Box<dyn PortIo>) -> Result<Quad04, HwError> {
        let mut card = Quad04 {
            port,
            last_raw: [0; CHANNELS],
            position: [0; CHANNELS],
        };
        for ch in 1..=CHANNELS {
            for (control, value) in INIT {
                let offset = if control {
                    control_port(ch)
                } else {
                    data_port(ch)
                };
                card.write(offset, value)?;
            }
        }
        card.write(INDEX_ROUTING, 0x0F)?;
        card.write(CASCADE, 0x00)?;
        for ch in 1..=CHANNELS {
            card.write(control_port(ch), RESET_COUNTER)?;
        }
        // The first read after the reset is position 0 plus whatever moved since.
        for ch in 1..=CHANNELS {
            let raw = card.read_raw(ch)?;
            card.last_raw[ch - 1] = raw;
            card.position[ch - 1] = step_24(0, raw);
        }
        Ok(card)
    }

    fn write(&mut self, offset: u16, value: u8) -> Result<(), HwError> {
        self.port
            .write_u8(offset, value)
            .map_err(|e| failed(offset, CardFault::WriteFailed(e.kind())))
    }

    fn read(&mut self, offset: u16) -> Result<u8, HwError> {
        self.port
            .read_u8(offset)
            .map_err(|e| failed(offset, CardFault::ReadFailed(e.kind())))
    }

    /// Channel `ch`'s flag register (bit 4: noise error).
    pub fn read_flags(&mut self, ch: usize) -> Result<u8, HwError> {
        self.read(control_port(ch))
    }

    /// Channel `ch`'s 24-bit count: latch it, then read low, middle and high bytes.
    /// All ones in the count and the flags (a noise error among them, which the
    /// initialisation cleared) is a card that reads 0xFF: not answering.
    pub fn read_raw(&mut self, ch: usize) -> Result<u32, HwError> {
        self.write(control_port(ch), LATCH)?;
        let data = data_port(ch);
        let low = self.read(data)?;
        let middle = self.read(data)?;
        let high = self.read(data)?;
        let raw = u32::from_le_bytes([low, middle, high, 0]);
        if raw == MASK_24 {
            let flags = self.read_flags(ch)?;
            if flags == 0xFF {
                let channel = ch.clamp(1, CHANNELS) as u8;
                return Err(failed(
                    control_port(ch),
                    CardFault::CounterReadsFf { channel },
                ));
            }
        }
        Ok(raw)
    }

    /// Channel `ch`'s position in counts since open, unwrapped across 24-bit wraps.
    pub(crate) fn read_counts(&mut self, ch: usize) -> Result<i64, HwError> {
        let i = ch.clamp(1, CHANNELS) - 1;
        let raw = self.read_raw(ch)?;
        self.position[i] += step_24(self.last_raw[i], raw);
        self.last_raw[i] = raw;
        Ok(self.position[i])
    }
}

#[cfg(test)]
#[path = "quad04_tests.rs"]
mod tests;
