//! GNSS fixes in the row filter, at the pose the receiver measured them.

use super::*;

#[test]
fn a_gnss_fix_is_taken_where_the_robot_was_when_the_receiver_measured_it() {
    // Now: the row 5 cm to the left of the rear axle and 0.02 rad to the left ahead, no
    // map error. Since the fix, the robot drove 0.3 m turning 0.01 rad to the left: there
    // the row was 0.3 x (0.02 + 0.01) nearer, less the 0.3 x 0.01 / 2 the arc moved the
    // robot to the right of where it is now, 4.25 cm.
    let now = RowState {
        offset_m: 0.05,
        heading_rad: 0.02,
        ..RowState::default()
    };
    let since = Travel {
        travelled_m: 0.3,
        turned_rad: 0.01,
    };
    let fused = |since: Travel| {
        let mut f = RowFilter::new(FilterSettings::default());
        f.reset(now, f.sd());
        let outcome = f.update_gnss(0.0425, 0.01, since);
        (outcome, f.state())
    };
    // Taken there, the fix agrees with the filter: nothing moves.
    let (outcome, placed) = fused(since);
    assert_eq!(outcome, Outcome::Used);
    assert!((placed.offset_m - now.offset_m).abs() < 1e-12, "{placed:?}");
    assert!((placed.map_bias_m).abs() < 1e-12, "{placed:?}");
    // Taken as of now, the same fix, 7.5 mm nearer than the row, pulls the row nearer.
    let (_, as_now) = fused(Travel::default());
    assert!(
        as_now.offset_m + as_now.map_bias_m < now.offset_m - 0.003,
        "{as_now:?}"
    );
}
