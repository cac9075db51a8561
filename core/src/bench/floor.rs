//! What no filter could do better than on the realistic field: the error at the tool of
//! an exact Kalman filter of the field's own error model, in its steady state, for each
//! source and speed, as the benchmark measures it (the s.d. over the measured stretch of
//! one row, its mean taken out). `bench rows --field realistic` prints it beside the row
//! filter's measured error, so that a figure asked of the benchmark can be checked
//! against what the sensors allow before any steering law is blamed: whatever steers,
//! the robot cannot correct what no estimate knows, and the steering's own error adds to
//! this one. It is an expectation over fields like this one: a single row's draw of the
//! map's and the slope's slow errors can fall either side of it.
//!
//! The model, per camera frame (the robot drives ds = speed / frame rate between them),
//! state: the rear axle's offset y from the row, the heading error h, the crab angle c,
//! the camera's lasting error b (camera_bias) and the map's error m:
//!     y' = y + ds (h + c), h' = h + bump heading kicks, y also gains bump side kicks,
//!     c, b, m: first-order (Gauss-Markov) over distance with the field's s.d. and lengths
//!     (the slope's levels, uniform in 0..max, have the s.d. max / sqrt 12);
//! camera: y + x_c h + b and h, with the simulated camera's noise; GNSS (RTK fixed): the
//! antenna's y + x_a h + m with the receiver's noise (scaled to the camera's frame rate).
//! Left out, because they can only add: gaps, weed patches, float episodes, wheel slip,
//! a curved row, the camera's latency and the receiver's slow wander. Bumps are taken as
//! a steady trickle (their variance per metre) rather than as kicks.

use mechweed_hw::sim::SimParams;
use mechweed_hw::sim::gnss_model::RTK_FIXED_WHITE_SD_M;
use nalgebra::{SMatrix, SVector};

use crate::config::SteerSource;

const N: usize = 5;
const Y: usize = 0;
const HEADING: usize = 1;
const CRAB: usize = 2;
const CAMERA_BIAS: usize = 3;
const MAP_BIAS: usize = 4;
type Matrix = SMatrix<f64, N, N>;

use crate::steer::lqr::riccati;

/// Where the robot's sensors and tool are, ahead of the rear axle, m.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Geometry {
    pub tool_x_m: f64,
    pub camera_x_m: f64,
    pub antenna_x_m: f64,
}

/// The s.d. of the tool's error over `measured_m` of row that an exact Kalman filter of
/// `plant`'s realistic field leaves when `source` steers at `speed_mps`, cm (None for a
/// speed or a distance that is not positive).
pub(crate) fn floor_cm(
    plant: &SimParams,
    at: Geometry,
    source: SteerSource,
    speed_mps: f64,
    measured_m: f64,
) -> Option<f64> {
    if !(speed_mps > 0.0 && plant.camera_rate_hz > 0.0 && measured_m > 0.0) {
        return None;
    }
    let t = &plant.tier;
    let ds = speed_mps / plant.camera_rate_hz;
    let forget = |length_m: f64| {
        if length_m > 0.0 {
            (-ds / length_m).exp()
        } else {
            0.0
        }
    };
    let (a_crab, a_camera, a_map) = (
        forget(t.slope_length_m),
        forget(t.camera_bias_length_m),
        forget(plant.gnss.map_error_length_m),
    );
    let mut f = Matrix::identity();
    f[(Y, HEADING)] = ds;
    f[(Y, CRAB)] = ds;
    f[(CRAB, CRAB)] = a_crab;
    f[(CAMERA_BIAS, CAMERA_BIAS)] = a_camera;
    f[(MAP_BIAS, MAP_BIAS)] = a_map;
    let per_bump = ds / t.bump_every_m.max(f64::MIN_POSITIVE);
    let crab_sd_rad = t.slope_max_deg.to_radians() / 12f64.sqrt();
    let q = Matrix::from_diagonal(&SVector::from([
        t.bump_side_sd_m.powi(2) * per_bump,
        t.bump_heading_sd_deg.to_radians().powi(2) * per_bump,
        crab_sd_rad.powi(2) * (1.0 - a_crab * a_crab),
        t.camera_bias_sd_m.powi(2) * (1.0 - a_camera * a_camera),
        plant.gnss.map_error_sd_m.powi(2) * (1.0 - a_map * a_map),
    ]));
    let (camera_r, gnss_r) = sensor_variances(plant);
    let camera_h = [
        [1.0, at.camera_x_m, 0.0, 1.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.0],
    ];
    let gnss_h = [1.0, at.antenna_x_m, 0.0, 0.0, 1.0];
    let (p, a) = match source {
        SteerSource::Camera => steady_posterior(
            &f,
            &q,
            &SMatrix::<f64, 2, N>::from_row_slice(camera_h.as_flattened()),
            &SMatrix::from_diagonal(&SVector::from(camera_r)),
        ),
        SteerSource::Gnss => steady_posterior(
            &f,
            &q,
            &SMatrix::<f64, 1, N>::from_row_slice(&gnss_h),
            &SMatrix::from_element(gnss_r),
        ),
        SteerSource::Fused => {
            let mut h = SMatrix::<f64, 3, N>::zeros();
            for (row, values) in camera_h.iter().chain([&gnss_h]).enumerate() {
                h.row_mut(row).copy_from_slice(values);
            }
            let r = SVector::from([camera_r[0], camera_r[1], gnss_r]);
            steady_posterior(&f, &q, &h, &SMatrix::from_diagonal(&r))
        }
    }?;
    let mut tool = SVector::<f64, N>::zeros();
    tool[Y] = 1.0;
    tool[HEADING] = at.tool_x_m;
    let frames = ((measured_m / ds).round() as usize).max(1);
    let variance = within_stretch_variance(&p, &a, &tool, frames);
    (variance >= 0.0).then(|| variance.sqrt() * 100.0)
}

