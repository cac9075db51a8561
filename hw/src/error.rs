//! What went wrong with a card during a tick, as a value: which card, which register,
//! what happened, in numbers.
//!
//! A tick whose card fails must still finish in time and leave the safe outputs, so
//! this error is `Copy` and built from numbers only: making it allocates nothing, and
//! the supervisor decides on its fields (the card that failed), never on its text. The
//! words a technician reads are made only when the error is displayed, after the tick.
//! What goes wrong while the cards are being found and opened is in open_error.rs.

use std::fmt;
use std::io::ErrorKind;

/// Why the hardware could not be read or written. The message names the card and the
/// register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HwError {
    /// A card did not answer as it should at one of its registers (offset in its
    /// register window, as in docs/function_spec.md section 4a).
    CardNotAnswering {
        card: &'static str,
        register: u16,
        fault: CardFault,
    },
}

/// What a card did wrong at one register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CardFault {
    /// Reading the register failed; the system gave this reason.
    ReadFailed(ErrorKind),
    /// Writing the register failed; the system gave this reason.
    WriteFailed(ErrorKind),
    /// The DAS08's status shows another multiplexer channel than the one `selected`
    /// (a status of 0xFF: as a card that is not there).
    WrongChannel { status: u8, selected: u8 },
    /// The DAS08's A/D did not finish converting `channel` within `timeout_us`; its
    /// status at the last read.
    ConversionTimeout {
        channel: u8,
        timeout_us: u32,
        status: u8,
    },
    /// A QUAD04 channel reads 0xFF in its count and its flags, as a card that is not
    /// there.
    CounterReadsFf { channel: u8 },
}

impl HwError {
    /// The card that failed, for the fault's cause.
    pub fn card(&self) -> &'static str {
        match self {
            HwError::CardNotAnswering { card, .. } => card,
        }
    }

    /// The reason the system gave, if a read or write itself failed.
    pub(crate) fn io_kind(&self) -> Option<ErrorKind> {
        match self {
            HwError::CardNotAnswering {
                fault: CardFault::ReadFailed(kind) | CardFault::WriteFailed(kind),
                ..
            } => Some(*kind),
            HwError::CardNotAnswering { .. } => None,
        }
    }
}

/// A register offset as docs/function_spec.md section 4a writes it: +2, +9, +0x0c.
struct Register(u16);

impl fmt::Display for Register {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0 < 10 {
            write!(f, "+{}", self.0)
        } else {
            write!(f, "+{:#04x}", self.0)
        }
    }
}

impl fmt::Display for HwError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let HwError::CardNotAnswering {
            card,
            register,
            fault,
        } = *self;
        let at = Register(register);
        write!(f, "{card} stopped answering: ")?;
        match fault {
            CardFault::ReadFailed(kind) => write!(f, "reading register {at}: {kind}"),
            CardFault::WriteFailed(kind) => write!(f, "writing register {at}: {kind}"),
            CardFault::WrongChannel { status, selected } => {
                let why = if status == 0xFF {
                    "reads 0xFF, as a card that is not there"
                } else {
                    "shows another channel than the one selected"
                };
                write!(
                    f,
                    "status {status:#04x} (register {at}) after selecting channel {selected}: {why}"
                )
            }
            CardFault::ConversionTimeout {
                channel,
                timeout_us,
                status,
            } => write!(
                f,
                "its A/D did not finish a conversion of channel {channel} within {timeout_us} us \
                 (status {status:#04x} at register {at})"
            ),
            CardFault::CounterReadsFf { channel } => write!(
                f,
                "channel {channel} reads 0xFF in its count and its flags (register {at}), \
                 as a card that is not there"
            ),
        }
    }
}

impl std::error::Error for HwError {}
