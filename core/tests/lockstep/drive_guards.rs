//! What the supervisor does with the driving commands it is given, through the real
//! supervisor on the simulated robot: the dead-man checked every tick, a broken
//! joystick axis, stale steer commands, and one wheel-angle limit in every mode.

use crate::common;

use common::{autonomous, record, settings_with, tick_by_hand};
use mechweed_core::rt::health::ThreadHealth;
use mechweed_core::state::fault_cause::{FaultCause, JoystickAxis};
use mechweed_core::state::modes::{Mode, Request};
use mechweed_core::steer::SteerCommand;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::Outputs;

/// Joystick mode, powered and calibrated, driving forward at full deflection.
fn joystick_driving() -> Lockstep {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    record(&mut sim, 1.0);
    assert_eq!(sim.supervisor.mode(), Mode::Joystick);
    sim.robot.set_joystick(0.0, 4.0, true);
    record(&mut sim, 3.0);
    assert!(sim.robot.truth().speed_mps > 0.5, "not driving");
    sim
}

#[test]
fn releasing_the_dead_man_brakes_in_the_very_next_tick() {
    let mut sim = joystick_driving();
    sim.robot.set_joystick(0.0, 4.0, false);
    let outputs = sim.tick();
    // Not at the steer thread's next 10 Hz tick, and not a ramp with brakes released.
    assert_eq!(
        outputs,
        Outputs {
            main_power_on: true,
            ..Outputs::SAFE
        }
    );
    record(&mut sim, 2.0);
    assert!(sim.robot.truth().speed_mps.abs() < 0.01, "still rolling");
    assert_eq!(sim.supervisor.mode(), Mode::Joystick, "no fault, no halt");
    // Pressed again: it starts from rest, the speed ramping up.
    sim.robot.set_joystick(0.0, 4.0, true);
    record(&mut sim, 0.3);
    let speed_ref = sim.supervisor.status().speed_ref_mps;
    assert!(
        speed_ref > 0.0 && speed_ref < 0.3,
        "speed reference {speed_ref}"
    );
}

#[test]
fn a_joystick_axis_beyond_full_scale_is_a_fault_not_full_speed() {
    let mut sim = joystick_driving();
    // A broken wiper reads the supply.
    sim.robot.set_joystick(0.0, 4.95, true);
    let ticks = record(&mut sim, 0.2);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(
        log[0].cause,
        FaultCause::JoystickAxis {
            axis: JoystickAxis::Speed,
            volts: 4.95
        }
    );
    assert!(ticks.iter().all(|t| t.outputs == Outputs::SAFE));
}

/// Supervisor ticks from `t0_s` on with a steer command the steer thread no longer
/// renews; returns the speed reference after `seconds`.
fn tick_with_frozen_command(
    sim: &mut Lockstep,
    t0_s: f64,
    command: &SteerCommand,
    seconds: f64,
) -> f64 {
    let ticks = (seconds * 100.0).round() as usize;
    for k in 1..=ticks {
        let now = t0_s + k as f64 * 0.01;
        sim.robot.advance_to(now);
        let outputs = sim.supervisor.tick(
            now,
            &sim.robot.inputs(),
            command,
            sim.link.status(),
            &ThreadHealth::default(),
        );
        sim.robot.set_outputs(&outputs);
    }
    sim.supervisor.status().speed_ref_mps
}

#[test]
fn a_steer_command_older_than_two_steer_periods_asks_for_no_speed() {
    let s = settings_with("", &[]);
    let mut sim = autonomous(&s);
    record(&mut sim, 4.0);
    let driving = sim.supervisor.status().speed_ref_mps;
    assert!(driving > 0.4, "speed reference {driving}");
    let frozen = sim.steer_command;
    // Past two steer periods, within the camera's time-out (no fault yet).
    let t0_s = sim.now_s();
    let speed_ref = tick_with_frozen_command(&mut sim, t0_s, &frozen, 0.35);
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    assert!(
        speed_ref < driving - 0.04,
        "still asking {speed_ref} m/s of a command 0.35 s old"
    );
}

#[test]
fn a_steer_command_made_for_another_mode_asks_for_no_speed() {
    let s = settings_with("", &[]);
    let mut sim = autonomous(&s);
    record(&mut sim, 4.0);
    let driving = sim.supervisor.status().speed_ref_mps;
    // A joystick command, fresh, arriving while the supervisor is autonomous.
    let mut t = sim.now_s();
    let mut speed_ref = driving;
    for _ in 0..20 {
        let command = SteerCommand {
            t_s: t,
            mode: Mode::Joystick,
            speed_mps: 1.0,
            ..sim.steer_command
        };
        speed_ref = tick_with_frozen_command(&mut sim, t, &command, 0.01);
        t += 0.01;
    }
    assert!(
        speed_ref < driving - 0.05,
        "took a joystick command in autonomous: {speed_ref} m/s"
    );
}

