//! What the best linear steering could do on the realistic field: the tool's error s.d.
//! that a linear-quadratic-Gaussian (LQG) steering leaves on a linear model of the
//! field, the robot and its sensors, measured as the benchmark measures (over the
//! measured stretch of one row, its mean taken out). `bench rows --field realistic`
//! prints it beside the tool's measured s.d., as `floor` (bench_floor.rs) is printed
//! beside the filter's error, and in the same measure as the tool's RMS: the mean
//! kept, the stretch's mean square of a zero-mean error is its steady variance.
//! achievable.rs adds to the same model the loop's delay and the wheel's rate limit. LQG is the best law of all for a linear model with
//! Gaussian disturbances; the field's bumps are sparse kicks and its slope's levels are
//! uniform, so a law that exploits that could in principle do a little better, and the
//! LQG minimises the whole mean square where the benchmark takes the row's mean out. A
//! figure asked of the benchmark below the bound asks more than a linear law can give.
//!
//! The model, per camera frame (period T): the floor's field (bumps, the camera's and the
//! map's lasting errors, the sensors' noise) and the robot that moves in it:
//!     y' = v (h + c) (the rear axle's offset from the row),  h' = v δ / wheelbase,
//!     δ the wheel angle, turned by the steering regulator (kp, kd) through the motor
//!     (rate per volt, lag) towards the angle commanded at each frame and held;
//!     c the crab, moved at a rate that is a Gauss-Markov process over distance: the
//!     field's slope is a smooth profile between levels `slope_length_m` apart, whose
//!     rate has the s.d. max π / (√48 length) over half that length;
//! the steering sees the wheel angle and its rate (the encoder), the camera and GNSS as
//! the floor does, and minimises the tool's mean square offset (a small price on the
//! commanded angle keeps the problem well posed). The Kalman filter's and the optimal
//! gain's Riccati equations and the closed loop's steady covariance are solved by
//! doubling (the slope's and the map's slow errors take thousands of frames to settle).
//!
//! Left out, because they can only add: gaps, weed patches, float episodes, wheel slip,
//! a curved row, every latency, the wheel angle's rate limit and its largest angle (so
//! the regulator's gain matters little here: the model's steering may ask for any
//! angle). It is an expectation over fields like this one, like the floor: one row can
//! fall either side of it, and the smooth slope is a model of the field's profile, not
//! the profile itself.

use mechweed_hw::sim::SimParams;
use nalgebra::{SMatrix, SVector};

use crate::bench::floor::{Geometry, sensor_variances, steady_filter, within_stretch_variance};
use crate::config::{PdSettings, SteerSource};

use crate::steer::lqr::{
    ANGLE_PRICE, CAMERA_BIAS, CRAB_RATE, Column, DOUBLINGS, Gain, HEADING, MAP_BIAS, Matrix, N,
    SteeringModel, WHEEL, WHEEL_RATE, Y, continuous, discrete as held, forget_per_s, priced_gain,
};

/// The closed loop: the state and the filter's error.
type Loop = SMatrix<f64, { 2 * N }, { 2 * N }>;

/// How the model's steering acts: the price it puts on the wheel's rate, m² s² per rad²,
/// and whether each measurement reaches it a frame late (it then steers by the filter's
/// prediction, not by the estimate updated with the frame's own measurement).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Law {
    pub rate_price: f64,
    pub delayed: bool,
}

impl Law {
    /// The bound's: nothing late, the wheel as fast as the steering likes.
    pub(crate) const BOUND: Law = Law {
        rate_price: 0.0,
        delayed: false,
    };
}

/// A reference's figures over one stretch of row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Reference {
    /// The tool's error s.d. over the stretch, its mean taken out, cm.
    pub sd_cm: f64,
    /// The tool's RMS over the stretch, its mean kept, as the benchmark's RMS, cm.
    pub rms_cm: f64,
    /// The wheel's RMS rate, deg/s.
    pub wheel_rate_rms_dps: f64,
}

