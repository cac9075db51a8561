//! The tool's cross-track figures of a run, from the supervisor's ticks: the one
//! computation behind the run report's figures and `record summary`'s.
//!
//! The plant's own statistics (`CrossTrackStats`, a sample at each centimetre mark of
//! its 1 ms steps) are not in a record, so a record cannot give them again. The run
//! report and `record summary` therefore take the same points, the simulated robot's
//! truth after each supervisor tick (as the record holds it), through this code: each
//! tick's error weighs as much as the distance the rear axle truly drove since the tick
//! before, from `from_m` on and while the tool is within the row. With every tick
//! recorded (`[record] every_n_ticks` = 1, none dropped) the two are the same to the
//! last digit. Recording never allocates.

use hdrhistogram::Histogram;

use super::crosstrack::CrossTrackSummary;

/// Histogram units per metre of error and per metre of travel (micrometres).
const UM_PER_M: f64 = 1e6;
/// Largest |error| the histogram tells apart (10 m); `max_cm` still shows larger ones.
const HIGHEST_UM: u64 = 10_000_000;

/// Cross-track figures by distance over a run's ticks (see the module's words).
#[derive(Clone)]
pub struct TickCrossTrack {
    from_m: f64,
    /// The true distance at the tick before, m (None: no tick yet).
    last_distance_m: Option<f64>,
    /// |error| in micrometres, each counted once per micrometre of travel.
    abs_um: Histogram<u64>,
    distance_m: f64,
    sum_m2: f64,
    sum_sq_m3: f64,
    max_abs_m: f64,
    over_2cm_m: f64,
}

impl std::fmt::Debug for TickCrossTrack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("TickCrossTrack")
            .field(&self.summary())
            .finish()
    }
}

impl TickCrossTrack {
    /// Figures from `from_m` of true travel on.
    pub fn new(from_m: f64) -> TickCrossTrack {
        TickCrossTrack {
            from_m,
            last_distance_m: None,
            // Three significant figures: 10 um resolution at 1 cm.
            abs_um: Histogram::new_with_bounds(1, HIGHEST_UM, 3).expect("constant, valid bounds"),
            distance_m: 0.0,
            sum_m2: 0.0,
            sum_sq_m3: 0.0,
            max_abs_m: 0.0,
            over_2cm_m: 0.0,
        }
    }

    /// One tick: the tool's signed error, the true distance driven so far and whether
    /// the tool has passed the row's end. Non-finite values add nothing.
    pub fn tick(&mut self, error_m: f64, distance_m: f64, row_done: bool) {
        if !distance_m.is_finite() {
            return;
        }
        let weight_m = self
            .last_distance_m
            .replace(distance_m)
            .map_or(0.0, |last| (distance_m - last).max(0.0));
        if distance_m < self.from_m || row_done || weight_m <= 0.0 || !error_m.is_finite() {
            return;
        }
        let abs_m = error_m.abs();
        self.distance_m += weight_m;
        self.sum_m2 += error_m * weight_m;
        self.sum_sq_m3 += error_m * error_m * weight_m;
        self.max_abs_m = self.max_abs_m.max(abs_m);
        if abs_m > 0.02 {
            self.over_2cm_m += weight_m;
        }
        // `as` saturates, and saturating_record_n clamps to the histogram's range.
        let weight_um = (weight_m * UM_PER_M).round() as u64;
        self.abs_um
            .saturating_record_n((abs_m * UM_PER_M).round() as u64, weight_um.max(1));
    }

    /// The figures so far (all zero before any travel from `from_m` on).
    pub fn summary(&self) -> CrossTrackSummary {
        CrossTrackSummary::from_sums(
            self.distance_m,
            self.sum_m2,
            self.sum_sq_m3,
            self.abs_um.value_at_quantile(0.95) as f64 / UM_PER_M,
            self.max_abs_m,
            self.over_2cm_m,
            self.distance_m,
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
    fn each_tick_weighs_the_distance_since_the_one_before() {
        // -3, -1, +1, +3 cm, each over 0.25 m; standing still at 50 cm weighs nothing,
        // and the first tick has no tick before it.
        let mut track = TickCrossTrack::new(0.0);
        track.tick(0.5, 0.0, false);
        for (k, e_cm) in [-3.0, -1.0, 1.0, 3.0].into_iter().enumerate() {
            track.tick(e_cm / 100.0, 0.25 * (k + 1) as f64, false);
        }
        track.tick(0.5, 1.0, false);
        let s = track.summary();
        assert!(close(s.mean_cm, 0.0, 1e-9) && close(s.distance_m, 1.0, 1e-12));
        assert!(close(s.sd_cm, 5f64.sqrt(), 1e-9) && close(s.rms_cm, 5f64.sqrt(), 1e-9));
        assert!(close(s.p95_cm, 3.0, 0.01) && close(s.max_cm, 3.0, 1e-9));
        assert!(close(s.share_over_2cm, 0.5, 1e-12));
    }

    #[test]
    fn nothing_before_from_m_or_past_the_row_or_not_a_number() {
        let mut track = TickCrossTrack::new(5.0);
        track.tick(0.10, 0.0, false);
        track.tick(0.10, 4.9, false);
        assert_eq!(track.summary(), CrossTrackSummary::default());
        track.tick(0.01, 5.4, false);
        track.tick(0.50, 5.5, true);
        track.tick(f64::NAN, 5.6, false);
        track.tick(0.50, f64::NAN, false);
        let s = track.summary();
        assert!(
            close(s.distance_m, 0.5, 1e-12) && close(s.max_cm, 1.0, 1e-9),
            "{s:?}"
        );
        // The p95 is by distance: 96 % of the way at 1 cm, 4 % at 10 cm.
        let mut track = TickCrossTrack::new(0.0);
        track.tick(0.0, 0.0, false);
        track.tick(0.01, 0.96, false);
        track.tick(0.10, 1.0, false);
        assert!(close(track.summary().p95_cm, 1.0, 0.01));
    }
}
