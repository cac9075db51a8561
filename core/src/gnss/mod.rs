//! The GNSS receiver's link, as plain functions: bytes in, fixes out, and a status the
//! steer thread, the GUI and the record read. The thread around it (`thread.rs`, like
//! the camera link's) reads the port; lockstep calls it directly.
//!
//! `place.rs` turns a fix into where the row map's line lies from the robot.

pub mod place;
pub mod rowmap;
pub mod run;
pub mod thread;

use mechweed_hw::nmea::{Epoch, Fix, FixAssembler, FixCounters, NmeaCounters, NmeaDecoder};

/// What the GNSS link knows now: a plain `Copy` snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssStatus {
    /// The newest epoch with a position (None after an epoch without one), and when the
    /// last position arrived (program time, s).
    pub last_fix: Option<Fix>,
    pub last_fix_s: f64,
    /// When any epoch arrived, with or without a position: the receiver is alive.
    pub last_epoch_s: f64,
    /// Epochs without a position.
    pub no_fix_epochs: u64,
    pub fixes: u64,
    pub sentences: NmeaCounters,
    pub epochs: FixCounters,
    /// The link thread is alive at this time (the GUI and the report show it; a silent
    /// receiver is judged by the steer thread from `last_fix_s`).
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
                    // The last position is not the receiver's any more: nothing that
                    // shows or records the fix may go on saying RTK fixed.
                    Epoch::NoFix { .. } => {
                        status.last_fix = None;
                        status.no_fix_epochs += 1;
                    }
                }
            });
        });
        self.status.sentences = self.decoder.counters();
        self.status.epochs = self.assembler.counters();
        fixed
    }

    /// The receiver's port was opened again: what it sent before is not finished now.
    pub(crate) fn reconnected(&mut self) {
        self.assembler.drop_pending();
    }

    /// The link thread is alive at `now_s`.
    pub fn beat(&mut self, now_s: f64) {
        self.status.beat_s = now_s;
    }
}

#[cfg(test)]
mod tests {
    use mechweed_hw::nmea::FixQuality;
    use mechweed_hw::nmea::encode::{NmeaEncoder, NmeaLine, ReceiverEpoch};

    use super::GnssCore;

    fn epoch(utc_s_of_day: f64, quality: FixQuality) -> ReceiverEpoch {
        ReceiverEpoch {
            utc_s_of_day,
            lat_deg: 52.0,
            lon_deg: 5.66,
            altitude_m: 10.0,
            quality,
            satellites: 14,
            hdop: 0.7,
            correction_age_s: Some(1.0),
            sd_lat_m: 0.01,
            sd_lon_m: 0.01,
            sd_alt_m: 0.02,
            speed_mps: 0.5,
            course_deg: 90.0,
        }
    }

    fn send(core: &mut GnssCore, lines: &[NmeaLine], now_s: f64) {
        for line in lines {
            core.receive(line.as_bytes(), now_s);
        }
    }

    /// Whole epochs of `quality`, each arriving at its own time.
    fn epochs(core: &mut GnssCore, times_s: &[f64], quality: FixQuality) {
        let encoder = NmeaEncoder::new();
        for &t in times_s {
            send(core, &encoder.epoch(&epoch(t, quality)).unwrap(), t);
        }
    }

    #[test]
    fn an_epoch_begun_before_the_port_was_lost_is_never_passed_on_as_new() {
        let mut core = GnssCore::new();
        epochs(&mut core, &[1.0, 2.0, 3.0], FixQuality::RtkFixed);
        // Epoch 4's GGA, then the cable is pulled for 30 s before its GST.
        let lines = NmeaEncoder::new()
            .epoch(&epoch(4.0, FixQuality::RtkFixed))
            .unwrap();
        send(&mut core, &lines[..1], 4.0);
        core.reconnected();
        epochs(&mut core, &[34.0, 35.0], FixQuality::RtkFixed);
        let status = core.status();
        let utc_s = status.last_fix.map(|f| f.utc_s_of_day);
        assert!(
            utc_s.is_some_and(|t| t >= 34.0),
            "the last fix is from {utc_s:?}"
        );
        // Epochs 1, 2 and 3 and the two after: 4 never went out.
        assert!(status.fixes <= 5, "{status:?}");
    }

    #[test]
    fn an_epoch_without_a_position_ends_the_last_fix() {
        let mut core = GnssCore::new();
        epochs(&mut core, &[1.0, 2.0, 3.0], FixQuality::RtkFixed);
        assert_eq!(
            core.status().last_fix.unwrap().quality,
            FixQuality::RtkFixed
        );
        epochs(&mut core, &[4.0, 5.0, 6.0], FixQuality::None);
        let status = core.status();
        assert_eq!(status.last_fix, None, "{status:?}");
        assert!(status.no_fix_epochs >= 2, "{status:?}");
        assert!(status.last_fix_s <= 3.0, "{status:?}");
    }
}
