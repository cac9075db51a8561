//! The odometry's covariances, from what robot.ini says of the encoders and of slip, so
//! that robot_localization and Nav2 weigh /odom by what it is worth (all zeros would
//! read as certainty).
//!
//! - **Pose** (x, y, yaw in `odom`): dead reckoning drifts. The heading walks with wheel
//!   slip, `[filter] slip_sd_deg_per_sqrt_m` per sqrt(m) driven (the row filter's own
//!   figure), and with the steering encoder's resolution through the yaw rate; the
//!   heading's error is carried into x and y along the way (the pose's Jacobian). The
//!   encoders' resolution adds one count's quantisation to x and y (it does not grow:
//!   distance is a count, not a sum of rounded steps).
//! - **Twist** (in `base_link`): the speed is counts over one supervisor period, each
//!   end rounded to a count; the yaw rate is the speed over the wheelbase through the
//!   wheel angle, rounded to a steering count, and walks with slip over one tick.
//!   Sideways the wheels do not slide, known as well as the speed.
//! - z, roll and pitch, and their rates: the robot does not measure them (a plane), so
//!   their variance is 1e6, which nothing trusts.

use nalgebra::Matrix3;

use super::model::RobotModel;
use super::msgs::Covariance6;
use super::sensors::off_the_plane_unknown;

/// One step of dead reckoning: distance (- = backwards), mean heading and time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Move {
    pub ds_m: f64,
    pub mid_rad: f64,
    pub dt_s: f64,
}

/// The pose's covariance so far: x, y, yaw (m², m·rad, rad²).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PoseSpread {
    p: Matrix3<f64>,
}

/// The variance of a uniform rounding to steps of `step`, each end rounded: 2 × step²/12.
fn rounding_var(step: f64) -> f64 {
    step * step / 6.0
}

/// The heading's variance from one step: slip over its length, and the steering's
/// rounding through the yaw rate (speed × tan(angle) / wheelbase).
fn heading_step_var(ds_m: f64, wheel_angle_rad: f64, m: &RobotModel) -> f64 {
    let slip = m.slip_sd_rad_per_sqrt_m.powi(2) * ds_m.abs();
    let angle_sd_rad = (1.0 / m.steer_counts_per_rad) / 12f64.sqrt();
    let per_rad = ds_m / m.wheelbase_m / wheel_angle_rad.cos().powi(2);
    slip + (per_rad * angle_sd_rad).powi(2)
}

impl PoseSpread {
    /// P = F P Fᵀ + Q for one step along `mid_rad`: F carries the heading's error
    /// into x and y, Q is the step's own heading error.
    pub fn step(&mut self, step: Move, wheel_angle_rad: f64, model: &RobotModel) {
        let (s, c) = step.mid_rad.sin_cos();
        #[rustfmt::skip]
        let f = Matrix3::new(
            1.0, 0.0, -step.ds_m * s,
            0.0, 1.0, step.ds_m * c,
            0.0, 0.0, 1.0,
        );
        self.p = f * self.p * f.transpose();
        self.p[(2, 2)] += heading_step_var(step.ds_m, wheel_angle_rad, model);
    }

    /// The 6 × 6 covariance of nav_msgs/Odometry's pose.
    pub fn pose_covariance(&self, model: &RobotModel) -> Covariance6 {
        let mut cov = [0.0; 36];
        let rounding = rounding_var(1.0 / model.enc_counts_per_m);
        // Rows and columns x, y, z, roll, pitch, yaw: the plane's are 0, 1 and 5.
        let at = [0, 1, 5];
        for (i, &a) in at.iter().enumerate() {
            for (j, &b) in at.iter().enumerate() {
                cov[6 * a + b] = self.p[(i, j)];
            }
        }
        cov[0] += rounding;
        cov[7] += rounding;
        off_the_plane_unknown(&mut cov);
        cov
    }
}