/// Per camera frame, the variances of the camera's offset (m²) and angle (rad²) and of
/// RTK fixed GNSS's position across the row (m²), white.
pub(crate) fn sensor_variances(plant: &SimParams) -> ([f64; 2], f64) {
    let camera = [
        plant.camera_noise_offset_m.powi(2),
        plant.camera_noise_angle_deg.to_radians().powi(2),
    ];
    // Fewer fixes than frames: each frame's share of GNSS is as good as that many fixes.
    let fixes_per_frame = plant.gnss.rate_hz / plant.camera_rate_hz;
    let gnss = RTK_FIXED_WHITE_SD_M.powi(2) / fixes_per_frame.max(f64::MIN_POSITIVE);
    (camera, gnss)
}

/// The expected variance of tool . e over `frames` successive frames about their own
/// mean, for the steady error e with covariance p that moves on as e' = a e + noise:
/// the variance less that of the mean, (1/n) (V + 2 sum over lags k of (1 - k/n) C(k)),
/// C(k) = tool . a^k p . tool. The error's slow part (the map's, the slope's) is largely
/// a row's own mean, which the s.d. leaves out.
pub(crate) fn within_stretch_variance<const S: usize>(
    p: &SMatrix<f64, S, S>,
    a: &SMatrix<f64, S, S>,
    tool: &SVector<f64, S>,
    frames: usize,
) -> f64 {
    let at_tool = |m: &SMatrix<f64, S, S>| (tool.transpose() * m * tool)[0];
    let n = frames as f64;
    let variance = at_tool(p);
    let (mut lagged, mut sum) = (*p, variance);
    for lag in 1..frames {
        lagged = a * lagged;
        sum += 2.0 * (1.0 - lag as f64 / n) * at_tool(&lagged);
    }
    variance - sum / n
}

/// The covariance just after a measurement, once predict (f, q) and update (h, r) have
/// run long enough to forget the start, and how the error after one measurement carries
/// into the next, (I - K H) f; None if anything does not stay finite.
#[allow(clippy::type_complexity)]
fn steady_posterior<const S: usize, const M: usize>(
    f: &SMatrix<f64, S, S>,
    q: &SMatrix<f64, S, S>,
    h: &SMatrix<f64, M, S>,
    r: &SMatrix<f64, M, M>,
) -> Option<(SMatrix<f64, S, S>, SMatrix<f64, S, S>)> {
    let (prior, k) = steady_filter(f, q, h, r)?;
    let i_kh = SMatrix::<f64, S, S>::identity() - k * h;
    // Joseph's form keeps the posterior symmetric and positive.
    let p = i_kh * prior * i_kh.transpose() + k * r * k.transpose();
    let carried = i_kh * f;
    let finite = p.iter().chain(carried.iter()).all(|v| v.is_finite());
    finite.then_some((p, carried))
}

