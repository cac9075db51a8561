//! The steering law: from the camera's row angle and offset to a front wheel angle.
//!
//! 1. Latency. Each estimate describes an image taken about `latency_s` before it
//!    arrived, and it ages further until the next one. Using the measured speed and
//!    heading rate, the row line seen then is moved into the robot's frame now.
//! 2. Row model. Near the robot the row is a parabola in the robot frame (x forward,
//!    y left): y(x) = y0 + tan(angle) (x - x0) + curvature/2 (x - x0)^2, through the
//!    camera's point (x0, y0). The curvature is the robot's own path curvature smoothed
//!    over `curvature_filter_m` of travel: following a row, the robot turns as the row does.
//! 3. Pure pursuit. Steer along the circle that passes through the row point
//!    `lookahead_m` ahead of the rear axle: curvature = 2 y / d^2 (d the distance to the
//!    point). Linearised, the lateral error then behaves as a second-order system with
//!    damping 0.71 at every speed, and its time constant is lookahead / speed; on an arc
//!    the circle is exact, so pure pursuit holds an arc by itself.
//! 4. Integral on the tool point. A side slope makes the robot crab: pure pursuit then
//!    settles with the tool off the row. The row's offset at the weeding tool, integrated
//!    over distance driven (not time, so the gain means the same at every speed), adds a
//!    curvature that removes it. It is limited to `integral_max_deg` of wheel angle.

use mechweed_hw::camproto::RowEstimate;

use crate::config::{RobotSettings, SteerSettings};

/// What the robot's own motion says, from the supervisor's measurements.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Motion {
    pub speed_mps: f64,
    pub yaw_rate_rps: f64,
    pub wheel_angle_rad: f64,
}

/// The law's result and the quantities behind it (for plots and records).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LawOutput {
    pub wheel_angle_rad: f64,
    /// Row offset at the look-ahead point, now, m (positive: row to the left).
    pub lookahead_offset_m: f64,
    /// Row offset at the weeding tool, now, m.
    pub tool_offset_m: f64,
    /// Row curvature used, 1/m (positive: turning left).
    pub row_curvature_per_m: f64,
    /// Curvature added by the integral, 1/m.
    pub integral_per_m: f64,
}

#[derive(Debug, Clone)]
pub struct RowFollower {
    s: SteerSettings,
    wheelbase_m: f64,
    max_wheel_angle_rad: f64,
    camera_x_m: f64,
    tool_x_m: f64,
    row_curvature_per_m: f64,
    integral_per_m: f64,
    last_t_s: Option<f64>,
}

impl RowFollower {
    pub fn new(s: &SteerSettings, robot: &RobotSettings) -> RowFollower {
        RowFollower {
            s: *s,
            wheelbase_m: robot.wheelbase_m,
            max_wheel_angle_rad: robot.max_wheel_angle_deg.to_radians(),
            camera_x_m: robot.camera_lookahead_m,
            tool_x_m: robot.tool_offset_m,
            row_curvature_per_m: 0.0,
            integral_per_m: 0.0,
            last_t_s: None,
        }
    }

    /// Start afresh (entering autonomous mode).
    pub fn reset(&mut self) {
        self.row_curvature_per_m = 0.0;
        self.integral_per_m = 0.0;
        self.last_t_s = None;
    }

    /// The wheel angle for `estimate`, which arrived at `arrived_s`, at time `now_s`.
    pub fn update(
        &mut self,
        estimate: &RowEstimate,
        arrived_s: f64,
        now_s: f64,
        motion: &Motion,
    ) -> LawOutput {
        let age_s = self.s.latency_s + (now_s - arrived_s).max(0.0);
        self.update_aged(estimate, age_s, now_s, motion)
    }

