//! The supervisor's rules for the operator's requests: why a mode or a power-up would
//! be refused now. The supervisor decides with them (requests.rs), and the GUI asks
//! them to grey out a button and say why, so that the two never disagree.

use crate::state::modes::{Mode, Refusal, Request};
use crate::state::status::{PowerState, Status};

/// Below this the robot counts as standing, m/s.
pub(crate) const STANDING_MPS: f64 = 0.01;

/// The supervisor's rule for a mode request: why it would refuse `wanted` now, or None.
pub(crate) fn mode_refusal(wanted: Mode, st: &Status) -> Option<Refusal> {
    // Before its first tick the robot stands in Halt with its outputs safe: a HALT
    // asked then is already done, and is never refused.
    if st.tick == 0 && wanted != Mode::Halt {
        return Some(Refusal::NotStarted);
    }
    match wanted {
        Mode::Fault => Some(Refusal::FaultIsNotAMode),
        _ if st.mode == Mode::Fault => Some(Refusal::FaultLatched(st.fault.map(|f| f.cause))),
        Mode::Halt => None,
        Mode::Test if st.mode != Mode::Halt => Some(Refusal::OnlyFromHalt(st.mode)),
        Mode::Test if st.measured.speed_mps.abs() > STANDING_MPS => Some(Refusal::NotStanding),
        Mode::Test => None,
        // Joystick or Autonomous: from Halt, or switching between the two.
        _ if !(st.mode == Mode::Halt || st.mode.drives()) => Some(Refusal::OnlyFromHalt(st.mode)),
        _ if matches!(st.power, PowerState::Closing { .. }) => Some(Refusal::PowerComingOn),
        _ if st.power != PowerState::On => Some(Refusal::NotPowered),
        _ if !st.measured.calibrated => Some(Refusal::NotCalibrated),
        Mode::Autonomous => st.sensor_down.map(Refusal::SensorDown),
        _ => None,
    }
}

/// How long after the dead-man was last held a person still counts as at the robot, s:
/// a hand that slips off for a moment does not hand the robot to the bus.
pub(crate) const DEADMAN_GRACE_S: f64 = 2.0;

/// The rule for a request that came over the bus: a person at the robot comes first.
/// While someone holds the joystick's dead-man (or did, less than DEADMAN_GRACE_S ago,
/// at `deadman_held_s`), in any mode, the bus may not send the robot into Autonomous or
/// Test: a HALT first and then Autonomous does not take it from them either. Halt and
/// Joystick stay allowed; the other rules still apply after this one.
pub(crate) fn remote_refusal(
    request: &Request,
    st: &Status,
    deadman_held_s: f64,
) -> Option<Refusal> {
    let person_there = st.t_s - deadman_held_s < DEADMAN_GRACE_S;
    match request {
        Request::Mode(Mode::Autonomous | Mode::Test) if person_there => {
            Some(Refusal::PersonAtTheRobot)
        }
        _ => None,
    }
}

/// The supervisor's rule for `PowerUp`: why it would refuse now, or None.
pub fn power_up_refusal(st: &Status) -> Option<Refusal> {
    if st.tick == 0 {
        return Some(Refusal::NotStarted);
    }
    if let Some(cause) = st.standing_cause {
        return Some(Refusal::CauseStillActive(cause));
    }
    if st.mode == Mode::Test {
        return Some(Refusal::PanelHasThePower);
    }
    if st.mode != Mode::Fault && st.power != PowerState::Off {
        return Some(Refusal::AlreadyPowered);
    }
    None
}