/// The steady Kalman filter of predict (f, q) and update (h, r): its predicted
/// covariance and its gain.
#[allow(clippy::type_complexity)]
pub(crate) fn steady_filter<const S: usize, const M: usize>(
    f: &SMatrix<f64, S, S>,
    q: &SMatrix<f64, S, S>,
    h: &SMatrix<f64, M, S>,
    r: &SMatrix<f64, M, M>,
) -> Option<(SMatrix<f64, S, S>, SMatrix<f64, S, M>)> {
    // The prior's Riccati equation is the control's with fᵀ for A.
    let prior = riccati(&f.transpose(), &(h.transpose() * r.try_inverse()? * h), q)?;
    let gain = prior * h.transpose() * (h * prior * h.transpose() + r).try_inverse()?;
    Some((prior, gain))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use mechweed_hw::sim::FieldKind;

    /// The default plant on the realistic field (also bench_bound.rs's).
    pub(crate) fn realistic() -> SimParams {
        SimParams {
            field: FieldKind::Realistic,
            ..SimParams::default()
        }
    }

    /// The realistic field with nothing that moves the robot unseen and no lasting
    /// error of a sensor: only the sensors' white noise is left.
    pub(crate) fn still() -> SimParams {
        let mut plant = realistic();
        let t = &mut plant.tier;
        (
            t.camera_bias_sd_m,
            t.slope_max_deg,
            t.bump_heading_sd_deg,
            t.bump_side_sd_m,
        ) = (0.0, 0.0, 0.0, 0.0);
        plant.gnss.map_error_sd_m = 0.0;
        plant
    }

    /// The shipped robot's tool, camera and antenna.
    pub(crate) const AT: Geometry = Geometry {
        tool_x_m: -0.4,
        camera_x_m: 0.8,
        antenna_x_m: 0.5,
    };

    #[test]
    fn the_doubling_riccati_solves_each_scalar_equation_in_closed_form() {
        // Diagonal A, G, H are independent scalar equations x = a² x / (1 + g x) + h,
        // g x² + (1 - a² - g h) x - h = 0: a random walk seen through noise (a filter's
        // case, a = 1), a stable and an unstable state under control.
        let (a, g, h) = ([1.0, 0.9, 1.1], [2.0, 0.5, 1.0], [0.3, 1.0, 0.01]);
        let diagonal = |v: [f64; 3]| SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from(v));
        let x = riccati(&diagonal(a), &diagonal(g), &diagonal(h)).unwrap();
        for i in 0..3 {
            let p = 1.0 - a[i] * a[i] - g[i] * h[i];
            let want = (-p + (p * p + 4.0 * g[i] * h[i]).sqrt()) / (2.0 * g[i]);
            assert!(
                (x[(i, i)] - want).abs() < 1e-12,
                "{i}: {} {want}",
                x[(i, i)]
            );
        }
    }

    #[test]
    fn a_random_walk_seen_through_white_noise_settles_where_the_closed_form_says() {
        // One state wandering by q per step, measured with variance r each step: the
        // posterior P solves P = M r / (M + r) with M = P + q, so
        // P = (sqrt(q^2 + 4 q r) - q) / 2.
        let (q, r) = (1e-4, 4e-4);
        let p = steady_posterior(
            &SMatrix::<f64, 1, 1>::identity(),
            &SMatrix::from_element(q),
            &SMatrix::<f64, 1, 1>::identity(),
            &SMatrix::from_element(r),
        )
        .unwrap()
        .0[0];
        let expected = ((q * q + 4.0 * q * r).sqrt() - q) / 2.0;
        assert!((p - expected).abs() < 1e-15, "{p} {expected}");
    }

    #[test]
    fn both_sensors_beat_either_and_the_cameras_lasting_error_costs() {
        let plant = realistic();
        let floor = |plant: &SimParams, source| floor_cm(plant, AT, source, 1.0, 55.0).unwrap();
        let fused = floor(&plant, SteerSource::Fused);
        assert!(fused < floor(&plant, SteerSource::Camera), "{fused}");
        assert!(fused < floor(&plant, SteerSource::Gnss), "{fused}");
        let mut steady_camera = plant.clone();
        steady_camera.tier.camera_bias_sd_m = 0.0;
        assert!(floor(&steady_camera, SteerSource::Fused) < 0.8 * fused);
    }

    #[test]
    fn with_nothing_moving_the_robot_and_no_lasting_errors_the_floor_vanishes() {
        let plant = still();
        let floor = floor_cm(&plant, AT, SteerSource::Fused, 1.0, 55.0).unwrap();
        assert!(floor < 0.05, "{floor} cm");
        assert_eq!(floor_cm(&plant, AT, SteerSource::Fused, 0.0, 55.0), None);
        assert_eq!(floor_cm(&plant, AT, SteerSource::Fused, 1.0, 0.0), None);
    }

    #[test]
    fn a_stretch_leaves_out_the_errors_mean_and_a_white_error_keeps_all_but_one_nth() {
        // A white error (carried into nothing) of variance 4 over 10 frames: the sample
        // variance about its own mean expects (1 - 1/10) of it.
        let p = Matrix::identity() * 4.0;
        let mut tool = SVector::<f64, N>::zeros();
        tool[Y] = 1.0;
        let v = within_stretch_variance(&p, &Matrix::zeros(), &tool, 10);
        assert!((v - 3.6).abs() < 1e-12, "{v}");
        // An error that never changes is all mean.
        let v = within_stretch_variance(&p, &Matrix::identity(), &tool, 10);
        assert!(v.abs() < 1e-12, "{v}");
    }
}
