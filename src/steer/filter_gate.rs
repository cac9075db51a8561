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
//! - Both sensors suspect at once (the other's last rejection within `BOTH_WITHIN_M` of
//!   travel): the camera and GNSS agree against the filter, so the filter is what is off.
//!   A bump kicks the robot's heading and position, odometry does not feel it, and the
//!   first camera row after it can fall outside the gate; the rows and fixes after it fall
//!   further out as the robot steers by the wrong row, until every one is rejected. Then
//!   the sensor's third rejection in a row resets at once: the camera its offset, heading
//!   and bias, GNSS the row's offset alone. A fix is one number: with the heading widened
//!   too, it set the heading anywhere along the line it allows, and the robot swung off.
//!   (Without this rule GNSS, after its 20 rejections, took the filter's own error into
//!   the map's bias and the robot steered 25 cm off the row on a realistic field.)

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
    /// ... and the robot's travel since its last rejection, m.
    since_rejected_m: [f64; 2],
}

impl GateMemory {
    pub fn new() -> GateMemory {
        GateMemory {
            streak: [0; 2],
            agreed: [0; 2],
            since_rejected_m: [f64::INFINITY; 2],
        }
    }

    /// The robot drove `travelled_m` (either way).
    pub fn travelled(&mut self, travelled_m: f64) {
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

    /// `sensor`'s measurement failed the gate; `limit` rejections in a row reset its
    /// part. `fused`: both sensors feed the filter and the map's bias is estimated.
    pub fn failed(&mut self, sensor: Sensor, limit: u32, fused: bool) -> Verdict {
        let (i, other) = (sensor as usize, 1 - sensor as usize);
        self.agreed[i] = 0;
        self.streak[i] = self.streak[i].saturating_add(1);
        self.since_rejected_m[i] = 0.0;
        let filter_off = fused
            && self.streak[other] >= SUSPECT_AFTER
            && self.since_rejected_m[other] <= BOTH_WITHIN_M;
        let limit = match filter_off {
            true => SUSPECT_AFTER,
            false => limit.max(1),
        };
        if self.streak[i] < limit {
            return Verdict::Reject;
        }
        (self.streak[i], self.agreed[i]) = (0, 0);
        Verdict::Reset(match (sensor, filter_off) {
            (Sensor::Gnss, true) => &[OFFSET],
            _ => sensor.part(fused),
        })
    }
}
