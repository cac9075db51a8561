//! The regulators on the simulated robot: bumpless switching between joystick and
//! autonomous, wheel speeds that follow Ackermann geometry, calibration before motion.

use crate::common;

use common::{record, settings_with};
use mechweed_core::state::modes::{Mode, Refusal, Request};
use mechweed_core::threads::lockstep::Lockstep;

/// Joystick speed-axis voltage that asks for `speed_mps`.
fn joystick_volts(s: &mechweed_core::config::Settings, speed_mps: f64) -> f64 {
    let j = &s.joystick;
    j.deadband_v + speed_mps / j.max_speed_mps * (j.full_scale_v - j.deadband_v)
}

#[test]
fn switching_joystick_to_autonomous_is_bumpless() {
    let s = settings_with("", &["steer.speed_mps=0.5"]);
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    sim.robot.set_joystick(0.0, joystick_volts(&s, 0.5), true);
    let before = record(&mut sim, 6.0);
    let last = before.last().unwrap();
    assert_eq!(last.mode, Mode::Joystick);
    assert!((sim.supervisor.status().measured.speed_mps - 0.5).abs() < 0.02);
    sim.request(Request::Mode(Mode::Autonomous))
        .expect("switch while driving");
    let after = record(&mut sim, 1.0);
    let jump = |k: usize| (after[k].outputs.amp_left_v - last.outputs.amp_left_v).abs();
    // No reset of the integrators and no step in the reference: the voltage moves
    // smoothly.
    assert!(jump(0) < 0.3, "left amplifier jumped by {:.2} V", jump(0));
    for pair in after.windows(2) {
        let step = (pair[1].outputs.amp_left_v - pair[0].outputs.amp_left_v).abs();
        assert!(step < 1.0, "step of {step:.2} V at {}", pair[1].t_s);
    }
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
}

#[test]
fn wheel_speed_references_follow_ackermann_geometry() {
    // A robot with a 1.3 m wheelbase: with the shipped 1 m, a term wrongly multiplied or
    // divided by it would not show.
    let s = settings_with("", &["robot.wheelbase_m=1.3", "sim.wheelbase_m=1.3"]);
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    // Full left at a steady speed.
    sim.robot.set_joystick(-4.0, joystick_volts(&s, 0.4), true);
    record(&mut sim, 5.0);
    let st = sim.supervisor.status();
    let k = st.measured.wheel_angle_rad.tan() / s.robot.wheelbase_m;
    assert!(
        st.measured.wheel_angle_rad.to_degrees() > 20.0,
        "not steering left"
    );
    let expected_ratio = (1.0 + 0.5 * s.robot.track_m * k) / (1.0 - 0.5 * s.robot.track_m * k);
    let ratio = st.v_right_ref_mps / st.v_left_ref_mps;
    assert!(
        (ratio - expected_ratio).abs() < 1e-9,
        "outer/inner {ratio} vs {expected_ratio}"
    );
    // And the wheels follow their references.
    assert!((st.measured.v_left_mps - st.v_left_ref_mps).abs() < 0.02);
    assert!((st.measured.v_right_mps - st.v_right_ref_mps).abs() < 0.02);
}

#[test]
fn steering_is_calibrated_before_any_motion() {
    // The wheel stands at 10 deg at power-up, where the relative encoder reads 0.
    let s = settings_with("", &["sim.initial_wheel_angle_deg=10"]);
    let mut sim = Lockstep::new(&s, Mode::Halt);
    sim.tick();
    sim.request(Request::PowerUp).unwrap();
    sim.tick();
    sim.tick();
    assert_eq!(
        sim.supervisor.status().power,
        mechweed_core::state::status::PowerState::On
    );
    assert_eq!(
        sim.request(Request::Mode(Mode::Joystick)),
        Err(Refusal::NotCalibrated)
    );
    let ticks = record(&mut sim, 1.0);
    assert!(
        ticks
            .iter()
            .all(|t| t.outputs.amp_steer_v == 0.0 && t.outputs.amp_left_v == 0.0)
    );
    let m = sim.supervisor.status().measured;
    assert!(m.calibrated);
    assert!(
        (m.wheel_angle_rad.to_degrees() - 10.0).abs() < 0.3,
        "calibrated to {}",
        m.wheel_angle_rad.to_degrees()
    );
    sim.request(Request::Mode(Mode::Joystick))
        .expect("calibrated now");
}

