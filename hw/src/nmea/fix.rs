//! Sentences of one epoch into one fix: the receiver sends GGA, RMC, VTG and GST for
//! each solution, in an order that depends on the make; a consumer wants one `Fix` per
//! epoch, as soon as that epoch is complete.
//!
//! Sentences belong together when their UTC times agree (VTG has none and joins the
//! epoch of the sentence before it). An epoch is passed on as soon as it holds its GGA
//! and every kind the previous epoch had, so a receiver that sends GST after GGA gets
//! its standard deviations into the fix without waiting for the next epoch. If a
//! sentence of the epoch is lost on the line, the epoch goes out when the next one
//! begins, without it; if the receiver stops sending a kind, two epochs go out late
//! before the assembler stops waiting for it.

use super::sentence::{FixQuality, Gga, Sentence};

/// Two times closer than this are the same epoch (receivers print 0.01 s at most).
const SAME_EPOCH_S: f64 = 1e-3;

const SEEN_GGA: u8 = 1;
const SEEN_RMC: u8 = 2;
const SEEN_VTG: u8 = 4;
const SEEN_GST: u8 = 8;

/// One epoch's position solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fix {
    pub utc_s_of_day: f64,
    pub lat_deg: f64,
    pub lon_deg: f64,
    /// Above mean sea level.
    pub altitude_m: Option<f64>,
    pub quality: FixQuality,
    pub satellites: Option<u8>,
    pub hdop: Option<f32>,
    pub correction_age_s: Option<f32>,
    /// From a GST of the same epoch: the receiver's own error estimate, 1 s.d.
    pub sd_east_m: Option<f64>,
    pub sd_north_m: Option<f64>,
    /// From VTG, else RMC.
    pub speed_mps: Option<f64>,
    pub course_deg: Option<f64>,
}

impl Fix {
    /// The receiver's own s.d. in the worse of east and north, m: what it allows across
    /// a row of any direction (None without a GST).
    pub fn sd_m(&self) -> Option<f64> {
        self.sd_east_m.zip(self.sd_north_m).map(|(e, n)| e.max(n))
    }
}

/// What the consumer gets per epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Epoch {
    Fix(Fix),
    /// The receiver is alive but has no position (under trees, before its first fix).
    NoFix {
        utc_s_of_day: Option<f64>,
        satellites: Option<u8>,
    },
}

/// What the assembler has done, for the status display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct FixCounters {
    pub fixes: u64,
    pub no_fixes: u64,
    /// Epochs passed on only when the next began (a sentence of theirs was lost) or
    /// at `finish`.
    pub late: u64,
    /// Sentences that could not join an epoch (a VTG before any timed sentence).
    pub orphans: u64,
    /// A second GGA with the same time: ignored.
    pub repeated: u64,
}

/// An epoch being collected.
#[derive(Debug, Clone, Copy)]
struct Pending {
    utc_s_of_day: f64,
    seen: u8,
    passed_on: bool,
    gga: Option<Gga>,
    rmc_motion: (Option<f64>, Option<f64>),
    vtg_motion: (Option<f64>, Option<f64>),
    sd_north_east_m: (Option<f64>, Option<f64>),
}

impl Pending {
    fn new(utc_s_of_day: f64) -> Pending {
        Pending {
            utc_s_of_day,
            seen: 0,
            passed_on: false,
            gga: None,
            rmc_motion: (None, None),
            vtg_motion: (None, None),
            sd_north_east_m: (None, None),
        }
    }

    fn epoch(&self) -> Option<Epoch> {
        let gga = self.gga?;
        let no_fix = Epoch::NoFix {
            utc_s_of_day: gga.utc_s_of_day,
            satellites: gga.satellites,
        };
        let (Some(position), true) = (gga.position, gga.quality.carries_position()) else {
            return Some(no_fix);
        };
        Some(Epoch::Fix(Fix {
            utc_s_of_day: self.utc_s_of_day,
            lat_deg: position.lat_deg,
            lon_deg: position.lon_deg,
            altitude_m: gga.altitude_m,
            quality: gga.quality,
            satellites: gga.satellites,
            hdop: gga.hdop,
            correction_age_s: gga.correction_age_s,
            sd_east_m: self.sd_north_east_m.1,
            sd_north_m: self.sd_north_east_m.0,
            speed_mps: self.vtg_motion.0.or(self.rmc_motion.0),
            course_deg: self.vtg_motion.1.or(self.rmc_motion.1),
        }))
    }
}

