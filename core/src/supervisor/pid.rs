//! The regulators: PI with anti-windup for each drive wheel's speed, PD for the
//! steering angle. Plain state machines; the supervisor calls them once per tick.

use crate::config::{PdSettings, PiSettings};

/// PI speed regulator with feed-forward and anti-windup.
///
/// Anti-windup by conditional integration: while the output is saturated, the
/// integrator only moves in the direction that brings the output back into range, so
/// that after a long saturation (a steep slope, a wheel held by the brake) the wheel
/// does not overshoot by the error accumulated meanwhile.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pi {
    pub gains: PiSettings,
    /// Integrator state, in volts of output.
    pub integral_v: f64,
}

impl Pi {
    pub fn new(gains: PiSettings) -> Pi {
        Pi {
            gains,
            integral_v: 0.0,
        }
    }

    /// Forget the accumulated error (the robot is standing).
    pub fn reset(&mut self) {
        self.integral_v = 0.0;
    }

    /// Output voltage for a speed reference and measurement (m/s) over `dt_s`.
    pub(crate) fn update(&mut self, reference_mps: f64, measured_mps: f64, dt_s: f64) -> f64 {
        let g = &self.gains;
        let error = reference_mps - measured_mps;
        let proportional_v = g.kff * reference_mps + g.kp * error;
        let candidate_v = self.integral_v + g.ki * error * dt_s;
        let unsaturated_v = proportional_v + candidate_v;
        let winding_up = (unsaturated_v > g.out_max_v && error > 0.0)
            || (unsaturated_v < -g.out_max_v && error < 0.0);
        if !winding_up {
            self.integral_v = candidate_v.clamp(-g.out_max_v, g.out_max_v);
        }
        (proportional_v + self.integral_v).clamp(-g.out_max_v, g.out_max_v)
    }
}

/// PD angle regulator: derivative on the measurement (a step in the reference does
/// not kick the motor) through a first-order low-pass filter (the encoder's counts
/// make a raw derivative noisy).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pd {
    pub gains: PdSettings,
    rate_rad_s: f64,
    last_measured_rad: Option<f64>,
}

impl Pd {
    pub fn new(gains: PdSettings) -> Pd {
        Pd {
            gains,
            rate_rad_s: 0.0,
            last_measured_rad: None,
        }
    }

    pub fn reset(&mut self) {
        self.rate_rad_s = 0.0;
        self.last_measured_rad = None;
    }