    /// The wheel angle for `estimate` of an image taken `age_s` ago, at time `now_s`
    /// (the row filter's row goes in as old as a camera row on average: sources.rs).
    pub fn update_aged(
        &mut self,
        estimate: &RowEstimate,
        age_s: f64,
        now_s: f64,
        motion: &Motion,
    ) -> LawOutput {
        let dt_s = self.last_t_s.map_or(0.0, |t| (now_s - t).max(0.0));
        self.last_t_s = Some(now_s);
        let travelled_m = motion.speed_mps.abs() * dt_s;

        // 2. The row turns as the robot does when the robot follows it.
        let robot_curvature = motion.wheel_angle_rad.tan() / self.wheelbase_m;
        let blend = (travelled_m / self.s.curvature_filter_m).min(1.0);
        self.row_curvature_per_m += (robot_curvature - self.row_curvature_per_m) * blend;

        // 1. Move the row line seen in the image into the robot's frame now.
        let moved_m = motion.speed_mps * age_s;
        let turned_rad = motion.yaw_rate_rps * age_s;
        let (robot_x, robot_y) = (
            moved_m * (turned_rad / 2.0).cos(),
            moved_m * (turned_rad / 2.0).sin(),
        );
        let (dx, dy) = (self.camera_x_m - robot_x, estimate.offset_m - robot_y);
        let (sin, cos) = turned_rad.sin_cos();
        let point_x = dx * cos + dy * sin;
        let point_y = -dx * sin + dy * cos;
        let slope = (estimate.angle_rad - turned_rad).tan();
        let curvature = self.row_curvature_per_m;
        let row_y_at =
            |x: f64| point_y + slope * (x - point_x) + 0.5 * curvature * (x - point_x).powi(2);

        // 3. Pure pursuit to the look-ahead point.
        let ahead_m = self.s.lookahead_m;
        let lookahead_offset_m = row_y_at(ahead_m);
        let pursuit = 2.0 * lookahead_offset_m
            / (ahead_m * ahead_m + lookahead_offset_m * lookahead_offset_m);

        // 4. Integral of the tool's offset over distance, limited.
        let tool_offset_m = row_y_at(self.tool_x_m);
        let limit = self.s.integral_max_deg.to_radians().tan() / self.wheelbase_m;
        self.integral_per_m = (self.integral_per_m
            + self.s.ki_per_m2 * tool_offset_m * travelled_m)
            .clamp(-limit, limit);

        let wheel_angle_rad = ((pursuit + self.integral_per_m) * self.wheelbase_m)
            .atan()
            .clamp(-self.max_wheel_angle_rad, self.max_wheel_angle_rad);
        LawOutput {
            wheel_angle_rad,
            lookahead_offset_m,
            tool_offset_m,
            row_curvature_per_m: curvature,
            integral_per_m: self.integral_per_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    fn follower() -> RowFollower {
        let s = Settings::shipped();
        RowFollower::new(&s.steer, &s.robot)
    }

    fn estimate(angle_rad: f64, offset_m: f64) -> RowEstimate {
        RowEstimate {
            seq: 0,
            angle_rad,
            offset_m,
            quality: 90,
        }
    }

    #[test]
    fn steers_towards_the_row() {
        let mut law = follower();
        let standing = Motion::default();
        let left = law.update(&estimate(0.0, 0.05), 0.0, 0.0, &standing);
        assert!(
            left.wheel_angle_rad > 0.0,
            "row to the left must steer left"
        );
        let right = law.update(&estimate(0.0, -0.05), 0.0, 0.0, &standing);
        assert!(
            right.wheel_angle_rad < 0.0,
            "row to the right must steer right"
        );
    }

    #[test]
    fn latency_is_compensated_with_the_robots_own_motion() {
        // The robot drives straight at 1 m/s, the row is straight and 5 cm to its left
        // but heads 0.05 rad to the left: in the 0.1 s since the image the row point
        // at the look-ahead has moved 0.1 m * 0.05 = 5 mm further left.
        let mut law = follower();
        let motion = Motion {
            speed_mps: 1.0,
            ..Motion::default()
        };
        let out = law.update(&estimate(0.05, 0.05), 1.0, 1.0, &motion);
        let expected = 0.05 + 0.05f64.tan() * 0.1;
        assert!((out.lookahead_offset_m - expected).abs() < 1e-4, "{out:?}");
    }

    #[test]
    fn integral_grows_with_distance_not_time() {
        let mut standing = follower();
        let mut moving = follower();
        let est = estimate(0.0, 0.02);
        for k in 0..20 {
            let t = k as f64 * 0.1;
            standing.update(&est, t, t, &Motion::default());
            moving.update(
                &est,
                t,
                t,
                &Motion {
                    speed_mps: 0.5,
                    ..Motion::default()
                },
            );
        }
        assert_eq!(standing.integral_per_m, 0.0);
        assert!(moving.integral_per_m > 0.0);
    }
}