/// The tool's error over `measured_m` of row under the best linear steering of the
/// model when `source` steers at `speed_mps` on `plant`'s realistic field with the
/// steering regulator `steering` (None for a speed, a distance or a camera rate that
/// is not positive, or where the model has no steady state).
pub(crate) fn bound(
    plant: &SimParams,
    at: Geometry,
    steering: &PdSettings,
    source: SteerSource,
    speed_mps: f64,
    measured_m: f64,
) -> Option<Reference> {
    reference(
        plant,
        at,
        steering,
        (source, speed_mps, measured_m),
        Law::BOUND,
    )
}

/// The same under the best linear steering that acts as `law` says.
pub(crate) fn reference(
    plant: &SimParams,
    at: Geometry,
    steering: &PdSettings,
    (source, speed_mps, measured_m): (SteerSource, f64, f64),
    law: Law,
) -> Option<Reference> {
    if !(speed_mps > 0.0 && plant.camera_rate_hz > 0.0 && measured_m > 0.0) {
        return None;
    }
    let period_s = 1.0 / plant.camera_rate_hz;
    let (a, b, q) = discrete(plant, steering, speed_mps, period_s);
    let model = (&a, &b, &q);
    let k = priced_gain(&a, &b, at.tool_x_m, ANGLE_PRICE, law.rate_price)?;
    let ([camera_offset_r, camera_angle_r], gnss_r) = sensor_variances(plant);
    // The encoder's wheel angle and rate: a little noise keeps the filter's equations
    // regular; half or five times as much moves no figure the benchmark prints.
    let wheel_r = [0.05f64.to_radians().powi(2), 0.5f64.to_radians().powi(2)];
    let row = |entries: &[(usize, f64)]| {
        let mut h = [0.0; N];
        entries.iter().for_each(|&(i, value)| h[i] = value);
        h
    };
    let camera_offset = row(&[(Y, 1.0), (HEADING, at.camera_x_m), (CAMERA_BIAS, 1.0)]);
    let camera_angle = row(&[(HEADING, 1.0)]);
    let gnss = row(&[(Y, 1.0), (HEADING, at.antenna_x_m), (MAP_BIAS, 1.0)]);
    let (wheel, wheel_rate) = (row(&[(WHEEL, 1.0)]), row(&[(WHEEL_RATE, 1.0)]));
    let (x, closed) = match source {
        SteerSource::Camera => closed_loop::<4>(
            model,
            (&k, law.delayed),
            [camera_offset, camera_angle, wheel, wheel_rate],
            [camera_offset_r, camera_angle_r, wheel_r[0], wheel_r[1]],
        ),
        SteerSource::Gnss => closed_loop::<3>(
            model,
            (&k, law.delayed),
            [gnss, wheel, wheel_rate],
            [gnss_r, wheel_r[0], wheel_r[1]],
        ),
        SteerSource::Fused => closed_loop::<5>(
            model,
            (&k, law.delayed),
            [camera_offset, camera_angle, gnss, wheel, wheel_rate],
            [
                camera_offset_r,
                camera_angle_r,
                gnss_r,
                wheel_r[0],
                wheel_r[1],
            ],
        ),
    }?;
    let mut tool = SVector::<f64, { 2 * N }>::zeros();
    (tool[Y], tool[HEADING]) = (1.0, at.tool_x_m);
    let frames = ((measured_m / (speed_mps * period_s)).round() as usize).max(1);
    let variance = within_stretch_variance(&x, &closed, &tool, frames);
    // Every part of the model has a zero mean: a stretch's mean square is, on average
    // over fields, the steady variance, the stretch's own mean included.
    let mean_square = (tool.transpose() * x * tool)[0];
    let wheel_rate = x[(WHEEL_RATE, WHEEL_RATE)];
    (variance >= 0.0 && mean_square >= variance && wheel_rate >= 0.0).then(|| Reference {
        sd_cm: variance.sqrt() * 100.0,
        rms_cm: mean_square.sqrt() * 100.0,
        wheel_rate_rms_dps: wheel_rate.sqrt().to_degrees(),
    })
}

