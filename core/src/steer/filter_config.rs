//! The row filter's settings from robot.ini's [filter], for the source that steers.

use super::filter::{FilterSettings, GateProbability};
use crate::config::{FilterConfig, SteerSource};

/// GNSS or the camera alone: the row's offset at start, s.d., m (a robot put down anywhere
/// near its row).
const INITIAL_OFFSET_SD_M: f64 = 0.5;

/// The filter's settings from [filter], for a source. GNSS alone has nothing to tell
/// the map's error from the robot's offset by: the map is taken as the row (its bias
/// known to be 0), or the filter would split each GNSS offset between the two and steer
/// by a part of it. The camera's lasting error is told from the map's only with both.
pub(crate) fn filter_settings(c: &FilterConfig, source: SteerSource) -> FilterSettings {
    let mut f = FilterSettings {
        offset_sd_per_sqrt_m: c.offset_sd_per_sqrt_m,
        heading_sd_per_sqrt_m: c.heading_sd_per_sqrt_m,
        curvature_sd_per_sqrt_m: c.curvature_sd_per_sqrt_m,
        map_bias_sd_per_sqrt_m: c.map_bias_sd_per_sqrt_m,
        slip_sd_per_sqrt_m: c.slip_sd_per_sqrt_m,
        camera_bias_length_m: c.camera_bias_length_m,
        gate: match c.gate {
            g if g < 0.995 => GateProbability::P0_99,
            g if g < 0.9995 => GateProbability::P0_999,
            _ => GateProbability::P0_9999,
        },
        camera_rejections_to_reset: c.camera_rejections_to_reset,
        gnss_rejections_to_reset: c.gnss_rejections_to_reset,
        ..FilterSettings::default()
    };
    match source {
        SteerSource::Gnss => {
            f.map_bias_sd_per_sqrt_m = 0.0;
            f.initial_sd.map_bias_m = 0.0;
            // Before its first fix the filter does not know where the row is: a robot
            // put down 40 cm beside it must be told so by that fix, not have it rejected
            // (a rejected fix is not heard, and the robot would stop for want of GNSS).
            f.initial_sd.offset_m = INITIAL_OFFSET_SD_M;
        }
        SteerSource::Fused => {
            f.camera_bias_sd_m = c.camera_bias_sd_m;
            f.initial_sd.camera_bias_m = c.camera_bias_sd_m;
        }
        // The camera alone, as GNSS alone: its first row may be anywhere in its view (a
        // start beside the row, plants found after a gap at the start).
        SteerSource::Camera => f.initial_sd.offset_m = INITIAL_OFFSET_SD_M,
    }
    f
}
