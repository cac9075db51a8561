//! Tests of a row in the local frame and of the projection that gives cross-track
//! error: beside a straight row, on an arc against the analytic circle, at a corner,
//! beyond both ends, with a hint far off, the sign of the offset and the curvature.

use std::f64::consts::FRAC_PI_2;

use super::*;
use crate::gnss::rowmap::test_rows::{arc_m, field_frame, row_from_m};
use mechweed_hw::geo::Enu;

const RADIUS_M: f64 = 20.0;

fn local(points_m: &[(f64, f64)]) -> LocalRow {
    let frame = field_frame();
    LocalRow::new(&row_from_m(&frame, "test", points_m), &frame).expect("a good row")
}

fn straight_east() -> LocalRow {
    let points: Vec<(f64, f64)> = (0..=20).map(|i| (f64::from(i), 0.0)).collect();
    local(&points)
}

fn arc() -> LocalRow {
    local(&arc_m(RADIUS_M, 0.25, 30.0))
}

fn foot(row: &LocalRow, east_m: f64, north_m: f64, hint: &mut usize) -> Foot {
    row.project(east_m, north_m, hint).expect("a finite point")
}

#[test]
fn beside_a_straight_row_gives_arclength_offset_and_heading() {
    let row = straight_east();
    assert!((row.length_m() - 20.0).abs() < 1e-6);
    let mut hint = 0;
    let left = foot(&row, 7.3, 0.2, &mut hint);
    assert!((left.s_m - 7.3).abs() < 1e-6, "s {}", left.s_m);
    assert!(
        (left.offset_m - 0.2).abs() < 1e-6,
        "offset {}",
        left.offset_m
    );
    assert!(left.heading_rad.abs() < 1e-6);
    assert!(left.curvature_per_m.abs() < 1e-6);
    assert_eq!(hint, 7, "the hint follows the point");
    let right = foot(&row, 7.6, -0.15, &mut hint);
    assert!(
        (right.offset_m + 0.15).abs() < 1e-6,
        "offset {}",
        right.offset_m
    );
}

#[test]
fn left_is_positive_looking_along_the_row_whichever_way_it_runs() {
    // Driven west: north of the row is on the right.
    let points: Vec<(f64, f64)> = (0..=10).rev().map(|i| (f64::from(i), 0.0)).collect();
    let row = local(&points);
    let north = foot(&row, 4.0, 0.3, &mut 0);
    assert!(
        (north.offset_m + 0.3).abs() < 1e-6,
        "offset {}",
        north.offset_m
    );
    assert!((north.s_m - 6.0).abs() < 1e-6);
    assert!((north.heading_rad.abs() - std::f64::consts::PI).abs() < 1e-6);
    let south = foot(&row, 4.0, -0.3, &mut 0);
    assert!(
        (south.offset_m - 0.3).abs() < 1e-6,
        "offset {}",
        south.offset_m
    );
}