/// The model over one period: (A, B, Q) of x' = A x + B u + w, u the commanded wheel
/// angle held over the period, w of covariance Q.
fn discrete(
    plant: &SimParams,
    steering: &PdSettings,
    v: f64,
    period_s: f64,
) -> (Matrix, Column, Matrix) {
    let t = &plant.tier;
    let forget_per_s = |length_m: f64| forget_per_s(v, length_m);
    let (mut a, b) = continuous(&SteeringModel::new(plant, steering, plant.wheelbase_m), v);
    let slope_m = t.slope_length_m.max(1e-3);
    a[(CAMERA_BIAS, CAMERA_BIAS)] = -forget_per_s(t.camera_bias_length_m);
    a[(MAP_BIAS, MAP_BIAS)] = -forget_per_s(plant.gnss.map_error_length_m);
    let crab_rate_sd_per_m =
        t.slope_max_deg.to_radians() * std::f64::consts::PI / 48f64.sqrt() / slope_m;
    let bumps_per_s = v / t.bump_every_m.max(f64::MIN_POSITIVE);
    let mut qc = Matrix::zeros();
    qc[(Y, Y)] = t.bump_side_sd_m.powi(2) * bumps_per_s;
    qc[(HEADING, HEADING)] = t.bump_heading_sd_deg.to_radians().powi(2) * bumps_per_s;
    // A Gauss-Markov process of s.d. sd forgetting at rate k has white noise 2 k sd².
    qc[(CRAB_RATE, CRAB_RATE)] = 2.0 * forget_per_s(slope_m / 2.0) * crab_rate_sd_per_m.powi(2);
    qc[(CAMERA_BIAS, CAMERA_BIAS)] =
        2.0 * forget_per_s(t.camera_bias_length_m) * t.camera_bias_sd_m.powi(2);
    qc[(MAP_BIAS, MAP_BIAS)] =
        2.0 * forget_per_s(plant.gnss.map_error_length_m) * plant.gnss.map_error_sd_m.powi(2);
    // Exact over the period: A and B from one exponential, Q from Van Loan's.
    let (_, b_d) = held(&a, &b, period_s);
    let mut van_loan = SMatrix::<f64, { 2 * N }, { 2 * N }>::zeros();
    van_loan
        .fixed_view_mut::<N, N>(0, 0)
        .copy_from(&(-a * period_s));
    van_loan
        .fixed_view_mut::<N, N>(0, N)
        .copy_from(&(qc * period_s));
    van_loan
        .fixed_view_mut::<N, N>(N, N)
        .copy_from(&(a.transpose() * period_s));
    let e = van_loan.exp();
    let a_d: Matrix = e.fixed_view::<N, N>(N, N).transpose();
    let q_d = a_d * e.fixed_view::<N, N>(0, N);
    (a_d, b_d, (q_d + q_d.transpose()) / 2.0)
}

