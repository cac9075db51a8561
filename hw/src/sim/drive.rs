//! One drive wheel: amplifier voltage -> wheel speed, with the spring brake.
//!
//! the simulated plant: dv/dt = (K*V_eff - v)/tau, where V_eff is the voltage beyond a dead band of
//! +-0.3 V (friction the motor must overcome first). The brake, when on, slows the wheel
//! at a fixed rate (1.2 m/s in brake_stop_s) and holds it at rest: the motor can slow
//! the wheel faster than that, never speed it up against the brake.

/// The speed the brake is specified to stop from in `brake_stop_s`, m/s.
const BRAKE_REFERENCE_SPEED_MPS: f64 = 1.2;

#[derive(Debug, Clone)]
pub(crate) struct DriveWheel {
    gain_mps_per_v: f64,
    tau_s: f64,
    deadband_v: f64,
    brake_decel_mps2: f64,
    speed_mps: f64,
    /// Signed distance the wheel has rolled, m (what its encoder counts).
    travel_m: f64,
}

impl DriveWheel {
    pub fn new(gain_mps_per_v: f64, tau_s: f64, deadband_v: f64, brake_stop_s: f64) -> DriveWheel {
        DriveWheel {
            gain_mps_per_v,
            tau_s,
            deadband_v,
            brake_decel_mps2: BRAKE_REFERENCE_SPEED_MPS / brake_stop_s,
            speed_mps: 0.0,
            travel_m: 0.0,
        }
    }

    pub fn speed_mps(&self) -> f64 {
        self.speed_mps
    }

    pub fn travel_m(&self) -> f64 {
        self.travel_m
    }

    /// The voltage that turns the motor: what is left beyond the dead band.
    fn effective_v(&self, amp_v: f64) -> f64 {
        let beyond_v = amp_v.abs() - self.deadband_v;
        if beyond_v > 0.0 {
            beyond_v.copysign(amp_v)
        } else {
            0.0
        }
    }

    /// Advance dt seconds with `amp_v` at the motor (already 0 V without motor power).
    pub fn step(&mut self, amp_v: f64, brake_on: bool, dt_s: f64) {
        let target_mps = self.gain_mps_per_v * self.effective_v(amp_v);
        // Exact solution of the first-order lag over one step, stable for any dt.
        let alpha = if self.tau_s > 0.0 {
            1.0 - (-dt_s / self.tau_s).exp()
        } else {
            1.0
        };
        let v = self.speed_mps;
        let v_motor = v + (target_mps - v) * alpha;
        let v_new = if !brake_on {
            v_motor
        } else if v_motor * v <= 0.0 {
            // Stopped, or the motor alone brings it through zero: the brake holds it at rest.
            0.0
        } else {
            let v_brake = v - (self.brake_decel_mps2 * dt_s).min(v.abs()).copysign(v);
            if v_motor.abs() < v_brake.abs() {
                v_motor
            } else {
                v_brake
            }
        };
        // Trapezoidal travel: the encoder sees the mean speed over the step.
        self.travel_m += 0.5 * (v + v_new) * dt_s;
        self.speed_mps = v_new;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(wheel: &mut DriveWheel, amp_v: f64, brake_on: bool, t_s: f64) {
        for _ in 0..(t_s / 0.001).round() as usize {
            wheel.step(amp_v, brake_on, 0.001);
        }
    }

    #[test]
    fn reaches_gain_times_voltage_beyond_the_dead_band() {
        let mut wheel = DriveWheel::new(0.12, 0.1, 0.3, 0.3);
        run(&mut wheel, 5.0, false, 1.0);
        assert!(
            (wheel.speed_mps() - 0.12 * 4.7).abs() < 1e-4,
            "{}",
            wheel.speed_mps()
        );
        run(&mut wheel, -5.0, false, 1.5);
        assert!((wheel.speed_mps() + 0.12 * 4.7).abs() < 1e-4);
    }

    #[test]
    fn time_constant_is_tau() {
        let mut wheel = DriveWheel::new(0.12, 0.1, 0.3, 0.3);
        run(&mut wheel, 10.3, false, 0.1);
        // After one time constant: 63.2 % of the final 1.2 m/s.
        assert!(
            (wheel.speed_mps() - 1.2 * 0.632).abs() < 0.002,
            "{}",
            wheel.speed_mps()
        );
    }

    #[test]
    fn inside_the_dead_band_the_wheel_does_not_move() {
        let mut wheel = DriveWheel::new(0.12, 0.1, 0.3, 0.3);
        run(&mut wheel, 0.29, false, 1.0);
        assert_eq!(wheel.speed_mps(), 0.0);
        assert_eq!(wheel.travel_m(), 0.0);
    }

    #[test]
    fn brake_stops_from_full_speed_within_0_3_s_even_against_the_motor() {
        let mut wheel = DriveWheel::new(0.12, 0.1, 0.3, 0.3);
        run(&mut wheel, 10.0, false, 1.5);
        assert!(wheel.speed_mps() > 1.1);
        run(&mut wheel, 10.0, true, 0.3);
        assert_eq!(wheel.speed_mps(), 0.0);
        let parked_m = wheel.travel_m();
        run(&mut wheel, 10.0, true, 1.0);
        assert_eq!(wheel.travel_m(), parked_m, "a braked wheel stays put");
    }

    #[test]
    fn travel_integrates_speed() {
        let mut wheel = DriveWheel::new(0.12, 0.1, 0.3, 0.3);
        run(&mut wheel, 5.3, false, 3.0);
        // Final speed 0.6 m/s; a first-order lag lags the ramp by tau: 0.6*(3 - 0.1).
        assert!(
            (wheel.travel_m() - 0.6 * 2.9).abs() < 0.002,
            "{}",
            wheel.travel_m()
        );
    }
}
