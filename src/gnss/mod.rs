//! The GNSS receiver's link, as plain functions: bytes in, fixes out, and a status the
//! steer thread, the GUI and the record read. The thread around it (`thread.rs`, like
//! the camera link's) reads the port; lockstep calls it directly.
//!
//! `place.rs` turns a fix into where the row map's line lies from the robot.

pub mod place;
pub mod run;
pub mod thread;

use mechweed_hw::nmea::{Epoch, Fix, FixAssembler, FixCounters, NmeaCounters, NmeaDecoder};

/// What the GNSS link knows now: a plain `Copy` snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssStatus {
    /// The newest epoch with a position, and when it arrived (program time, s).
    pub last_fix: Option<Fix>,
    pub last_fix_s: f64,
    /// When any epoch arrived, with or without a position: the receiver is alive.
    pub last_epoch_s: f64,
    /// Epochs without a position.
    pub no_fix_epochs: u64,
    pub fixes: u64,
    pub sentences: NmeaCounters,
    pub epochs: FixCounters,
    /// The link thread is alive at this time (the supervisor watches it).
    pub beat_s: f64,
}

impl Default for GnssStatus {
    fn default() -> Self {
        GnssStatus {
            last_fix: None,
            last_fix_s: f64::NEG_INFINITY,
            last_epoch_s: f64::NEG_INFINITY,
            no_fix_epochs: 0,
            fixes: 0,
            sentences: NmeaCounters::default(),
            epochs: FixCounters::default(),
            beat_s: f64::NEG_INFINITY,
        }
    }
}

/// The receiver's bytes decoded and assembled into the status.
#[derive(Default)]
pub struct GnssCore {
    decoder: NmeaDecoder,
    assembler: FixAssembler,
    status: GnssStatus,
}

impl GnssCore {
    pub fn new() -> GnssCore {
        GnssCore::default()
    }

    pub fn status(&self) -> &GnssStatus {
        &self.status
    }

    /// Decode bytes that arrived at `now_s`. Returns true if a new fix came.
    pub fn receive(&mut self, bytes: &[u8], now_s: f64) -> bool {
        let mut fixed = false;
        let (assembler, status) = (&mut self.assembler, &mut self.status);
        self.decoder.push(bytes, |sentence| {
            assembler.push(sentence, |epoch| {
                status.last_epoch_s = now_s;
                match epoch {
                    Epoch::Fix(fix) => {
                        status.last_fix = Some(fix);
                        status.last_fix_s = now_s;
                        status.fixes += 1;
                        fixed = true;
                    }
                    Epoch::NoFix { .. } => status.no_fix_epochs += 1,
                }
            });
        });
        self.status.sentences = self.decoder.counters();
        self.status.epochs = self.assembler.counters();
        fixed
    }

    /// The link thread is alive at `now_s`.
    pub fn beat(&mut self, now_s: f64) {
        self.status.beat_s = now_s;
    }
}
