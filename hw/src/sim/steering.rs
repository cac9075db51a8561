//! The steered front wheel: steering voltage -> wheel angle, with its sensors.
//!
//! the simulated plant: the angle moves at a rate proportional to the voltage (6 deg/s per V),
//! through a first-order lag of 0.05 s on that rate, and stops hard at +-30 deg. The
//! end switches close beyond +-28 deg; the potentiometer gives the absolute angle,
//! the motor's encoder the angle relative to where it was at power-up.

use crate::Side;

/// Potentiometer: 2.5 V at straight ahead, 2 V per 30 deg (0.5 V at -30, 4.5 V at +30).
pub(crate) const POT_CENTRE_V: f64 = 2.5;
pub(crate) const POT_V_PER_DEG: f64 = 2.0 / 30.0;

#[derive(Debug, Clone)]
pub(crate) struct Steering {
    rate_dps_per_v: f64,
    lag_s: f64,
    limit_deg: f64,
    end_switch_deg: f64,
    angle_deg: f64,
    rate_dps: f64,
}

impl Steering {
    pub fn new(
        rate_dps_per_v: f64,
        lag_s: f64,
        limit_deg: f64,
        end_switch_deg: f64,
        angle_deg: f64,
    ) -> Steering {
        Steering {
            rate_dps_per_v,
            lag_s,
            limit_deg,
            end_switch_deg,
            angle_deg: angle_deg.clamp(-limit_deg, limit_deg),
            rate_dps: 0.0,
        }
    }

    pub fn angle_deg(&self) -> f64 {
        self.angle_deg
    }

    pub fn angle_rad(&self) -> f64 {
        self.angle_deg.to_radians()
    }

    /// Advance dt seconds with `amp_v` at the motor (already 0 V without motor power).
    pub fn step(&mut self, amp_v: f64, dt_s: f64) {
        let commanded_dps = self.rate_dps_per_v * amp_v;
        let alpha = if self.lag_s > 0.0 {
            1.0 - (-dt_s / self.lag_s).exp()
        } else {
            1.0
        };
        self.rate_dps += (commanded_dps - self.rate_dps) * alpha;
        self.angle_deg += self.rate_dps * dt_s;
        // The mechanical stop: the wheel stops dead, so the rate is gone too.
        if self.angle_deg >= self.limit_deg && self.rate_dps >= 0.0 {
            self.angle_deg = self.limit_deg;
            self.rate_dps = 0.0;
        } else if self.angle_deg <= -self.limit_deg && self.rate_dps <= 0.0 {
            self.angle_deg = -self.limit_deg;
            self.rate_dps = 0.0;
        }
    }

    /// A stone kicks the wheel just past that side's end switch (left = positive angle).
    pub fn kick(&mut self, side: Side) {
        let beyond_deg = (self.end_switch_deg + 1.0).min(self.limit_deg);
        self.angle_deg = match side {
            Side::Left => beyond_deg,
            Side::Right => -beyond_deg,
        };
        self.rate_dps = 0.0;
    }

    pub fn end_switch_left(&self) -> bool {
        self.angle_deg > self.end_switch_deg
    }

    pub fn end_switch_right(&self) -> bool {
        self.angle_deg < -self.end_switch_deg
    }

    /// Potentiometer voltage without noise.
    pub fn pot_v(&self) -> f64 {
        POT_CENTRE_V + self.angle_deg * POT_V_PER_DEG
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steering() -> Steering {
        Steering::new(6.0, 0.05, 30.0, 28.0, 0.0)
    }

    fn run(s: &mut Steering, amp_v: f64, t_s: f64) {
        for _ in 0..(t_s / 0.001).round() as usize {
            s.step(amp_v, 0.001);
        }
    }

    #[test]
    fn rate_is_proportional_to_voltage_after_the_lag() {
        let mut s = steering();
        run(&mut s, 2.0, 1.0);
        // 12 deg/s for 1 s, less the 0.05 s lag.
        assert!(
            (s.angle_deg() - 12.0 * 0.95).abs() < 0.01,
            "{}",
            s.angle_deg()
        );
    }

    #[test]
    fn stops_at_the_limit_and_end_switch_closes_beyond_28_deg() {
        let mut s = steering();
        // 6 deg/s: 27.3 deg after 4.6 s, switch still open; 28.5 deg after 4.8 s, closed.
        run(&mut s, 1.0, 4.6);
        assert!(
            (s.angle_deg() - 27.3).abs() < 0.01 && !s.end_switch_left(),
            "{}",
            s.angle_deg()
        );
        run(&mut s, 1.0, 0.2);
        assert!(s.end_switch_left());
        run(&mut s, 10.0, 2.0);
        assert_eq!(s.angle_deg(), 30.0);
        assert!(s.end_switch_left() && !s.end_switch_right());
        // It leaves the stop as soon as it is driven the other way (no wind-up).
        run(&mut s, -10.0, 0.1);
        assert!(s.angle_deg() < 30.0 - 2.0);
        run(&mut s, -10.0, 20.0);
        assert_eq!(s.angle_deg(), -30.0);
        assert!(s.end_switch_right() && !s.end_switch_left());
    }

    #[test]
    fn pot_maps_half_a_volt_to_four_and_a_half() {
        let mut s = steering();
        assert_eq!(s.pot_v(), 2.5);
        run(&mut s, -10.0, 10.0);
        assert!((s.pot_v() - 0.5).abs() < 1e-12);
        run(&mut s, 10.0, 10.0);
        assert!((s.pot_v() - 4.5).abs() < 1e-12);
    }

    #[test]
    fn a_kick_closes_that_sides_switch() {
        let mut s = steering();
        s.kick(Side::Right);
        assert_eq!(s.angle_deg(), -29.0);
        assert!(s.end_switch_right());
        s.kick(Side::Left);
        assert!(s.end_switch_left());
    }
}
