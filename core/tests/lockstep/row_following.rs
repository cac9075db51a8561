//! The steering law on the simulated robot, closed loop: it converges from 5 cm off
//! the row, and holds an arc and a side slope without steady-state error; through gaps
//! in the row, where the camera computer repeats its last estimate unchanged at a lower
//! quality, it holds the row line it last saw, moved by the robot's own motion, and stops
//! naming the camera when the repeat lasts longer than [camera] gap_hold_m; and the
//! benchmark's split of a fused robot's error into the filter's part and the steering's.

use crate::common;

use crate::gnss_safety::said;
use common::settings_with;
use mechweed_core::bench::rows::run_row;
use mechweed_core::config::{Settings, SteerSource};
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::{Mode, Request};
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::sim::{FieldKind, RowShape, SimParams};

/// Settings for one row with chosen disturbances (noise-free unless asked).
fn quiet_row(row: RowShape, side_slip_deg: f64) -> Settings {
    let mut s = settings_with("", &[]);
    s.sim = SimParams::benchmark(row, 7);
    s.sim.side_slip_deg = side_slip_deg;
    s.sim.motor_mismatch = 0.0;
    s.sim.camera_noise_offset_m = 0.0;
    s.sim.camera_noise_angle_deg = 0.0;
    s.sim.camera_drop = 0.0;
    s.sim.plant_scatter_m = 0.0;
    s.sim.start_offset_m = 0.0;
    s
}

/// Mean of the tool's cross-track error over the window [from_m, to_m] of distance, cm.
fn mean_error_cm(sim: &mut Lockstep, from_m: f64, to_m: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    while sim.robot.truth().distance_m < to_m {
        sim.tick();
        assert!(sim.now_s() < 400.0, "the robot did not get to {to_m} m");
        let t = sim.robot.truth();
        if t.distance_m >= from_m {
            sum += t.tool_cross_track_m * 100.0;
            n += 1;
        }
    }
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    sum / n as f64
}

#[test]
fn converges_from_5_cm_off_the_row() {
    let mut s = quiet_row(RowShape::Straight, 0.0);
    s.sim.start_offset_m = 0.05;
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let start = sim.robot.truth().tool_cross_track_m;
    assert!((start - 0.05).abs() < 1e-6, "start {start}");
    let mut worst_after_5m: f64 = 0.0;
    while sim.robot.truth().distance_m < 15.0 {
        sim.tick();
        assert!(sim.now_s() < 100.0, "the robot did not get to 15 m");
        let t = sim.robot.truth();
        if t.distance_m > 5.0 {
            worst_after_5m = worst_after_5m.max(t.tool_cross_track_m.abs());
        }
    }
    // Through the row filter the camera's first rows are taken whole, and pure pursuit's
    // integral carries the tool a little past the row: 0.53 cm at worst (0.4 when the
    // camera's rows went to the law as they came).
    assert!(
        worst_after_5m < 0.006,
        "still {:.2} cm off after 5 m",
        worst_after_5m * 100.0
    );
}