/// The steady covariance of (state, filter's error) under the gain k and the steady
/// Kalman filter of the M measurements h (rows) with variances r, the gain acting on
/// the updated estimate or (`delayed`) on the predicted one, and how the covariance
/// carries from one period to the next; None if anything does not stay finite.
fn closed_loop<const M: usize>(
    (a, b, q): (&Matrix, &Column, &Matrix),
    (k, delayed): (&Gain, bool),
    rows: [[f64; N]; M],
    variances: [f64; M],
) -> Option<(Loop, Loop)> {
    let h = SMatrix::<f64, M, N>::from_row_slice(rows.as_flattened());
    let r = SMatrix::<f64, M, M>::from_diagonal(&SVector::from(variances));
    let (_, l) = steady_filter(a, q, &h, &r)?;
    // u = -K x̂, e the predicted estimate's error: updated, x̂ = x - (I - L H) e + L v;
    // predicted (the frame's measurement not yet there), x̂ = x - e.
    let i_lh = Matrix::identity() - l * h;
    let mut closed = Loop::zeros();
    closed.fixed_view_mut::<N, N>(0, 0).copy_from(&(a - b * k));
    closed
        .fixed_view_mut::<N, N>(0, N)
        .copy_from(&(b * k * if delayed { Matrix::identity() } else { i_lh }));
    closed
        .fixed_view_mut::<N, N>(N, N)
        .copy_from(&(a - a * l * h));
    let mut w_in = SMatrix::<f64, { 2 * N }, N>::zeros();
    w_in.fixed_view_mut::<N, N>(0, 0)
        .copy_from(&Matrix::identity());
    w_in.fixed_view_mut::<N, N>(N, 0)
        .copy_from(&Matrix::identity());
    let mut v_in = SMatrix::<f64, { 2 * N }, M>::zeros();
    if !delayed {
        v_in.fixed_view_mut::<N, M>(0, 0).copy_from(&(-b * k * l));
    }
    v_in.fixed_view_mut::<N, M>(N, 0).copy_from(&(-a * l));
    // X = Σ Aᵏ W Aᵏᵀ, by doubling: after n rounds, 2ⁿ terms.
    let (mut x, mut power) = (
        w_in * q * w_in.transpose() + v_in * r * v_in.transpose(),
        closed,
    );
    for _ in 0..DOUBLINGS {
        x += power * x * power.transpose();
        power *= power;
    }
    let finite = x.iter().chain(closed.iter()).all(|v| v.is_finite());
    finite.then_some((x, closed))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::floor::sensor_variances;
    use crate::bench::floor::tests::{AT, realistic, still};
    use crate::config::Settings;

    fn bound(plant: &SimParams, steering: &PdSettings, source: SteerSource) -> f64 {
        super::bound(plant, AT, steering, source, 1.0, 55.0)
            .unwrap()
            .sd_cm
    }

    #[test]
    fn the_closed_loop_agrees_with_the_estimate_driven_by_its_innovations() {
        // Written the other way round: the current estimate moves as
        // x̂' = (A - B K) x̂ + L ν, the innovations ν white with covariance H P Hᵀ + R
        // (P the predicted covariance), and the state is the estimate plus its error,
        // uncorrelated with it: cov(x) = Y + (I - L H) P, Y = (A - B K) Y (A - B K)ᵀ +
        // L (H P Hᵀ + R) Lᵀ, here by plain iteration. GNSS and the encoder steer.
        let plant = realistic();
        let steering = Settings::shipped().pid_steer;
        let (a, b, q) = discrete(&plant, &steering, 1.0, 0.1);
        let (_, gnss_r) = sensor_variances(&plant);
        let mut rows = [[0.0; N]; 3];
        (rows[0][Y], rows[0][HEADING], rows[0][MAP_BIAS]) = (1.0, AT.antenna_x_m, 1.0);
        (rows[1][WHEEL], rows[2][WHEEL_RATE]) = (1.0, 1.0);
        let variances = [gnss_r, 1e-6, 1e-4];
        let k = priced_gain(&a, &b, AT.tool_x_m, ANGLE_PRICE, 0.0).unwrap();
        let (x, _) = closed_loop::<3>((&a, &b, &q), (&k, false), rows, variances).unwrap();
        let h = SMatrix::<f64, 3, N>::from_row_slice(rows.as_flattened());
        let r = SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from(variances));
        let (predicted, l) = steady_filter(&a, &q, &h, &r).unwrap();
        let innovations = h * predicted * h.transpose() + r;
        let steered = a - b * k;
        let mut y = Matrix::zeros();
        for _ in 0..100_000 {
            y = steered * y * steered.transpose() + l * innovations * l.transpose();
        }
        let want = y + (Matrix::identity() - l * h) * predicted;
        let got: Matrix = x.fixed_view::<N, N>(0, 0).into();
        assert!((got - want).norm() < 1e-9 * want.norm(), "{got} {want}");
        // The filter's error, the other block, is the predicted covariance.
        let error: Matrix = x.fixed_view::<N, N>(N, N).into();
        assert!((error - predicted).norm() < 1e-9 * predicted.norm());
    }

    #[test]
    fn with_nothing_moving_the_robot_and_no_lasting_errors_the_bound_vanishes() {
        let plant = still();
        let steering = Settings::shipped().pid_steer;
        let b = bound(&plant, &steering, SteerSource::Fused);
        assert!(b < 0.05, "{b} cm");
        let at =
            |speed, metres| super::bound(&plant, AT, &steering, SteerSource::Fused, speed, metres);
        assert_eq!((at(0.0, 55.0), at(1.0, 0.0)), (None, None));
    }

    #[test]
    fn a_frames_delay_doubles_a_random_walks_variance_under_deadbeat_steering() {
        // By hand: y' = y + u + w, measured exactly. Steered on the frame's own
        // measurement, u = -y leaves y' = w: variance q. A frame late, u = -(y - e) with
        // e the last frame's w: y' = e + w, variance 2 q. The other states are still.
        let mut a = Matrix::identity() * 0.5;
        a[(Y, Y)] = 1.0;
        let mut b = Column::zeros();
        b[Y] = 1.0;
        let mut q = Matrix::zeros();
        q[(Y, Y)] = 1e-4;
        let mut only_y = [[0.0; N]; 1];
        only_y[0][Y] = 1.0;
        let k = priced_gain(&a, &b, 0.0, ANGLE_PRICE, 0.0).unwrap();
        let variance = |delayed| {
            let (x, _) = closed_loop::<1>((&a, &b, &q), (&k, delayed), only_y, [1e-10]).unwrap();
            x[(Y, Y)]
        };
        let (now, late) = (variance(false), variance(true));
        assert!((now / 1e-4 - 1.0).abs() < 0.01, "{now}");
        assert!((late / now - 2.0).abs() < 0.01, "{late} {now}");
    }

    #[test]
    fn the_bounds_rms_keeps_the_stretchs_mean_and_so_is_above_its_sd() {
        let plant = realistic();
        let steering = Settings::shipped().pid_steer;
        let at =
            |metres| super::bound(&plant, AT, &steering, SteerSource::Fused, 1.0, metres).unwrap();
        let (short, long) = (at(5.0), at(500.0));
        // The RMS does not depend on the stretch; the s.d. loses the more of it to the
        // stretch's mean the shorter the stretch, the slow errors' share.
        assert!(
            (short.rms_cm - long.rms_cm).abs() < 1e-9,
            "{short:?} {long:?}"
        );
        assert!(
            short.sd_cm < long.sd_cm && long.sd_cm < long.rms_cm,
            "{short:?} {long:?}"
        );
    }

    #[test]
    fn both_sensors_beat_either_the_floor_lies_beneath_and_level_ground_lowers_it() {
        let plant = realistic();
        let steering = Settings::shipped().pid_steer;
        let fused = bound(&plant, &steering, SteerSource::Fused);
        assert!(
            fused < bound(&plant, &steering, SteerSource::Camera),
            "{fused}"
        );
        assert!(
            fused < bound(&plant, &steering, SteerSource::Gnss),
            "{fused}"
        );
        // The tool cannot be steered better than it is known; the slope's changing crab,
        // which moves the robot unseen until it has moved, costs the steering most.
        let floor = crate::bench::floor::floor_cm(&plant, AT, SteerSource::Fused, 1.0, 55.0);
        assert!(floor.is_some_and(|f| f < fused), "{floor:?} {fused}");
        let mut level = plant.clone();
        level.tier.slope_max_deg = 0.0;
        let on_level = bound(&level, &steering, SteerSource::Fused);
        assert!(on_level < 0.8 * fused, "{on_level} {fused}");
    }
}
