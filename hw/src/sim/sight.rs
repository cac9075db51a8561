//! What the row camera sees: the row's offset and angle at the look-ahead line.
//!
//! the camera link's geometry (function_spec.md section 7) in the robot frame (x forward, y left): follow the robot's
//! lateral line x = look-ahead until it meets the row's centre line; `offset` is the y
//! of that meeting point (positive: the row lies to the left), `angle` the row's heading
//! there relative to the robot's heading (positive: the row turns left).

use super::body::{Pose, wrap_rad};
use super::field::Field;

/// The true row, as the camera would see it without noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RowView {
    pub offset_m: f64,
    pub angle_rad: f64,
    /// Arclength along the row where the look-ahead line meets it, m.
    pub s_m: f64,
}

/// Where the robot's line x = `ahead_m` crosses the row, or None if it does not cross
/// the row's line (before its start or beyond the extra line past its end). `hint` is a
/// point index kept between calls: the search walks from it, O(distance moved).
pub(crate) fn row_at_lookahead(
    field: &Field,
    pose: &Pose,
    ahead_m: f64,
    hint: &mut usize,
) -> Option<RowView> {
    let line = field.centre_line();
    let last = line.len() - 1;
    let (cos_h, sin_h) = (pose.heading_rad.cos(), pose.heading_rad.sin());
    // How far point i lies ahead of the look-ahead line, along the robot's heading.
    let ahead_of_line =
        |i: usize| (line[i].0 - pose.x_m) * cos_h + (line[i].1 - pose.y_m) * sin_h - ahead_m;

    let mut i = (*hint).min(last);
    while i > 0 && ahead_of_line(i) > 0.0 {
        i -= 1;
    }
    if ahead_of_line(i) > 0.0 {
        return None;
    }
    while i < last && ahead_of_line(i + 1) <= 0.0 {
        i += 1;
    }
    if i == last {
        return None;
    }
    *hint = i;
    // Point i is on or behind the line, point i + 1 beyond it: interpolate the crossing.
    let (f0, f1) = (ahead_of_line(i), ahead_of_line(i + 1));
    let t = -f0 / (f1 - f0);
    let seg = field.segment(i);
    let along_m = t * seg.length_m;
    let (qx, qy) = (seg.a.0 + seg.dir.0 * along_m, seg.a.1 + seg.dir.1 * along_m);
    let view = RowView {
        offset_m: -(qx - pose.x_m) * sin_h + (qy - pose.y_m) * cos_h,
        angle_rad: wrap_rad(seg.heading_rad() - pose.heading_rad),
        s_m: seg.s_m + along_m,
    };
    let finite = view.offset_m.is_finite() && view.angle_rad.is_finite() && view.s_m.is_finite();
    finite.then_some(view)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::{RowShape, SimParams};

    fn field(row: RowShape) -> Field {
        Field::new(&SimParams {
            row,
            row_length_m: 30.0,
            ..SimParams::default()
        })
    }

    #[test]
    fn robot_left_of_a_straight_row_sees_it_to_the_right() {
        let f = field(RowShape::Straight);
        let pose = Pose {
            x_m: 3.0,
            y_m: 0.05,
            heading_rad: 0.0,
        };
        let view = row_at_lookahead(&f, &pose, 0.8, &mut 0).unwrap();
        assert!((view.offset_m + 0.05).abs() < 1e-12);
        assert!(view.angle_rad.abs() < 1e-12);
        assert!((view.s_m - 3.8).abs() < 1e-9);
    }

    #[test]
    fn robot_turned_right_sees_the_row_turn_left() {
        let f = field(RowShape::Straight);
        let yaw = -0.1f64;
        let pose = Pose {
            x_m: 5.0,
            y_m: 0.0,
            heading_rad: yaw,
        };
        let view = row_at_lookahead(&f, &pose, 0.8, &mut 900).unwrap();
        assert!((view.angle_rad - 0.1).abs() < 1e-12);
        // The line x_robot = 0.8 meets the row at 0.8/cos(yaw) along it, 0.8*tan(0.1) to the left.
        assert!(
            (view.offset_m - 0.8 * 0.1f64.tan()).abs() < 1e-9,
            "{}",
            view.offset_m
        );
    }

    #[test]
    fn arc_seen_from_its_centre_line() {
        let f = field(RowShape::Arc);
        let r = 20.0;
        let theta = 0.5f64;
        let pose = Pose {
            x_m: r * theta.sin(),
            y_m: r * (1.0 - theta.cos()),
            heading_rad: theta,
        };
        let view = row_at_lookahead(&f, &pose, 0.8, &mut 0).unwrap();
        // The circle meets the line x = 0.8 at y = R - sqrt(R^2 - 0.8^2) to the left.
        let expected_offset = r - (r * r - 0.64f64).sqrt();
        assert!(
            (view.offset_m - expected_offset).abs() < 1e-5,
            "{}",
            view.offset_m
        );
        assert!((view.angle_rad - (0.8f64 / r).asin()).abs() < 1e-3);
    }

    #[test]
    fn no_crossing_past_the_extra_line() {
        let f = field(RowShape::Straight);
        let pose = Pose {
            x_m: 34.5,
            y_m: 0.0,
            heading_rad: 0.0,
        };
        assert!(row_at_lookahead(&f, &pose, 0.8, &mut 0).is_none());
        let nan = Pose {
            x_m: f64::NAN,
            ..pose
        };
        assert!(row_at_lookahead(&f, &nan, 0.8, &mut 0).is_none());
    }
}