/// Why the operator cannot have `wanted` now, in words; None if the supervisor would take it.
pub fn why_not(wanted: Mode, st: &Status) -> Option<String> {
    mode_refusal(wanted, st).map(|r| r.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::fault_cause::FaultCause;

    #[test]
    fn the_bus_never_takes_the_robot_from_a_person_holding_the_dead_man() {
        let mut st = Status {
            t_s: 10.0,
            tick: 1000,
            mode: Mode::Joystick,
            ..Status::default()
        };
        let auto = Request::Mode(Mode::Autonomous);
        // Held now, in Joystick and after a HALT alike.
        for mode in [Mode::Joystick, Mode::Halt] {
            st.mode = mode;
            for wanted in [Mode::Autonomous, Mode::Test] {
                let asked = Request::Mode(wanted);
                assert_eq!(
                    remote_refusal(&asked, &st, 10.0),
                    Some(Refusal::PersonAtTheRobot),
                    "{mode} -> {wanted}"
                );
            }
            assert_eq!(remote_refusal(&Request::Mode(Mode::Halt), &st, 10.0), None);
        }
        // Let go a moment ago: still the person's.
        assert!(remote_refusal(&auto, &st, 10.0 - DEADMAN_GRACE_S + 0.1).is_some());
        // Let go long enough: the bus may ask, and the supervisor's rules decide.
        assert_eq!(
            remote_refusal(&auto, &st, 10.0 - DEADMAN_GRACE_S - 0.1),
            None
        );
        assert_eq!(remote_refusal(&auto, &st, f64::NEG_INFINITY), None);
    }

    #[test]
    fn fault_is_never_a_mode_to_ask_for() {
        // Powered, calibrated and standing: every other rule would let a mode in. Fault
        // without a cause would leave the operator a latched fault that says nothing.
        let mut st = Status {
            tick: 1,
            power: PowerState::On,
            ..Status::default()
        };
        st.measured.calibrated = true;
        for mode in [Mode::Halt, Mode::Joystick, Mode::Autonomous] {
            st.mode = mode;
            assert_eq!(
                mode_refusal(Mode::Fault, &st),
                Some(Refusal::FaultIsNotAMode),
                "{mode} -> fault"
            );
        }
    }

    #[test]
    fn why_not_says_what_the_supervisor_would_refuse() {
        let mut st = Status::default();
        assert_eq!(mode_refusal(Mode::Halt, &st), None, "HALT is never refused");
        assert_eq!(mode_refusal(Mode::Joystick, &st), Some(Refusal::NotStarted));
        assert_eq!(power_up_refusal(&st), Some(Refusal::NotStarted));
        st.tick = 1;
        assert_eq!(
            why_not(Mode::Autonomous, &st).as_deref(),
            Some("motor power is off: press Power up first")
        );
        assert_eq!(why_not(Mode::Test, &st), None, "test needs no power");
        // Power up accepted, the contactor still closing: not "press Power up".
        st.power = PowerState::Closing { since_s: 0.5 };
        assert_eq!(
            mode_refusal(Mode::Autonomous, &st),
            Some(Refusal::PowerComingOn)
        );
        assert!(
            why_not(Mode::Joystick, &st)
                .unwrap()
                .contains("still coming on")
        );
        st.power = PowerState::Off;
        assert_eq!(why_not(Mode::Halt, &st), None);
        st.power = PowerState::On;
        assert_eq!(
            why_not(Mode::Joystick, &st).as_deref(),
            Some("the steering is still being calibrated")
        );
        st.measured.calibrated = true;
        assert_eq!(why_not(Mode::Joystick, &st), None);
        assert_eq!(power_up_refusal(&st), Some(Refusal::AlreadyPowered));
        // In Test the panel's relay switch is the power switch, not Power up.
        st.mode = Mode::Test;
        st.power = PowerState::Off;
        assert_eq!(power_up_refusal(&st), Some(Refusal::PanelHasThePower));
        st.power = PowerState::On;
        st.mode = Mode::Halt;
        st.mode = Mode::Autonomous;
        st.measured.speed_mps = 0.5;
        assert_eq!(
            mode_refusal(Mode::Test, &st),
            Some(Refusal::OnlyFromHalt(Mode::Autonomous))
        );
        st.mode = Mode::Halt;
        assert_eq!(mode_refusal(Mode::Test, &st), Some(Refusal::NotStanding));
        st.mode = Mode::Fault;
        st.standing_cause = Some(FaultCause::EstopBack);
        assert_eq!(
            power_up_refusal(&st),
            Some(Refusal::CauseStillActive(FaultCause::EstopBack))
        );
        assert!(
            why_not(Mode::Halt, &st)
                .unwrap()
                .starts_with("a fault is latched")
        );
    }
}
