//! From raw inputs to physical measurements: wheel speeds from encoder counts, the
//! wheel angle from the steering encoder, and the steering encoder's calibration from
//! the potentiometer at start (the encoder is relative: it reads 0 wherever the wheel
//! was at power-up, while the potentiometer knows the absolute angle but is noisy).

use mechweed_hw::Inputs;

use crate::config::{FaultSettings, RobotSettings, SupervisorSettings};

/// What the supervisor knows about the robot's motion, in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Measured {
    pub v_left_mps: f64,
    pub v_right_mps: f64,
    /// Speed of the rear axle centre, m/s.
    pub speed_mps: f64,
    /// Wheel angle from the calibrated steering encoder, rad (positive = left).
    pub wheel_angle_rad: f64,
    /// Wheel angle from the potentiometer, low-pass filtered, rad.
    pub pot_angle_filtered_rad: f64,
    /// Wheel angle from the encoder through the same filter, so that the two can be
    /// compared while the wheel turns fast without the filter's lag looking like a fault.
    pub wheel_angle_filtered_rad: f64,
    /// Heading rate from the bicycle model, rad/s (positive = turning left).
    pub yaw_rate_rps: f64,
    /// Distance driven by the rear axle centre, m.
    pub distance_m: f64,
    /// The steering encoder has been calibrated from the potentiometer.
    pub calibrated: bool,
}

/// The potentiometer's noise is filtered over this time before comparing, s.
const POT_FILTER_S: f64 = 0.05;

pub struct Measurement {
    robot: RobotSettings,
    speed_filter_s: f64,
    calibration_samples: u32,
    pot_band_v: (f64, f64),
    last_counts: Option<[i64; 3]>,
    /// Sum and count of (pot angle - raw encoder angle) while calibrating, deg.
    calib_sum_deg: f64,
    calib_n: u32,
    /// Absolute angle of encoder count 0, deg, once calibrated.
    steer_zero_deg: Option<f64>,
    pub measured: Measured,
    /// Counts moved since the last update: left, right, steering.
    pub counts_moved: [bool; 3],
}

impl Measurement {
    pub fn new(robot: &RobotSettings, sup: &SupervisorSettings, faults: &FaultSettings) -> Self {
        Measurement {
            robot: robot.clone(),
            speed_filter_s: sup.speed_filter_s,
            calibration_samples: (sup.calibration_s * sup.rate_hz).ceil().max(1.0) as u32,
            pot_band_v: (faults.pot_min_v, faults.pot_max_v),
            last_counts: None,
            calib_sum_deg: 0.0,
            calib_n: 0,
            steer_zero_deg: None,
            measured: Measured::default(),
            counts_moved: [false; 3],
        }
    }

    /// Forget the steering encoder's zero and take it again from the potentiometer
    /// (after a potentiometer fault, at the next power-up, with the robot standing).
    pub(crate) fn recalibrate(&mut self) {
        self.calib_sum_deg = 0.0;
        self.calib_n = 0;
        self.steer_zero_deg = None;
        self.measured.calibrated = false;
    }