#[test]
fn gains_change_only_in_halt() {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    record(&mut sim, 3.0);
    let mut gains = sim.supervisor.gains();
    gains.left.kp *= 2.0;
    assert_eq!(sim.request(Request::Gains(gains)), Err(Refusal::OnlyInHalt));
    assert_eq!(sim.supervisor.gains().left.kp, s.pid_left.kp);
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    sim.request(Request::Gains(gains)).expect("halted");
    assert_eq!(sim.supervisor.gains(), gains);
}

#[test]
fn gains_and_steering_law_are_applied_together_or_not_at_all() {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    record(&mut sim, 3.0);
    let mut gains = sim.supervisor.gains();
    gains.steer.kp *= 1.5;
    let mut law = sim.steer.law_settings();
    law.lookahead_m += 0.2;
    let tuning = Request::Tuning(gains, law);
    assert_eq!(sim.request(tuning), Err(Refusal::OnlyInHalt));
    assert_eq!(
        sim.supervisor.gains().steer.kp,
        s.pid_steer.kp,
        "gains taken"
    );
    assert_eq!(sim.steer.law_settings().lookahead_m, s.steer.lookahead_m);
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    sim.request(tuning).expect("halted");
    assert_eq!(sim.supervisor.gains(), gains);
    assert_eq!(sim.steer.law_settings().lookahead_m, law.lookahead_m);
}

#[test]
fn steering_lock_to_lock_does_not_trip_the_potentiometer_check() {
    // The steering at its fastest; the potentiometer is filtered against its noise,
    // and that filter's lag must not look like a disagreement with the encoder.
    let s = settings_with(
        "",
        &["supervisor.wheel_angle_rate_dps=200", "pid.steer.kp=300"],
    );
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    record(&mut sim, 1.0);
    let mut widest_deg: f64 = 0.0;
    for k in 0..6 {
        let steer_v = if k % 2 == 0 { 4.0 } else { -4.0 };
        sim.robot.set_joystick(steer_v, 0.0, true);
        record(&mut sim, 1.0);
        widest_deg = widest_deg.max(sim.robot.truth().wheel_angle_rad.to_degrees().abs());
    }
    assert!(
        widest_deg > 24.0,
        "the steering only reached {widest_deg} deg"
    );
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
}

#[test]
fn wheel_references_are_zero_once_the_robot_stops_driving() {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    record(&mut sim, 3.0);
    assert!(sim.supervisor.status().v_left_ref_mps > 0.1);
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    record(&mut sim, 0.1);
    let st = sim.supervisor.status();
    assert_eq!(
        (st.speed_ref_mps, st.v_left_ref_mps, st.v_right_ref_mps),
        (0.0, 0.0, 0.0)
    );
}

#[test]
fn driving_again_after_halt_starts_the_regulators_from_rest() {
    // Halted while accelerating, the wheels' integrators hold what the ramp needed; kept
    // into the next start, the robot would lurch forward when the dead-man is pressed
    // with the joystick at rest.
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    record(&mut sim, 1.0);
    sim.robot.set_joystick(0.0, joystick_volts(&s, 0.8), true);
    record(&mut sim, 0.6);
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    record(&mut sim, 2.0);
    assert!(sim.robot.truth().speed_mps.abs() < 0.01, "still rolling");
    sim.robot.set_joystick(0.0, joystick_volts(&s, 0.0), true);
    sim.request(Request::Mode(Mode::Joystick)).unwrap();
    let first = sim.tick();
    assert!(
        first.amp_left_v.abs() < 0.2 && first.amp_right_v.abs() < 0.2,
        "{} V, {} V at rest",
        first.amp_left_v,
        first.amp_right_v
    );
}
