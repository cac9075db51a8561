//! The gate's memory: both sensors rejected at once reset the row, one alone does not.

use super::sim::{EVERY, Sim};
use super::*;

/// `exchanges` times: drive, a camera row `camera_error_m` off, a fix `gnss_error_m`
/// off; the outcomes.
fn exchange(
    sim: &mut Sim,
    f: &mut RowFilter,
    exchanges: usize,
    camera_error_m: f64,
    gnss_error_m: f64,
) -> Vec<(Outcome, Outcome)> {
    (0..exchanges)
        .map(|_| {
            (0..EVERY).for_each(|_| sim.drive(f));
            (sim.camera(f, camera_error_m), sim.gnss(f, gnss_error_m))
        })
        .collect()
}

/// A filter settled on the row by 20 m of both sensors.
fn settled(seed: u64) -> (Sim, RowFilter) {
    let mut sim = Sim::new(seed, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 2000);
    (sim, f)
}

#[test]
fn a_bump_both_sensors_see_resets_the_row_at_once_not_the_maps_bias() {
    let (mut sim, mut f) = settled(7);
    // A clod knocks the robot 5 cm right and 1 degree right, unseen by odometry: the row
    // is 5 cm further left and heads 1 degree further left. Camera and GNSS both say so,
    // and both fall outside the gate.
    sim.truth.offset_m += 0.05;
    sim.truth.heading_rad += 1f64.to_radians();
    let outcomes = exchange(&mut sim, &mut f, 3, 0.0, 0.0);
    assert!(
        outcomes[..2]
            .iter()
            .all(|&o| o == (Outcome::Rejected, Outcome::Rejected)),
        "{outcomes:?}"
    );
    // In each exchange the camera comes first: its third rejection still finds GNSS at
    // two; GNSS's third, the camera's being rejected too, resets the row's offset.
    assert_eq!(outcomes[2], (Outcome::Rejected, Outcome::Reset));
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
    exchange(&mut sim, &mut f, 20, 0.0, 0.0);
    let (state, truth) = (f.state(), sim.truth);
    assert!(close(state.offset_m, truth.offset_m, 0.01), "{state:?}");
    assert!(
        close(state.heading_rad, truth.heading_rad, 0.3f64.to_radians()),
        "{state:?} {truth:?}"
    );
}

#[test]
fn a_weed_patch_the_gnss_does_not_see_resets_nothing() {
    let (mut sim, mut f) = settled(8);
    // Nine frames of weeds 8 cm beside the row (one fewer than the camera's reset count),
    // while every fix agrees with the filter.
    let outcomes = exchange(&mut sim, &mut f, 9, 0.08, 0.0);
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

#[test]
fn a_bump_gnss_saw_first_resets_the_row_from_the_camera() {
    let (mut sim, mut f) = settled(9);
    sim.truth.offset_m += 0.05;
    sim.truth.heading_rad += 1f64.to_radians();
    // The fix comes first in each exchange here: the camera's third rejection resets its
    // part, the row's offset and heading, at once.
    let outcomes: Vec<_> = (0..3)
        .map(|_| {
            (0..EVERY).for_each(|_| sim.drive(&mut f));
            (sim.gnss(&mut f, 0.0), sim.camera(&mut f, 0.0))
        })
        .collect();
    assert_eq!(
        outcomes[2],
        (Outcome::Rejected, Outcome::Reset),
        "{outcomes:?}"
    );
    assert_eq!(f.counters().camera_resets, 1);
    let (state, truth) = (f.state(), sim.truth);
    assert!(close(state.offset_m, truth.offset_m, 0.015), "{state:?}");
    assert!(
        close(state.heading_rad, truth.heading_rad, 0.5f64.to_radians()),
        "{state:?} {truth:?}"
    );
}

#[test]
fn weeds_and_a_receivers_jump_to_either_side_reset_nothing_early() {
    let (mut sim, mut f) = settled(10);
    // Weeds 8 cm to the left, the receiver jumped 10 cm to the right: both rejected, but
    // they do not agree with each other, so neither is reset before its own count.
    let outcomes = exchange(&mut sim, &mut f, 9, 0.08, -0.10);
    assert!(
        outcomes
            .iter()
            .all(|&o| o == (Outcome::Rejected, Outcome::Rejected)),
        "{outcomes:?}"
    );
    let (state, truth, c) = (f.state(), sim.truth, f.counters());
    assert_eq!((c.camera_resets, c.gnss_resets), (0, 0));
    assert!(close(state.offset_m, truth.offset_m, 0.01), "{state:?}");
}

#[test]
fn a_receiver_silent_since_its_rejections_does_not_count_as_disagreeing_now() {
    let (mut sim, mut f) = settled(11);
    // Three fixes 10 cm off are rejected, then the receiver falls silent for a metre ...
    exchange(&mut sim, &mut f, 3, 0.0, 0.10);
    (0..100).for_each(|_| sim.drive(&mut f));
    // ... and weeds 8 cm to the same side come: the camera waits for its own count.
    let outcomes: Vec<_> = (0..9)
        .map(|_| {
            (0..EVERY).for_each(|_| sim.drive(&mut f));
            sim.camera(&mut f, 0.08)
        })
        .collect();
    assert!(
        outcomes.iter().all(|&o| o == Outcome::Rejected),
        "{outcomes:?}"
    );
    assert_eq!(f.counters().camera_resets, 0);
}
