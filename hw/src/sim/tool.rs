//! The weeding tool's path relative to the row: where the tool is now, and the
//! cross-track samples the benchmark is judged by.
//!
//! the simulated plant: measure after the first 5 m (`SimParams::cross_track_from_m`), against the interpolated centre line. One
//! sample per centimetre travelled by the rear axle, while the tool is within the row.

use super::body::Pose;
use super::crosstrack::{CrossTrackStats, SAMPLE_SPACING_M};
use super::field::{Field, Projection};

pub(crate) struct ToolTrack {
    /// Tool point along the heading from the rear axle, m (negative = behind).
    offset_m: f64,
    /// No samples before this distance travelled, m.
    from_m: f64,
    hint: usize,
    now: Projection,
    row_done: bool,
    stats: CrossTrackStats,
    /// Next centimetre of travel at which to take a sample.
    next_mark: u64,
}

impl ToolTrack {
    pub fn new(offset_m: f64, from_m: f64) -> ToolTrack {
        ToolTrack {
            offset_m,
            from_m,
            hint: 0,
            now: Projection::default(),
            row_done: false,
            stats: CrossTrackStats::new(),
            next_mark: 0,
        }
    }

    /// Signed offset of the tool from the row, m (positive = tool is left of the row).
    pub fn cross_track_m(&self) -> f64 {
        self.now.signed_offset_m
    }

    /// The tool has passed the end of the row.
    pub fn row_done(&self) -> bool {
        self.row_done
    }

    pub fn stats(&self) -> &CrossTrackStats {
        &self.stats
    }

    /// Locate the tool for the robot at `pose` having travelled `distance_m`, and take a
    /// sample for every centimetre mark passed since the last call.
    pub fn measure(&mut self, field: &Field, pose: &Pose, distance_m: f64) {
        let (x_m, y_m) = pose.point_ahead(self.offset_m);
        self.now = field.project(x_m, y_m, &mut self.hint);
        self.row_done = self.now.s_m > field.length_m();
        let marks_passed = (distance_m / SAMPLE_SPACING_M).floor() as u64;
        if marks_passed < self.next_mark {
            return;
        }
        let count = marks_passed - self.next_mark + 1;
        self.next_mark = marks_passed + 1;
        if distance_m >= self.from_m && !self.row_done {
            self.stats.record(self.now.signed_offset_m, count);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::params::{RowShape, SimParams};

    #[test]
    fn samples_every_centimetre_from_5_m() {
        let field = Field::new(&SimParams {
            row: RowShape::Straight,
            row_length_m: 20.0,
            ..SimParams::default()
        });
        let mut tool = ToolTrack::new(-0.4, 5.0);
        let mut pose = Pose {
            x_m: 0.0,
            y_m: 0.03,
            heading_rad: 0.0,
        };
        for k in 0..=1000 {
            pose.x_m = k as f64 * 0.0075;
            tool.measure(&field, &pose, pose.x_m);
        }
        assert!((tool.cross_track_m() - 0.03).abs() < 1e-12 && !tool.row_done());
        // 7.5 m travelled: marks 500..=750.
        assert!(
            (250..=251).contains(&tool.stats().samples()),
            "{}",
            tool.stats().samples()
        );
    }
}
