//! Driver of the PCI-DAS08 (docs/function_spec.md, section 4a): 12-bit A/D on eight inputs of fixed
//! +-5 V range, three digital inputs IP1..IP3 and four digital outputs OP1..OP4.
//!
//! Register +2 is status when read and control when written, and the control byte
//! carries both the multiplexer channel and the outputs. The outputs cannot be read
//! back, so the driver keeps them in a shadow byte and writes them with every control
//! write; the first write, at open, sets them to the safe state.

use std::time::{Duration, Instant};

use crate::cards::port::PortIo;
use crate::{CardFault, HwError};

/// The card's name in every message.
pub const NAME: &str = "PCI-DAS08";

const DATA_LOW: u16 = 0;
const DATA_HIGH: u16 = 1;
const STATUS_CONTROL: u16 = 2;
/// Status bit 7: a conversion is running.
const EOC_BUSY: u8 = 0x80;
const MUX_BITS: u8 = 0x07;
/// The A/D's volts per code step: 10 V over 4096 codes.
const VOLTS_PER_CODE: f64 = 10.0 / 4096.0;
/// The code of 0 V (offset binary: 0 is -5 V).
const ZERO_CODE: f64 = 2048.0;
/// Status reads before a conversion may be declared stuck, whatever the clock says: a
/// thread preempted while it waits must not blame the card. A read takes about 1 us,
/// so on a running thread the time-out decides.
const MIN_POLLS: u32 = 16;

pub struct Das08 {
    port: Box<dyn PortIo>,
    /// Outputs OP4..OP1 in bits 7..4 as last written; interrupt enable (bit 3) stays 0.
    shadow: u8,
    /// The multiplexer channel last written.
    mux: u8,
    eoc_timeout: Duration,
}

fn failed(register: u16, fault: CardFault) -> HwError {
    HwError::CardNotAnswering {
        card: NAME,
        register,
        fault,
    }
}

/// Status bits 6..4 as IP1..IP3 in bits 0..2.
pub(crate) fn inputs_of_status(status: u8) -> u8 {
    (status >> 4) & 0x07
}

/// Volts at the input from a 12-bit code: 0 -> -5 V, 2048 -> 0 V, 4095 -> +4.9976 V.
pub fn code_to_volts(code: u16) -> f64 {
    (f64::from(code) - ZERO_CODE) * VOLTS_PER_CODE
}

impl Das08 {
    /// Take the card. Before anything else, write the control byte: outputs
    /// `safe_outputs` (OP1..OP4 in bits 0..3), interrupts off, channel 0, because
    /// the outputs' power-up state is not documented; then check that the card
    /// answers. `eoc_timeout` is the longest
    /// wait for a conversion; longer means the card stopped answering.
    pub fn open(
        port: Box<dyn PortIo>,
        safe_outputs: u8,
        eoc_timeout: Duration,
    ) -> Result<Das08, HwError> {
        let mut card = Das08 {
            port,
            shadow: 0,
            mux: 0,
            eoc_timeout,
        };
        card.write_outputs(safe_outputs)?;
        // A card that is not there (0xFF) is found now, not in the first tick.
        card.read_status()?;
        Ok(card)
    }

    fn read(&mut self, offset: u16) -> Result<u8, HwError> {
        self.port
            .read_u8(offset)
            .map_err(|e| failed(offset, CardFault::ReadFailed(e.kind())))
    }

    fn write_control(&mut self) -> Result<(), HwError> {
        let control = self.shadow | self.mux;
        self.port
            .write_u8(STATUS_CONTROL, control)
            .map_err(|e| failed(STATUS_CONTROL, CardFault::WriteFailed(e.kind())))
    }

    /// Set OP1..OP4 from bits 0..3 of `bits`.
    pub(crate) fn write_outputs(&mut self, bits: u8) -> Result<(), HwError> {
        self.shadow = (bits & 0x0F) << 4;
        self.write_control()
    }

    /// The outputs as last written, OP1..OP4 in bits 0..3.
    pub fn outputs(&self) -> u8 {
        self.shadow >> 4
    }

    /// The status register. A status whose channel bits differ from the channel last
    /// selected means the card is not answering (a dead card reads 0xFF).
    pub fn read_status(&mut self) -> Result<u8, HwError> {
        let status = self.read(STATUS_CONTROL)?;
        if status & MUX_BITS != self.mux {
            let selected = self.mux;
            return Err(failed(
                STATUS_CONTROL,
                CardFault::WrongChannel { status, selected },
            ));
        }
        Ok(status)
    }

    /// IP1..IP3 in bits 0..2, as levels at the card (1 = high).
    pub(crate) fn read_inputs(&mut self) -> Result<u8, HwError> {
        Ok(inputs_of_status(self.read_status()?))
    }

    /// One 12-bit conversion of input `channel` (0..7): select it (with the outputs),
    /// start, wait for the end of conversion, read the high byte then the low nibble.
    pub fn read_code(&mut self, channel: u8) -> Result<u16, HwError> {
        self.mux = channel & MUX_BITS;
        self.write_control()?;
        self.port
            .write_u8(DATA_HIGH, 0)
            .map_err(|e| failed(DATA_HIGH, CardFault::WriteFailed(e.kind())))?;
        let deadline = Instant::now() + self.eoc_timeout;
        let mut polls = 0;
        loop {
            // Look at the clock before reading, so that a pause between the two (the
            // thread preempted) still leaves a read after the deadline.
            let expired = Instant::now() >= deadline;
            let status = self.read_status()?;
            polls += 1;
            if status & EOC_BUSY == 0 {
                break;
            }
            if expired && polls >= MIN_POLLS {
                let timeout_us = u32::try_from(self.eoc_timeout.as_micros()).unwrap_or(u32::MAX);
                return Err(failed(
                    STATUS_CONTROL,
                    CardFault::ConversionTimeout {
                        channel: self.mux,
                        timeout_us,
                        status,
                    },
                ));
            }
        }
        let high = self.read(DATA_HIGH)?;
        let low = self.read(DATA_LOW)?;
        Ok(u16::from(high) << 4 | u16::from(low >> 4))
    }

    /// Volts on input `channel` (-5 .. +4.9976 V).
    pub(crate) fn read_volts(&mut self, channel: u8) -> Result<f64, HwError> {
        Ok(code_to_volts(self.read_code(channel)?))
    }
}

#[cfg(test)]
#[path = "das08_tests.rs"]
mod tests;
