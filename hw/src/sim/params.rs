//! Every number of the simulated plant (the [sim] settings in config/robot.ini), with its default.
//!
//! config/robot.ini [sim] overrides any of them. Whatever arrives here is made safe by
//! [`SimParams::sanitized`] before the plant uses it, so no setting can make the
//! simulation panic or loop for ever.

use super::events::SimEvent;
use super::gnss::SimGnssParams;
use super::miswire::Miswire;

/// The shape of the crop row's centre line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowShape {
    /// Along +x.
    Straight,
    /// y = A sin(2 pi x / wavelength).
    SCurve,
    /// A circle turning left.
    Arc,
}

/// Which field the robot drives in: the clean benchmark's, or one with what real fields
/// add (field_tier.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    Clean,
    Realistic,
}

/// The field tier's disturbances ([sim] field_*), used when the field is realistic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldTierParams {
    /// The camera's correlated offset error (Gauss-Markov over distance): s.d., m.
    pub camera_bias_sd_m: f64,
    /// ... and its correlation length, m.
    pub camera_bias_length_m: f64,
    /// Mean distance between gaps in the row, m.
    pub gap_every_m: f64,
    pub gap_min_m: f64,
    pub gap_max_m: f64,
    /// In a gap the camera repeats its last estimate with this quality (0..100).
    pub gap_quality: u8,
    /// Mean distance between weed patches, m.
    pub weed_every_m: f64,
    pub weed_length_m: f64,
    /// The camera's offset in a weed patch is off by this much, either side, m.
    pub weed_offset_min_m: f64,
    pub weed_offset_max_m: f64,
    /// The side slope's slip varies between 0 and this (positive = slides left), deg ...
    pub slope_max_deg: f64,
    /// ... taking a new level every this far, m.
    pub slope_length_m: f64,
    /// Mean distance between bumps, m.
    pub bump_every_m: f64,
    /// A bump kicks the heading by this s.d., deg ...
    pub bump_heading_sd_deg: f64,
    /// ... and the body sideways by this s.d., m.
    pub bump_side_sd_m: f64,
    /// The drive wheels slip between 0 and this share (0.05 = 5 %) ...
    pub wheel_slip_max: f64,
    /// ... taking a new level every this far, m.
    pub wheel_slip_length_m: f64,
}

impl Default for FieldTierParams {
    fn default() -> Self {
        FieldTierParams {
            camera_bias_sd_m: 0.015,
            camera_bias_length_m: 3.0,
            gap_every_m: 15.0,
            gap_min_m: 0.5,
            gap_max_m: 2.0,
            gap_quality: 40,
            weed_every_m: 25.0,
            weed_length_m: 1.0,
            weed_offset_min_m: 0.05,
            weed_offset_max_m: 0.10,
            slope_max_deg: 3.0,
            slope_length_m: 10.0,
            bump_every_m: 2.0,
            bump_heading_sd_deg: 0.5,
            bump_side_sd_m: 0.005,
            wheel_slip_max: 0.05,
            wheel_slip_length_m: 10.0,
        }
    }
}

impl FieldTierParams {
    fn sanitized(&self) -> FieldTierParams {
        let d = FieldTierParams::default();
        let gap_min_m = non_negative_or(self.gap_min_m, d.gap_min_m);
        let weed_offset_min_m = non_negative_or(self.weed_offset_min_m, d.weed_offset_min_m);
        FieldTierParams {
            camera_bias_sd_m: non_negative_or(self.camera_bias_sd_m, d.camera_bias_sd_m),
            camera_bias_length_m: positive_or(self.camera_bias_length_m, d.camera_bias_length_m),
            // Closer than every 10 cm would only fill memory.
            gap_every_m: positive_or(self.gap_every_m, d.gap_every_m).max(0.1),
            gap_min_m,
            gap_max_m: non_negative_or(self.gap_max_m, d.gap_max_m).max(gap_min_m),
            gap_quality: self.gap_quality.min(100),
            weed_every_m: positive_or(self.weed_every_m, d.weed_every_m).max(0.1),
            weed_length_m: non_negative_or(self.weed_length_m, d.weed_length_m),
            weed_offset_min_m,
            weed_offset_max_m: non_negative_or(self.weed_offset_max_m, d.weed_offset_max_m)
                .max(weed_offset_min_m),
            slope_max_deg: finite_or(self.slope_max_deg, d.slope_max_deg).clamp(-89.0, 89.0),
            slope_length_m: positive_or(self.slope_length_m, d.slope_length_m).max(0.1),
            bump_every_m: positive_or(self.bump_every_m, d.bump_every_m).max(0.01),
            bump_heading_sd_deg: non_negative_or(self.bump_heading_sd_deg, d.bump_heading_sd_deg),
            bump_side_sd_m: non_negative_or(self.bump_side_sd_m, d.bump_side_sd_m),
            wheel_slip_max: non_negative_or(self.wheel_slip_max, d.wheel_slip_max).min(0.9),
            wheel_slip_length_m: positive_or(self.wheel_slip_length_m, d.wheel_slip_length_m)
                .max(0.1),
        }
    }
}

