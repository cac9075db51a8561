//! Unit tests of the fault checks that need a constructed context.

use super::*;
use crate::config::Settings;

/// The checks on a healthy, powered, standing robot, with `overruns` so far at `now_s`.
fn check_overruns(checks: &mut FaultChecks, now_s: f64, overruns: u64) -> Option<FaultCause> {
    let inputs = Inputs {
        pot_v: 2.5,
        battery_v: 25.0,
        estop_front_released: true,
        estop_back_released: true,
        motor_power_present: true,
        ..Inputs::default()
    };
    let steer = SteerCommand {
        t_s: now_s,
        ..SteerCommand::default()
    };
    let link = LinkStatus {
        beat_s: now_s,
        ..LinkStatus::default()
    };
    let health = ThreadHealth {
        supervisor_overruns: overruns,
        ..ThreadHealth::default()
    };
    checks.check(&CheckContext {
        now_s,
        mode: Mode::Halt,
        mode_since_s: 0.0,
        power: PowerState::On,
        inputs: &inputs,
        measured: &Measured::default(),
        driven_v: [0.0; 3],
        counts_moved: [false; 3],
        endswitch_hit: None,
        steer: &steer,
        link: &link,
        health: &health,
    })
}

fn checks() -> (FaultChecks, RtSettings) {
    let s = Settings::shipped();
    (
        FaultChecks::new(s.faults, s.camera, s.rt, s.supervisor.power_up_timeout_s),
        s.rt,
    )
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
