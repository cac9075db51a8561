//! Unit tests of the fault checks that need a constructed context.

use super::*;
use crate::camlink::LinkStatus;
use crate::config::Settings;
use crate::rt::health::ThreadHealth;
use crate::state::measure::Measured;
use crate::steer::SteerCommand;

/// What one tick's checks see; `Scene::at(now_s)` is a healthy, powered robot standing
/// in Halt whose threads all beat at `now_s`.
#[derive(Clone, Copy)]
struct Scene {
    now_s: f64,
    tick_gap_s: f64,
    mode: Mode,
    power: PowerState,
    measured: Measured,
    driven_v: [f64; 3],
    relay_closed: bool,
    expected_mps: [f64; 2],
    overruns: u64,
}

impl Scene {
    fn at(now_s: f64) -> Scene {
        Scene {
            now_s,
            tick_gap_s: 0.01,
            mode: Mode::Halt,
            power: PowerState::On,
            measured: Measured::default(),
            driven_v: [0.0; 3],
            relay_closed: true,
            expected_mps: [0.0; 2],
            overruns: 0,
        }
    }

    fn check(&self, checks: &mut FaultChecks) -> Option<FaultCause> {
        let inputs = healthy_inputs();
        let steer = SteerCommand {
            t_s: self.now_s,
            ..SteerCommand::default()
        };
        let link = LinkStatus {
            beat_s: self.now_s,
            ..LinkStatus::default()
        };
        let health = ThreadHealth {
            supervisor_overruns: self.overruns,
            ..ThreadHealth::default()
        };
        checks.check(&CheckContext {
            now_s: self.now_s,
            tick_gap_s: self.tick_gap_s,
            mode: self.mode,
            mode_since_s: 0.0,
            power: self.power,
            inputs: &inputs,
            measured: &self.measured,
            driven_v: self.driven_v,
            relay_closed: self.relay_closed,
            brakes_released: [false; 2],
            expected_mps: self.expected_mps,
            counts_moved: [false; 3],
            endswitch_hit: None,
            steer: &steer,
            link: &link,
            health: &health,
        })
    }
}

/// The checks with `overruns` so far at `now_s`.
fn check_overruns(checks: &mut FaultChecks, now_s: f64, overruns: u64) -> Option<FaultCause> {
    Scene {
        overruns,
        ..Scene::at(now_s)
    }
    .check(checks)
}

fn checks() -> (FaultChecks, RtSettings) {
    let s = Settings::shipped();
    (FaultChecks::new(&s), s.rt)
}

#[test]
fn overruns_up_to_the_limit_are_tolerated_one_more_in_the_window_is_not() {
    let (mut checks, rt) = checks();
    let limit = rt.max_overruns as u64;
    assert_eq!(check_overruns(&mut checks, 1.0, limit), None);
    assert_eq!(check_overruns(&mut checks, 1.01, limit), None);
    assert!(matches!(
        check_overruns(&mut checks, 1.02, limit + 1),
        Some(FaultCause::Overruns { .. })
    ));
}

#[test]
fn overruns_spread_wider_than_the_window_are_tolerated() {
    let (mut checks, rt) = checks();
    let spacing_s = rt.overrun_window_s / rt.max_overruns as f64 + 0.01;
    for k in 1..=(3 * rt.max_overruns as u64) {
        let cause = check_overruns(&mut checks, k as f64 * spacing_s, k);
        assert_eq!(cause, None, "overrun {k}");
    }
}

/// A powered robot whose encoders all stand still, its motors driven with `driven_v`
/// and asked for `expected_mps`, the potentiometer turning at `pot_dps`, checked every
/// 10 ms for `seconds`: the first cause found.
fn still_encoders(
    driven_v: [f64; 3],
    expected_mps: [f64; 2],
    pot_dps: f64,
    seconds: f64,
) -> Option<FaultCause> {
    still_encoders_from(0.0, driven_v, expected_mps, pot_dps, seconds)
}

/// The same, the potentiometer starting at `pot_deg`.
fn still_encoders_from(
    pot_deg: f64,
    driven_v: [f64; 3],
    expected_mps: [f64; 2],
    pot_dps: f64,
    seconds: f64,
) -> Option<FaultCause> {
    let (mut checks, _) = checks();
    (1..=(seconds * 100.0) as usize).find_map(|k| {
        let now_s = k as f64 * 0.01;
        let scene = Scene {
            mode: Mode::Joystick,
            measured: Measured {
                pot_angle_filtered_rad: (pot_deg + pot_dps * now_s).to_radians(),
                ..Measured::default()
            },
            driven_v,
            expected_mps,
            ..Scene::at(now_s)
        };
        scene.check(&mut checks)
    })
}