/// Parameters of the simulated robot, field and camera computer.
#[derive(Debug, Clone, PartialEq)]
pub struct SimParams {
    /// Everything random is derived from this one number.
    pub seed: u64,
    /// Integration step, s.
    pub step_s: f64,
    // --- the robot (the simulated plant's table) ---
    pub wheelbase_m: f64,
    pub track_m: f64,
    /// Drive motor: wheel speed per volt at steady state, m/s per V.
    pub motor_gain_mps_per_v: f64,
    pub motor_tau_s: f64,
    pub motor_deadband_v: f64,
    /// Gain mismatch: left gain * (1 + m/2), right gain * (1 - m/2).
    pub motor_mismatch: f64,
    /// Steering: wheel angle rate per volt, deg/s per V.
    pub steer_rate_dps_per_v: f64,
    pub steer_lag_s: f64,
    pub steer_limit_deg: f64,
    pub end_switch_deg: f64,
    pub pot_noise_v: f64,
    pub enc_counts_per_m: f64,
    pub steer_counts_per_deg: f64,
    /// Weeding tool point along the centre line from the rear axle, m (negative = behind).
    pub tool_offset_m: f64,
    /// Time to stop from full speed (1.2 m/s) with the brake on, s.
    pub brake_stop_s: f64,
    /// Body velocity direction = heading + slip; positive slips to the left.
    pub side_slip_deg: f64,
    pub battery_v: f64,
    /// Wheel angle at start; the steering encoder reads 0 here (it is relative).
    pub initial_wheel_angle_deg: f64,
    // --- the field ---
    /// Clean, or with what real fields add (`tier`).
    pub field: FieldKind,
    pub tier: FieldTierParams,
    pub row: RowShape,
    pub row_length_m: f64,
    /// The robot starts this far to the LEFT of the row, heading along it.
    pub start_offset_m: f64,
    pub scurve_amplitude_m: f64,
    pub scurve_wavelength_m: f64,
    pub arc_radius_m: f64,
    pub plant_spacing_m: f64,
    /// Standard deviation of the plants' sideways scatter, m.
    pub plant_scatter_m: f64,
    // --- the camera computer ---
    pub camera_lookahead_m: f64,
    pub camera_rate_hz: f64,
    pub camera_latency_s: f64,
    /// The latency is uniform in latency +- jitter.
    pub camera_jitter_s: f64,
    pub camera_noise_offset_m: f64,
    pub camera_noise_angle_deg: f64,
    /// Probability that a frame is not sent (its seq number is still used).
    pub camera_drop: f64,
    /// Probability per byte that it is flipped.
    pub camera_corrupt: f64,
    /// Silent this long after a reboot, then waits for START.
    pub camera_reboot_s: f64,
    /// The GNSS receiver on the robot, and the field's place and map.
    pub gnss: SimGnssParams,
    /// Scheduled plant and operator events.
    pub events: Vec<SimEvent>,
    /// A wiring mistake made on purpose (miswire.rs).
    pub miswire: Miswire,
    /// The tool's cross-track figures leave out the travel before this distance, m
    /// (the simulated plant: the first 5 m, while the robot settles onto the row).
    pub cross_track_from_m: f64,
}