#[test]
fn on_an_arc_the_offset_matches_the_circle_within_a_millimetre() {
    let row = arc();
    let mut checked = 0;
    // Walk along the arc in 10 cm steps at several distances from it, keeping the hint
    // as the robot would.
    for offset_m in [-0.5, -0.1, 0.0, 0.05, 0.3] {
        let mut hint = 0;
        for step in 0..=300 {
            let angle_rad = f64::from(step) * 0.1 / RADIUS_M;
            let r_m = RADIUS_M - offset_m;
            let (east_m, north_m) = (r_m * angle_rad.sin(), RADIUS_M - r_m * angle_rad.cos());
            let f = foot(&row, east_m, north_m, &mut hint);
            assert!(
                (f.offset_m - offset_m).abs() < 1e-3,
                "at {angle_rad} rad, {offset_m} m off: offset {}",
                f.offset_m
            );
            // A chord's direction is off the tangent by up to half a point's turn
            // (0.00625 rad), which moves the foot of a point beside it along the row.
            let s_tolerance_m = 2e-3 + offset_m.abs() * 0.007;
            assert!(
                (f.s_m - RADIUS_M * angle_rad).abs() < s_tolerance_m,
                "s {}",
                f.s_m
            );
            assert!(
                (f.heading_rad - angle_rad).abs() < 0.007,
                "heading {}",
                f.heading_rad
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 5 * 301);
}

#[test]
fn curvature_of_a_20_m_arc_is_a_twentieth_per_metre() {
    let row = arc();
    for s_m in [1.0, 5.0, 12.5, 29.0] {
        let angle_rad = s_m / RADIUS_M;
        let (east_m, north_m) = (
            RADIUS_M * angle_rad.sin(),
            RADIUS_M * (1.0 - angle_rad.cos()),
        );
        let f = foot(&row, east_m, north_m, &mut 0);
        assert!(
            (f.curvature_per_m - 0.05).abs() < 1e-3,
            "at {s_m} m: {}",
            f.curvature_per_m
        );
    }
    // Mirrored, the arc turns right: negative.
    let mirrored: Vec<(f64, f64)> = arc_m(RADIUS_M, 0.25, 30.0)
        .iter()
        .map(|p| (p.0, -p.1))
        .collect();
    let f = foot(&local(&mirrored), 9.6, -2.4, &mut 0);
    assert!(
        (f.curvature_per_m + 0.05).abs() < 1e-3,
        "{}",
        f.curvature_per_m
    );
}

#[test]
fn at_a_corner_the_nearer_segment_wins() {
    // East 10 m, then a left turn to the north.
    let row = local(&[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)]);
    for hint in [0, 1] {
        let inside_first = foot(&row, 9.0, 0.5, &mut { hint });
        assert!((inside_first.s_m - 9.0).abs() < 1e-6);
        assert!((inside_first.offset_m - 0.5).abs() < 1e-6);
        assert!(inside_first.heading_rad.abs() < 1e-6);
        let inside_second = foot(&row, 9.5, 1.0, &mut { hint });
        assert!((inside_second.s_m - 11.0).abs() < 1e-6);
        assert!((inside_second.offset_m - 0.5).abs() < 1e-6);
        assert!((inside_second.heading_rad - FRAC_PI_2).abs() < 1e-6);
        // Outside the corner the nearest point is the corner itself, on the right.
        let outside = foot(&row, 11.0, -1.0, &mut { hint });
        assert!((outside.s_m - 10.0).abs() < 1e-6);
        assert!(
            (outside.offset_m + 2f64.sqrt()).abs() < 1e-6,
            "{}",
            outside.offset_m
        );
    }
    // Round the outside of the corner the offset does not jump.
    let mut hint = 0;
    let mut before_m = foot(&row, 9.0, -0.5, &mut hint).offset_m;
    for step in 0..=100 {
        let angle_rad = -FRAC_PI_2 + f64::from(step) / 100.0 * FRAC_PI_2;
        let now_m = foot(
            &row,
            10.0 + 0.5 * angle_rad.cos(),
            0.5 * angle_rad.sin(),
            &mut hint,
        )
        .offset_m;
        assert!(
            (now_m - before_m).abs() < 0.02 && (now_m + 0.5).abs() < 1e-6,
            "{now_m}"
        );
        before_m = now_m;
    }
}

#[test]
fn before_the_start_and_past_the_end_the_line_goes_on_straight() {
    let row = straight_east();
    let before = foot(&row, -3.0, 0.4, &mut 5);
    assert!((before.s_m + 3.0).abs() < 1e-6, "s {}", before.s_m);
    assert!((before.offset_m - 0.4).abs() < 1e-6);
    let past = foot(&row, 23.5, -0.2, &mut 5);
    assert!((past.s_m - 23.5).abs() < 1e-6, "s {}", past.s_m);
    assert!((past.offset_m + 0.2).abs() < 1e-6);
    assert!(past.curvature_per_m.abs() < 1e-9);
}

#[test]
fn a_hint_far_off_still_finds_the_nearest_segment() {
    let row = arc();
    let angle_rad = 27.1 / RADIUS_M;
    let (east_m, north_m) = (19.9 * angle_rad.sin(), RADIUS_M - 19.9 * angle_rad.cos());
    for start in [0, 3, usize::MAX] {
        let mut hint = start;
        let f = foot(&row, east_m, north_m, &mut hint);
        assert!(
            (f.s_m - 27.1).abs() < 2e-3,
            "from hint {start}: s {}",
            f.s_m
        );
        assert!((f.offset_m - 0.1).abs() < 1e-3);
        assert_eq!(hint, 108, "27.1 m along 0.25 m segments");
    }
    assert_eq!(
        foot(&row, east_m, north_m, &mut 0),
        row.project_scan(east_m, north_m).expect("finite")
    );
}

#[test]
fn a_point_that_is_not_a_number_has_no_foot() {
    let row = straight_east();
    let mut hint = 4;
    assert_eq!(row.project(f64::NAN, 0.0, &mut hint), None);
    assert_eq!(row.project(0.0, f64::INFINITY, &mut hint), None);
    assert_eq!(hint, 4, "the hint is kept");
}

#[test]
fn the_map_sits_at_the_frames_height_as_the_gnss_positions_do() {
    // A position 40 m east at the field's height, as the receiver gives it with its
    // height, lies on a row drawn through the same latitude and longitude.
    let frame = field_frame();
    let row = local(&[(0.0, 0.0), (40.0, 0.0)]);
    let on_row = frame.to_geodetic(Enu {
        east_m: 40.0,
        north_m: 0.0,
        up_m: 0.0,
    });
    let enu = frame.to_enu(on_row);
    let f = foot(&row, enu.east_m, enu.north_m, &mut 0);
    assert!((f.s_m - 40.0).abs() < 1e-4, "s {}", f.s_m);
    assert!(
        (row.length_m() - 40.0).abs() < 1e-4,
        "length {}",
        row.length_m()
    );
}

#[test]
fn a_row_without_two_distinct_points_on_the_earth_is_refused() {
    let frame = field_frame();
    let twice = MapRow {
        name: "7".to_string(),
        points_deg: vec![(48.0, 11.0), (48.0, 11.0)],
    };
    let error = LocalRow::new(&twice, &frame).expect_err("one point twice");
    assert_eq!(
        error.to_string(),
        "row '7': has fewer than 2 distinct points"
    );
    let off = MapRow {
        name: "8".to_string(),
        points_deg: vec![(48.0, 11.0), (91.0, 11.0)],
    };
    let error = LocalRow::new(&off, &frame).expect_err("off the earth");
    assert_eq!(
        error.to_string(),
        "row '8': point 2: latitude 91 is outside -90..90"
    );
}
