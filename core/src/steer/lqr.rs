//! The robot steering along its row as a linear model, and the linear-quadratic regulator
//! (LQR) on it: the gains of the `lqr` steering law (law_lqr.rs), and the model the
//! benchmark's steering bound is computed on (bench/bound.rs), so that the two cannot
//! drift apart.
//!
//! The state, in the row's frame at the rear axle (x forward along the row, y left):
//! - `Y`: the rear axle's offset from the row, m (positive: the robot left of the row);
//! - `HEADING`: the robot's heading from the row's, rad (positive: turned left);
//! - `WHEEL`, `WHEEL_RATE`: the front wheel's angle, rad, and its rate, rad/s;
//! - `CRAB`: the crab angle, the direction of travel minus the heading, rad (a side slope);
//! - `CRAB_RATE`: its change per metre, rad/m;
//! - `CAMERA_BIAS`, `MAP_BIAS`: the sensors' lasting errors, m (they move no wheel; the
//!   bound's filter estimates them).
//!
//! Its motion on a straight row at speed v (a curved row adds its curvature's own wheel
//! angle, which the law feeds forward):
//!     y' = v (heading + crab),  heading' = v wheel / wheelbase,
//!     wheel'' = (rate kp (u - wheel) - (1 + rate kd) wheel') / lag,
//! the steering regulator's PD (kp, kd, volts per rad) driving the motor (rate: rad/s per
//! volt, through its lag) towards the commanded angle u; the crab and the biases drift as
//! Gauss-Markov processes over distance. The LQR minimises the tool's mean square offset
//! (y + tool_x heading) plus ANGLE_PRICE u², u held over each steer period.

use mechweed_hw::sim::SimParams;
use nalgebra::{SMatrix, SVector};

use crate::config::PdSettings;

pub(crate) const N: usize = 8;
pub(crate) const Y: usize = 0;
pub(crate) const HEADING: usize = 1;
pub(crate) const WHEEL: usize = 2;
pub(crate) const WHEEL_RATE: usize = 3;
pub(crate) const CRAB: usize = 4;
pub(crate) const CRAB_RATE: usize = 5;
pub(crate) const CAMERA_BIAS: usize = 6;
pub(crate) const MAP_BIAS: usize = 7;
pub(crate) type Matrix = SMatrix<f64, N, N>;
pub(crate) type Column = SVector<f64, N>;
pub(crate) type Gain = SMatrix<f64, 1, N>;

/// The price of the commanded wheel angle against the tool's offset, m² per rad²: small
/// enough that the steering is as fast as the model lets it be.
pub(crate) const ANGLE_PRICE: f64 = 1e-5;
/// The crab's own drift back to level, in slope lengths: slow, only so that the model
/// has a steady state.
const CRAB_RETURN_LENGTHS: f64 = 20.0;
/// Rounds of the doubling algorithm: 2⁴⁰ steps, far past the slowest error's settling.
pub(crate) const DOUBLINGS: usize = 40;

/// What the model needs of the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SteeringModel {
    pub wheelbase_m: f64,
    /// The steering motor: wheel rate per volt, rad/s per V, and its lag, s.
    pub rate_rps_per_v: f64,
    pub lag_s: f64,
    /// The steering regulator's PD gains, V per rad and V per rad/s.
    pub kp: f64,
    pub kd: f64,
    /// Over what distance the side slope changes, m.
    pub slope_length_m: f64,
}

impl SteeringModel {
    /// The model of a robot of `wheelbase_m` whose steering motor is `plant`'s ([sim]
    /// steer_rate_dps_per_v, steer_lag_s), regulated by `steering` ([pid.steer]), on
    /// `plant`'s field's slope.
    pub(crate) fn new(plant: &SimParams, steering: &PdSettings, wheelbase_m: f64) -> Self {
        SteeringModel {
            wheelbase_m,
            rate_rps_per_v: plant.steer_rate_dps_per_v.to_radians(),
            lag_s: plant.steer_lag_s,
            kp: steering.kp,
            kd: steering.kd,
            slope_length_m: plant.tier.slope_length_m,
        }
    }
}

/// How fast a Gauss-Markov process over `length_m` forgets at `v`, 1/s.
pub(crate) fn forget_per_s(v: f64, length_m: f64) -> f64 {
    if length_m > 0.0 { v / length_m } else { 1e3 }
}