/// the simulated plant: cross-track statistics start after the first 5 m.
pub const CROSS_TRACK_FROM_M: f64 = 5.0;

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            seed: 1,
            step_s: 0.001,
            wheelbase_m: 1.0,
            track_m: 0.9,
            motor_gain_mps_per_v: 0.12,
            motor_tau_s: 0.10,
            motor_deadband_v: 0.3,
            motor_mismatch: 0.02,
            steer_rate_dps_per_v: 6.0,
            steer_lag_s: 0.05,
            steer_limit_deg: 30.0,
            end_switch_deg: 28.0,
            pot_noise_v: 0.020,
            enc_counts_per_m: 10_000.0,
            steer_counts_per_deg: 100.0,
            tool_offset_m: -0.40,
            brake_stop_s: 0.3,
            side_slip_deg: 1.0,
            battery_v: 25.0,
            initial_wheel_angle_deg: 0.0,
            field: FieldKind::Clean,
            tier: FieldTierParams::default(),
            row: RowShape::SCurve,
            row_length_m: 60.0,
            start_offset_m: 0.0,
            scurve_amplitude_m: 0.05,
            scurve_wavelength_m: 10.0,
            arc_radius_m: 20.0,
            plant_spacing_m: 0.20,
            plant_scatter_m: 0.01,
            camera_lookahead_m: 0.8,
            camera_rate_hz: 10.0,
            camera_latency_s: 0.100,
            camera_jitter_s: 0.020,
            camera_noise_offset_m: 0.01,
            camera_noise_angle_deg: 0.5,
            camera_drop: 0.02,
            camera_corrupt: 0.0,
            camera_reboot_s: 2.0,
            gnss: SimGnssParams::default(),
            events: Vec::new(),
            miswire: Miswire::None,
            cross_track_from_m: CROSS_TRACK_FROM_M,
        }
    }
}

impl SimParams {
    /// The benchmark scenario of the simulated plant for one row shape: straight 60 m starting 5 cm
    /// left of the row, S-curve 60 m, arc 40 m; every disturbance on (the defaults).
    /// The speed is the controller's business, so it is not a parameter of the plant.
    pub fn benchmark(row: RowShape, seed: u64) -> SimParams {
        let (row_length_m, start_offset_m) = match row {
            RowShape::Straight => (60.0, 0.05),
            RowShape::SCurve => (60.0, 0.0),
            RowShape::Arc => (40.0, 0.0),
        };
        SimParams {
            seed,
            row,
            row_length_m,
            start_offset_m,
            ..SimParams::default()
        }
    }

