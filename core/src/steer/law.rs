//! The steering law (pure pursuit): from a row line's angle and offset at the camera's
//! point (the row filter's) to a front wheel angle.
//!
//! 1. Latency. Each estimate describes an image taken about `latency_s` before it
//!    arrived, and it ages further until the next one. By the robot's motion since
//!    (from odometry, or the measured speed and heading rate times the age), the row
//!    line seen then is moved into the robot's frame now.
//! 2. Row model. Near the robot the row is a parabola in the robot frame (x forward,
//!    y left): y(x) = y0 + tan(angle) (x - x0) + curvature/2 (x - x0)^2, through the
//!    camera's point (x0, y0). The curvature is the robot's own path curvature smoothed
//!    over `curvature_filter_m` of travel: following a row, the robot turns as the row does.
//!    (A gap in the row does not reach the law: the row filter carries the row through
//!    it by odometry, sources.rs.)
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

use super::filter::Travel;
use crate::config::{RobotSettings, SteerSettings};

/// What the robot's own motion says, from the supervisor's measurements.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Motion {
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
pub(crate) struct RowFollower {
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

    /// The wheel angle for `estimate` of an image taken where the robot stood before it
    /// drove and turned `since`, at time `now_s`.
    pub(crate) fn update_moved(
        &mut self,
        estimate: &RowEstimate,
        since: Travel,
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
        let (moved_m, turned_rad) = (since.travelled_m, since.turned_rad);
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
#[path = "law_tests.rs"]
mod tests;
