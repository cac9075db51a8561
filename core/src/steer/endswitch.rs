//! The end-switch procedure: when the steering reached an end switch while driving,
//! stop, steer back off the switch towards the centre, and report, so that the
//! operator decides what happens next (the supervisor then goes to Halt).
//!
//! The supervisor latches the hit (the steering regulator may pull the wheel off the
//! switch again before this thread's next tick), stops the drive at once and never
//! drives the steering further into the switch; this procedure finishes the job.

use mechweed_hw::Inputs;
use mechweed_hw::Side;

/// Where the procedure is; the supervisor watches it (a switch that stays closed
/// without the procedure running is a fault).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum EndSwitchState {
    #[default]
    Idle,
    Active {
        side: Side,
        since_s: f64,
    },
}

/// The wheel angle must come this close to the back-off angle, rad.
const ANGLE_TOLERANCE_RAD: f64 = 0.035;
/// The robot counts as stopped below this, m/s.
const STOPPED_MPS: f64 = 0.02;

#[derive(Debug, Clone, Default)]
pub(crate) struct EndSwitchProcedure {
    pub state: EndSwitchState,
    /// Procedures completed so far; the supervisor reacts when it changes.
    pub done_count: u32,
    pub last_side: Option<Side>,
}

impl EndSwitchProcedure {
    /// Advance the procedure for the supervisor's latched `hit`. Returns the
    /// (speed, wheel angle) it commands while active.
    pub fn tick(
        &mut self,
        hit: Option<Side>,
        inputs: &Inputs,
        speed_mps: f64,
        wheel_angle_rad: f64,
        back_deg: f64,
        now_s: f64,
    ) -> Option<(f64, f64)> {
        if self.state == EndSwitchState::Idle {
            let side = hit?;
            self.state = EndSwitchState::Active {
                side,
                since_s: now_s,
            };
        }
        let EndSwitchState::Active { side, .. } = self.state else {
            return None;
        };
        let target_rad = match side {
            Side::Left => back_deg.to_radians(),
            Side::Right => -back_deg.to_radians(),
        };
        let off_switch = !inputs.end_switch_left && !inputs.end_switch_right;
        if off_switch
            && (wheel_angle_rad - target_rad).abs() < ANGLE_TOLERANCE_RAD
            && speed_mps.abs() < STOPPED_MPS
        {
            self.state = EndSwitchState::Idle;
            self.done_count += 1;
            self.last_side = Some(side);
        }
        Some((0.0, target_rad))
    }

    /// Abandon a procedure (the mode changed under it).
    pub(crate) fn cancel(&mut self) {
        self.state = EndSwitchState::Idle;
    }
}