/// The 6 × 6 covariance of nav_msgs/Odometry's twist at `speed_mps` and
/// `wheel_angle_rad`, over a tick of `dt_s`.
pub fn twist_covariance(
    speed_mps: f64,
    wheel_angle_rad: f64,
    dt_s: f64,
    model: &RobotModel,
) -> Covariance6 {
    let mut cov = [0.0; 36];
    let speed_var = rounding_var(1.0 / (model.enc_counts_per_m * model.period_s));
    let speed_mps = if speed_mps.is_finite() {
        speed_mps
    } else {
        0.0
    };
    let dt_s = if dt_s > 0.0 { dt_s } else { model.period_s };
    let tan = wheel_angle_rad.tan();
    let yaw_rate_var = heading_step_var(speed_mps * dt_s, wheel_angle_rad, model) / (dt_s * dt_s)
        + speed_var * (tan / model.wheelbase_m).powi(2);
    cov[0] = speed_var;
    cov[7] = speed_var;
    cov[35] = yaw_rate_var;
    off_the_plane_unknown(&mut cov);
    cov
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_core::config::Settings;

    fn model() -> RobotModel {
        RobotModel::of(&Settings::shipped())
    }

    fn straight(spread: &mut PoseSpread, metres: usize, m: &RobotModel) {
        for _ in 0..metres * 10 {
            let step = Move {
                ds_m: 0.1,
                mid_rad: 0.0,
                dt_s: 0.1,
            };
            spread.step(step, 0.0, m);
        }
    }

    #[test]
    fn the_heading_walks_with_slip_and_carries_its_error_sideways_not_ahead() {
        let m = model();
        let mut spread = PoseSpread::default();
        straight(&mut spread, 10, &m);
        let cov = spread.pose_covariance(&m);
        // Slip alone (the steering's rounding is far smaller): slip² × 10 m.
        let slip_var = m.slip_sd_rad_per_sqrt_m.powi(2) * 10.0;
        assert!((cov[35] - slip_var).abs() < 0.01 * slip_var, "{}", cov[35]);
        // A random walk of the heading integrated over L: y's variance ≈ slip² L³ / 3.
        let y_var = slip_var * 100.0 / 3.0;
        assert!((cov[7] / y_var - 1.0).abs() < 0.05, "{} {y_var}", cov[7]);
        // Ahead, only the encoders' rounding: the heading's error does not reach x.
        assert!(cov[0] < 1e-6, "{}", cov[0]);
        assert!(cov[7] > 1e3 * cov[0]);
        assert!(cov[6 * 2 + 2] >= 1e6 && cov[6 * 4 + 4] >= 1e6);

        // Twice the slip setting, four times the heading's variance.
        let mut slippery = m.clone();
        slippery.slip_sd_rad_per_sqrt_m *= 2.0;
        let mut spread = PoseSpread::default();
        straight(&mut spread, 10, &slippery);
        let ratio = spread.pose_covariance(&slippery)[35] / cov[35];
        assert!((ratio - 4.0).abs() < 0.05, "{ratio}");
    }

    #[test]
    fn the_twist_is_known_to_the_encoders_resolution() {
        let m = model();
        let cov = twist_covariance(1.0, 0.0, 0.1, &m);
        let count_mps = 1.0 / (m.enc_counts_per_m * m.period_s);
        assert!((cov[0] - count_mps * count_mps / 6.0).abs() < 1e-12);
        // Finer encoders, a smaller variance: ten times the counts, a hundredth.
        let mut fine = m.clone();
        fine.enc_counts_per_m *= 10.0;
        let ratio = twist_covariance(1.0, 0.0, 0.1, &fine)[0] / cov[0];
        assert!((ratio - 0.01).abs() < 1e-9, "{ratio}");
        // The yaw rate's variance grows with speed (slip over the tick's travel).
        assert!(twist_covariance(2.0, 0.0, 0.1, &m)[35] > cov[35] && cov[35] > 0.0);
        assert!(cov.iter().all(|v| v.is_finite()));
    }
}
