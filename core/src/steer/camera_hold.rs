//! A camera computer that sees no plants (a gap in the row) may go on sending the last
//! estimate it made, unchanged but with less confidence, as if it were new. Taken as new,
//! that row line moves with the robot: the steering law turns towards it, the line turns
//! too, and the robot turns in a circle off its row. Known for what it is (the same
//! offset and angle to the last digit, at a lower quality than the camera gave before,
//! when they first came or in the frame before, in case that one was lost), the estimate
//! keeps the time it first came, so that the law moves it by all the robot's motion
//! since; and it is steered by for a limited distance only.
//!
//! The same numbers at the same quality are a new image that saw the same: a camera
//! without noise on a robot on its row sends them, and on a side slope, where the robot
//! slides sideways unseen by odometry, only the new image is right.

use mechweed_hw::camproto::RowEstimate;

/// The estimate last steered by: its numbers and quality, when it first came, and the
/// distance the robot had driven then.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct CameraHold {
    numbers: Option<(f64, f64)>,
    /// The quality the camera gave when these numbers first came or just before.
    quality_before: u8,
    /// The quality of the last frame that came.
    last_quality: u8,
    first_s: f64,
    first_distance_m: f64,
    last_arrival_s: f64,
    repeated: bool,
}

/// What the hold says of the link's last usable estimate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Held {
    /// When its image's estimate first came, s.
    pub first_s: f64,
    /// The robot's travel since then, m (0 for a new estimate).
    pub held_m: f64,
    /// A new image's estimate arrived since the last call.
    pub new: bool,
    /// The camera repeats an old image's estimate.
    pub repeated: bool,
}

impl CameraHold {
    /// The link's last usable `estimate`, which arrived at `arrived_s`, with the robot
    /// having driven `distance_m` (odometry).
    pub fn see(&mut self, estimate: &RowEstimate, arrived_s: f64, distance_m: f64) -> Held {
        let numbers = (estimate.offset_m, estimate.angle_rad);
        let arrived = arrived_s > self.last_arrival_s;
        self.last_arrival_s = self.last_arrival_s.max(arrived_s);
        let old_image = self.numbers == Some(numbers) && estimate.quality < self.quality_before;
        let new = arrived && !old_image;
        if new || self.numbers.is_none() {
            *self = CameraHold {
                numbers: Some(numbers),
                quality_before: estimate.quality.max(self.last_quality),
                last_quality: estimate.quality,
                first_s: arrived_s,
                first_distance_m: distance_m,
                last_arrival_s: self.last_arrival_s,
                repeated: false,
            };
        } else if arrived {
            self.repeated = true;
            self.last_quality = estimate.quality;
        }
        Held {
            first_s: self.first_s,
            held_m: (distance_m - self.first_distance_m).abs(),
            new,
            repeated: self.repeated,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(offset_m: f64, angle_rad: f64, quality: u8) -> RowEstimate {
        RowEstimate {
            seq: 0,
            angle_rad,
            offset_m,
            quality,
        }
    }

    #[test]
    fn a_repeated_estimate_keeps_its_first_time_and_counts_the_distance_since() {
        let mut hold = CameraHold::default();
        let first = hold.see(&row(0.01, 0.002, 90), 1.0, 10.0);
        assert_eq!((first.first_s, first.held_m), (1.0, 0.0));
        assert!(first.new && !first.repeated);
        // A steer tick between frames: nothing new, nothing repeated.
        let between = hold.see(&row(0.01, 0.002, 90), 1.0, 10.05);
        assert!(!between.new && !between.repeated);
        // The camera sends the same numbers again, twice, with less confidence: a gap.
        hold.see(&row(0.01, 0.002, 40), 1.1, 10.1);
        let again = hold.see(&row(0.01, 0.002, 40), 1.2, 10.2);
        assert_eq!(again.first_s, 1.0);
        assert!((again.held_m - 0.2).abs() < 1e-12);
        assert!(again.repeated && !again.new);
        // New numbers end the hold.
        let seen = hold.see(&row(0.012, 0.002, 90), 1.3, 10.3);
        assert_eq!((seen.first_s, seen.held_m), (1.3, 0.0));
        assert!(seen.new && !seen.repeated);
    }

    #[test]
    fn a_repeat_whose_first_frame_was_lost_is_known_by_the_frame_before() {
        let mut hold = CameraHold::default();
        hold.see(&row(0.02, 0.001, 90), 1.0, 10.0);
        // The frame with (0.01, 0.002) at quality 90 was lost on the way: its numbers
        // first come repeated, at 40.
        let first = hold.see(&row(0.01, 0.002, 40), 1.2, 10.2);
        assert!(first.new && !first.repeated);
        let again = hold.see(&row(0.01, 0.002, 40), 1.3, 10.3);
        assert!(again.repeated && !again.new);
        assert_eq!(again.first_s, 1.2);
    }

    #[test]
    fn the_same_numbers_at_the_same_quality_are_a_new_image() {
        // A camera without noise on a robot on its row.
        let mut hold = CameraHold::default();
        hold.see(&row(0.0, 0.0, 90), 1.0, 10.0);
        let next = hold.see(&row(0.0, 0.0, 90), 1.1, 10.1);
        assert!(next.new && !next.repeated);
        assert_eq!((next.first_s, next.held_m), (1.1, 0.0));
    }
}
