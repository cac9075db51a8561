//! Which GNSS fixes may steer, beyond their quality ([gnss] trust): each epoch must be
//! later than the last one, its corrections no older than [gnss] max_correction_age_s,
//! and RTK float, which wanders by decimetres, steers without the camera to confirm it
//! only slowly and only for [gnss] float_hold_m past the last RTK fixed fix.
//!
//! Each check names what it found, for the notice that says why GNSS does not steer.

use mechweed_hw::nmea::{Fix, FixQuality};

use crate::config::GnssSettings;

pub(crate) const NO_TRUSTED_FIX: &str =
    "no trusted GNSS fix (of [gnss] trusted quality) for [steer] gnss_fallback_s";
const NOT_LATER: &str =
    "the GNSS receiver sent an epoch no later than the one before (out of order or repeated)";
const OLD_CORRECTIONS: &str =
    "the GNSS fixes' corrections are older than [gnss] max_correction_age_s";
const FLOAT_TOO_LONG: &str =
    "RTK float for longer than [gnss] float_hold_m with no camera row to confirm it";
const REJECTED: &str = "the row filter's gate rejects the GNSS fixes (they disagree with the row)";

/// Half a day: an epoch's UTC time of day that went back by more than this went on past
/// midnight.
const HALF_DAY_S: f64 = 43_200.0;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FixChecks {
    /// The last epoch's UTC time of day, s.
    last_utc_s: Option<f64>,
    /// The distance driven at the last RTK fixed fix used, m.
    fixed_at_m: f64,
    /// Why GNSS does not steer, as of the last fix.
    pub trouble: &'static str,
}

impl Default for FixChecks {
    fn default() -> FixChecks {
        FixChecks {
            last_utc_s: None,
            fixed_at_m: f64::NEG_INFINITY,
            trouble: NO_TRUSTED_FIX,
        }
    }
}

impl FixChecks {
    /// A new autonomous run: float is judged from its first fixed fix again. The epochs'
    /// order is the receiver's and carries on.
    pub fn reset(&mut self) {
        self.fixed_at_m = f64::NEG_INFINITY;
        self.trouble = NO_TRUSTED_FIX;
    }

    /// Whether `fix` may go into the row filter: its epoch later than the last one and
    /// its quality trusted with corrections young enough.
    pub fn admit(&mut self, fix: &Fix, gnss: &GnssSettings) -> bool {
        let t_s = fix.utc_s_of_day;
        let later = t_s.is_finite()
            && self.last_utc_s.is_none_or(|last_s| {
                let ahead_s = (t_s - last_s).rem_euclid(2.0 * HALF_DAY_S);
                ahead_s > 0.0 && ahead_s < HALF_DAY_S
            });
        // A later epoch is the receiver's newest, whatever becomes of it here.
        if later {
            self.last_utc_s = Some(t_s);
        }
        let young = fix
            .correction_age_s
            .is_none_or(|age_s| f64::from(age_s) <= gnss.max_correction_age_s);
        let (admitted, trouble) = match () {
            _ if !later => (false, NOT_LATER),
            _ if !gnss.trusts(fix.quality) => (false, NO_TRUSTED_FIX),
            _ if !young => (false, OLD_CORRECTIONS),
            _ => (true, self.trouble),
        };
        self.trouble = trouble;
        admitted
    }

    /// Whether an admitted fix that the filter took (`used`: its gate passed it) counts
    /// as GNSS heard, the robot having driven `driven_m`; `camera_in`: the camera's rows
    /// steer beside it and confirm it.
    pub fn heard(
        &mut self,
        fix: &Fix,
        used: bool,
        driven_m: f64,
        camera_in: bool,
        gnss: &GnssSettings,
    ) -> bool {
        if !used {
            self.trouble = REJECTED;
            return false;
        }
        if fix.quality == FixQuality::RtkFixed {
            self.fixed_at_m = driven_m;
        }
        let floating_m = driven_m - self.fixed_at_m;
        let float_alone = fix.quality == FixQuality::RtkFloat && !camera_in;
        if float_alone && floating_m > gnss.float_hold_m {
            self.trouble = FLOAT_TOO_LONG;
            return false;
        }
        self.trouble = NO_TRUSTED_FIX;
        true
    }
}

/// Whether a fix of `quality` steering without the camera must slow down: anything less
/// than RTK fixed.
pub(crate) fn degraded(quality: FixQuality) -> bool {
    quality != FixQuality::RtkFixed
}

#[cfg(test)]
#[path = "fix_checks_tests.rs"]
mod tests;