    /// Update from one tick's inputs, `dt_s` after the previous one.
    pub(crate) fn update(&mut self, i: &Inputs, dt_s: f64) -> Measured {
        let counts = [i.enc_left_counts, i.enc_right_counts, i.enc_steer_counts];
        let last = self.last_counts.unwrap_or(counts);
        self.last_counts = Some(counts);
        for k in 0..3 {
            self.counts_moved[k] = counts[k] != last[k];
        }
        let m = &mut self.measured;
        let blend = |filter_s: f64| {
            if filter_s > 0.0 {
                dt_s / (filter_s + dt_s)
            } else {
                1.0
            }
        };

        if dt_s > 0.0 {
            let per_m = self.robot.enc_counts_per_m;
            let raw_left = (counts[0] - last[0]) as f64 / per_m / dt_s;
            let raw_right = (counts[1] - last[1]) as f64 / per_m / dt_s;
            m.v_left_mps += (raw_left - m.v_left_mps) * blend(self.speed_filter_s);
            m.v_right_mps += (raw_right - m.v_right_mps) * blend(self.speed_filter_s);
        }
        m.speed_mps = 0.5 * (m.v_left_mps + m.v_right_mps);
        m.distance_m += m.speed_mps.abs() * dt_s;

        let pot_deg = (i.pot_v - self.robot.pot_centre_v) / self.robot.pot_v_per_deg;
        let pot_ok = (self.pot_band_v.0..=self.pot_band_v.1).contains(&i.pot_v);
        let encoder_deg = counts[2] as f64 / self.robot.steer_counts_per_deg;
        if self.steer_zero_deg.is_none() && pot_ok {
            // Average many noisy potentiometer readings into one offset, before any motion.
            self.calib_sum_deg += pot_deg - encoder_deg;
            self.calib_n += 1;
            if self.calib_n >= self.calibration_samples {
                self.steer_zero_deg = Some(self.calib_sum_deg / self.calib_n as f64);
                m.pot_angle_filtered_rad = pot_deg.to_radians();
                m.wheel_angle_filtered_rad = pot_deg.to_radians();
            }
        }
        m.calibrated = self.steer_zero_deg.is_some();
        m.pot_angle_filtered_rad +=
            (pot_deg.to_radians() - m.pot_angle_filtered_rad) * blend(POT_FILTER_S);
        m.wheel_angle_rad = match self.steer_zero_deg {
            Some(zero) => (zero + encoder_deg).to_radians(),
            None => m.pot_angle_filtered_rad,
        };
        m.wheel_angle_filtered_rad +=
            (m.wheel_angle_rad - m.wheel_angle_filtered_rad) * blend(POT_FILTER_S);
        m.yaw_rate_rps = m.speed_mps * m.wheel_angle_rad.tan() / self.robot.wheelbase_m;
        *m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    fn measurement() -> (Measurement, Settings) {
        let s = Settings::shipped();
        (Measurement::new(&s.robot, &s.supervisor, &s.faults), s)
    }

    /// A second of standing with the steering at the centre, every `dt_s`: calibrated.
    /// Returns those inputs.
    fn calibrated_at_the_centre(m: &mut Measurement, s: &Settings, dt_s: f64) -> Inputs {
        let inputs = Inputs {
            pot_v: s.robot.pot_centre_v,
            ..Inputs::default()
        };
        for _ in 0..(1.0 / dt_s) as usize {
            m.update(&inputs, dt_s);
        }
        assert!(m.measured.calibrated);
        inputs
    }

    #[test]
    fn speeds_from_counts_are_smoothed_over_the_speed_filters_time() {
        // From rest, both wheels at 1 m/s from now on: counts in whole steps jitter by
        // a count per tick, and the speed regulator must not see each jitter whole.
        let (mut m, s) = measurement();
        let dt_s = 0.01;
        let per_tick = (s.robot.enc_counts_per_m * 1.0 * dt_s) as i64;
        let mut inputs = Inputs::default();
        m.update(&inputs, dt_s);
        inputs.enc_left_counts += per_tick;
        inputs.enc_right_counts += per_tick;
        let first = m.update(&inputs, dt_s);
        let blend = dt_s / (s.supervisor.speed_filter_s + dt_s);
        assert!(blend < 0.5, "the shipped filter smooths little");
        assert!(
            (first.speed_mps - blend).abs() < 1e-9,
            "{}",
            first.speed_mps
        );
        for _ in 0..50 {
            inputs.enc_left_counts += per_tick;
            inputs.enc_right_counts += per_tick;
            m.update(&inputs, dt_s);
        }
        assert!((m.measured.speed_mps - 1.0).abs() < 1e-6);
        // A second update in the same instant (no time between): the speeds stay, and
        // are numbers, not 0/0.
        let again = m.update(&inputs, 0.0);
        assert!((again.speed_mps - 1.0).abs() < 1e-6, "{}", again.speed_mps);
    }

    #[test]
    fn the_heading_rate_is_the_bicycle_models() {
        // 1 m/s with the wheel at 10 degrees on a 1.3 m wheelbase (not the shipped 1 m,
        // where a term wrongly multiplied or divided by it would not show).
        let mut s = Settings::shipped();
        s.robot.wheelbase_m = 1.3;
        let mut m = Measurement::new(&s.robot, &s.supervisor, &s.faults);
        let dt_s = 0.01;
        let mut inputs = calibrated_at_the_centre(&mut m, &s, dt_s);
        inputs.enc_steer_counts = (10.0 * s.robot.steer_counts_per_deg) as i64;
        let per_tick = (s.robot.enc_counts_per_m * dt_s) as i64;
        for _ in 0..100 {
            inputs.enc_left_counts += per_tick;
            inputs.enc_right_counts += per_tick;
            m.update(&inputs, dt_s);
        }
        let expected = 10f64.to_radians().tan() / 1.3;
        let yaw_rate = m.measured.yaw_rate_rps;
        assert!((yaw_rate - expected).abs() < 1e-6, "{yaw_rate} rad/s");
    }

    #[test]
    fn the_potentiometers_noise_is_smoothed_before_it_is_compared() {
        // Calibrated at the centre, then one reading 3 degrees off (noise): the filtered
        // angle moves by a sixth of it over one 10 ms tick, not all of it.
        let (mut m, s) = measurement();
        let dt_s = 0.01;
        let mut inputs = calibrated_at_the_centre(&mut m, &s, dt_s);
        inputs.pot_v += 3.0 * s.robot.pot_v_per_deg;
        let after = m.update(&inputs, dt_s).pot_angle_filtered_rad.to_degrees();
        let expected = 3.0 * dt_s / (POT_FILTER_S + dt_s);
        assert!((after - expected).abs() < 1e-6, "{after} deg");
    }
}