pub(super) fn healthy_inputs() -> Inputs {
    Inputs {
        pot_v: 2.5,
        battery_v: 25.0,
        estop_front_released: true,
        estop_back_released: true,
        motor_power_present: true,
        ..Inputs::default()
    }
}

#[test]
fn a_wheel_held_on_a_slope_by_its_integrator_is_no_stuck_encoder() {
    // 3 V held, nothing asked: the robot rightly stands.
    assert_eq!(still_encoders([3.0, 3.0, 0.0], [0.0, 0.0], 0.0, 2.0), None);
}

#[test]
fn a_wheel_asked_to_move_whose_encoder_stands_is_a_stuck_encoder() {
    assert_eq!(
        still_encoders([4.0, 4.0, 0.0], [0.5, 0.5], 0.0, 2.0),
        Some(FaultCause::EncoderStuck(EncoderId::Left))
    );
}

#[test]
fn a_creeping_wheel_driven_far_harder_than_its_creep_needs_is_a_stuck_encoder() {
    // 0.03 m/s asked (below what counts as motion), the integrator wound up behind a
    // dead encoder: the wheel runs away at full voltage.
    assert_eq!(
        still_encoders([10.0, 0.2, 0.0], [0.03, 0.03], 0.0, 2.0),
        Some(FaultCause::EncoderStuck(EncoderId::Left))
    );
    // The same creep with the voltage it needs is no fault.
    assert_eq!(
        still_encoders([0.3, 0.3, 0.0], [0.03, 0.03], 0.0, 2.0),
        None
    );
}

#[test]
fn steering_held_by_ground_friction_is_no_stuck_encoder() {
    // Driven hard, but the potentiometer says the wheel does not turn either.
    assert_eq!(still_encoders([0.0, 0.0, 6.0], [0.0, 0.0], 0.0, 2.0), None);
}

#[test]
fn steering_that_turns_while_its_encoder_stands_is_a_stuck_encoder() {
    assert_eq!(
        still_encoders([0.0, 0.0, 6.0], [0.0, 0.0], 20.0, 2.0),
        Some(FaultCause::EncoderStuck(EncoderId::Steer))
    );
}

/// One tick `gap_s` after the previous one, the relay as given: the cause found.
fn tick_after(checks: &mut FaultChecks, now_s: f64, gap_s: f64, relay: bool) -> Option<FaultCause> {
    Scene {
        tick_gap_s: gap_s,
        power: if relay {
            PowerState::On
        } else {
            PowerState::Off
        },
        relay_closed: relay,
        ..Scene::at(now_s)
    }
    .check(checks)
}

#[test]
fn one_tick_later_than_its_limit_is_a_fault() {
    let s = Settings::shipped();
    let period_s = 1.0 / s.supervisor.rate_hz;
    let limit_s = s.rt.max_late_periods * period_s;
    let (mut checks, _) = checks();
    assert_eq!(
        tick_after(&mut checks, 1.0, period_s + limit_s * 0.9, true),
        None
    );
    assert!(matches!(
        tick_after(&mut checks, 2.0, period_s + limit_s * 1.1, true),
        Some(FaultCause::LateTick { .. })
    ));
}

#[test]
fn motor_power_that_stays_on_after_the_relay_opened_is_a_welded_contactor() {
    let drop_s = Settings::shipped().faults.contactor_drop_s;
    let (mut checks, _) = checks();
    let inputs = healthy_inputs();
    let mut t = 1.0;
    // Within the drop time, a contactor may still be opening.
    while t < 1.0 + drop_s * 0.9 {
        assert_eq!(tick_after(&mut checks, t, 0.01, false), None, "at {t}");
        assert_eq!(checks.standing_cause(&inputs), None);
        t += 0.01;
    }
    while t < 1.0 + drop_s * 1.1 {
        t += 0.01;
    }
    assert_eq!(
        tick_after(&mut checks, t, 0.01, false),
        Some(FaultCause::ContactorWelded)
    );
    assert_eq!(
        checks.standing_cause(&inputs),
        Some(FaultCause::ContactorWelded)
    );
}