#[test]
fn holds_an_arc_without_steady_state_error() {
    let s = quiet_row(RowShape::Arc, 0.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let mean = mean_error_cm(&mut sim, 15.0, 35.0);
    assert!(mean.abs() < 0.2, "mean tool error on the arc {mean:.3} cm");
}

#[test]
fn holds_a_side_slope_without_steady_state_error() {
    let s = quiet_row(RowShape::Straight, 1.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let mean = mean_error_cm(&mut sim, 20.0, 40.0);
    assert!(
        mean.abs() < 0.2,
        "mean tool error on the slope {mean:.3} cm"
    );
}

#[test]
fn same_seed_gives_the_same_run_and_another_seed_does_not() {
    let s = settings_with("", &[]);
    let a = run_row(
        &s,
        FieldKind::Clean,
        SteerSource::Camera,
        RowShape::SCurve,
        1.0,
        11,
    );
    let b = run_row(
        &s,
        FieldKind::Clean,
        SteerSource::Camera,
        RowShape::SCurve,
        1.0,
        11,
    );
    let c = run_row(
        &s,
        FieldKind::Clean,
        SteerSource::Camera,
        RowShape::SCurve,
        1.0,
        12,
    );
    assert_eq!(a.cross_track_cm, b.cross_track_cm);
    assert_ne!(a.cross_track_cm, c.cross_track_cm);
}

#[test]
fn benchmark_scurve_at_half_a_metre_per_second_stays_on_the_row() {
    // Every disturbance of the simulated plant on. The aim is an s.d. of 1 cm; this test guards
    // against a controller that loses the row, with room for noise between seeds.
    let run = run_row(
        &settings_with("", &[]),
        FieldKind::Clean,
        SteerSource::Camera,
        RowShape::SCurve,
        0.5,
        1,
    );
    assert!(run.faults.is_empty(), "{:?}", run.faults);
    assert!(
        run.cross_track_cm.distance_m > 50.0,
        "measured over {} m",
        run.cross_track_cm.distance_m
    );
    assert!(run.cross_track_cm.sd_cm < 1.5, "{:?}", run.cross_track_cm);
}

#[test]
fn the_benchmark_splits_the_fused_tools_error_into_the_filters_part_and_gives_floor_and_bound() {
    let s = settings_with("", &[]);
    let row = |source| run_row(&s, FieldKind::Realistic, source, RowShape::Straight, 1.0, 1);
    let camera = row(SteerSource::Camera);
    assert_eq!(
        camera.filter_error_cm, None,
        "the camera alone has no filter"
    );
    let fused = row(SteerSource::Fused);
    let filter = fused
        .filter_error_cm
        .expect("a fused run measures its filter");
    // Over the same stretch of row, sampled every centimetre like the tool's error. The
    // filter tracks the tool: its error is the smaller part (with the sign of the row's
    // offset turned the wrong way it would be near twice the tool's error).
    let tool = fused.cross_track_cm;
    assert!(
        (filter.distance_m - tool.distance_m).abs() < 1.0,
        "{filter:?} {tool:?}"
    );
    assert!(filter.sd_cm > 0.1, "{filter:?}");
    assert!(filter.sd_cm < 0.8 * tool.sd_cm, "{filter:?} {tool:?}");
    // What an exact filter would leave: less with both sensors than with the camera.
    let (fused_floor, camera_floor) = (fused.filter_floor_cm, camera.filter_floor_cm);
    assert!(
        fused_floor
            .zip(camera_floor)
            .is_some_and(|(f, c)| 0.1 < f && f < c),
        "{fused_floor:?} {camera_floor:?}"
    );
    // What the best steering of the field's model leaves: above the floor, which it
    // adds to (the robot moves before the sensors see it).
    let bound = fused.steering_bound_cm;
    assert!(
        bound.zip(fused_floor).is_some_and(|(b, f)| f < b),
        "{bound:?} {fused_floor:?}"
    );
    let clean = run_row(
        &s,
        FieldKind::Clean,
        SteerSource::Fused,
        RowShape::Straight,
        1.0,
        1,
    );
    assert_eq!(
        (clean.filter_floor_cm, clean.steering_bound_cm),
        (None, None),
        "a floor and a bound of the realistic field only"
    );
}

#[test]
fn the_realistic_benchmark_takes_the_fields_gnss_float_episodes_from_the_settings() {
    // [sim] field_gnss_float_* are the field's, like the other field_* settings: a field
    // whose receiver floats all along must steer GNSS alone worse than the shipped one,
    // whose one float episode per 200 m may not even fall on this 60 m row.
    let run = |s: &Settings| {
        run_row(
            s,
            FieldKind::Realistic,
            SteerSource::Gnss,
            RowShape::Straight,
            1.0,
            1,
        )
    };
    let shipped = run(&settings_with("", &[]));
    let floating = run(&settings_with(
        "",
        &[
            "sim.field_gnss_float_every_m=1",
            "sim.field_gnss_float_s=10000",
        ],
    ));
    let (calm, wild) = (shipped.cross_track_cm.sd_cm, floating.cross_track_cm.sd_cm);
    assert!(
        !floating.faults.is_empty() || wild > 2.0 * calm,
        "s.d. {calm:.2} cm fixed, {wild:.2} cm floating; faults {:?}",
        floating.faults
    );
}

/// The straight benchmark row at 1 m/s on a field whose only disturbance is gaps of
/// `gap_m`, one every `every_m` on average, in which the camera repeats its last estimate
/// at quality 40 (usable: [camera] min_quality is 30).
pub(crate) fn gappy_row(gap_m: f64, every_m: f64) -> Settings {
    let mut s = settings_with("", &[]);
    s.sim = SimParams {
        field: FieldKind::Realistic,
        ..SimParams::benchmark(RowShape::Straight, 3)
    };
    s.sim.start_offset_m = 0.0;
    let t = &mut s.sim.tier;
    (t.camera_bias_sd_m, t.slope_max_deg, t.wheel_slip_max) = (0.0, 0.0, 0.0);
    (t.weed_every_m, t.bump_every_m) = (1e6, 1e6);
    (t.gap_every_m, t.gap_min_m, t.gap_max_m) = (every_m, gap_m, gap_m);
    s.steer.speed_mps = 1.0;
    s
}

/// What a drive through gaps saw: the worst |tool error| after 5 m (m), and the
/// camera's last numbers with the distance driven since they first came (m).
struct ThroughGaps {
    worst_m: f64,
    numbers: (f64, f64),
    repeated_m: f64,
}

/// Drive until the row's end, a fault (and the robot stopped), `limit_s`, or the camera
/// having repeated one estimate for `repeated_m` of driving.
fn drive_through_gaps(sim: &mut Lockstep, limit_s: f64, repeated_m: f64) -> ThroughGaps {
    let (mut worst_m, mut numbers, mut new_at_m) = (0.0f64, (f64::NAN, f64::NAN), 0.0);
    while !sim.robot.truth().row_done && sim.now_s() < limit_s {
        sim.tick();
        let truth = sim.robot.truth();
        let last = sim.link.status().last_usable;
        if (last.offset_m, last.angle_rad) != numbers {
            (numbers, new_at_m) = ((last.offset_m, last.angle_rad), truth.distance_m);
        }
        if truth.distance_m > 5.0 {
            worst_m = worst_m.max(truth.tool_cross_track_m.abs());
        }
        let stopped = !sim.supervisor.faults().is_empty() && truth.speed_mps.abs() < 1e-3;
        if stopped || truth.distance_m - new_at_m > repeated_m {
            break;
        }
    }
    let repeated_m = sim.robot.truth().distance_m - new_at_m;
    ThroughGaps {
        worst_m,
        numbers,
        repeated_m,
    }
}

/// The first fault is "camera sees no row".
fn assert_the_camera_sees_no_row(sim: &Lockstep) {
    let faults = sim.supervisor.faults();
    assert!(
        matches!(
            faults.first().map(|f| f.cause),
            Some(FaultCause::CameraSeesNoRow { .. })
        ),
        "{faults:?}"
    );
}

#[test]
fn through_gaps_of_one_and_a_half_metres_the_camera_steered_tool_stays_on_the_row() {
    // Taken as new, a repeated estimate moves with the robot: the robot turned towards
    // it, and further, and swung its tool 31 cm off the row (seeds 1 to 8 but 6: 9 to 31 cm,
    // one of them stopping; held, 2 to 4 cm).
    let s = gappy_row(1.5, 10.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let worst_m = drive_through_gaps(&mut sim, 120.0, f64::INFINITY).worst_m;
    let faults = sim.supervisor.faults();
    assert!(faults.is_empty(), "{faults:?}");
    assert!(
        sim.robot.truth().row_done,
        "the robot reached the row's end"
    );
    assert!(worst_m < 0.05, "worst tool error {worst_m} m");
}

#[test]
fn a_gap_longer_than_the_hold_stops_the_robot_naming_the_camera() {
    // One gap of 10 m in every 12: the camera repeats one estimate for 10 m.
    let s = gappy_row(10.0, 12.0);
    assert_eq!(s.camera.gap_hold_m, 3.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let gaps = drive_through_gaps(&mut sim, 120.0, f64::INFINITY);
    let (worst_m, repeated_m) = (gaps.worst_m, gaps.repeated_m);
    assert_the_camera_sees_no_row(&sim);
    assert!(!sim.robot.truth().row_done, "it stopped in the gap");
    // 3 m held, then braking from 1 m/s.
    assert!(
        (3.0..4.5).contains(&repeated_m),
        "drove {repeated_m} m on one repeated estimate"
    );
    assert!(worst_m < 0.05, "worst tool error {worst_m} m");
}

#[test]
fn started_again_in_a_gap_the_robot_looks_for_plants_straight_ahead_slowly_then_faults() {
    // The odometry starts afresh in each autonomous spell, so it no longer knows where
    // the repeated estimate's image was taken: moved as the robot moves now, the old row
    // line would steer the robot on for the rest of the hold. It is not steered by: the
    // robot stands for [steer] camera_fallback_s, then drives straight ahead at [camera]
    // gap_speed_mps for at most [camera] first_row_m, saying so, and faults on finding no
    // plants (this gap is 12 m long).
    let s = gappy_row(10.0, 12.0);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let gaps = drive_through_gaps(&mut sim, 60.0, 1.0);
    assert!(gaps.repeated_m > 1.0, "no gap came");
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    sim.run_for(2.0);
    assert!(sim.robot.truth().speed_mps.abs() < 1e-3, "stopped");
    sim.request(Request::Mode(Mode::Autonomous)).unwrap();
    let restarted_at_m = sim.robot.truth().distance_m;
    sim.run_for(s.sources.camera_fallback_s - 0.05);
    let standing_m = sim.robot.truth().distance_m - restarted_at_m;
    assert!(standing_m < 0.01, "drove {standing_m} m before looking");
    let mut top_mps = 0.0f64;
    let searched_for_s = s.camera.first_row_m / s.camera.gap_speed_mps + 5.0;
    let until_s = sim.now_s() + searched_for_s;
    while sim.now_s() < until_s && sim.supervisor.faults().is_empty() {
        sim.tick();
        top_mps = top_mps.max(sim.robot.truth().speed_mps);
    }
    let (last, driven_m) = (sim.link.status().last_usable, sim.robot.truth().distance_m);
    assert_eq!(
        (last.offset_m, last.angle_rad),
        gaps.numbers,
        "still in the gap"
    );
    let slow = s.camera.gap_speed_mps;
    // Within the speed regulator's overshoot.
    assert!(top_mps < slow + 0.05, "{top_mps} m/s, gap speed {slow}");
    let searched_m = driven_m - restarted_at_m;
    let most_m = s.camera.first_row_m + 0.2;
    assert!(
        searched_m < most_m,
        "drove {searched_m} m looking for plants"
    );
    assert!(
        searched_m > s.camera.first_row_m - 0.1,
        "drove {searched_m} m"
    );
    assert!(
        said(&sim, "no row in sight yet"),
        "{:?}",
        sim.supervisor.notices()
    );
    assert_the_camera_sees_no_row(&sim);
}
