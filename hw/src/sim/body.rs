//! The robot's body: a kinematic bicycle about the rear axle centre (the simulated plant).
//!
//! Speed is the mean of the two rear wheels; the heading turns at v*tan(delta)/L. A
//! difference between the wheels that Ackermann geometry does not ask for is taken up
//! by the tyres slipping, not by extra turning. The side slope makes the body move at
//! `slip` to the side of its heading.

/// Position of the rear axle centre in the field frame, and the heading.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Pose {
    pub x_m: f64,
    pub y_m: f64,
    /// Counter-clockwise from +x, not wrapped (so it can be plotted without jumps).
    pub heading_rad: f64,
}

impl Pose {
    /// A point `ahead_m` in front of the rear axle centre along the heading (negative: behind).
    pub(crate) fn point_ahead(&self, ahead_m: f64) -> (f64, f64) {
        (
            self.x_m + ahead_m * self.heading_rad.cos(),
            self.y_m + ahead_m * self.heading_rad.sin(),
        )
    }

    /// Advance dt seconds at speed v with the front wheel at `wheel_angle_rad`.
    pub fn step(
        &mut self,
        speed_mps: f64,
        wheel_angle_rad: f64,
        wheelbase_m: f64,
        slip_rad: f64,
        dt_s: f64,
    ) {
        let turn_rad = speed_mps * wheel_angle_rad.tan() / wheelbase_m * dt_s;
        // Move along the mean heading of the step (midpoint rule: second order on arcs).
        let course_rad = self.heading_rad + 0.5 * turn_rad + slip_rad;
        self.x_m += speed_mps * course_rad.cos() * dt_s;
        self.y_m += speed_mps * course_rad.sin() * dt_s;
        self.heading_rad += turn_rad;
    }
}

impl Pose {
    /// A bump: the heading turns by `heading_rad` and the body moves `side_m` to its
    /// left at once.
    pub fn kick(&mut self, heading_rad: f64, side_m: f64) {
        self.x_m -= side_m * self.heading_rad.sin();
        self.y_m += side_m * self.heading_rad.cos();
        self.heading_rad += heading_rad;
    }
}

/// Angle wrapped to [-pi, pi).
pub(crate) fn wrap_rad(angle_rad: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    (angle_rad + PI).rem_euclid(TAU) - PI
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive(pose: &mut Pose, v: f64, delta: f64, slip: f64, t_s: f64) {
        for _ in 0..(t_s / 0.001).round() as usize {
            pose.step(v, delta, 1.0, slip, 0.001);
        }
    }

    #[test]
    fn drives_a_circle_of_radius_l_over_tan_delta() {
        let mut pose = Pose::default();
        let delta = 0.1f64;
        let radius_m = 1.0 / delta.tan();
        let t_half = std::f64::consts::PI * radius_m / 0.5;
        drive(&mut pose, 0.5, delta, 0.0, t_half);
        // Half a turn to the left ends 2R to the left, heading back.
        assert!(pose.x_m.abs() < 1e-3, "{pose:?}");
        assert!((pose.y_m - 2.0 * radius_m).abs() < 1e-3, "{pose:?}");
        assert!((pose.heading_rad - std::f64::consts::PI).abs() < 1e-3);
    }

    #[test]
    fn side_slip_moves_sideways_without_turning() {
        let mut pose = Pose::default();
        drive(&mut pose, 1.0, 0.0, 1f64.to_radians(), 10.0);
        assert_eq!(pose.heading_rad, 0.0);
        assert!((pose.y_m - 10.0 * 1f64.to_radians().sin()).abs() < 1e-9);
        let tool = pose.point_ahead(-0.4);
        assert!((tool.0 - (pose.x_m - 0.4)).abs() < 1e-12);
    }

    #[test]
    fn wrap_keeps_angles_in_range() {
        assert!((wrap_rad(3.0 * std::f64::consts::PI) + std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_rad(-0.1) + 0.1).abs() < 1e-15);
        assert!(wrap_rad(f64::NAN).is_nan());
    }
}
