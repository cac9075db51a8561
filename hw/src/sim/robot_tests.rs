//! Tests of the whole simulated robot, in lockstep.

use super::*;
use crate::Side;
use crate::camproto::{CMD_START, Decoder, Frame};
use crate::sim::events::{EventAction, parse_events};
use crate::sim::params::RowShape;
use crate::sim::pipe::byte_pipe;

/// A robot on a straight row, 5 cm left of it, with the disturbances turned off so
/// that the geometry can be checked exactly.
fn quiet_params() -> SimParams {
    SimParams {
        row: RowShape::Straight,
        start_offset_m: 0.05,
        side_slip_deg: 0.0,
        motor_mismatch: 0.0,
        pot_noise_v: 0.0,
        ..SimParams::default()
    }
}

fn robot(params: &SimParams) -> (SimRobot, PipeEnd) {
    let (camera, robot_end) = byte_pipe(4096);
    (SimRobot::new(params, camera), robot_end)
}

fn drive(volts: f64) -> Outputs {
    Outputs {
        amp_left_v: volts,
        amp_right_v: volts,
        main_power_on: true,
        brake_release_left: true,
        brake_release_right: true,
        ..Outputs::SAFE
    }
}

#[test]
fn starts_still_braked_and_powered_down() {
    let (robot, _) = robot(&SimParams::default());
    let inputs = robot.inputs();
    assert!((inputs.pot_v - 2.5).abs() < 0.1);
    assert_eq!(inputs.battery_v, 25.0);
    assert!(inputs.estop_front_released && inputs.estop_back_released);
    assert!(!inputs.motor_power_present && !inputs.joystick_enable);
    assert_eq!((inputs.enc_left_counts, inputs.enc_steer_counts), (0, 0));
    assert!(robot.outputs().is_safe());
    assert_eq!(robot.time_s(), 0.0);
}

#[test]
fn cross_track_of_a_robot_5_cm_left_of_a_straight_row_is_5_cm() {
    let (mut robot, _) = robot(&quiet_params());
    assert!((robot.truth().tool_cross_track_m - 0.05).abs() < 1e-12);
    robot.set_outputs(&drive(5.0));
    robot.advance_to(20.0);
    let truth = robot.truth();
    assert!(truth.distance_m > 10.0);
    assert!((truth.tool_cross_track_m - 0.05).abs() < 1e-9);
    let s = robot.cross_track().summary();
    assert!((s.mean_cm - 5.0).abs() < 1e-6 && (s.max_cm - 5.0).abs() < 1e-6 && s.sd_cm < 1e-4);
    assert_eq!(s.share_over_2cm, 1.0);
    // Sampled every centimetre from 5 m on.
    assert!(
        (s.distance_m - (truth.distance_m - 5.0)).abs() < 0.011,
        "{s:?}"
    );
}

#[test]
fn wheels_reach_gain_times_voltage_beyond_the_dead_band_with_mismatch() {
    let (mut robot, _) = robot(&SimParams::default());
    robot.set_outputs(&drive(5.0));
    robot.advance_to(2.0);
    let truth = robot.truth();
    assert!(
        (truth.v_left_mps - 0.12 * 1.01 * 4.7).abs() < 1e-5,
        "{truth:?}"
    );
    assert!((truth.v_right_mps - 0.12 * 0.99 * 4.7).abs() < 1e-5);
    assert!((truth.speed_mps - 0.12 * 4.7).abs() < 1e-5);
    let travel_m = robot.inputs().enc_left_counts as f64 / 10_000.0;
    assert!(
        (travel_m - 0.12 * 1.01 * 4.7 * 1.9).abs() < 0.002,
        "{travel_m}"
    );
}

#[test]
fn brakes_stop_the_robot_within_0_3_s() {
    let (mut robot, _) = robot(&SimParams::default());
    robot.set_outputs(&drive(10.0));
    robot.advance_to(2.0);
    assert!(robot.truth().speed_mps > 1.1);
    robot.set_outputs(&Outputs {
        brake_release_left: false,
        brake_release_right: false,
        ..drive(10.0)
    });
    robot.advance_to(2.3);
    assert_eq!(
        (robot.truth().v_left_mps, robot.truth().v_right_mps),
        (0.0, 0.0)
    );
}