    /// A copy in which every value the plant cannot work with (NaN, negative times,
    /// probabilities outside 0..1, absurd sizes) is replaced by its default or clamped.
    pub(crate) fn sanitized(&self) -> SimParams {
        let d = SimParams::default();
        let limit_deg = positive_or(self.steer_limit_deg, d.steer_limit_deg).min(89.0);
        SimParams {
            seed: self.seed,
            step_s: positive_or(self.step_s, d.step_s).clamp(1e-5, 0.05),
            wheelbase_m: positive_or(self.wheelbase_m, d.wheelbase_m),
            track_m: positive_or(self.track_m, d.track_m),
            motor_gain_mps_per_v: non_negative_or(
                self.motor_gain_mps_per_v,
                d.motor_gain_mps_per_v,
            ),
            motor_tau_s: non_negative_or(self.motor_tau_s, d.motor_tau_s),
            motor_deadband_v: non_negative_or(self.motor_deadband_v, d.motor_deadband_v),
            motor_mismatch: finite_or(self.motor_mismatch, d.motor_mismatch).clamp(-1.0, 1.0),
            steer_rate_dps_per_v: finite_or(self.steer_rate_dps_per_v, d.steer_rate_dps_per_v),
            steer_lag_s: non_negative_or(self.steer_lag_s, d.steer_lag_s),
            steer_limit_deg: limit_deg,
            end_switch_deg: finite_or(self.end_switch_deg, d.end_switch_deg),
            pot_noise_v: non_negative_or(self.pot_noise_v, d.pot_noise_v),
            enc_counts_per_m: finite_or(self.enc_counts_per_m, d.enc_counts_per_m),
            steer_counts_per_deg: finite_or(self.steer_counts_per_deg, d.steer_counts_per_deg),
            tool_offset_m: finite_or(self.tool_offset_m, d.tool_offset_m),
            brake_stop_s: positive_or(self.brake_stop_s, d.brake_stop_s),
            side_slip_deg: finite_or(self.side_slip_deg, d.side_slip_deg).clamp(-89.0, 89.0),
            battery_v: non_negative_or(self.battery_v, d.battery_v),
            initial_wheel_angle_deg: finite_or(self.initial_wheel_angle_deg, 0.0)
                .clamp(-limit_deg, limit_deg),
            field: self.field,
            tier: self.tier.sanitized(),
            row: self.row,
            row_length_m: positive_or(self.row_length_m, d.row_length_m).clamp(0.1, 5000.0),
            start_offset_m: finite_or(self.start_offset_m, 0.0),
            scurve_amplitude_m: finite_or(self.scurve_amplitude_m, d.scurve_amplitude_m),
            scurve_wavelength_m: positive_or(self.scurve_wavelength_m, d.scurve_wavelength_m),
            arc_radius_m: positive_or(self.arc_radius_m, d.arc_radius_m).max(0.5),
            // Closer than 1 cm would only fill memory with plants.
            plant_spacing_m: positive_or(self.plant_spacing_m, d.plant_spacing_m).max(0.01),
            plant_scatter_m: non_negative_or(self.plant_scatter_m, d.plant_scatter_m),
            camera_lookahead_m: finite_or(self.camera_lookahead_m, d.camera_lookahead_m),
            // 0 Hz is allowed: a camera that never captures.
            camera_rate_hz: non_negative_or(self.camera_rate_hz, d.camera_rate_hz).min(1000.0),
            camera_latency_s: non_negative_or(self.camera_latency_s, d.camera_latency_s),
            camera_jitter_s: non_negative_or(self.camera_jitter_s, d.camera_jitter_s),
            camera_noise_offset_m: non_negative_or(
                self.camera_noise_offset_m,
                d.camera_noise_offset_m,
            ),
            camera_noise_angle_deg: non_negative_or(
                self.camera_noise_angle_deg,
                d.camera_noise_angle_deg,
            ),
            camera_drop: non_negative_or(self.camera_drop, 0.0).min(1.0),
            camera_corrupt: non_negative_or(self.camera_corrupt, 0.0).min(1.0),
            camera_reboot_s: non_negative_or(self.camera_reboot_s, d.camera_reboot_s),
            cross_track_from_m: non_negative_or(self.cross_track_from_m, d.cross_track_from_m),
            gnss: self.gnss.sanitized(),
            events: self
                .events
                .iter()
                .filter(|e| e.t_s.is_finite())
                .copied()
                .collect(),
            miswire: self.miswire,
        }
    }
}

fn finite_or(value: f64, default: f64) -> f64 {
    if value.is_finite() { value } else { default }
}

fn non_negative_or(value: f64, default: f64) -> f64 {
    if value.is_finite() && value >= 0.0 {
        value
    } else {
        default
    }
}

fn positive_or(value: f64, default: f64) -> f64 {
    if value.is_finite() && value > 0.0 {
        value
    } else {
        default
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn benchmark_sets_the_scenario_of_docs_simulation_md() {
        let straight = SimParams::benchmark(RowShape::Straight, 7);
        assert_eq!(
            (
                straight.row_length_m,
                straight.start_offset_m,
                straight.seed
            ),
            (60.0, 0.05, 7)
        );
        assert_eq!(SimParams::benchmark(RowShape::Arc, 1).row_length_m, 40.0);
        let s = SimParams::benchmark(RowShape::SCurve, 1);
        assert_eq!(
            (s.side_slip_deg, s.motor_mismatch, s.camera_drop),
            (1.0, 0.02, 0.02)
        );
    }

    #[test]
    fn sanitized_replaces_nonsense_and_keeps_good_values() {
        let bad = SimParams {
            step_s: f64::NAN,
            camera_drop: 3.0,
            camera_rate_hz: -1.0,
            row_length_m: 1e12,
            wheelbase_m: 0.0,
            ..SimParams::default()
        };
        let s = bad.sanitized();
        assert_eq!(s.step_s, 0.001);
        assert_eq!(s.camera_drop, 1.0);
        assert_eq!(s.camera_rate_hz, 10.0);
        assert_eq!(s.row_length_m, 5000.0);
        assert_eq!(s.wheelbase_m, 1.0);
        assert_eq!(SimParams::default().sanitized(), SimParams::default());
    }
}
