//! How far the GNSS receiver's own error may have moved between two fixes. The row
//! filter carries that error in the map's bias, whose slow drift along the row suits an
//! RTK fixed solution. Two things it does not cover:
//! - the error jumps when the solution changes (fixed to float and back): by the larger
//!   of the two solutions' typical errors;
//! - a solution that is not fixed wanders by about its typical error within WANDER_S.
//!   Its fixes, ten a second, are then not ten independent looks at the row: without
//!   this, a float episode's wander pulled the fused row by its decimetres.

use mechweed_hw::nmea::FixQuality;

/// An RTK float (or worse) solution wanders by about its typical error within this
/// time, s: decimetres within tens of seconds.
pub(crate) const WANDER_S: f64 = 30.0;

/// The s.d. by which the receiver's error may have moved since the last fix used (of
/// quality `used`, `since_s` ago) for a fix of `quality`, m; None when only the map's
/// own drift applies.
pub(crate) fn receiver_moved_sd_m(
    used: Option<FixQuality>,
    quality: FixQuality,
    since_s: f64,
) -> Option<f64> {
    let typical_m = quality.typical_sd_m();
    match used {
        Some(used) if used != quality => Some(typical_m.max(used.typical_sd_m())),
        _ if quality != FixQuality::RtkFixed && since_s.is_finite() => {
            // A first-order drift of s.d. typical over WANDER_S moves by about
            // typical * sqrt(2 dt / WANDER_S) in a short dt.
            let share = (2.0 * since_s.clamp(0.0, WANDER_S) / WANDER_S).sqrt();
            Some(typical_m * share)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_change_of_solution_widens_by_the_worse_and_rtk_fixed_not_at_all() {
        let (fixed, float) = (FixQuality::RtkFixed, FixQuality::RtkFloat);
        let float_m = float.typical_sd_m();
        assert_eq!(receiver_moved_sd_m(Some(fixed), float, 0.1), Some(float_m));
        assert_eq!(receiver_moved_sd_m(Some(float), fixed, 0.1), Some(float_m));
        assert_eq!(receiver_moved_sd_m(Some(fixed), fixed, 0.1), None);
        assert_eq!(receiver_moved_sd_m(None, fixed, f64::INFINITY), None);
    }

    #[test]
    fn a_float_solution_wanders_with_the_time_between_fixes() {
        let float = FixQuality::RtkFloat;
        let tenth = receiver_moved_sd_m(Some(float), float, 0.1).unwrap();
        let second = receiver_moved_sd_m(Some(float), float, 1.0).unwrap();
        // Its variance grows in proportion to the time: ten tenths make one second.
        assert!((10.0 * tenth * tenth - second * second).abs() < 1e-12);
        // And no further than two independent draws of it apart, however long the silence.
        let long = receiver_moved_sd_m(Some(float), float, 1e6).unwrap();
        assert!((long - float.typical_sd_m() * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(receiver_moved_sd_m(None, float, f64::INFINITY), None);
    }

    #[test]
    fn widened_the_maps_bias_takes_a_jump_of_the_receiver_and_the_row_stays() {
        use crate::steer::filter::{FilterSettings, Outcome, RowFilter, Travel};
        // The row well known from the camera; then the receiver's error jumps by 15 cm
        // (fixed to float) and its fixes say so, 10 cm s.d. each, ten of them.
        let run = |widen: bool| {
            let mut f = RowFilter::new(FilterSettings::default());
            for _ in 0..50 {
                f.predict(0.1, 0.0);
                f.update_camera(0.0, 0.0, 0.8, 0.01, 0.01, Default::default());
                f.update_gnss(0.0, 0.01, Travel::default());
            }
            if widen {
                let float_m = FixQuality::RtkFloat.typical_sd_m();
                assert_eq!(f.widen_map_bias(float_m), Outcome::Used);
            }
            for _ in 0..10 {
                f.update_gnss(0.15, 0.10, Travel::default());
            }
            f.state()
        };
        let (kept, widened) = (run(false), run(true));
        assert!(widened.map_bias_m > 0.12, "{widened:?}");
        assert!(widened.offset_m.abs() < 0.005, "{widened:?}");
        assert!(
            kept.offset_m > 2.0 * widened.offset_m.abs(),
            "{kept:?} {widened:?}"
        );
    }

    #[test]
    fn a_widening_that_is_not_a_standard_deviation_is_refused() {
        use crate::steer::filter::{FilterSettings, Outcome, RowFilter};
        let mut f = RowFilter::new(FilterSettings::default());
        let before = f.covariance();
        for bad in [f64::NAN, -0.1, f64::INFINITY, 1e200] {
            assert_eq!(f.widen_map_bias(bad), Outcome::Refused, "{bad}");
        }
        assert_eq!(f.covariance(), before);
        assert_eq!(f.counters().refused_bad_input, 4);
    }
}
