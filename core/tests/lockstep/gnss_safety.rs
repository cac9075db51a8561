//! GNSS that must not move the robot: fixes beside no row of the map, fixes too old for the
//! row filter to place, and no fix yet when
//! autonomous mode begins. Each starts from what used to drive the robot blind: the row
//! filter's first guess (the row straight ahead) steering at the cruising speed.

use crate::common;

use common::settings_with;
use mechweed_core::config::{CameraPort, GnssPort, Settings, SteerSource};
use mechweed_core::gnss::place::RowPlace;
use mechweed_core::state::modes::Mode;
use mechweed_core::state::status::Notice;
use mechweed_core::steer::SteerCore;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::geo::Geodetic;
use mechweed_hw::sim::{RowShape, SimParams, parse_events};

/// Whether the supervisor gave a steering notice with `words` in it.
pub(crate) fn said(sim: &Lockstep, words: &str) -> bool {
    sim.supervisor
        .notices()
        .iter()
        .any(|n| matches!(n, Notice::Steering { .. }) && n.to_string().contains(words))
}

pub(crate) fn gnss_alone(events: &str) -> Settings {
    let mut s = settings_with("", &[]);
    s.sim = SimParams {
        events: parse_events(events).unwrap(),
        ..SimParams::benchmark(RowShape::Straight, 1)
    };
    s.sources.source = SteerSource::Gnss;
    s.gnss.port = GnssPort::Link(CameraPort::Sim);
    s.steer.speed_mps = 1.0;
    s
}

/// Run for `seconds`; the largest distance driven.
fn run(sim: &mut Lockstep, seconds: f64) -> f64 {
    let mut driven_m = 0.0f64;
    while sim.now_s() < seconds {
        sim.tick();
        driven_m = driven_m.max(sim.robot.truth().distance_m);
    }
    driven_m
}

/// The robot steers by `points` as its row map instead of its field's own.
pub(crate) fn give_map(sim: &mut Lockstep, s: &Settings, points: &[Geodetic]) {
    let place = RowPlace::from_points(points, s.gnss.antenna_ahead_m, s.gnss.antenna_left_m);
    sim.steer = SteerCore::with_map(s, Some(place.unwrap()));
}

/// The run ended in the one fault that names both sensors.
pub(crate) fn stopped_with_no_row(sim: &Lockstep) {
    let faults = sim.supervisor.faults();
    assert_eq!(faults.len(), 1, "{faults:?}");
    let cause = faults[0].cause.to_string();
    assert!(cause.starts_with("no row to steer by"), "{cause}");
}

#[test]
fn fixes_beside_no_row_of_the_map_do_not_drive_the_robot_and_it_faults() {
    let s = gnss_alone("");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    // The map of another field: the simulated field's row 1.1 km to the north.
    let elsewhere: Vec<Geodetic> = sim
        .robot
        .planted_map()
        .iter()
        .map(|p| Geodetic {
            lat_deg: p.lat_deg + 0.01,
            ..*p
        })
        .collect();
    give_map(&mut sim, &s, &elsewhere);
    let driven_m = run(&mut sim, 10.0);
    assert!(driven_m < 0.02, "the robot drove {driven_m:.2} m on no row");
    stopped_with_no_row(&sim);
    assert!(sim.robot.outputs().is_safe());
}

#[test]
fn past_the_end_of_its_row_on_the_map_the_robot_stops() {
    let s = gnss_alone("");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    // A map of the row's first 6 m (the planted points every 25 cm): the rest of the
    // field lies beyond what the map knows, as a headland does.
    let first_6_m: Vec<Geodetic> = sim.robot.planted_map().into_iter().take(25).collect();
    give_map(&mut sim, &s, &first_6_m);
    let driven_m = run(&mut sim, 30.0);
    // Stopped within the margin of a metre past the map's end and the time to stop.
    assert!(
        (5.0..8.5).contains(&driven_m),
        "the robot drove {driven_m:.2} m on a 6 m map"
    );
    stopped_with_no_row(&sim);
}

#[test]
fn no_fix_when_autonomous_mode_begins_keeps_the_robot_standing() {
    // The receiver has lost its fix before the robot is powered up and sent off.
    let s = gnss_alone("0 gnss_lost");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let driven_m = run(&mut sim, 10.0);
    assert!(
        driven_m < 0.02,
        "the robot drove {driven_m:.2} m with no fix"
    );
    stopped_with_no_row(&sim);
}

#[test]
fn fixes_the_filter_cannot_place_do_not_keep_gnss_alive() {
    // A receiver 0.9 s late at 1.2 m/s: once the robot is up to speed, each fix is more
    // than the filter's metre of travel old and refused. The settings check refuses such
    // a receiver; set here behind its back, GNSS must still count as lost. When refused
    // fixes counted as heard, the robot drove 31 m in 30 s on odometry alone, 101 fixes
    // refused, and no fault.
    let mut s = gnss_alone("");
    (s.sim.gnss.latency_s, s.gnss.latency_s) = (0.9, 0.9);
    s.steer.speed_mps = 1.2;
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let driven_m = run(&mut sim, 30.0);
    assert!(driven_m < 10.0, "the robot drove {driven_m:.2} m");
    // Stopped by a fault: GNSS lost ("no row to steer by"), or the robot off its row
    // while the few fixes it could place steered it.
    let faults = sim.supervisor.faults();
    assert!(!faults.is_empty(), "{faults:?}");
    assert!(sim.robot.outputs().is_safe());
}

#[test]
fn with_its_fix_the_same_robot_drives_its_row() {
    // The tests above would pass on a robot that never moves: this one must.
    let s = gnss_alone("");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let driven_m = run(&mut sim, 10.0);
    assert!(driven_m > 3.0, "the robot drove {driven_m:.2} m");
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
}
