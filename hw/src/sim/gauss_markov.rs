//! A first-order Gauss-Markov process: a slowly wandering error with a given standard
//! deviation and correlation span, the usual model of a GNSS solution's bias (over
//! time) and of a camera that misreads a stretch of row the same way (over distance).
//! The span is in whatever unit the caller steps it by: seconds or metres.
//!
//! Stepped with the exact discrete form, x' = phi x + s sqrt(1 - phi^2) w with
//! phi = exp(-dt / tau), so its statistics do not depend on the step size and a long
//! gap (receiver off, simulation paused) simply forgets the old value. The caller
//! draws the unit normals, so that one random stream can feed many processes in a
//! fixed order.

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GaussMarkov {
    /// Stationary standard deviation, m.
    sd_m: f64,
    /// Correlation span (s or m): the autocorrelation falls to 1/e over this.
    span: f64,
    value_m: f64,
}

impl GaussMarkov {
    /// Starts at `sd_m * unit_normal`: already stationary, as if it had always run.
    pub fn new(sd_m: f64, span: f64, unit_normal: f64) -> GaussMarkov {
        GaussMarkov {
            sd_m,
            span,
            value_m: sd_m * unit_normal,
        }
    }

    pub(crate) fn value_m(&self) -> f64 {
        self.value_m
    }

    /// Advance by `step` (s or m, as the span); a step of zero, negative or NaN length
    /// changes nothing.
    pub fn step(&mut self, step: f64, unit_normal: f64) -> f64 {
        if step > 0.0 {
            let phi = (-step / self.span).exp();
            self.value_m = phi * self.value_m + self.sd_m * (1.0 - phi * phi).sqrt() * unit_normal;
        }
        self.value_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rand_distr::StandardNormal;

    /// Sample s.d. and lag-`lag` autocorrelation of a run of `n` steps of `dt_s`.
    fn run(dt_s: f64, n: usize, lag: usize) -> (f64, f64) {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut process = GaussMarkov::new(0.5, 10.0, rng.sample(StandardNormal));
        let xs: Vec<f64> = (0..n)
            .map(|_| process.step(dt_s, rng.sample(StandardNormal)))
            .collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        let cov = xs
            .windows(lag + 1)
            .map(|w| (w[0] - mean) * (w[lag] - mean))
            .sum::<f64>()
            / (n - lag) as f64;
        (var.sqrt(), cov / var)
    }

    #[test]
    fn keeps_its_standard_deviation_and_correlation_time_at_any_step() {
        // 2000 correlation times: the sample s.d. is within a few percent.
        for (dt_s, lag) in [(0.1, 100), (1.0, 10)] {
            let n = (20_000.0 / dt_s) as usize;
            let (sd_m, rho) = run(dt_s, n, lag);
            assert!((0.45..0.55).contains(&sd_m), "dt {dt_s}: s.d. {sd_m}");
            // One correlation time apart: e^-1 = 0.37.
            assert!(
                (0.32..0.42).contains(&rho),
                "dt {dt_s}: autocorrelation {rho}"
            );
        }
    }

    #[test]
    fn a_step_of_no_time_changes_nothing() {
        let mut process = GaussMarkov::new(1.0, 5.0, 0.3);
        for dt_s in [0.0, -1.0, f64::NAN] {
            assert_eq!(process.step(dt_s, 3.0), 0.3);
        }
        // A long gap forgets the old value entirely.
        assert_eq!(process.step(1e6, -2.0), -2.0);
    }
}
