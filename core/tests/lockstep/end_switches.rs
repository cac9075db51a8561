//! The end switches' two faults through the real supervisor on the simulated robot,
//! each from the unsafe state it guards against: a switch that closed while driving and
//! that no procedure takes, and a switch still closed long after the procedure began.
//! The test stands in for the steer thread, to be the steer thread that fails.

use crate::common;

use common::{record, settings_with, tick_by_hand};
use mechweed_core::config::Settings;
use mechweed_core::state::fault_cause::FaultCause;
use mechweed_core::state::modes::Mode;
use mechweed_core::steer::{EndSwitchState, SteerCommand};
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::{Outputs, Side};

/// A stone kicks the steered wheel past the left end switch at this time, s.
const KICK_S: f64 = 4.0;

/// Joystick mode, powered and calibrated, driving forward by the real steer thread
/// until just before the kick.
fn driving_by_joystick(s: &Settings) -> Lockstep {
    let mut sim = Lockstep::new(s, Mode::Joystick);
    record(&mut sim, 1.0);
    sim.robot.set_joystick(0.0, 3.0, true);
    record(&mut sim, KICK_S - 1.5);
    assert_eq!(sim.supervisor.mode(), Mode::Joystick);
    assert!(sim.robot.truth().speed_mps > 0.3, "not driving");
    sim
}

/// The run's one fault is `cause`, latched after `allowed_s` from the switch closing at
/// `hit_s` (`None`: it never closed) and within the tick after.
fn the_only_fault_in_its_time(
    sim: &Lockstep,
    hit_s: Option<f64>,
    cause: FaultCause,
    allowed_s: f64,
) {
    let hit_s = hit_s.expect("the kick never closed the switch");
    let log = sim.supervisor.faults();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].cause, cause);
    let after_s = log[0].t_s - hit_s;
    assert!(
        after_s > allowed_s && after_s < allowed_s + 0.015,
        "{after_s:.3} s after the switch closed, allowed {allowed_s} s"
    );
}

/// The time of the tick at `k` steps of 10 ms after `t0_s`.
fn tick_time(t0_s: f64, k: usize) -> f64 {
    t0_s + k as f64 * 0.01
}

#[test]
fn an_end_switch_that_no_procedure_takes_is_a_fault_in_its_time() {
    // The steer thread keeps steering but never starts the procedure: the robot would
    // sit on the switch, stopped, with nobody told why.
    let s = settings_with(&format!("{KICK_S} endswitch left"), &[]);
    let unhandled_s = s.faults.endswitch_unhandled_s;
    let mut sim = driving_by_joystick(&s);
    let command = SteerCommand {
        endswitch: EndSwitchState::Idle,
        ..sim.steer_command
    };
    let t0_s = sim.now_s();
    let mut hit_s = None;
    for k in 1..=200 {
        let now_s = tick_time(t0_s, k);
        let outputs = tick_by_hand(&mut sim, now_s, &command, |_| {});
        if hit_s.is_none() && sim.supervisor.status().inputs.end_switch_left {
            hit_s = Some(now_s);
        }
        if let Some(hit_s) = hit_s
            && now_s > hit_s + unhandled_s + 0.015
        {
            assert_eq!(outputs, Outputs::SAFE, "at {now_s:.2} s");
        }
    }
    the_only_fault_in_its_time(
        &sim,
        hit_s,
        FaultCause::EndSwitchUnhandled(Side::Left),
        unhandled_s,
    );
    assert_eq!(sim.supervisor.mode(), Mode::Fault);
}

#[test]
fn an_end_switch_still_closed_after_its_time_out_is_a_fault() {
    // The procedure runs and steers back, but the switch's contacts stay closed (a
    // switch jammed by soil): the procedure can never finish, and the operator must be
    // told rather than left with a robot that waits for ever.
    let s = settings_with(&format!("{KICK_S} endswitch left"), &[]);
    let timeout_s = s.faults.endswitch_timeout_s;
    let back_rad = s.steer.endswitch_back_deg.to_radians();
    let mut sim = driving_by_joystick(&s);
    let t0_s = sim.now_s();
    let mut command = sim.steer_command;
    let mut hit_s = None;
    let ticks = ((KICK_S - t0_s + timeout_s + 0.5) * 100.0).round() as usize;
    for k in 1..=ticks {
        let now_s = tick_time(t0_s, k);
        // From the kick on, the switch's contacts stay closed whatever the wheel does.
        let held = hit_s.is_some();
        let outputs = tick_by_hand(&mut sim, now_s, &command, |i| i.end_switch_left |= held);
        if hit_s.is_none() && sim.supervisor.status().inputs.end_switch_left {
            hit_s = Some(now_s);
            // What the procedure commands from its first tick on: stand, steer back.
            command = SteerCommand {
                speed_mps: 0.0,
                wheel_angle_rad: back_rad,
                endswitch: EndSwitchState::Active {
                    side: Side::Left,
                    since_s: now_s,
                },
                ..command
            };
        }
        if let Some(hit_s) = hit_s
            && now_s > hit_s + timeout_s + 0.015
        {
            assert_eq!(outputs, Outputs::SAFE, "at {now_s:.2} s");
        }
    }
    the_only_fault_in_its_time(
        &sim,
        hit_s,
        FaultCause::EndSwitchStuck(Side::Left),
        timeout_s,
    );
}
