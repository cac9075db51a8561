//! What the row filter's gate remembers of each sensor, and what a run of rejections
//! resets.
//!
//! - A sensor rejected `SUSPECT_AFTER` times in a row is suspect: it is used again only
//!   from the `TRUSTED_AGAIN_AFTER`-th measurement in a row that passes the gate. A weed
//!   patch's frames are 5 to 10 cm off with 1 cm of noise: now and then one comes close
//!   enough to pass, and taken alone it would pull the row towards the weeds and let the
//!   next in.
//! - After `*_rejections_to_reset` rejections in a row the sensor's part of the state is
//!   reset from it (`Sensor::part`): the truth must not stay locked out.
//! - Both sensors rejected at once, and on the same side of the filter's row: the camera
//!   and GNSS agree against the filter, so the filter is what is off. A bump kicks the
//!   robot's heading and position, odometry does not feel it, and the first camera row
//!   after it can fall outside the gate; the rows and fixes after it fall further out as
//!   the robot steers by the wrong row, until every one is rejected. Then each sensor's
//!   own third rejection in a row (the other's being rejected too) resets at once: a
//!   camera row resets the row's offset and heading and the camera's bias, a fix the
//!   row's offset alone (a fix is one number: with the heading widened too, it set the
//!   heading anywhere along the line it allows, and the robot swung off). The other
//!   sensor is then no longer suspect: its rejections were the filter's fault. "At once": the other is not passing on
//!   probation, and its last rejection came within `BOTH_WITHIN_M` of travel. A weed
//!   patch during an RTK jump (with no change of the fix's quality) passes for this
//!   only where both put the row on the same side; the row then follows the fix, as it
//!   does with GNSS alone.

use super::OFFSET;
use super::types::Sensor;

/// A sensor rejected this many times in a row is suspect ...
const SUSPECT_AFTER: u32 = 3;
/// ... until this many of its measurements in a row pass the gate.
const TRUSTED_AGAIN_AFTER: u32 = 3;
/// The other sensor counts as disagreeing now if its last rejection came within this
/// much travel, m: a sensor that has gone silent (a gap in the row, no fix) since its
/// rejections says nothing about the filter now.
const BOTH_WITHIN_M: f64 = 0.5;

/// What to do with a measurement the gate has judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Verdict {
    Use,
    Reject,
    /// Reset these parts of the state, then use the measurement.
    Reset(&'static [usize]),
}

#[derive(Debug, Clone)]
pub(super) struct GateMemory {
    /// Per `Sensor`: rejections in a row ...
    streak: [u32; 2],
    /// ... while suspect, measurements in a row that passed the gate ...
    agreed: [u32; 2],
    /// ... the robot's travel since its last rejection, m ...
    since_rejected_m: [f64; 2],
    /// ... and on which side of the filter's row that rejection put the row's offset.
    rejected_side: [f64; 2],
}

impl GateMemory {
    pub fn new() -> GateMemory {
        GateMemory {
            streak: [0; 2],
            agreed: [0; 2],
            since_rejected_m: [f64::INFINITY; 2],
            rejected_side: [0.0; 2],
        }
    }

    /// The robot drove `travelled_m` (either way).
    pub(crate) fn travelled(&mut self, travelled_m: f64) {
        for since_m in &mut self.since_rejected_m {
            *since_m += travelled_m.abs();
        }
    }

    /// `sensor`'s measurement passed the gate.
    pub fn passed(&mut self, sensor: Sensor) -> Verdict {
        let i = sensor as usize;
        if self.streak[i] >= SUSPECT_AFTER {
            self.agreed[i] += 1;
            if self.agreed[i] < TRUSTED_AGAIN_AFTER {
                return Verdict::Reject;
            }
        }
        (self.streak[i], self.agreed[i]) = (0, 0);
        Verdict::Use
    }

    /// `sensor`'s measurement failed the gate, its row's offset `offset_innovation_m`
    /// from the filter's; `limit` rejections in a row reset its part. `fused`: both
    /// sensors feed the filter and the map's bias is estimated.
    pub fn failed(
        &mut self,
        sensor: Sensor,
        offset_innovation_m: f64,
        limit: u32,
        fused: bool,
    ) -> Verdict {
        let (i, other) = (sensor as usize, 1 - sensor as usize);
        self.agreed[i] = 0;
        self.streak[i] = self.streak[i].saturating_add(1);
        self.since_rejected_m[i] = 0.0;
        self.rejected_side[i] = offset_innovation_m.signum();
        // The other sensor is being rejected now (not passing on probation, not silent
        // since), and puts the row on the same side.
        let filter_off = fused
            && self.streak[other] >= SUSPECT_AFTER
            && self.agreed[other] == 0
            && self.since_rejected_m[other] <= BOTH_WITHIN_M
            && self.rejected_side[other] == self.rejected_side[i];
        let limit = match filter_off {
            true => limit.clamp(1, SUSPECT_AFTER),
            false => limit.max(1),
        };
        if self.streak[i] < limit {
            return Verdict::Reject;
        }
        (self.streak[i], self.agreed[i]) = (0, 0);
        if filter_off {
            // The other's rejections were the filter's fault: its next measurement is
            // judged afresh against the row reset, not on probation.
            (self.streak[other], self.agreed[other]) = (0, 0);
        }
        Verdict::Reset(match (sensor, filter_off) {
            (Sensor::Gnss, true) => &[OFFSET],
            _ => sensor.part(fused),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_suspect_sensor_is_used_again_only_from_its_third_pass_in_a_row() {
        // A weed patch: frames 5 to 10 cm off, one now and then close enough to pass.
        // Each alone would pull the row towards the weeds and let the next one in.
        let mut gate = GateMemory::new();
        let camera = Sensor::Camera;
        for _ in 0..SUSPECT_AFTER {
            assert_eq!(gate.failed(camera, 0.07, 100, false), Verdict::Reject);
        }
        for _ in 1..TRUSTED_AGAIN_AFTER {
            assert_eq!(gate.passed(camera), Verdict::Reject, "a lone pass used");
        }
        // A rejection between starts the count again.
        assert_eq!(gate.failed(camera, 0.07, 100, false), Verdict::Reject);
        for _ in 1..TRUSTED_AGAIN_AFTER {
            assert_eq!(gate.passed(camera), Verdict::Reject, "a lone pass used");
        }
        assert_eq!(gate.passed(camera), Verdict::Use, "never trusted again");
        // Trusted again: from now on each pass is used at once.
        assert_eq!(gate.passed(camera), Verdict::Use);
    }
}
