//! Steering by GNSS and by the fused row, in lockstep on the simulated robot with its
//! receiver: the fallbacks when one sensor is lost, the fault when both are, and the
//! gate that keeps a weed patch from pulling the robot off the row, and a float
//! episode that does not, nor a bump that both sensors see.

use crate::common;

use common::settings_with;
use mechweed_core::bench::rows::run_row;
use mechweed_core::config::{CameraPort, GnssPort, Settings, SteerSource};
use mechweed_core::state::modes::Mode;
use mechweed_core::steer::Steering;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::sim::{FieldKind, RowShape, SimParams, parse_events};

/// The benchmark's straight row at `speed_mps`, steered by `source`, with `events`.
fn settings(source: SteerSource, field: FieldKind, speed_mps: f64, events: &str) -> Settings {
    let mut s = settings_with("", &[]);
    s.sim = SimParams {
        field,
        events: parse_events(events).unwrap(),
        ..SimParams::benchmark(RowShape::Straight, 1)
    };
    s.sources.source = source;
    s.gnss.port = GnssPort::Link(CameraPort::Sim);
    s.steer.speed_mps = speed_mps;
    s
}

/// Which sensors steered at each whole second, and the tool's cross-track error (m)
/// at each supervisor tick after 5 m, until the row's end or `limit_s`.
struct Run {
    sim: Lockstep,
    steering_at_s: Vec<Steering>,
    /// (time s, error m) after the first 5 m.
    errors_m: Vec<(f64, f64)>,
}

fn drive(s: &Settings, limit_s: f64) -> Run {
    let mut sim = Lockstep::new(s, Mode::Autonomous);
    let (mut steering_at_s, mut errors_m) = (Vec::new(), Vec::new());
    while !sim.robot.truth().row_done && sim.now_s() < limit_s {
        sim.tick();
        let truth = sim.robot.truth();
        if truth.distance_m > 5.0 && sim.supervisor.mode() == Mode::Autonomous {
            errors_m.push((sim.now_s(), truth.tool_cross_track_m));
        }
        if (sim.now_s() - sim.now_s().round()).abs() < 1e-6 {
            steering_at_s.push(sim.steer_command.sources.steering);
        }
    }
    Run {
        sim,
        steering_at_s,
        errors_m,
    }
}

fn sd_cm(errors_m: &[(f64, f64)]) -> f64 {
    let n = errors_m.len() as f64;
    let mean = errors_m.iter().map(|e| e.1).sum::<f64>() / n;
    100.0 * (errors_m.iter().map(|e| (e.1 - mean).powi(2)).sum::<f64>() / n).sqrt()
}

/// The largest error between two times, cm.
fn worst_cm(errors_m: &[(f64, f64)], from_s: f64, to_s: f64) -> f64 {
    let within = errors_m.iter().filter(|e| (from_s..to_s).contains(&e.0));
    100.0 * within.fold(0.0f64, |m, e| m.max(e.1.abs()))
}

#[test]
fn rtk_lost_for_30_s_keeps_the_fused_robot_on_the_row_by_the_camera() {
    let lost = settings(
        SteerSource::Fused,
        FieldKind::Realistic,
        1.0,
        "10 gnss_dgps, 40 gnss_fixed",
    );
    let run = drive(&lost, 120.0);
    assert!(
        run.sim.supervisor.faults().is_empty(),
        "{:?}",
        run.sim.supervisor.faults()
    );
    assert!(
        run.sim.robot.truth().distance_m > 55.0,
        "the robot drove the row"
    );
    assert_eq!(
        run.steering_at_s[25],
        Steering::FilterCamera,
        "{:?}",
        run.steering_at_s
    );
    assert_eq!(run.steering_at_s[50], Steering::Fused);
    // Within what the camera alone does on the same row.
    let camera = drive(
        &settings(SteerSource::Camera, FieldKind::Realistic, 1.0, ""),
        120.0,
    );
    let (with_outage, alone) = (sd_cm(&run.errors_m), sd_cm(&camera.errors_m));
    assert!(
        with_outage <= alone,
        "{with_outage:.2} cm with RTK lost for 30 s, {alone:.2} cm by the camera alone"
    );
}

