//! The row filter's settings, its state as named quantities, and what it reports.

use super::{CAMERA_BIAS, CURVATURE, Covariance, HEADING, MAP_BIAS, OFFSET, SLIP, Vector};

/// Probability that a good measurement passes the gate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GateProbability {
    P0_99,
    #[default]
    P0_999,
    P0_9999,
}

impl GateProbability {
    /// Chi-square quantiles: 1 dof (Φ⁻¹((1+p)/2))², 2 dof exactly -2 ln(1-p). Values of
    /// the NIST/SEMATECH e-Handbook of Statistical Methods, 1.3.6.7.4 (0.99, 0.999), and
    /// from the same formulas for 0.9999.
    pub(super) fn threshold(self, dof: usize) -> f64 {
        match (self, dof) {
            (GateProbability::P0_99, 1) => 6.635,
            (GateProbability::P0_99, _) => 9.210,
            (GateProbability::P0_999, 1) => 10.828,
            (GateProbability::P0_999, _) => 13.816,
            (GateProbability::P0_9999, 1) => 15.137,
            (GateProbability::P0_9999, _) => 18.421,
        }
    }
}

/// The row as the filter sees it, or (from `sd`) each part's standard deviation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RowState {
    pub offset_m: f64,
    pub heading_rad: f64,
    pub curvature_per_m: f64,
    pub map_bias_m: f64,
    pub slip_rad: f64,
    /// How far the camera misreads the row's offset now (its error that lasts).
    pub camera_bias_m: f64,
}

impl RowState {
    pub(super) fn to_vector(self) -> Vector {
        Vector::new(
            self.offset_m,
            self.heading_rad,
            self.curvature_per_m,
            self.map_bias_m,
            self.slip_rad,
            self.camera_bias_m,
        )
    }

    pub(super) fn from_vector(v: &Vector) -> RowState {
        RowState {
            offset_m: v[OFFSET],
            heading_rad: v[HEADING],
            curvature_per_m: v[CURVATURE],
            map_bias_m: v[MAP_BIAS],
            slip_rad: v[SLIP],
            camera_bias_m: v[CAMERA_BIAS],
        }
    }
}

/// The robot's travel and turn over an interval, from odometry and steering.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Travel {
    pub travelled_m: f64,
    pub turned_rad: f64,
}

