//! New measurements into the row filter, each at the pose where it was taken: the
//! camera's estimate at its image's capture, a GNSS fix where the receiver measured it
//! (its latency before it came), both by the odometry since.

use super::RowSources;
use crate::camlink::LinkStatus;
use crate::config::SteerSource;
use crate::gnss::GnssStatus;
use crate::state::steering::Steering;
use crate::steer::filter::Outcome;
use crate::steer::receiver::receiver_moved_sd_m;

impl RowSources {
    /// A new usable camera estimate into the filter, at its capture pose.
    pub(super) fn fuse_camera(&mut self, link: &LinkStatus) {
        let estimate = link.last_usable;
        if estimate.quality < self.fuse_min_quality {
            return;
        }
        // An image older than the odometry kept is placed at the oldest tick kept.
        let (since, _) = self.odometry.since(link.last_usable_s - self.latency_s);
        // A rejected row (a weed patch) is counted by the filter; nothing else to do.
        self.filter.update_camera(
            estimate.offset_m,
            estimate.angle_rad,
            self.camera_x_m,
            self.camera_sd_offset_m,
            self.camera_sd_angle_rad,
            since,
        );
    }

    /// A new trusted fix into the filter, against the row map; the robot has driven
    /// `driven_m` (odometry).
    pub(super) fn fuse_gnss(&mut self, gnss: &GnssStatus, driven_m: f64) {
        let (Some(fix), Some(place)) = (gnss.last_fix, &mut self.place) else {
            return;
        };
        if gnss.last_fix_s <= self.used_fix_s {
            return;
        }
        self.used_fix_s = gnss.last_fix_s;
        if !self.fix_checks.admit(&fix, &self.gnss) {
            return;
        }
        // The fix is of the pose the receiver measured at, its latency before it came; the
        // row's heading from the robot then locates the rear axle from the antenna. A fix
        // older than the odometry kept (measured before autonomous mode began) cannot be
        // placed: the next one, a tenth of a second later, can.
        let (since, known) = self.odometry.since(gnss.last_fix_s - self.gnss.latency_s);
        if !known {
            return;
        }
        let then = self.filter.state_before(since);
        // A fix beside no row of the map (another field's map, a headland) is no GNSS
        // to steer by: the robot must not drive on the filter's guess.
        let Some(view) = place.locate(&fix, then.heading_rad, driven_m) else {
            return;
        };
        // Until the fixes have shown which way the robot drives its row (place.rs), they
        // cannot say on which side the row is: they are heard, and the filter's row, the
        // one straight ahead where GNSS steers alone, is held for those few decimetres.
        if !view.direction_known {
            self.gnss_good_s = gnss.last_fix_s;
            return;
        }
        // Fused with the camera in the filter: the receiver's own error, which the map's
        // bias carries, may have moved since the last fix used. (GNSS alone, the map is
        // the row: a wider bias would take part of each fix from the robot's offset.)
        let last = self.last_fix_used.replace((fix.quality, gnss.last_fix_s));
        let camera_in = matches!(self.steering, Steering::Fused | Steering::FilterCamera);
        if self.s.source == SteerSource::Fused && camera_in {
            let (used, since_s) = match last {
                Some((quality, t_s)) => (Some(quality), gnss.last_fix_s - t_s),
                None => (None, f64::INFINITY),
            };
            if let Some(sd_m) = receiver_moved_sd_m(used, fix.quality, since_s) {
                self.filter.widen_map_bias(sd_m);
            }
        }
        let sd_m = fix.sd_m().unwrap_or(fix.quality.typical_sd_m());
        // GNSS is there while the filter takes its fixes: not while its gate rejects them
        // (they disagree with the row), nor while it refuses them (a fix it cannot relate
        // to now), nor on RTK float alone for long (fix_checks.rs). Then GNSS is lost after
        // its time-out, and the robot stops saying why.
        let outcome = self
            .filter
            .update_gnss(view.offset_m, sd_m.max(0.005), since);
        let used = matches!(outcome, Outcome::Used | Outcome::Reset);
        if (self.fix_checks).heard(&fix, used, driven_m, camera_in, &self.gnss) {
            self.gnss_good_s = gnss.last_fix_s;
        }
    }
}