#[test]
fn estop_opens_the_contactor_and_the_wheels_roll_down_with_tau() {
    let params = SimParams {
        events: parse_events("2 estop_front").unwrap(),
        ..SimParams::default()
    };
    let (mut robot, _) = robot(&params);
    robot.set_outputs(&drive(10.0));
    robot.advance_to(2.0);
    let inputs = robot.inputs();
    assert!(!inputs.estop_front_released && !inputs.motor_power_present);
    let v0 = robot.truth().speed_mps;
    robot.advance_to(2.1);
    let ratio = robot.truth().speed_mps / v0;
    assert!((ratio - (-1.0f64).exp()).abs() < 0.01, "{ratio}");
    robot.apply(&EventAction::EstopRelease);
    assert!(robot.inputs().motor_power_present);
}

#[test]
fn steering_stops_at_30_deg_and_the_end_switch_closes_beyond_28() {
    let (mut robot, _) = robot(&SimParams::default());
    robot.set_outputs(&Outputs {
        amp_steer_v: 10.0,
        main_power_on: true,
        ..Outputs::SAFE
    });
    robot.advance_to(0.4);
    assert!(!robot.inputs().end_switch_left);
    robot.advance_to(1.0);
    let inputs = robot.inputs();
    assert!((robot.truth().wheel_angle_rad - 30f64.to_radians()).abs() < 1e-12);
    assert!(inputs.end_switch_left && !inputs.end_switch_right);
    assert!((inputs.pot_v - 4.5).abs() < 0.1, "{}", inputs.pot_v);
    assert_eq!(inputs.enc_steer_counts, 3000);
    robot.set_outputs(&Outputs {
        amp_steer_v: 0.0,
        ..Outputs::SAFE
    });
    robot.advance_to(2.0);
    assert_eq!(
        robot.inputs().enc_steer_counts,
        3000,
        "no power, no steering"
    );
}

#[test]
fn plant_events_change_the_sensors() {
    let text = "1 encoder_stuck left, 1 pot_broken, 1 battery 21.5, 1 endswitch right, 1 mode test";
    let params = SimParams {
        events: parse_events(text).unwrap(),
        ..SimParams::default()
    };
    let (mut robot, _) = robot(&params);
    robot.set_outputs(&drive(5.0));
    robot.advance_to(1.0);
    let stuck_at = robot.inputs().enc_left_counts;
    assert!(stuck_at > 0);
    robot.advance_to(2.0);
    let inputs = robot.inputs();
    assert_eq!(inputs.enc_left_counts, stuck_at);
    assert!(
        inputs.enc_right_counts > stuck_at + 3000,
        "the other wheel still counts"
    );
    assert_eq!((inputs.pot_v, inputs.battery_v), (0.0, 21.5));
    assert!(inputs.end_switch_right);
    // The steering motor can bring the wheel back.
    robot.set_outputs(&Outputs {
        amp_steer_v: 5.0,
        ..drive(5.0)
    });
    robot.advance_to(2.5);
    assert!(!robot.inputs().end_switch_right);
    robot.apply(&EventAction::PowerLoss);
    assert_eq!(
        (robot.inputs().battery_v, robot.inputs().motor_power_present),
        (0.0, false)
    );
    robot.apply(&EventAction::PowerRestore);
    assert!(robot.inputs().motor_power_present);
}

#[test]
fn end_switch_kick_left_closes_the_left_switch() {
    let (mut robot, _) = robot(&SimParams::default());
    robot.apply(&EventAction::EndSwitch(Side::Left));
    assert!(robot.inputs().end_switch_left);
    assert!((robot.truth().wheel_angle_rad - 29f64.to_radians()).abs() < 1e-12);
}

