//! Every scripted fault ends in safe outputs in the supervisor tick that first sees it,
//! with its cause in the fault log.

use crate::common;

use common::{Tick, autonomous, record, settings_with};
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::{Mode, Request};
use mechweed_hw::{EncoderId, Outputs};

/// Run the default row in autonomous mode with `events`; return the ticks and the log.
fn scenario(
    events: &str,
    seconds: f64,
) -> (Vec<Tick>, Vec<mechweed_core::state::status::FaultRecord>) {
    let settings = settings_with(events, &[]);
    let mut sim = autonomous(&settings);
    let ticks = record(&mut sim, seconds);
    (ticks, sim.supervisor.faults().to_vec())
}

/// The robot was driving autonomously before `t_s`.
fn was_driving(ticks: &[Tick], t_s: f64) {
    let before: Vec<_> = ticks
        .iter()
        .filter(|t| t.t_s < t_s && t.t_s > t_s - 0.5)
        .collect();
    assert!(
        before.iter().all(|t| t.mode == Mode::Autonomous),
        "not autonomous before {t_s}"
    );
    assert!(
        before.iter().any(|t| t.outputs.amp_left_v.abs() > 0.5),
        "not driving before {t_s}"
    );
}

/// From the fault's tick on, every output is safe.
fn safe_from(ticks: &[Tick], t_s: f64) {
    for t in ticks.iter().filter(|t| t.t_s >= t_s - 1e-9) {
        assert_eq!(t.outputs, Outputs::SAFE, "unsafe outputs at {} s", t.t_s);
        assert_eq!(t.mode, Mode::Fault);
    }
}

/// The first tick whose inputs satisfy `seen`.
fn first_seen(ticks: &[Tick], seen: impl Fn(&Tick) -> bool) -> &Tick {
    ticks
        .iter()
        .find(|t| seen(t))
        .expect("the condition never showed in the inputs")
}

#[test]
fn estop_front_is_safe_in_the_tick_that_sees_it() {
    let (ticks, log) = scenario("5 estop_front", 7.0);
    was_driving(&ticks, 5.0);
    let seen = first_seen(&ticks, |t| !t.inputs.estop_front_released);
    assert_eq!(
        seen.outputs,
        Outputs::SAFE,
        "the tick that read the e-stop wrote {:?}",
        seen.outputs
    );
    safe_from(&ticks, seen.t_s);
    assert_eq!(log[0].cause, FaultCause::EstopFront);
    assert_eq!(log[0].tick_safe - log[0].tick_seen, 0);
}

#[test]
fn estop_back_is_safe_in_the_tick_that_sees_it() {
    let (ticks, log) = scenario("5 estop_back", 7.0);
    was_driving(&ticks, 5.0);
    let seen = first_seen(&ticks, |t| !t.inputs.estop_back_released);
    assert_eq!(seen.outputs, Outputs::SAFE);
    safe_from(&ticks, seen.t_s);
    assert_eq!(log[0].cause, FaultCause::EstopBack);
}

#[test]
fn power_loss_is_safe_in_the_tick_that_sees_it() {
    let (ticks, log) = scenario("5 power_loss", 7.0);
    was_driving(&ticks, 5.0);
    let seen = first_seen(&ticks, |t| t.t_s > 1.0 && !t.inputs.motor_power_present);
    assert_eq!(seen.outputs, Outputs::SAFE);
    safe_from(&ticks, seen.t_s);
    assert_eq!(log[0].cause, FaultCause::MotorPowerLost);
}

#[test]
fn stuck_encoders_are_found_while_driving() {
    let settings = settings_with("", &[]);
    let limit_s = settings.faults.encoder_stuck_s + 0.3;
    for (name, id) in [("left", EncoderId::Left), ("right", EncoderId::Right)] {
        let (ticks, log) = scenario(&format!("5 encoder_stuck {name}"), 7.0);
        was_driving(&ticks, 5.0);
        assert_eq!(log.len(), 1, "{name}: {log:?}");
        assert_eq!(log[0].cause, FaultCause::EncoderStuck(id));
        assert!(
            log[0].t_s > 5.0 && log[0].t_s < 5.0 + limit_s,
            "{name} found at {}",
            log[0].t_s
        );
        safe_from(&ticks, log[0].t_s);
    }
}

#[test]
fn stuck_steering_encoder_is_found_when_the_steering_moves() {
    // Steer hard by hand in joystick mode so the steering motor is driven.
    let settings = settings_with("2 encoder_stuck steer", &[]);
    let mut sim = mechweed_core::threads::lockstep::Lockstep::new(&settings, Mode::Joystick);
    record(&mut sim, 2.5);
    sim.robot.set_joystick(-4.0, 0.0, true);
    let ticks = record(&mut sim, 1.5);
    let log = &sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, FaultCause::EncoderStuck(EncoderId::Steer));
    safe_from(&ticks, log[0].t_s);
}

