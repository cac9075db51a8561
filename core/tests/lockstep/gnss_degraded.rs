//! GNSS that is there but not good enough to steer by alone: RTK float, which wanders by
//! decimetres, and fixes the row filter's gate rejects. Each starts from what drove the
//! robot off its row: the degraded fixes steering at full speed with no fault.

use crate::gnss_safety::{give_map, gnss_alone, said, stopped_with_no_row};
use mechweed_core::config::SteerSource;
use mechweed_core::state::modes::Mode;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::geo::Geodetic;

/// Where the robot had driven when GNSS began to float, and the fastest it went after
/// `settle_s` more.
fn run_past(sim: &mut Lockstep, from_s: f64, settle_s: f64, until_s: f64) -> (f64, f64, f64) {
    let (mut at_m, mut top_mps, mut driven_m) = (0.0, 0.0f64, 0.0f64);
    while sim.now_s() < until_s {
        sim.tick();
        let truth = sim.robot.truth();
        if sim.now_s() <= from_s {
            at_m = truth.distance_m;
        } else if sim.now_s() > from_s + settle_s {
            top_mps = top_mps.max(truth.speed_mps);
        }
        driven_m = driven_m.max(truth.distance_m);
    }
    (at_m, top_mps, driven_m)
}

#[test]
fn rtk_float_with_no_camera_slows_the_robot_and_then_stops_it_saying_why() {
    // Float from 5 s on, trusted as shipped (rtk_fixed, rtk_float). Steering by it at full
    // speed drove 12.8 cm RMS off the row with no fault.
    let s = gnss_alone("5 gnss_float");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let (float_at_m, top_mps, driven_m) = run_past(&mut sim, 5.0, 2.0, 30.0);
    assert!(
        float_at_m > 2.0,
        "the robot drove {float_at_m:.2} m on RTK fixed"
    );
    let slow = s.sources.gnss_only_speed_mps;
    assert!(
        top_mps < slow + 0.05,
        "{top_mps:.2} m/s on float, slow is {slow}"
    );
    let floated_m = driven_m - float_at_m;
    // The hold, then stopping from the slow speed (0.25 m at 0.5 m/s/s) and a fix's wait.
    let most_m = s.gnss.float_hold_m + 1.0;
    assert!(
        floated_m < most_m,
        "{floated_m:.2} m on float, hold {}",
        s.gnss.float_hold_m
    );
    stopped_with_no_row(&sim);
    assert!(said(&sim, "RTK float for longer than [gnss] float_hold_m"));
    assert!(sim.robot.outputs().is_safe());
}

#[test]
fn fixes_the_gate_rejects_do_not_keep_gnss_alive() {
    // The map's line steps 40 cm sideways 10 m along the row (a map made with a jump in
    // its RTK): the gate rejects every fix past it. When rejected fixes counted as heard,
    // the robot drove on by odometry until the filter reset and swung it 40 cm across.
    let s = gnss_alone("");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let planted = sim.robot.planted_map();
    let (first, last) = (planted[0], planted[planted.len() - 1]);
    let (north, east) = (last.lat_deg - first.lat_deg, last.lon_deg - first.lon_deg);
    let metres_per_deg_lat = 111_320.0;
    let metres_per_deg_lon = metres_per_deg_lat * first.lat_deg.to_radians().cos();
    let (north_m, east_m) = (north * metres_per_deg_lat, east * metres_per_deg_lon);
    let length_m = north_m.hypot(east_m);
    // 40 cm to the left of the row's direction.
    let (left_north_m, left_east_m) = (0.4 * east_m / length_m, -0.4 * north_m / length_m);
    let stepped: Vec<Geodetic> = (planted.iter().enumerate())
        .map(|(i, p)| match i >= 40 {
            true => Geodetic {
                lat_deg: p.lat_deg + left_north_m / metres_per_deg_lat,
                lon_deg: p.lon_deg + left_east_m / metres_per_deg_lon,
                ..*p
            },
            false => *p,
        })
        .collect();
    give_map(&mut sim, &s, &stepped);
    let (_, _, driven_m) = run_past(&mut sim, 0.0, 0.0, 30.0);
    assert!(driven_m < 12.0, "the robot drove {driven_m:.2} m");
    let worst_cm = sim.robot.cross_track().summary().max_cm;
    assert!(worst_cm < 10.0, "{worst_cm:.1} cm off the row");
    stopped_with_no_row(&sim);
    assert!(said(&sim, "gate rejects the GNSS fixes"));
}

#[test]
fn a_row_driven_against_its_maps_point_order_is_followed_that_way() {
    // The map's points listed from the row's far end. Taken the map's way round, every
    // fix put the row on the wrong side: the robot swung 7 cm away from it and faulted
    // with "the row is 25 cm to its left".
    for source in [SteerSource::Gnss, SteerSource::Fused] {
        let mut s = gnss_alone("");
        s.sources.source = source;
        let mut sim = Lockstep::new(&s, Mode::Autonomous);
        let mut reversed = sim.robot.planted_map();
        reversed.reverse();
        give_map(&mut sim, &s, &reversed);
        let (_, _, driven_m) = run_past(&mut sim, 0.0, 0.0, 20.0);
        let faults = sim.supervisor.faults();
        let notices = sim.supervisor.notices();
        assert!(
            driven_m > 15.0,
            "{source:?}: the robot drove {driven_m:.2} m; {faults:?} {notices:?}"
        );
        assert!(
            sim.supervisor.faults().is_empty(),
            "{:?}",
            sim.supervisor.faults()
        );
        let worst_cm = sim.robot.cross_track().summary().max_cm;
        assert!(worst_cm < 6.0, "{source:?}: {worst_cm:.1} cm off the row");
        assert!(said(&sim, "against its map's point order"), "{source:?}");
    }
}