#[test]
fn the_camera_silent_for_5_s_leaves_the_fused_robot_on_the_row_by_rtk_at_reduced_speed() {
    let s = settings(
        SteerSource::Fused,
        FieldKind::Clean,
        1.0,
        "20 link_silent 5",
    );
    let run = drive(&s, 120.0);
    assert!(
        run.sim.supervisor.faults().is_empty(),
        "{:?}",
        run.sim.supervisor.faults()
    );
    assert_eq!(
        run.steering_at_s[22],
        Steering::FilterGnss,
        "{:?}",
        run.steering_at_s
    );
    assert_eq!(run.steering_at_s[30], Steering::Fused);
    // The notice names what the camera lacked, not a camera "lost" that may still be
    // sending frames.
    let said: Vec<String> = (run.sim.supervisor.notices().iter())
        .map(|n| n.to_string())
        .collect();
    let fell_back = (said.iter())
        .find(|n| n.starts_with("steering by GNSS alone: the camera"))
        .unwrap_or_else(|| panic!("{said:?}"));
    assert!(!fell_back.contains("lost"), "{fell_back}");
    // The 5 s without the camera and the 2 s it takes to settle back.
    let during = worst_cm(&run.errors_m, 20.0, 27.0);
    assert!(during < 3.0, "the tool {during:.2} cm off the row");
    assert!(run.sim.robot.truth().row_done);
}

#[test]
fn losing_both_the_camera_and_rtk_halts_the_robot_naming_both() {
    let s = settings(
        SteerSource::Fused,
        FieldKind::Clean,
        0.5,
        "15 gnss_lost, 18 link_silent 30",
    );
    let run = drive(&s, 30.0);
    let faults = run.sim.supervisor.faults();
    assert_eq!(faults.len(), 1, "{faults:?}");
    let text = faults[0].cause.to_string();
    assert!(
        text.starts_with("no row to steer by: the camera has given no usable row for"),
        "{text}"
    );
    assert!(
        text.contains("and GNSS no fix it may steer by for"),
        "{text}"
    );
    // GNSS went first, then the camera: the robot steered by the camera alone between.
    assert_eq!(
        run.steering_at_s[17],
        Steering::FilterCamera,
        "{:?}",
        run.steering_at_s
    );
    assert!(
        (18.0..20.0).contains(&faults[0].t_s),
        "fault at {} s",
        faults[0].t_s
    );
    assert!(run.sim.robot.outputs().is_safe());
    // Each change is said with what the others lack, and the map is driven its own way.
    let said: Vec<String> = (run.sim.supervisor.notices().iter())
        .map(|n| n.to_string())
        .collect();
    let camera_alone = "steering by the camera alone: no trusted GNSS fix";
    let neither = ": neither the camera nor GNSS has given a usable row";
    assert!(said.iter().any(|n| n.starts_with(camera_alone)), "{said:?}");
    assert!(said.iter().any(|n| n.ends_with(neither)), "{said:?}");
    assert!(
        !said.iter().any(|n| n.contains("against its map")),
        "{said:?}"
    );
}

#[test]
fn weed_patches_are_rejected_by_the_gate_and_the_fused_tool_stays_within_2_cm_of_the_row() {
    // The realistic field's weed patches and nothing else, and another seed's field.
    let mut s = settings(SteerSource::Fused, FieldKind::Realistic, 0.5, "");
    s.sim.tier = mechweed_hw::sim::FieldTierParams {
        camera_bias_sd_m: 0.0,
        gap_every_m: 1e4,
        slope_max_deg: 0.0,
        bump_heading_sd_deg: 0.0,
        bump_side_sd_m: 0.0,
        wheel_slip_max: 0.0,
        weed_every_m: 10.0,
        ..s.sim.tier
    };
    // A camera whose errors do not last, and the filter told so: a weed patch's 5 to
    // 10 cm then stand out of its 1 cm noise.
    s.filter.camera_bias_sd_m = 0.0;
    // On the row from the start, so that only the weeds pull the tool aside.
    s.sim.start_offset_m = 0.0;
    let run = drive(&s, 200.0);
    assert!(run.sim.supervisor.faults().is_empty());
    let counters = run.sim.steer.rows().filter().counters();
    let worst = worst_cm(&run.errors_m, 0.0, f64::INFINITY);
    let at = run
        .errors_m
        .iter()
        .find(|e| (100.0 * e.1.abs() - worst).abs() < 1e-9);
    assert!(
        worst <= 2.0,
        "the tool {worst:.2} cm off the row at {at:?}; {counters:?}"
    );
    assert!(counters.camera_rejected >= 20, "{counters:?}");
    // The camera alone goes through the same filter and gate: it followed the weeds
    // more than 3 cm aside when its estimates went to the law as they came.
    s.sources.source = SteerSource::Camera;
    let camera = drive(&s, 200.0);
    let camera_worst_cm = worst_cm(&camera.errors_m, 0.0, f64::INFINITY);
    assert!(
        camera_worst_cm <= 2.0,
        "the camera alone {camera_worst_cm:.2} cm off"
    );
}