impl Travel {
    /// The travel over `age_s` of a robot that moved all along at `speed_mps`, turning
    /// at `yaw_rate_rps`: for an interval the odometry kept does not cover.
    pub(crate) fn at_rates(speed_mps: f64, yaw_rate_rps: f64, age_s: f64) -> Travel {
        Travel {
            travelled_m: speed_mps * age_s,
            turned_rad: yaw_rate_rps * age_s,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSettings {
    /// Side slip and bumps that odometry does not see, m per √m travelled.
    pub offset_sd_per_sqrt_m: f64,
    /// The row's wiggle and odometry's turn error, rad per √m.
    pub heading_sd_per_sqrt_m: f64,
    /// Change of the row's curvature, 1/m per √m.
    pub curvature_sd_per_sqrt_m: f64,
    /// Drift of the map's error and the live receiver's slow error along the row, m per √m.
    pub map_bias_sd_per_sqrt_m: f64,
    /// Change of the crab angle as the slope changes, rad per √m.
    pub slip_sd_per_sqrt_m: f64,
    /// The camera's error that lasts (it misreads a stretch of row the same way): its
    /// s.d., m (0: the camera's errors are independent from frame to frame) ...
    pub camera_bias_sd_m: f64,
    /// ... and the distance over which it forgets itself, m.
    pub camera_bias_length_m: f64,
    /// S.d. at start, and the scale of a reset's widening.
    pub initial_sd: RowState,
    pub gate: GateProbability,
    /// Rejections in a row after which that sensor's part is reset (0 acts as 1,
    /// u32::MAX never resets); fewer where both sensors are rejected (filter_gate.rs).
    pub camera_rejections_to_reset: u32,
    pub gnss_rejections_to_reset: u32,
}

impl Default for FilterSettings {
    fn default() -> FilterSettings {
        FilterSettings {
            offset_sd_per_sqrt_m: 0.003,
            heading_sd_per_sqrt_m: 0.005,
            curvature_sd_per_sqrt_m: 0.01,
            map_bias_sd_per_sqrt_m: 0.002,
            slip_sd_per_sqrt_m: 0.003,
            // Off unless the camera is known to misread stretches (the steer thread
            // sets it for the fused row).
            camera_bias_sd_m: 0.0,
            camera_bias_length_m: 3.0,
            initial_sd: RowState {
                offset_m: 0.05,
                heading_rad: 0.05,
                curvature_per_m: 0.02,
                map_bias_m: 0.03,
                slip_rad: 0.03,
                camera_bias_m: 0.0,
            },
            gate: GateProbability::P0_999,
            camera_rejections_to_reset: 10,
            gnss_rejections_to_reset: 20,
        }
    }
}

/// What became of one call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Used,
    /// Outside the gate; state unchanged.
    Rejected,
    /// The last of a run of rejections: that sensor's part was reset, then the measurement used.
    Reset,
    /// Bad input or a singular S; state unchanged.
    Refused,
}

/// Counts since construction. `*_rejected` counts every gate failure, `*_resets` those
/// that ended a run and reset; `*_used` counts updates that passed the gate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FilterCounters {
    pub camera_used: u64,
    pub camera_rejected: u64,
    pub camera_resets: u64,
    pub gnss_used: u64,
    pub gnss_rejected: u64,
    pub gnss_resets: u64,
    pub refused_bad_input: u64,
    pub refused_singular: u64,
}

impl FilterCounters {
    /// Counts `outcome` of an update and passes it on.
    pub(super) fn count(&mut self, sensor: Sensor, outcome: Outcome) -> Outcome {
        let (used, rejected, resets) = match sensor {
            Sensor::Camera => (
                &mut self.camera_used,
                &mut self.camera_rejected,
                &mut self.camera_resets,
            ),
            Sensor::Gnss => (
                &mut self.gnss_used,
                &mut self.gnss_rejected,
                &mut self.gnss_resets,
            ),
        };
        match outcome {
            Outcome::Used => *used += 1,
            Outcome::Rejected => *rejected += 1,
            Outcome::Reset => {
                *rejected += 1;
                *resets += 1;
            }
            Outcome::Refused => {}
        }
        outcome
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sensor {
    Camera = 0,
    Gnss = 1,
}

impl Sensor {
    /// The part of the state a run of this sensor's rejections resets. GNSS speaks for
    /// the map's error while the map may have one; with the map taken as the row (GNSS
    /// alone steering) it is the only reference, and a run of it says the robot moved.
    pub(super) fn part(self, map_may_err: bool) -> &'static [usize] {
        match (self, map_may_err) {
            (Sensor::Camera, _) => &[OFFSET, HEADING, CAMERA_BIAS],
            (Sensor::Gnss, true) => &[MAP_BIAS],
            (Sensor::Gnss, false) => &[OFFSET, HEADING],
        }
    }
}

/// What the filter reports.
impl super::RowFilter {
    pub fn state(&self) -> RowState {
        RowState::from_vector(&self.x)
    }

    /// Each part's standard deviation.
    pub fn sd(&self) -> RowState {
        RowState::from_vector(&self.p.diagonal().map(|v| v.max(0.0).sqrt()))
    }

    pub fn covariance(&self) -> Covariance {
        self.p
    }

    pub fn counters(&self) -> FilterCounters {
        self.counters
    }

    /// NIS of the camera's last update, gated or not, for a consistency check.
    pub fn last_camera_nis(&self) -> Option<f64> {
        self.last_nis[Sensor::Camera as usize]
    }

    pub fn last_gnss_nis(&self) -> Option<f64> {
        self.last_nis[Sensor::Gnss as usize]
    }

    pub fn settings(&self) -> &FilterSettings {
        &self.settings
    }
}