    /// Output voltage for an angle reference and measurement (rad) over `dt_s`.
    pub(crate) fn update(&mut self, reference_rad: f64, measured_rad: f64, dt_s: f64) -> f64 {
        let g = &self.gains;
        if let Some(last) = self.last_measured_rad
            && dt_s > 0.0
        {
            let raw_rate = (measured_rad - last) / dt_s;
            let blend = dt_s / (g.d_filter_s + dt_s);
            self.rate_rad_s += (raw_rate - self.rate_rad_s) * blend;
        }
        self.last_measured_rad = Some(measured_rad);
        let volts = g.kp * (reference_rad - measured_rad) - g.kd * self.rate_rad_s;
        volts.clamp(-g.out_max_v, g.out_max_v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pi() -> Pi {
        Pi::new(PiSettings {
            kp: 16.7,
            ki: 167.0,
            kff: 8.33,
            out_max_v: 10.0,
        })
    }

    #[test]
    fn integrator_holds_while_saturated() {
        let mut reg = pi();
        // The wheel cannot follow (held by a brake): error stays large for 2 s.
        for _ in 0..200 {
            let out = reg.update(1.0, 0.0, 0.01);
            assert_eq!(out, 10.0);
        }
        // The integrator may only hold what keeps the output at the limit, not 2 s of error.
        assert!(reg.integral_v <= 10.0, "integral {}", reg.integral_v);
        let before = reg.integral_v;
        reg.update(1.0, 0.0, 0.01);
        assert_eq!(reg.integral_v, before, "integrator moved while saturated");
        // Once the wheel catches up, the output leaves saturation at once.
        let out = reg.update(1.0, 1.1, 0.01);
        assert!(out < 10.0, "output stayed saturated: {out}");
    }

    #[test]
    fn integrator_unwinds_when_error_reverses_in_saturation() {
        let mut reg = pi();
        reg.integral_v = 10.0;
        reg.update(1.0, 1.5, 0.01);
        assert!(reg.integral_v < 10.0);
    }

    #[test]
    fn pi_removes_steady_state_error_on_a_first_order_motor() {
        // Motor with a 10 % weaker gain than the feed-forward assumes, and a dead band.
        let (gain, tau, deadband) = (0.108, 0.1, 0.3);
        let mut reg = pi();
        let mut speed = 0.0;
        for _ in 0..300 {
            let volts = reg.update(0.5, speed, 0.01);
            let effective = (volts.abs() - deadband).max(0.0) * volts.signum();
            speed += (gain * effective - speed) / tau * 0.01;
        }
        assert!((speed - 0.5f64).abs() < 0.005, "speed {speed}");
    }

    #[test]
    fn the_integral_winds_up_only_to_the_limit_and_a_reset_forgets_it() {
        // Held by its brake for a second, forwards and in reverse, the integrator winds
        // up; standing resets it, and the next start gives feed-forward and proportional
        // only.
        for reference_mps in [0.2, -0.2] {
            let mut reg = pi();
            for _ in 0..100 {
                reg.update(reference_mps, 0.0, 0.01);
            }
            // Only as far as the output's limit: feed-forward and proportional give 5 V,
            // the integrator the rest, within one step.
            let g = reg.gains;
            let sign = f64::signum(reference_mps);
            let held_v = g.out_max_v - (g.kff + g.kp) * 0.2;
            let step_v = g.ki * 0.2 * 0.01;
            let integral_v = sign * reg.integral_v;
            assert!(
                integral_v > held_v - step_v && integral_v <= held_v + 1e-9,
                "integral {integral_v} V, limit {held_v} V at {reference_mps} m/s"
            );
            assert!(sign * reg.update(reference_mps, 0.0, 0.01) > g.out_max_v - step_v);
            reg.reset();
            let expected_v = sign * ((g.kff + g.kp) * 0.2 + step_v);
            assert!((reg.update(reference_mps, 0.0, 0.01) - expected_v).abs() < 1e-9);
        }
    }

    fn pd() -> Pd {
        Pd::new(PdSettings {
            kp: 100.0,
            kd: 2.0,
            d_filter_s: 0.02,
            out_max_v: 10.0,
        })
    }

    #[test]
    fn pd_damps_by_the_measured_rate_through_its_filter() {
        // The wheel turning steadily at 0.5 rad/s, the reference following it: only the
        // damping acts. It takes dt / (d_filter_s + dt) of the rate at the first step,
        // and all of it once the filter has settled.
        let mut reg = pd();
        let (dt_s, rate_rad_s) = (0.01, 0.5);
        let mut angle_rad = 0.0;
        reg.update(angle_rad, angle_rad, dt_s);
        angle_rad += rate_rad_s * dt_s;
        let first_v = reg.update(angle_rad, angle_rad, dt_s);
        let blend = dt_s / (0.02 + dt_s);
        assert!(
            (first_v + 2.0 * rate_rad_s * blend).abs() < 1e-9,
            "{first_v} V"
        );
        let mut settled_v = first_v;
        for _ in 0..100 {
            angle_rad += rate_rad_s * dt_s;
            settled_v = reg.update(angle_rad, angle_rad, dt_s);
        }
        assert!((settled_v + 2.0 * rate_rad_s).abs() < 1e-6, "{settled_v} V");
        // No time between two updates: the rate is kept, a number, not 0/0.
        let again_v = reg.update(angle_rad, angle_rad, 0.0);
        assert!((again_v - settled_v).abs() < 1e-12, "{again_v} V");
    }

    #[test]
    fn a_reset_pd_takes_no_rate_from_before_it() {
        // Turning fast, then standing and reset; at the next start the wheel is
        // elsewhere: no damping kick from the old rate nor from the jump since.
        let mut reg = pd();
        for k in 0..20 {
            reg.update(0.0, k as f64 * 0.02, 0.01);
        }
        reg.reset();
        let out_v = reg.update(0.05, 0.0, 0.01);
        assert!((out_v - 100.0 * 0.05).abs() < 1e-9, "{out_v} V");
    }

    #[test]
    fn pd_derivative_acts_on_measurement_not_reference() {
        let mut reg = Pd::new(PdSettings {
            kp: 100.0,
            kd: 2.0,
            d_filter_s: 0.02,
            out_max_v: 10.0,
        });
        reg.update(0.0, 0.0, 0.01);
        // A reference step gives only the proportional part.
        assert!((reg.update(0.05, 0.0, 0.01) - 5.0).abs() < 1e-9);
        // A moving measurement is damped.
        let out = reg.update(0.05, 0.01, 0.01);
        assert!(out < 100.0 * 0.04, "no damping: {out}");
    }
}