#[test]
fn a_robot_put_down_beside_its_row_is_off_the_row_and_stops_steering_by_gnss() {
    // 40 cm left of the row at the start: GNSS on the map sees it at once.
    let mut s = settings(SteerSource::Gnss, FieldKind::Clean, 0.5, "");
    s.sim.start_offset_m = 0.4;
    let run = drive(&s, 10.0);
    let faults = run.sim.supervisor.faults();
    assert_eq!(faults.len(), 1, "{faults:?}");
    let text = faults[0].cause.to_string();
    assert!(
        text.starts_with("the robot is off its row: the row is 4")
            && text.contains("cm to its right"),
        "{text}"
    );
    assert!(run.sim.robot.outputs().is_safe());
    // The filter's gate takes the first fixes for an RTK jump until twenty in a row
    // agree (2 s), then it knows: the robot stopped within a metre or so.
    assert!(faults[0].t_s < 5.0, "{faults:?}");
    assert!(
        run.sim.robot.truth().distance_m < 1.5,
        "{:?}",
        run.sim.robot.truth()
    );
}

#[test]
fn an_rtk_float_episode_moves_the_maps_bias_and_not_the_row() {
    // A float solution's error wanders by decimetres over tens of seconds: ten fixes a
    // second of it are not ten independent measurements of the row. Taken as such, the
    // tool was 4.1 cm off at worst in float, against 1.8 cm in RTK fixed.
    let float = settings(
        SteerSource::Fused,
        FieldKind::Clean,
        1.0,
        "10 gnss_float, 40 gnss_fixed",
    );
    let run = drive(&float, 120.0);
    let faults = run.sim.supervisor.faults();
    assert!(faults.is_empty(), "{faults:?}");
    let fixed = drive(
        &settings(SteerSource::Fused, FieldKind::Clean, 1.0, ""),
        120.0,
    );
    let (during, without) = (
        worst_cm(&run.errors_m, 10.0, 45.0),
        worst_cm(&fixed.errors_m, 10.0, 45.0),
    );
    assert!(
        during < without + 1.0,
        "{during:.2} cm in float, {without:.2} cm in RTK fixed"
    );
}

#[test]
fn gnss_alone_takes_each_fix_where_the_robot_was_when_the_receiver_measured_it() {
    // A receiver whose sentences come 0.3 s after it measured ([gnss] latency_s says
    // so): each fix is 0.3-0.4 s old when the filter takes it, 30-40 cm back at 1 m/s.
    // Taken as of its arrival (latency_s = 0), the robot swung 25 cm off its row and
    // stopped; taking 0.05 s of the 0.3, likewise (18 cm off when it stopped).
    let mut s = settings(SteerSource::Gnss, FieldKind::Clean, 1.0, "");
    s.sim.gnss.latency_s = 0.3;
    s.gnss.latency_s = 0.3;
    let run = drive(&s, 120.0);
    let faults = run.sim.supervisor.faults();
    assert!(faults.is_empty(), "{faults:?}");
    let worst = worst_cm(&run.errors_m, 0.0, 120.0);
    assert!(worst < 5.0, "{worst:.2} cm at worst");
}

#[test]
fn a_bump_both_sensors_see_does_not_lock_the_filter_out_and_take_the_robot_off_its_row() {
    // Found on the realistic field of seed 1 with the slope's levels 20 m apart: at 49 m
    // of the S-curve at 1 m/s two clods kick the robot within half a metre. The next
    // camera rows and fixes fell outside the filter's gate, and the further out the
    // longer the robot steered by the filter's row; GNSS, after 20 rejections, took the
    // filter's own error into the map's bias, and the tool went 25.8 cm off the row
    // without a fault. Both sensors rejected at once now reset the row at the third.
    // (A field drawn from the seed: if the simulator's draws change, find the case again
    // with the rule removed from core/src/steer/filter_gate.rs.)
    let s = settings_with("", &["sim.field_slope_length_m=20"]);
    let run = run_row(
        &s,
        FieldKind::Realistic,
        SteerSource::Fused,
        RowShape::SCurve,
        1.0,
        1,
    );
    let worst_cm = run.cross_track_cm.max_cm;
    assert!(
        run.faults.is_empty() && worst_cm < 10.0,
        "worst {worst_cm:.1} cm, faults {:?}",
        run.faults
    );
}

#[test]
fn fused_with_no_fix_at_the_start_drives_on_the_camera_without_waiting_for_gnss() {
    // Either sensor heard is enough to start: a fused robot whose receiver has no fix
    // yet must not stand until GNSS falls back ([steer] gnss_fallback_s) while its
    // camera sees the row.
    let s = settings(SteerSource::Fused, FieldKind::Clean, 0.5, "0 gnss_lost");
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    let fallback_s = s.sources.gnss_fallback_s;
    while sim.now_s() < fallback_s - 0.05 {
        sim.tick();
    }
    assert_eq!(sim.steer_command.sources.steering, Steering::Fused);
    let driven_m = sim.robot.truth().distance_m;
    assert!(driven_m > 0.05, "drove {driven_m:.3} m in {fallback_s} s");
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
}
