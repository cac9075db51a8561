//! The RTK GNSS receiver's NMEA 0183 sentences: the byte stream decoded into our own
//! small sentences (with the `nmea` crate), the sentences of one epoch assembled into a
//! fix, and lines written as a receiver writes them, for the simulated receiver.
//!
//! Pure computation: no threads, no I/O, no clock; time comes in as arguments, so the
//! same code runs on the robot, in the simulator and under the fuzzer.

// Receiver bytes are untrusted: outside tests, nothing here may panic on them.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::indexing_slicing,
        clippy::panic
    )
)]

pub mod decode;
pub mod encode;
pub mod fix;
pub mod fuzz;

mod convert;
mod error;
mod sentence;

pub use decode::{NmeaCounters, NmeaDecoder};
pub use error::{LineError, LineFault, SentenceKind};
pub use fix::{Epoch, Fix, FixAssembler, FixCounters};
pub use sentence::{FixQuality, Gga, Gst, LatLon, Rmc, RmcMode, Sentence, Vtg};