#[test]
fn the_end_switch_procedure_angle_does_not_widen_the_wheel_angle_limit() {
    // A procedure angle past the robot's limit (check-config refuses one; the
    // supervisor must not trust that), and a joystick that asks for as much.
    let mut s = settings_with("", &[]);
    s.steer.endswitch_back_deg = 40.0;
    s.joystick.max_angle_deg = 40.0;
    let limit_deg = s.robot.max_wheel_angle_deg;
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    record(&mut sim, 1.0);
    sim.robot.set_joystick(-4.0, 1.0, true);
    let mut widest_ref_deg: f64 = 0.0;
    for _ in 0..300 {
        sim.tick();
        let st = sim.supervisor.status();
        widest_ref_deg = widest_ref_deg.max(st.wheel_angle_ref_rad.to_degrees().abs());
    }
    assert!(
        widest_ref_deg <= limit_deg + 1e-9,
        "wheel angle reference {widest_ref_deg} deg, limit {limit_deg} deg"
    );
    assert!(widest_ref_deg > limit_deg - 0.5, "never reached the limit");
    assert!(sim.supervisor.status().endswitch_hit.is_none());
}

#[test]
fn the_end_switch_procedure_steers_back_within_the_wheel_angle_limit() {
    // A procedure angle past the robot's limit: the procedure keeps inside the limit,
    // and still finishes.
    let mut s = settings_with("3 endswitch left", &[]);
    s.steer.endswitch_back_deg = 40.0;
    let limit_deg = s.robot.max_wheel_angle_deg;
    let mut sim = autonomous(&s);
    let mut widest_ref_deg: f64 = 0.0;
    for _ in 0..800 {
        sim.tick();
        // While driving: standing, the reference follows the wheel wherever it is.
        let st = sim.supervisor.status();
        if st.mode.drives() {
            widest_ref_deg = widest_ref_deg.max(st.wheel_angle_ref_rad.to_degrees().abs());
        }
    }
    assert!(
        widest_ref_deg <= limit_deg + 1e-9,
        "wheel angle reference {widest_ref_deg} deg, limit {limit_deg} deg"
    );
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    let notices = sim.supervisor.notices();
    assert_eq!(notices.len(), 1, "the procedure finished: {notices:?}");
}

#[test]
fn the_references_ramp_at_their_rates_and_a_late_tick_steps_them_by_two_periods_at_most() {
    // Full speed and full left asked from rest: the speed reference grows at accel_mps2
    // and the wheel angle's at wheel_angle_rate_dps, so that neither jumps. A tick 40 ms
    // after the last (late, but within the late-tick limit) moves them by two periods'
    // worth, not four.
    let s = settings_with("", &[]);
    let mut sim = Lockstep::new(&s, Mode::Joystick);
    record(&mut sim, 1.0);
    sim.robot.set_joystick(-4.0, 4.0, true);
    let period_s = 1.0 / s.supervisor.rate_hz;
    let speed_step = s.supervisor.accel_mps2 * period_s;
    let angle_step = s.supervisor.wheel_angle_rate_dps.to_radians() * period_s;
    record(&mut sim, 0.3);
    let before = *sim.supervisor.status();
    let command = sim.steer_command;
    let t0_s = sim.now_s();
    tick_with_frozen_command(&mut sim, t0_s, &command, 0.01);
    let after = *sim.supervisor.status();
    let grew = |a: f64, b: f64| b - a;
    assert!((grew(before.speed_ref_mps, after.speed_ref_mps) - speed_step).abs() < 1e-9);
    assert!(
        (grew(before.wheel_angle_ref_rad, after.wheel_angle_ref_rad) - angle_step).abs() < 1e-9
    );
    // The next tick four periods after that one: the steps of two.
    let now_s = t0_s + 0.01 + 4.0 * period_s;
    let before = after;
    tick_by_hand(&mut sim, now_s, &command, |_| {});
    let after = *sim.supervisor.status();
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    let speed_grew = grew(before.speed_ref_mps, after.speed_ref_mps);
    assert!(
        (speed_grew - 2.0 * speed_step).abs() < 1e-9,
        "{speed_grew} m/s"
    );
    let angle_grew = grew(before.wheel_angle_ref_rad, after.wheel_angle_ref_rad);
    assert!(
        (angle_grew - 2.0 * angle_step).abs() < 1e-9,
        "{angle_grew} rad"
    );
}

#[test]
fn the_weeding_tool_runs_only_while_the_robot_moves_autonomously() {
    // Standing, starting, or driven by a person, the tool stays off: its blades must not
    // turn beside someone at the joystick, nor in one place on the crop.
    let s = settings_with("", &[]);
    let mut sim = autonomous(&s);
    let (mut ran, mut stood) = (0, 0);
    for _ in 0..500 {
        let tool_on = sim.tick().tool_on;
        let st = sim.supervisor.status();
        if st.speed_ref_mps <= 0.05 {
            assert!(!tool_on, "tool on at {} m/s", st.speed_ref_mps);
            stood += 1;
        } else if st.speed_ref_mps > 0.1 {
            assert!(tool_on, "tool off driving at {} m/s", st.speed_ref_mps);
            ran += 1;
        }
    }
    assert!(ran > 100 && stood > 10, "ran {ran} ticks, stood {stood}");

    let mut sim = joystick_driving();
    let ticks = record(&mut sim, 2.0);
    assert!(
        ticks.iter().all(|t| !t.outputs.tool_on),
        "tool on in Joystick"
    );
    sim.request(Request::Mode(Mode::Halt)).unwrap();
    let ticks = record(&mut sim, 1.0);
    assert!(ticks.iter().all(|t| !t.outputs.tool_on), "tool on in Halt");
}