/// Collects sentences into epochs; feed it every sentence the decoder passes on.
#[derive(Debug, Clone, Default)]
pub struct FixAssembler {
    current: Option<Pending>,
    /// The kinds the last two finished epochs had: what a complete epoch looks like for
    /// this receiver. Learned rather than configured, so any make works unconfigured;
    /// two epochs, so that one sentence lost on the line does not teach the assembler
    /// to stop waiting for its kind. Unknown until the first epoch has ended, which
    /// therefore goes out only then: one epoch late once, rather than without its GST.
    expected: Option<u8>,
    last_seen: u8,
    counters: FixCounters,
}

impl FixAssembler {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn counters(&self) -> FixCounters {
        self.counters
    }

    /// The link was lost: an epoch begun before is never finished with what comes after,
    /// nor passed on later as if it had just been measured.
    pub fn drop_pending(&mut self) {
        self.current = None;
    }

    /// Add one sentence; `out` gets each epoch once, as soon as it is complete.
    pub fn push(&mut self, sentence: Sentence, mut out: impl FnMut(Epoch)) {
        let time = sentence.utc_s_of_day();
        if let (Sentence::Gga(gga), None) = (sentence, time) {
            // A no-fix GGA from a receiver that does not know the time yet: nothing
            // to group it with, and nothing to wait for.
            self.counters.no_fixes += 1;
            out(Epoch::NoFix {
                utc_s_of_day: None,
                satellites: gga.satellites,
            });
            return;
        }
        if let Some(t) = time {
            let same = self
                .current
                .is_some_and(|p| (p.utc_s_of_day - t).abs() < SAME_EPOCH_S);
            if !same {
                self.close(&mut out);
                self.current = Some(Pending::new(t));
            }
        }
        let Some(pending) = self.current.as_mut() else {
            self.counters.orphans += 1;
            return;
        };
        match sentence {
            Sentence::Gga(gga) => {
                if pending.gga.is_some() {
                    self.counters.repeated += 1;
                    return;
                }
                pending.gga = Some(gga);
                pending.seen |= SEEN_GGA;
            }
            Sentence::Rmc(rmc) => {
                pending.rmc_motion = (rmc.speed_mps, rmc.course_deg);
                pending.seen |= SEEN_RMC;
            }
            Sentence::Vtg(vtg) => {
                pending.vtg_motion = (vtg.speed_mps, vtg.course_deg);
                pending.seen |= SEEN_VTG;
            }
            Sentence::Gst(gst) => {
                pending.sd_north_east_m = (gst.sd_lat_m, gst.sd_lon_m);
                pending.seen |= SEEN_GST;
            }
        }
        let complete = self.expected.is_some_and(|e| pending.seen & e == e);
        if complete && !pending.passed_on && pending.gga.is_some() {
            pending.passed_on = true;
            let epoch = pending.epoch();
            self.pass_on(epoch, &mut out);
        }
    }

    /// Pass on the epoch being collected, complete or not: at the end of a recording,
    /// or when the caller has waited longer than one epoch for more.
    pub fn finish(&mut self, mut out: impl FnMut(Epoch)) {
        self.close(&mut out);
    }

    fn close(&mut self, out: &mut impl FnMut(Epoch)) {
        let Some(pending) = self.current.take() else {
            return;
        };
        let learning = self.expected.is_none();
        self.expected = Some(pending.seen | self.last_seen);
        self.last_seen = pending.seen;
        if !pending.passed_on && pending.gga.is_some() {
            if !learning {
                self.counters.late += 1;
            }
            self.pass_on(pending.epoch(), out);
        }
    }

    fn pass_on(&mut self, epoch: Option<Epoch>, out: &mut impl FnMut(Epoch)) {
        match epoch {
            Some(epoch @ Epoch::Fix(_)) => {
                self.counters.fixes += 1;
                out(epoch);
            }
            Some(epoch @ Epoch::NoFix { .. }) => {
                self.counters.no_fixes += 1;
                out(epoch);
            }
            None => {}
        }
    }
}

#[cfg(test)]
#[path = "fix_tests.rs"]
mod tests;
