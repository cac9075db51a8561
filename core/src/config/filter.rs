//! [filter]: the row filter's model of the row, the robot and the sensors (used with
//! [steer] source = gnss or fused; the filter itself is core/src/steer/filter.rs).

use super::reader::Reader;

/// Longest travel the row filter relates a measurement to the present over (and the
/// longest predict step): its parabola and small angles hold over about a metre.
pub const FILTER_MAX_STEP_M: f64 = 1.0;

/// The row filter's settings, in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterConfig {
    /// How much each part may change per √m driven.
    pub offset_sd_per_sqrt_m: f64,
    pub heading_sd_per_sqrt_m: f64,
    pub curvature_sd_per_sqrt_m: f64,
    pub map_bias_sd_per_sqrt_m: f64,
    pub slip_sd_per_sqrt_m: f64,
    /// The camera's error from frame to frame: offset, m, and angle, rad.
    pub camera_sd_offset_m: f64,
    pub camera_sd_angle_rad: f64,
    /// The camera's lasting error (fused): s.d., m, and the length it lasts, m.
    pub camera_bias_sd_m: f64,
    pub camera_bias_length_m: f64,
    /// Camera estimates below this quality do not update the filter.
    pub fuse_min_quality: u8,
    /// The gate's probability: 0.99, 0.999 or 0.9999.
    pub gate: f64,
    pub camera_rejections_to_reset: u32,
    pub gnss_rejections_to_reset: u32,
}

pub(super) fn load(r: &mut Reader) -> FilterConfig {
    let s = "filter";
    let gates = [0.99, 0.999, 0.9999];
    FilterConfig {
        offset_sd_per_sqrt_m: r.f64(s, "offset_sd_m_per_sqrt_m", 0.0, 1.0),
        heading_sd_per_sqrt_m: r
            .f64(s, "heading_sd_deg_per_sqrt_m", 0.0, 30.0)
            .to_radians(),
        curvature_sd_per_sqrt_m: r.f64(s, "curvature_sd_per_m_per_sqrt_m", 0.0, 1.0),
        map_bias_sd_per_sqrt_m: r.f64(s, "map_bias_sd_m_per_sqrt_m", 0.0, 1.0),
        slip_sd_per_sqrt_m: r.f64(s, "slip_sd_deg_per_sqrt_m", 0.0, 30.0).to_radians(),
        camera_sd_offset_m: r.f64(s, "camera_sd_offset_m", 0.0001, 1.0),
        camera_sd_angle_rad: r.f64(s, "camera_sd_angle_deg", 0.001, 30.0).to_radians(),
        camera_bias_sd_m: r.f64(s, "camera_bias_sd_m", 0.0, 0.5),
        camera_bias_length_m: r.f64(s, "camera_bias_length_m", 0.01, 1000.0),
        fuse_min_quality: r.u64(s, "fuse_min_quality", 0, 100) as u8,
        gate: gates[r.choice(s, "gate", &["0.99", "0.999", "0.9999"])],
        camera_rejections_to_reset: r.u64(s, "camera_rejections_to_reset", 1, 100_000) as u32,
        gnss_rejections_to_reset: r.u64(s, "gnss_rejections_to_reset", 1, 100_000) as u32,
    }
}