#[test]
fn advance_counts_whole_steps_and_never_goes_back() {
    let (mut robot, _) = robot(&SimParams::default());
    robot.advance_to(0.01);
    assert!((robot.time_s() - 0.01).abs() < 1e-12);
    robot.advance_to(0.005);
    robot.advance_to(f64::NAN);
    assert!((robot.time_s() - 0.01).abs() < 1e-12);
    robot.advance_to(0.0105);
    assert!((robot.time_s() - 0.010).abs() < 1e-12);
}

#[test]
fn camera_on_the_robot_sees_the_start_offset() {
    let (mut robot, mut robot_end) = robot(&SimParams {
        camera_drop: 0.0,
        ..quiet_params()
    });
    robot_end.send(&[CMD_START]);
    robot.advance_to(5.0);
    let mut buf = [0u8; 1024];
    let n = robot_end.try_read(&mut buf);
    let mut decoder = Decoder::new();
    let offsets: Vec<f64> = buf[..n]
        .iter()
        .filter_map(|&b| match decoder.push(b) {
            Some(Frame::Row(est)) => Some(est.offset_m),
            _ => None,
        })
        .collect();
    assert!(offsets.len() >= 48);
    let mean_m = offsets.iter().sum::<f64>() / offsets.len() as f64;
    assert!((mean_m + 0.05).abs() < 0.005, "{mean_m}");
    assert!(robot.camera().is_streaming());
}

#[test]
fn row_done_when_the_tool_passes_the_end() {
    let params = SimParams {
        row_length_m: 6.0,
        ..quiet_params()
    };
    let (mut robot, _) = robot(&params);
    robot.set_outputs(&drive(10.0));
    robot.advance_to(6.0);
    let truth = robot.truth();
    assert!(truth.row_done && truth.distance_m > 6.4);
    // Sampled from 5 m of travel until the tool (0.4 m behind) left the 6 m row.
    let measured_m = robot.cross_track().summary().distance_m;
    assert!((measured_m - 1.4).abs() < 0.02, "{measured_m}");
}

#[test]
fn same_seed_same_run() {
    let run = |seed: u64| {
        let params = SimParams {
            seed,
            camera_corrupt: 0.001,
            ..SimParams::benchmark(RowShape::SCurve, seed)
        };
        let (mut robot, mut robot_end) = robot(&params);
        robot_end.send(&[CMD_START]);
        robot.set_outputs(&Outputs {
            amp_steer_v: 0.5,
            ..drive(6.0)
        });
        let mut bytes = Vec::new();
        let mut pots = Vec::new();
        for k in 1..=1000 {
            robot.advance_to(k as f64 * 0.01);
            pots.push(robot.inputs().pot_v);
            let mut buf = [0u8; 256];
            let n = robot_end.try_read(&mut buf);
            bytes.extend_from_slice(&buf[..n]);
        }
        (bytes, pots, robot.truth())
    };
    let a = run(11);
    assert!(a.0.len() > 900);
    assert_eq!(a, run(11));
    assert_ne!(a.0, run(12).0);
}

#[test]
fn in_a_realistic_field_the_encoders_over_read_and_bumps_push_the_robot_off_its_line() {
    let realistic = SimParams {
        field: crate::sim::FieldKind::Realistic,
        ..quiet_params()
    };
    let (mut clean, _) = robot(&quiet_params());
    let (mut field, _) = robot(&realistic);
    for r in [&mut clean, &mut field] {
        r.set_outputs(&drive(5.0));
        r.advance_to(60.0);
    }
    let counted_m = |r: &SimRobot| {
        let i = r.inputs();
        0.5 * (i.enc_left_counts + i.enc_right_counts) as f64 / 10_000.0
    };
    let over = counted_m(&field) / field.truth().distance_m - 1.0;
    assert!((0.0..=0.05).contains(&over), "odometry over-reads {over}");
    assert!(over > 0.003, "loose soil slips: {over}");
    assert!((counted_m(&clean) / clean.truth().distance_m - 1.0).abs() < 1e-3);
    // Driven straight with no steering, the clean robot stays on its line; bumps and
    // the changing slope take the realistic one away from it.
    assert!((clean.truth().tool_cross_track_m - 0.05).abs() < 1e-9);
    assert!((field.truth().tool_cross_track_m - 0.05).abs() > 0.05);
}