/// The model's motion at speed `v`: (A, B) of x' = A x + B u, without the sensors'
/// biases' forgetting (bench/bound.rs adds it with their noise).
pub(crate) fn continuous(m: &SteeringModel, v: f64) -> (Matrix, Column) {
    let lag_s = m.lag_s.max(1e-3);
    let mut a = Matrix::zeros();
    let mut b = Column::zeros();
    a[(Y, HEADING)] = v;
    a[(Y, CRAB)] = v;
    a[(HEADING, WHEEL)] = v / m.wheelbase_m;
    a[(WHEEL, WHEEL_RATE)] = 1.0;
    a[(WHEEL_RATE, WHEEL)] = -m.rate_rps_per_v * m.kp / lag_s;
    a[(WHEEL_RATE, WHEEL_RATE)] = -(1.0 + m.rate_rps_per_v * m.kd) / lag_s;
    b[WHEEL_RATE] = m.rate_rps_per_v * m.kp / lag_s;
    let slope_m = m.slope_length_m.max(1e-3);
    a[(CRAB, CRAB)] = -v / (CRAB_RETURN_LENGTHS * slope_m);
    a[(CRAB, CRAB_RATE)] = v;
    a[(CRAB_RATE, CRAB_RATE)] = -forget_per_s(v, slope_m / 2.0);
    (a, b)
}

/// (A, B) held over `period_s`, exactly: one exponential of [[A, B], [0, 0]] period.
pub(crate) fn discrete(a: &Matrix, b: &Column, period_s: f64) -> (Matrix, Column) {
    let mut ab = SMatrix::<f64, { N + 1 }, { N + 1 }>::zeros();
    ab.fixed_view_mut::<N, N>(0, 0).copy_from(&(a * period_s));
    ab.fixed_view_mut::<N, 1>(0, N).copy_from(&(b * period_s));
    let ab = ab.exp();
    (
        ab.fixed_view::<N, N>(0, 0).into(),
        ab.fixed_view::<N, 1>(0, N).into(),
    )
}

/// The gain K of u = -K x that minimises the mean of the tool's offset squared (the tool
/// `tool_x_m` ahead of the rear axle) plus `angle_price` u², m² per rad², and
/// `rate_price` times the wheel's rate squared, m² s² per rad², for the discrete (A, B).
pub(crate) fn priced_gain(
    a: &Matrix,
    b: &Column,
    tool_x_m: f64,
    angle_price: f64,
    rate_price: f64,
) -> Option<Gain> {
    let mut tool = Column::zeros();
    (tool[Y], tool[HEADING]) = (1.0, tool_x_m);
    let mut cost = tool * tool.transpose();
    cost[(WHEEL_RATE, WHEEL_RATE)] += rate_price;
    let s = riccati(a, &(b * b.transpose() / angle_price), &cost)?;
    let k = (b.transpose() * s * a) / (angle_price + (b.transpose() * s * b)[0]);
    k.iter().all(|v| v.is_finite()).then_some(k)
}

/// The steady solution X of the Riccati equation X = Aᵀ X (I + G X)⁻¹ A + H (control:
/// G = B R⁻¹ Bᵀ, H the cost; a Kalman filter's prior: Fᵀ for A, G = Hᵀ R⁻¹ H, H the
/// process noise), by the doubling algorithm: each round doubles the steps of the
/// recursion it stands for, so the field's slow errors (the slope's, the map's:
/// thousands of frames) settle in a few dozen rounds.
pub(crate) fn riccati<const S: usize>(
    a: &SMatrix<f64, S, S>,
    g: &SMatrix<f64, S, S>,
    h: &SMatrix<f64, S, S>,
) -> Option<SMatrix<f64, S, S>> {
    let (mut a, mut g, mut h) = (*a, *g, *h);
    for _ in 0..DOUBLINGS {
        let w = (SMatrix::<f64, S, S>::identity() + g * h).try_inverse()?;
        let (a_w, w_a) = (a * w, w * a);
        (a, g, h) = (
            a_w * a,
            g + a_w * g * a.transpose(),
            h + a.transpose() * h * w_a,
        );
        (g, h) = ((g + g.transpose()) / 2.0, (h + h.transpose()) / 2.0);
    }
    h.iter().all(|v| v.is_finite()).then_some(h)
}
