//! A fault that comes back soon after the power-up that cleared it: power-up did not
//! mend its cause, and the operator is told so (with what to check again) rather than
//! being sent round the same fault once more.

use std::mem::discriminant;

use crate::state::fault_cause::FaultCause;

/// The same cause within this long of the power-up that cleared it came back,
/// s. Long enough for an operator to power up, choose a mode and drive off (the
/// contactor may take [supervisor] power_up_timeout_s, the fault's own check its time:
/// a dead encoder showed again 0.6 s after driving off); short enough that a fault
/// minutes later, after the robot worked, is told as a new one.
pub(crate) const CAME_BACK_WITHIN_S: f64 = 30.0;

/// The last cause a power-up cleared, and when; kept in the supervisor, so nothing
/// here allocates.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LastCleared {
    cleared: Option<(FaultCause, f64)>,
}

/// The same cause in the same place: of one kind and, where the kind names a part (an
/// encoder, a side, a thread, an axis, a card), of that part. Measured values aside:
/// the battery's volts or a silence's seconds differ each time.
fn same_cause(a: &FaultCause, b: &FaultCause) -> bool {
    use FaultCause::*;
    match (a, b) {
        (EncoderStuck(x), EncoderStuck(y)) => x == y,
        (EndSwitchUnhandled(x), EndSwitchUnhandled(y)) | (EndSwitchStuck(x), EndSwitchStuck(y)) => {
            x == y
        }
        (ThreadStopped { thread: x, .. }, ThreadStopped { thread: y, .. })
        | (ThreadPanicked { thread: x }, ThreadPanicked { thread: y }) => x == y,
        (JoystickAxis { axis: x, .. }, JoystickAxis { axis: y, .. }) => x == y,
        (Hardware { card: x }, Hardware { card: y }) => x == y,
        _ => discriminant(a) == discriminant(b),
    }
}

impl LastCleared {
    /// A power-up at `power_up_s` cleared a fault of `cause`.
    pub(crate) fn cleared(&mut self, cause: &FaultCause, power_up_s: f64) {
        self.cleared = Some((*cause, power_up_s));
    }

    /// How long after the power-up that cleared the same cause (`same_cause`) `cause`
    /// came at `now_s`, s; None: it did not come back (another cause, or later than the
    /// window).
    pub(crate) fn came_back_after_s(&self, cause: &FaultCause, now_s: f64) -> Option<f64> {
        let (cleared, power_up_s) = self.cleared?;
        let after_s = now_s - power_up_s;
        (same_cause(&cleared, cause) && (0.0..=CAME_BACK_WITHIN_S).contains(&after_s))
            .then_some(after_s)
    }
}

#[cfg(test)]
mod tests {
    use mechweed_hw::{EncoderId, Inputs};

    use super::*;
    use crate::camlink::LinkStatus;
    use crate::config::Settings;
    use crate::rt::health::ThreadHealth;
    use crate::state::modes::{Mode, Request};
    use crate::steer::SteerCommand;
    use crate::supervisor::Supervisor;

    const LEFT_STUCK: FaultCause = FaultCause::EncoderStuck(EncoderId::Left);

    #[test]
    fn the_same_kind_of_cause_within_the_window_came_back_and_nothing_else_did() {
        let mut last = LastCleared::default();
        assert_eq!(
            last.came_back_after_s(&LEFT_STUCK, 1.0),
            None,
            "nothing cleared yet"
        );
        last.cleared(&LEFT_STUCK, 10.0);
        let after_s = last
            .came_back_after_s(&LEFT_STUCK, 10.6)
            .expect("came back");
        assert!((after_s - 0.6).abs() < 1e-9, "{after_s}");
        let other_volts = FaultCause::BatteryLow { volts: 19.0 };
        assert_eq!(
            last.came_back_after_s(&other_volts, 10.6),
            None,
            "another cause"
        );
        let late_s = 10.0 + CAME_BACK_WITHIN_S + 0.01;
        assert_eq!(
            last.came_back_after_s(&LEFT_STUCK, late_s),
            None,
            "after the window"
        );
        // Of one kind whatever its values: the battery reads other volts each time.
        last.cleared(&FaultCause::BatteryLow { volts: 20.0 }, 50.0);
        assert!(last.came_back_after_s(&other_volts, 52.0).is_some());
        assert_eq!(
            last.came_back_after_s(&LEFT_STUCK, 52.0),
            None,
            "cleared before"
        );
    }

    /// A supervisor that has ticked once, its inputs those of a robot ready to power up.
    fn ticked_at(supervisor: &mut Supervisor, t_s: f64) {
        let ready = Inputs {
            pot_v: 2.5,
            battery_v: 25.0,
            estop_front_released: true,
            estop_back_released: true,
            ..Inputs::default()
        };
        supervisor.tick(
            t_s,
            &ready,
            &SteerCommand::default(),
            &LinkStatus::default(),
            &ThreadHealth::default(),
        );
    }

    /// At `fault_s` `cause` latches; at `power_up_s` the operator powers up; at
    /// `again_s` `next` latches. The record of the second fault.
    fn fault_power_up_fault(
        cause: FaultCause,
        power_up_s: f64,
        next: FaultCause,
        again_s: f64,
    ) -> crate::state::status::FaultRecord {
        let mut supervisor = Supervisor::new(&Settings::shipped());
        ticked_at(&mut supervisor, 1.0);
        supervisor.enter_fault(cause);
        assert_eq!(supervisor.faults()[0].came_back_after_s, None, "the first");
        ticked_at(&mut supervisor, power_up_s);
        assert_eq!(supervisor.handle(Request::PowerUp), Ok(()));
        assert_eq!(supervisor.mode(), Mode::Halt, "cleared");
        supervisor.status.t_s = again_s;
        supervisor.enter_fault(next);
        supervisor.status().fault.expect("latched")
    }

    #[test]
    fn the_supervisor_says_a_fault_came_back_after_the_power_up_that_cleared_it() {
        let again = fault_power_up_fault(LEFT_STUCK, 2.0, LEFT_STUCK, 2.6);
        let after_s = again.came_back_after_s.expect("came back");
        assert!((after_s - 0.6).abs() < 1e-9, "{after_s}");

        // The other wheel's encoder is another part: a new fault, not this one again.
        let other = FaultCause::EncoderStuck(EncoderId::Right);
        let other_wheel = fault_power_up_fault(LEFT_STUCK, 2.0, other, 2.6);
        assert_eq!(other_wheel.came_back_after_s, None, "another encoder");

        let camera = FaultCause::CameraLinkLost { silent_s: 0.5 };
        let another = fault_power_up_fault(LEFT_STUCK, 2.0, camera, 2.6);
        assert_eq!(another.came_back_after_s, None, "another cause");

        let late_s = 2.0 + CAME_BACK_WITHIN_S + 1.0;
        let late = fault_power_up_fault(LEFT_STUCK, 2.0, LEFT_STUCK, late_s);
        assert_eq!(late.came_back_after_s, None, "after the window");
    }
}
