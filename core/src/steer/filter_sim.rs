//! Test support: the filter's own model simulated, and a count of heap allocations.

use super::super::{FilterSettings, Outcome, RowFilter, RowState, Travel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::collections::VecDeque;

/// 0.5 m/s at 50 Hz; camera and GNSS every 5th step (10 Hz), the image 0.1 s old.
pub(crate) const STEP_M: f64 = 0.01;
pub(crate) const EVERY: usize = 5;
pub(crate) const CAMERA_X_M: f64 = 0.8;
/// The camera's noise as `[sim]` in config/robot.ini has it.
pub(crate) const SD_OFFSET_M: f64 = 0.01;
pub(crate) const SD_ANGLE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// RTK's fast noise; its slow error (about 1 cm) is in map_bias.
pub(crate) const SD_GNSS_M: f64 = 0.005;
pub(crate) const LOOKAHEAD_M: f64 = 1.5;

/// The filter's own model, written out again: the true row, the robot steering by
/// pure pursuit on the filter's estimate, and the sensors with the filter's noise.
pub struct Sim {
    rng: ChaCha8Rng,
    pub truth: RowState,
    noise: FilterSettings,
    /// The truth before each of the last EVERY steps, and that step's motion.
    history: VecDeque<(RowState, Travel)>,
}

impl Sim {
    pub fn new(seed: u64, noise: FilterSettings) -> Sim {
        let (rng, truth) = (ChaCha8Rng::seed_from_u64(seed), RowState::default());
        let history = VecDeque::new();
        Sim {
            rng,
            truth,
            noise,
            history,
        }
    }

    pub(crate) fn gauss(&mut self, sd: f64) -> f64 {
        sd * self.rng.sample::<f64, _>(StandardNormal)
    }

    pub fn drive(&mut self, f: &mut RowFilter) {
        let ds = STEP_M;
        let turned_rad = 2.0 * f.row_at(LOOKAHEAD_M).0 / LOOKAHEAD_M.powi(2) * ds;
        let motion = Travel {
            travelled_m: ds,
            turned_rad,
        };
        self.history.push_back((self.truth, motion));
        if self.history.len() > EVERY {
            self.history.pop_front();
        }
        let (t, n, root) = (self.truth, self.noise, ds.sqrt());
        self.truth = RowState {
            offset_m: t.offset_m + t.heading_rad * ds + t.curvature_per_m * ds * ds / 2.0
                - t.slip_rad * ds
                - turned_rad * ds / 2.0
                + self.gauss(n.offset_sd_per_sqrt_m * root),
            heading_rad: t.heading_rad + t.curvature_per_m * ds - turned_rad
                + self.gauss(n.heading_sd_per_sqrt_m * root),
            curvature_per_m: t.curvature_per_m + self.gauss(n.curvature_sd_per_sqrt_m * root),
            map_bias_m: t.map_bias_m + self.gauss(n.map_bias_sd_per_sqrt_m * root),
            slip_rad: t.slip_rad + self.gauss(n.slip_sd_per_sqrt_m * root),
            // The model simulated here has a camera with independent errors.
            camera_bias_m: 0.0,
        };
        assert_eq!(f.predict(ds, turned_rad), Outcome::Used);
    }

    /// The camera's view of the row as it was EVERY steps ago, plus `error_m`.
    pub fn camera(&mut self, f: &mut RowFilter, error_m: f64) -> Outcome {
        let then = self.history[0].0;
        let since = self
            .history
            .iter()
            .fold(Travel::default(), |a, (_, m)| Travel {
                travelled_m: a.travelled_m + m.travelled_m,
                turned_rad: a.turned_rad + m.turned_rad,
            });
        let (x, c) = (CAMERA_X_M, then.curvature_per_m);
        let z_o = then.offset_m + then.heading_rad * x + c * x * x / 2.0 + error_m;
        let z_o = z_o + self.gauss(SD_OFFSET_M);
        let z_a = then.heading_rad + c * x + self.gauss(SD_ANGLE_RAD);
        f.update_camera(z_o, z_a, x, SD_OFFSET_M, SD_ANGLE_RAD, since)
    }

    pub fn gnss(&mut self, f: &mut RowFilter, error_m: f64) -> Outcome {
        let z = self.truth.offset_m + self.truth.map_bias_m + error_m + self.gauss(SD_GNSS_M);
        f.update_gnss(z, SD_GNSS_M, Travel::default())
    }

    /// `steps` steps with both sensors.
    pub fn settle(&mut self, f: &mut RowFilter, steps: usize) {
        for k in 0..steps {
            self.drive(f);
            if k % EVERY == 0 {
                self.camera(f, 0.0);
                self.gnss(f, 0.0);
            }
        }
    }
}
