//! The gate's memory: both sensors rejected at once reset the row, one alone does not.

use super::sim::{EVERY, Sim};
use super::*;

/// `exchanges` times: drive, a camera row `camera_error_m` off, a fix; the outcomes.
fn exchange(
    sim: &mut Sim,
    f: &mut RowFilter,
    exchanges: usize,
    camera_error_m: f64,
) -> Vec<(Outcome, Outcome)> {
    (0..exchanges)
        .map(|_| {
            (0..EVERY).for_each(|_| sim.drive(f));
            (sim.camera(f, camera_error_m), sim.gnss(f, 0.0))
        })
        .collect()
}

#[test]
fn a_bump_both_sensors_see_resets_the_row_at_once_not_the_maps_bias() {
    let mut sim = Sim::new(7, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 2000);
    // A clod knocks the robot 5 cm right and 1 degree right, unseen by odometry: the row
    // is 5 cm further left and heads 1 degree further left. Camera and GNSS both say so,
    // and both fall outside the gate.
    sim.truth.offset_m += 0.05;
    sim.truth.heading_rad += 1f64.to_radians();
    let outcomes = exchange(&mut sim, &mut f, 3, 0.0);
    assert!(
        outcomes[..2]
            .iter()
            .all(|&o| o == (Outcome::Rejected, Outcome::Rejected)),
        "{outcomes:?}"
    );
    // The third rejection of each resets: the filter is off, not either sensor.
    assert_eq!(outcomes[2].1, Outcome::Reset, "{outcomes:?}");
    let state = f.state();
    assert!(
        close(state.offset_m, sim.truth.offset_m, 0.015),
        "{state:?} {:?}",
        sim.truth
    );
    // The map's bias did not take the robot's knock, as a GNSS reset of it would.
    assert!(
        close(state.map_bias_m, sim.truth.map_bias_m, 0.01),
        "{state:?} {:?}",
        sim.truth
    );
    // Within a metre the camera is trusted again, and the row's heading is right.
    exchange(&mut sim, &mut f, 20, 0.0);
    let (state, truth) = (f.state(), sim.truth);
    assert!(close(state.offset_m, truth.offset_m, 0.01), "{state:?}");
    assert!(
        close(state.heading_rad, truth.heading_rad, 0.3f64.to_radians()),
        "{state:?} {truth:?}"
    );
}

#[test]
fn a_weed_patch_the_gnss_does_not_see_resets_nothing() {
    let mut sim = Sim::new(8, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 2000);
    // Nine frames of weeds 8 cm beside the row (one fewer than the camera's reset count),
    // while every fix agrees with the filter.
    let outcomes = exchange(&mut sim, &mut f, 9, 0.08);
    assert!(
        outcomes
            .iter()
            .all(|&o| o == (Outcome::Rejected, Outcome::Used)),
        "{outcomes:?}"
    );
    let (state, truth, c) = (f.state(), sim.truth, f.counters());
    assert_eq!((c.camera_resets, c.gnss_resets), (0, 0));
    assert!(close(state.offset_m, truth.offset_m, 0.01), "{state:?}");
}
