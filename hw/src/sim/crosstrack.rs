//! The benchmark's figure of merit: the weeding tool's cross-track error, by distance.
//!
//! the simulated plant asks for statistics "by distance", so the error is sampled once per
//! centimetre of travel (SAMPLE_SPACING_M): a robot that stands still adds nothing, and a
//! fast one is not under-weighted. Running sums give mean, s.d. and RMS; an HDR
//! histogram of |error| at micrometre resolution gives the 95th percentile. Recording
//! never allocates.

use hdrhistogram::Histogram;

/// Distance of travel between two samples, m.
pub const SAMPLE_SPACING_M: f64 = 0.01;
/// Histogram units per metre (micrometres).
const UNITS_PER_M: f64 = 1e6;
/// Largest |error| the histogram tells apart (10 m); larger ones count as 10 m there,
/// but `max_cm` still shows them.
const HIGHEST_UM: u64 = 10_000_000;

/// Cross-track statistics (the simulated plant): mean, s.d., RMS, p95, max, share over 2 cm.
#[derive(Clone)]
pub struct CrossTrackStats {
    abs_um: Histogram<u64>,
    samples: u64,
    sum_m: f64,
    sum_sq_m2: f64,
    max_abs_m: f64,
    over_2cm: u64,
}

/// The figures of the benchmark report, in cm (share as a fraction 0..1 of distance).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct CrossTrackSummary {
    pub mean_cm: f64,
    pub sd_cm: f64,
    pub rms_cm: f64,
    /// 95th percentile of |error|.
    pub p95_cm: f64,
    /// Largest |error|.
    pub max_cm: f64,
    /// Fraction of the measured distance with |error| > 2 cm.
    pub share_over_2cm: f64,
    /// Distance over which the error was measured, m.
    pub distance_m: f64,
}

impl CrossTrackSummary {
    /// The figures from sums of the signed error over a total `weight` (samples, or
    /// metres driven): the one arithmetic of both statistics, the plant's per centimetre
    /// and the ticks' (crosstrack_ticks.rs); zero before any weight.
    pub(crate) fn from_sums(
        weight: f64,
        sum_m: f64,
        sum_sq_m2: f64,
        p95_m: f64,
        max_abs_m: f64,
        over_2cm: f64,
        distance_m: f64,
    ) -> CrossTrackSummary {
        if weight <= 0.0 {
            return CrossTrackSummary::default();
        }
        let mean_m = sum_m / weight;
        let mean_sq_m2 = sum_sq_m2 / weight;
        // Population s.d.; max(0) guards the rounding of a near-constant error.
        let sd_m = (mean_sq_m2 - mean_m * mean_m).max(0.0).sqrt();
        CrossTrackSummary {
            mean_cm: mean_m * 100.0,
            sd_cm: sd_m * 100.0,
            rms_cm: mean_sq_m2.sqrt() * 100.0,
            p95_cm: p95_m * 100.0,
            max_cm: max_abs_m * 100.0,
            share_over_2cm: over_2cm / weight,
            distance_m,
        }
    }
}

impl Default for CrossTrackStats {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for CrossTrackStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("CrossTrackStats")
            .field(&self.summary())
            .finish()
    }
}

impl CrossTrackStats {
    pub fn new() -> CrossTrackStats {
        // Three significant figures: 10 um resolution at 1 cm, far below the camera's noise.
        let abs_um = Histogram::new_with_bounds(1, HIGHEST_UM, 3).expect("constant, valid bounds");
        CrossTrackStats {
            abs_um,
            samples: 0,
            sum_m: 0.0,
            sum_sq_m2: 0.0,
            max_abs_m: 0.0,
            over_2cm: 0,
        }
    }

    /// Record `count` samples (centimetres of travel) of the signed error `error_m`.
    /// Non-finite errors are ignored.
    pub fn record(&mut self, error_m: f64, count: u64) {
        if !error_m.is_finite() || count == 0 {
            return;
        }
        let abs_m = error_m.abs();
        let n = count as f64;
        self.samples += count;
        self.sum_m += error_m * n;
        self.sum_sq_m2 += error_m * error_m * n;
        self.max_abs_m = self.max_abs_m.max(abs_m);
        if abs_m > 0.02 {
            self.over_2cm += count;
        }
        // `as` saturates, and saturating_record_n clamps to the histogram's range.
        self.abs_um
            .saturating_record_n((abs_m * UNITS_PER_M).round() as u64, count);
    }

    /// Number of samples (centimetres of travel) recorded.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    pub fn summary(&self) -> CrossTrackSummary {
        let n = self.samples as f64;
        CrossTrackSummary::from_sums(
            n,
            self.sum_m,
            self.sum_sq_m2,
            self.abs_um.value_at_quantile(0.95) as f64 / UNITS_PER_M,
            self.max_abs_m,
            self.over_2cm as f64,
            n * SAMPLE_SPACING_M,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn constant_error_gives_zero_sd() {
        let mut stats = CrossTrackStats::new();
        stats.record(0.05, 100);
        let s = stats.summary();
        assert!(close(s.mean_cm, 5.0, 1e-9) && close(s.rms_cm, 5.0, 1e-9));
        assert!(close(s.sd_cm, 0.0, 1e-6));
        assert!(close(s.p95_cm, 5.0, 0.01) && close(s.max_cm, 5.0, 1e-9));
        assert_eq!(s.share_over_2cm, 1.0);
        assert!(close(s.distance_m, 1.0, 1e-12));
    }

    #[test]
    fn figures_of_a_known_distribution() {
        // Errors -3, -1, +1, +3 cm, each over 25 cm of travel.
        let mut stats = CrossTrackStats::new();
        for e_cm in [-3.0, -1.0, 1.0, 3.0] {
            stats.record(e_cm / 100.0, 25);
        }
        let s = stats.summary();
        assert!(close(s.mean_cm, 0.0, 1e-9));
        assert!(close(s.sd_cm, 5.0f64.sqrt(), 1e-9));
        assert!(close(s.rms_cm, 5.0f64.sqrt(), 1e-9));
        assert!(close(s.p95_cm, 3.0, 0.01));
        assert!(close(s.max_cm, 3.0, 1e-9));
        assert!(close(s.share_over_2cm, 0.5, 1e-12));
        assert_eq!(stats.samples(), 100);
    }

    #[test]
    fn empty_and_nonsense_are_harmless() {
        let mut stats = CrossTrackStats::new();
        assert_eq!(stats.summary(), CrossTrackSummary::default());
        stats.record(f64::NAN, 10);
        stats.record(1e300, 1);
        let s = stats.summary();
        assert_eq!(stats.samples(), 1);
        assert!(s.p95_cm <= 1001.0 && s.max_cm > 1e200);
    }
}