#[test]
fn power_up_waits_for_each_standing_cause_and_for_nothing_else() {
    let (checks, _) = checks();
    let s = Settings::shipped().faults;
    let healthy = healthy_inputs();
    // Healthy, or one end switch closed: the steering must have power to leave it.
    let one_switch = [
        Inputs {
            end_switch_left: true,
            ..healthy
        },
        Inputs {
            end_switch_right: true,
            ..healthy
        },
    ];
    for inputs in [healthy].iter().chain(&one_switch) {
        assert_eq!(checks.standing_cause(inputs), None, "{inputs:?}");
    }
    let both = Inputs {
        end_switch_left: true,
        end_switch_right: true,
        ..healthy
    };
    assert_eq!(
        checks.standing_cause(&both),
        Some(FaultCause::BothEndSwitches)
    );
    // A battery below its minimum: powered up, it would fault again at once.
    let volts = s.battery_min_v - 0.5;
    let low = Inputs {
        battery_v: volts,
        ..healthy
    };
    assert_eq!(
        checks.standing_cause(&low),
        Some(FaultCause::BatteryLow { volts })
    );
    let broken_pot = Inputs {
        pot_v: 0.0,
        ..healthy
    };
    assert_eq!(
        checks.standing_cause(&broken_pot),
        Some(FaultCause::PotOutOfRange { volts: 0.0 })
    );
}

#[test]
fn a_contactor_that_does_not_close_in_time_after_power_up_is_a_fault() {
    // Power up pressed, the contactor never closes (a broken coil or relay): the robot
    // must not wait for ever in "power coming on".
    let timeout_s = Settings::shipped().supervisor.power_up_timeout_s;
    let (mut checks, _) = checks();
    let closing = |now_s: f64| Scene {
        power: PowerState::Closing { since_s: 1.0 },
        relay_closed: true,
        ..Scene::at(now_s)
    };
    assert_eq!(closing(1.0 + timeout_s * 0.9).check(&mut checks), None);
    assert_eq!(
        closing(1.0 + timeout_s * 1.1).check(&mut checks),
        Some(FaultCause::PowerUpFailed)
    );
}

#[test]
fn an_encoder_that_stands_is_a_fault_only_after_its_time() {
    // A wheel starting from rest takes a moment to count: not a fault at once.
    let stuck_s = Settings::shipped().faults.encoder_stuck_s;
    assert_eq!(
        still_encoders([4.0, 4.0, 0.0], [0.5, 0.5], 0.0, stuck_s * 0.9),
        None
    );
    assert_eq!(
        still_encoders([4.0, 4.0, 0.0], [0.5, 0.5], 0.0, stuck_s * 1.1),
        Some(FaultCause::EncoderStuck(EncoderId::Left))
    );
}

#[test]
fn a_creep_up_a_slope_with_a_little_more_voltage_than_it_needs_is_no_stuck_encoder() {
    // 0.04 m/s asked (below what counts as motion) needs 0.33 V by the feed-forward; up
    // a slope the integrator adds a little: 2.2 V, above encoder_stuck_v (2 V) but not
    // above what the creep needs plus that margin. The wheel may stand a moment.
    let s = Settings::shipped();
    let needed_v = s.pid_left.kff * 0.04;
    let driven_v = s.faults.encoder_stuck_v + 0.2;
    assert!(driven_v < needed_v + s.faults.encoder_stuck_v);
    assert_eq!(
        still_encoders([driven_v, driven_v, 0.0], [0.04, 0.04], 0.0, 2.0),
        None
    );
}

#[test]
fn steering_held_off_centre_by_ground_friction_is_no_stuck_encoder() {
    // Held at 10 degrees, the potentiometer's filtered reading wandering by 0.8 degrees:
    // the wheel has not turned. What counts is the change since the encoder stood.
    assert_eq!(
        still_encoders_from(10.0, [0.0, 0.0, 6.0], [0.0, 0.0], 0.4, 2.0),
        None
    );
    assert_eq!(
        still_encoders_from(10.0, [0.0, 0.0, 6.0], [0.0, 0.0], 20.0, 2.0),
        Some(FaultCause::EncoderStuck(EncoderId::Steer))
    );
}
