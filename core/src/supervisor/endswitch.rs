//! The supervisor's side of the end-switch procedure (the steer thread runs the
//! procedure itself, steer/endswitch.rs): latch a switch that closed while driving,
//! however briefly, notice when the procedure is done, and never drive the steering
//! further into a closed switch.

use mechweed_hw::Side;
use mechweed_hw::{Inputs, Outputs};

use crate::steer::SteerCommand;

#[derive(Debug, Default)]
pub(crate) struct EndSwitchLatch {
    /// When the latched switch closed, s.
    since_s: f64,
    /// The steer thread's count of finished procedures, as last seen.
    done_seen: u32,
}

impl EndSwitchLatch {
    /// Latch into `hit` an end switch that closed while `driving`; standing clears it.
    pub fn latch(&mut self, hit: &mut Option<Side>, driving: bool, inputs: &Inputs, now_s: f64) {
        if !driving {
            *hit = None;
            return;
        }
        if hit.is_none() {
            let side = if inputs.end_switch_left {
                Some(Side::Left)
            } else if inputs.end_switch_right {
                Some(Side::Right)
            } else {
                None
            };
            if side.is_some() {
                *hit = side;
                self.since_s = now_s;
            }
        }
    }

    /// The latched switch and when it closed.
    pub fn hit(&self, hit: Option<Side>) -> Option<(Side, f64)> {
        hit.map(|side| (side, self.since_s))
    }

    /// The side of a procedure the steer thread finished since the last call (the
    /// latch is cleared then), or None.
    pub fn finished(&mut self, hit: &mut Option<Side>, steer: &SteerCommand) -> Option<Side> {
        if steer.endswitch_done_count == self.done_seen {
            return None;
        }
        self.done_seen = steer.endswitch_done_count;
        *hit = None;
        steer.endswitch_last_side
    }
}

/// Never drive the steering further into a closed end switch.
pub(crate) fn guard_steering(mut outputs: Outputs, inputs: &Inputs) -> Outputs {
    if inputs.end_switch_left {
        outputs.amp_steer_v = outputs.amp_steer_v.min(0.0);
    }
    if inputs.end_switch_right {
        outputs.amp_steer_v = outputs.amp_steer_v.max(0.0);
    }
    outputs
}
