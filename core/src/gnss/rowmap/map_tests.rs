//! Tests of choosing the row the robot is on among parallel rows, and of putting a
//! whole map in the local frame.

use super::*;
use crate::gnss::rowmap::test_rows::{field_frame, row_from_m};

const ROW_SPACING_M: f64 = 0.75;

/// Three rows 30 m long running east, 0.75 m apart, named 1 to 3 from the south.
fn three_rows() -> LocalMap {
    let frame = field_frame();
    let rows = (0..3)
        .map(|i| {
            let north_m = f64::from(i) * ROW_SPACING_M;
            let points: Vec<(f64, f64)> = (0..=60).map(|k| (f64::from(k) * 0.5, north_m)).collect();
            row_from_m(&frame, &(i + 1).to_string(), &points)
        })
        .collect();
    RowMap { rows }.to_local(&frame).expect("good rows")
}

#[test]
fn nearest_row_picks_the_row_the_point_is_beside() {
    let map = three_rows();
    let (index, foot) = map.nearest_row(10.0, 0.9).expect("beside the rows");
    assert_eq!(index, 1);
    assert_eq!(map.rows[index].name(), "2");
    assert!((foot.offset_m - 0.15).abs() < 1e-6, "{}", foot.offset_m);
    assert!((foot.s_m - 10.0).abs() < 1e-6);
    // Past the middle between rows 2 and 3: row 3, on its right.
    let (index, foot) = map.nearest_row(20.0, 1.2).expect("beside the rows");
    assert_eq!(index, 2);
    assert!((foot.offset_m + 0.3).abs() < 1e-6, "{}", foot.offset_m);
    let (index, _) = map.nearest_row(5.0, -0.3).expect("south of row 1");
    assert_eq!(index, 0);
}

#[test]
fn nearest_row_allows_a_margin_at_the_ends_and_no_more() {
    let map = three_rows();
    let (index, foot) = map.nearest_row(-0.5, 0.8).expect("lining up before row 2");
    assert_eq!(index, 1);
    assert!((foot.s_m + 0.5).abs() < 1e-6);
    assert!(map.nearest_row(30.9, 0.0).is_some());
    assert_eq!(map.nearest_row(-1.5, 0.75), None, "in the headland");
    assert_eq!(map.nearest_row(31.5, 0.75), None, "past the rows' ends");
    assert_eq!(map.nearest_row(f64::NAN, 0.75), None);
}

#[test]
fn a_map_with_a_bad_row_names_it() {
    let frame = field_frame();
    let map = RowMap {
        rows: vec![
            row_from_m(&frame, "1", &[(0.0, 0.0), (10.0, 0.0)]),
            MapRow {
                name: "2".to_string(),
                points_deg: vec![(48.0, 11.0)],
            },
        ],
    };
    let error = map.to_local(&frame).expect_err("row 2 has one point");
    assert_eq!(
        error.to_string(),
        "row '2': has fewer than 2 distinct points"
    );
}
