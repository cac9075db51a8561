//! The steering law's tests: which way it steers, latency, the integral, the row's bend
//! learnt and held, and a fresh start.

use super::*;
use crate::config::Settings;

impl RowFollower {
    /// The law for `estimate`, which arrived at `arrived_s`, at time `now_s`, the
    /// robot taken to have moved since the image as it moves now.
    fn update(
        &mut self,
        estimate: &RowEstimate,
        arrived_s: f64,
        now_s: f64,
        motion: &Motion,
    ) -> LawOutput {
        let age_s = self.s.latency_s + (now_s - arrived_s).max(0.0);
        let since = Travel::at_rates(motion.speed_mps, motion.yaw_rate_rps, age_s);
        self.update_moved(estimate, since, now_s, motion)
    }
}

/// The shipped law on a robot with a wheelbase of 1.3 m: with the shipped 1 m, a term
/// wrongly multiplied or divided by the wheelbase would not show.
fn follower() -> RowFollower {
    let mut s = Settings::shipped();
    s.robot.wheelbase_m = 1.3;
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

/// 10 m at 1 m/s on a steady left turn of 0.1 rad, the row's image 2 cm to the left.
fn after_a_steady_turn() -> RowFollower {
    let mut law = follower();
    let wheel_angle_rad: f64 = 0.1;
    let turning = Motion {
        speed_mps: 1.0,
        wheel_angle_rad,
        yaw_rate_rps: wheel_angle_rad.tan() / law.wheelbase_m,
    };
    let still = Travel::default();
    for k in 0..100 {
        let t = k as f64 * 0.1;
        law.update_moved(&estimate(0.0, 0.02), still, t, &turning);
    }
    law
}

#[test]
fn on_a_steady_turn_the_row_bends_as_the_robots_own_path() {
    // Following a row, the robot turns as the row does: the curvature learnt is the
    // path's, tan(wheel angle) / wheelbase, not a scaled one that would leave the
    // tool off the row on every arc.
    let law = after_a_steady_turn();
    let path_per_m = 0.1f64.tan() / law.wheelbase_m;
    let learnt = law.row_curvature_per_m;
    assert!(
        (learnt - path_per_m).abs() < 0.01 * path_per_m,
        "learnt {learnt} 1/m, path {path_per_m} 1/m"
    );
}

#[test]
fn entering_autonomous_forgets_the_last_rows_bend_and_integral() {
    // The last row's curvature and integral, kept into the next row, would steer the
    // robot off a straight row from its first tick.
    let mut law = after_a_steady_turn();
    assert!(law.integral_per_m > 0.0 && law.row_curvature_per_m > 0.0);
    law.reset();
    let standing = Motion::default();
    let out = law.update_moved(&estimate(0.0, 0.0), Travel::default(), 60.0, &standing);
    assert_eq!(out.wheel_angle_rad, 0.0, "{out:?}");
    assert_eq!((out.integral_per_m, out.row_curvature_per_m), (0.0, 0.0));
}

#[test]
fn the_row_seen_before_an_arc_is_moved_into_the_robots_frame_as_the_arc_moved_it() {
    // Since the image the robot drove 1 m and turned 0.4 rad, and the row point seen
    // was 0.5 m to the side: far more than over one latency (0.1 m), so that every term
    // of the move shows. The row seen then, in the robot's frame now, is where the exact
    // geometry of the arc puts it. The law takes the chord as long as the arc: 8 mm off
    // here, 0.01 mm over a real latency; a wrong term is 37 mm off or more.
    let mut law = follower();
    let (moved_m, turned_rad, offset_m) = (1.0, 0.4, 0.5);
    let angle_rad = turned_rad + std::f64::consts::FRAC_PI_4;
    let since = Travel {
        travelled_m: moved_m,
        turned_rad,
    };
    let standing = Motion::default();
    let out = law.update_moved(&estimate(angle_rad, offset_m), since, 0.0, &standing);

    // Where the arc took the robot, in the image's frame, and the camera's row point
    // seen from there.
    let radius_m = moved_m / turned_rad;
    let (x_m, y_m) = (
        radius_m * turned_rad.sin(),
        radius_m * (1.0 - turned_rad.cos()),
    );
    let (dx, dy) = (law.camera_x_m - x_m, offset_m - y_m);
    let (sin, cos) = turned_rad.sin_cos();
    let (point_x, point_y) = (dx * cos + dy * sin, -dx * sin + dy * cos);
    let expected_m = point_y + (angle_rad - turned_rad).tan() * (law.s.lookahead_m - point_x);
    let error_m = out.lookahead_offset_m - expected_m;
    assert!(error_m.abs() < 0.015, "{:.1} mm off", error_m * 1e3);
}

#[test]
fn pure_pursuit_steers_along_the_circle_through_the_look_ahead_point() {
    // A straight row, parallel, 10 cm to the left: the circle from the rear axle through
    // the row point at the look-ahead distance has curvature 2 y / (x^2 + y^2), and a
    // wheel angle of atan(wheelbase * curvature) drives it.
    let mut law = follower();
    let offset_m = 0.1;
    let out = law.update_moved(
        &estimate(0.0, offset_m),
        Travel::default(),
        0.0,
        &Motion::default(),
    );
    let x_m = law.s.lookahead_m;
    let curvature_per_m = 2.0 * offset_m / (x_m * x_m + offset_m * offset_m);
    let expected_rad = (law.wheelbase_m * curvature_per_m).atan();
    assert!(
        expected_rad < law.max_wheel_angle_rad,
        "beyond the steering's limit"
    );
    assert!((out.lookahead_offset_m - offset_m).abs() < 1e-12);
    assert!(
        (out.wheel_angle_rad - expected_rad).abs() < 1e-9,
        "{} rad, expected {expected_rad} rad",
        out.wheel_angle_rad
    );
}

#[test]
fn the_integral_adds_no_more_than_its_limit_of_wheel_angle() {
    // The tool 2 cm off for 100 m (a slope no crab could explain): the integral stops at
    // integral_max_deg of wheel angle, so that a wrong row cannot wind the steering up.
    let mut law = follower();
    let driving = Motion {
        speed_mps: 1.0,
        ..Motion::default()
    };
    for k in 0..1000 {
        law.update_moved(
            &estimate(0.0, 0.02),
            Travel::default(),
            k as f64 * 0.1,
            &driving,
        );
    }
    let integral_deg = (law.integral_per_m * law.wheelbase_m).atan().to_degrees();
    let limit_deg = law.s.integral_max_deg;
    assert!(
        (integral_deg - limit_deg).abs() < 1e-9,
        "{integral_deg} deg, limit {limit_deg} deg"
    );
}
