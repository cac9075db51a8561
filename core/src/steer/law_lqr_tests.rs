//! The lqr law's two designs: quick near the row, calm far from it.

use super::*;

/// The wheel angle per metre of the row's offset `offset_m` (no heading, wheel
/// straight) at 1 m/s.
fn angle_per_m(offset_m: f64) -> f64 {
    let mut law = LqrLaw::new(&Settings::shipped());
    let row = RowState {
        offset_m,
        heading_rad: 0.0,
        curvature_per_m: 0.0,
        map_bias_m: 0.0,
        slip_rad: 0.0,
        camera_bias_m: 0.0,
    };
    let motion = Motion {
        speed_mps: 1.0,
        yaw_rate_rps: 0.0,
        wheel_angle_rad: 0.0,
    };
    law.update(&row, 0.0, &motion).wheel_angle_rad / offset_m
}

#[test]
fn near_the_row_the_law_steers_quicker_than_far_from_it() {
    // The row to the left: the wheel turns left, towards it.
    let (near, far) = (angle_per_m(0.005), angle_per_m(0.05));
    assert!(far > 0.0, "{far}");
    // The cheaper wheel near the row: its gain on the offset is the larger.
    assert!(near > 1.3 * far, "{near} {far} rad per m");
    // Beyond FAR_M only the calm design steers, whatever the offset; between, a blend.
    assert!((angle_per_m(0.04) - far).abs() < 1e-9 * far);
    let between = angle_per_m(0.02);
    assert!(far < between && between < near, "{between}");
    // The side does not matter.
    assert!((angle_per_m(-0.05) - far).abs() < 1e-9 * far);
}