#[test]
fn silent_camera_link_faults_after_the_timeout() {
    let settings = settings_with("", &[]);
    let timeout = settings.camera.link_timeout_s;
    let (ticks, log) = scenario("5 link_silent 3", 7.0);
    was_driving(&ticks, 5.0);
    assert_eq!(log.len(), 1, "{log:?}");
    assert!(
        matches!(log[0].cause, FaultCause::CameraLinkLost { .. }),
        "{:?}",
        log[0].cause
    );
    // The last frame came at most one camera period (plus jitter) before the silence.
    assert!(
        log[0].t_s > 5.0 + timeout - 0.15 && log[0].t_s <= 5.0 + timeout + 0.02,
        "at {}",
        log[0].t_s
    );
    safe_from(&ticks, log[0].t_s);
}

#[test]
fn camera_reboot_while_autonomous_faults_with_link_lost() {
    let (ticks, log) = scenario("5 camera_reboot", 7.0);
    was_driving(&ticks, 5.0);
    assert!(
        matches!(log[0].cause, FaultCause::CameraLinkLost { .. }),
        "{log:?}"
    );
    safe_from(&ticks, log[0].t_s);
}

#[test]
fn low_battery_faults_after_its_time() {
    let settings = settings_with("", &[]);
    let (ticks, log) = scenario("5 battery 20", 8.0);
    was_driving(&ticks, 5.0);
    assert!(
        matches!(log[0].cause, FaultCause::BatteryLow { .. }),
        "{log:?}"
    );
    assert!(
        (log[0].t_s - 5.0 - settings.faults.battery_low_s).abs() < 0.03,
        "at {}",
        log[0].t_s
    );
    safe_from(&ticks, log[0].t_s);
}

#[test]
fn broken_potentiometer_is_safe_in_the_tick_that_sees_it() {
    let (ticks, log) = scenario("5 pot_broken", 6.0);
    was_driving(&ticks, 5.0);
    let seen = first_seen(&ticks, |t| t.inputs.pot_v < 0.3);
    assert_eq!(seen.outputs, Outputs::SAFE);
    assert!(
        matches!(log[0].cause, FaultCause::PotOutOfRange { .. }),
        "{log:?}"
    );
}

#[test]
fn end_switch_runs_the_procedure_and_halts_without_a_fault() {
    let settings = settings_with("5 endswitch left", &[]);
    let mut sim = autonomous(&settings);
    let ticks = record(&mut sim, 9.0);
    was_driving(&ticks, 5.0);
    let hit = first_seen(&ticks, |t| t.inputs.end_switch_left);
    // From the switch on, the supervisor never drives the steering further left.
    for t in ticks
        .iter()
        .filter(|t| t.t_s >= hit.t_s && t.inputs.end_switch_left)
    {
        assert!(
            t.outputs.amp_steer_v <= 0.0,
            "steering driven into the switch at {}",
            t.t_s
        );
    }
    assert!(
        sim.supervisor.faults().is_empty(),
        "{:?}",
        sim.supervisor.faults()
    );
    assert_eq!(sim.supervisor.notices().len(), 1);
    assert_eq!(sim.supervisor.mode(), Mode::Halt);
    let last = ticks.last().unwrap();
    assert!(!last.inputs.end_switch_left, "still on the switch");
    assert!(sim.robot.truth().speed_mps.abs() < 0.02, "still moving");
    assert!(sim.robot.truth().wheel_angle_rad.to_degrees() < 28.0);
}

#[test]
fn estop_needs_release_and_power_up() {
    let settings = settings_with("5 estop_front, 6 estop_release", &[]);
    let mut sim = autonomous(&settings);
    record(&mut sim, 5.5);
    assert_eq!(sim.supervisor.mode(), Mode::Fault);
    // Pressed: no power-up.
    assert!(sim.request(Request::PowerUp).is_err());
    record(&mut sim, 1.0);
    // Released: still latched, and no driving mode until power-up.
    assert_eq!(sim.supervisor.mode(), Mode::Fault);
    assert!(sim.request(Request::Mode(Mode::Autonomous)).is_err());
    let ticks = record(&mut sim, 0.5);
    assert!(ticks.iter().all(|t| t.outputs == Outputs::SAFE));
    sim.request(Request::PowerUp)
        .expect("power up after release");
    record(&mut sim, 0.5);
    assert_eq!(sim.supervisor.mode(), Mode::Halt);
    sim.request(Request::Mode(Mode::Autonomous))
        .expect("drive again");
    let ticks = record(&mut sim, 2.0);
    assert!(
        ticks.last().unwrap().outputs.amp_left_v > 0.5,
        "not driving again"
    );
}
