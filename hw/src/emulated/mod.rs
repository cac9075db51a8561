//! Register-level emulations of the three cards (docs/function_spec.md section 4a), so the drivers are
//! tested against the cards' behaviour rather than against an echo.
//!
//! Each emulated card is a cloneable handle to one set of registers: one clone goes to
//! the driver as its [`PortIo`](crate::cards::port::PortIo), another stays with the test or
//! the simulated plant, which sets the card's "wires" from physical signals (volts on
//! an A/D input, switch levels, encoder edges) and reads back what the card drives
//! (DAC volts, digital outputs). Failures on demand: an A/D that never finishes, a
//! counter that stops, a card that reads 0xFF everywhere (dead).
//!
//! Where function_spec.md section 4a leaves the power-up state undocumented, the emulation powers up
//! in the worst plausible state (outputs on, counters holding garbage), so a driver
//! that forgets to initialise something is caught.

mod das08;
mod dda06;
mod quad04;
mod rig;

use std::io;
use std::sync::{Mutex, MutexGuard};

pub use das08::EmulatedDas08;
pub use dda06::EmulatedDda06;
pub use quad04::EmulatedQuad04;
pub use rig::CardRig;

/// Lock a card's registers. A panic elsewhere cannot leave plain register values
/// half-written in a harmful way, so a poisoned lock is taken as it is.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The error for an offset outside an emulated card's window (a driver bug).
fn no_register(card: &str, offset: u16) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("the emulated {card} has no register at offset {offset:#x}"),
    )
}

/// Every access a driver made, in order (tests check sequences with it).
#[cfg(test)]
pub(crate) mod recording {
    use std::io;
    use std::sync::{Arc, Mutex};

    use crate::cards::port::PortIo;

    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Access {
        Read(u16),
        Write(u16, u8),
    }

    /// Wraps a port and records its accesses into a shared log.
    pub struct Recording<P> {
        pub inner: P,
        pub log: Arc<Mutex<Vec<Access>>>,
    }

    impl<P: PortIo> Recording<P> {
        pub fn new(inner: P) -> (Recording<P>, Arc<Mutex<Vec<Access>>>) {
            let log = Arc::new(Mutex::new(Vec::new()));
            (
                Recording {
                    inner,
                    log: log.clone(),
                },
                log,
            )
        }
    }

    impl<P: PortIo> PortIo for Recording<P> {
        fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
            self.log.lock().unwrap().push(Access::Read(offset));
            self.inner.read_u8(offset)
        }
        fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
            self.log.lock().unwrap().push(Access::Write(offset, value));
            self.inner.write_u8(offset, value)
        }
    }
}
