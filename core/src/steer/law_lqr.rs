//! The `lqr` steering law: the wheel angle from the row filter's whole state, by the
//! linear-quadratic regulator of the steering model in lqr.rs.
//!
//! 1. The state. The filter knows the row's offset, heading and curvature at the rear
//!    axle and the robot's crab; the supervisor measures the wheel's angle. Its rate is
//!    taken as 0: the steer thread runs at its rate and on every camera estimate, a few
//!    milliseconds apart at times, and the angle's change over so short a time is noise.
//!    In the model's terms the robot is
//!    -offset from the row and turned -heading from it (the filter speaks of the row seen
//!    from the robot, the model of the robot seen from the row).
//! 2. The curvature. A row that bends needs its own wheel angle, atan(wheelbase
//!    curvature), held whatever the error: it is fed forward, and the regulator acts on
//!    the state's distance from holding it.
//! 3. The gains. u = -K x minimises the tool's mean square offset, with a small price on
//!    the wheel angle and one on the wheel's rate, over the model of the robot at its
//!    speed. Two designs: a quick one near the row, and a calm one, with a dearer
//!    wheel, for an error of several centimetres, taken between the two by the tool's
//!    offset (step 6). The gains are designed
//!    once, at start, for speeds every SPEED_STEP_MPS up to the table's end, and taken
//!    between the two nearest to the measured speed; nothing is solved while steering.
//! 4. The crab. A side slope makes the robot crab; the filter estimates the angle and the
//!    gains turn the robot into it.
//! 5. The integral. What the model does not know (an arc's exact curvature, the crab's
//!    estimate's own error) leaves the tool a few millimetres to one side: the tool's
//!    offset integrated over distance adds its curvature, as in pure pursuit (law.rs).
//! 6. Far from the row, calm. The model's wheel turns as fast as asked, the robot's at
//!    most [supervisor] wheel_angle_rate_dps (40°/s). A quick law steering back from
//!    5 cm asks more than that all along: the ramp lags it, the robot overshoots, and
//!    the swing grows each time until the robot is off its row (seen at every stop of
//!    the cheaper prices below, most within 5 s of the start, whose tool is 5 cm off).
//!    With the tool more than FAR_M off, the calm design steers; within NEAR_M, the
//!    quick one; between, a blend.

use super::filter::RowState;
use super::law::{LawOutput, Motion};
use super::lqr::{
    ANGLE_PRICE, CRAB, Gain, HEADING, SteeringModel, WHEEL, Y, continuous, discrete, priced_gain,
};
use crate::config::Settings;

/// The prices of the wheel's rate against the tool's offset, m² s² per rad², near the
/// row and far from it. The model knows neither the 40°/s limit nor the filter's noise
/// on the heading, which the larger gains of a cheaper wheel turn into wheel jitter: on
/// the model, the price that keeps the wheel's RMS rate at half the limit is 2e-5 to
/// 1.2e-4 (bench/achievable.rs), but on the benchmark's realistic field, seeds 1 to 10,
/// fused, one price everywhere stopped runs below 3e-3: 3e-4 stopped 8 of 30 runs at
/// 1 m/s and 21 at 2 m/s, 1e-3 stopped 3 at 2 m/s. With the calm design far from the
/// row (step 6) none stopped at 1e-3 near it (median RMS over the bound's RMS 1.44,
/// 1.50, 1.80 at 0.5, 1, 2 m/s, against 1.44, 1.56, 1.85 at 3e-3 everywhere); 3e-4 near
/// it gave 1.46, 1.45, 1.85 and stopped 2 at 2 m/s (docs/gnss.md has seeds 11 to 40).
const NEAR_RATE_PRICE: f64 = 1e-3;
const FAR_RATE_PRICE: f64 = 3e-3;

/// The tool's offset within which the quick design steers alone, and beyond which the
/// calm one does, m.
const NEAR_M: f64 = 0.01;
const FAR_M: f64 = 0.03;

/// The integral acts only with the tool this close to the row, m.
const INTEGRATE_WITHIN_M: f64 = 0.01;

/// The gains' table: every 0.1 m/s from 0.1 to 3 m/s (beyond any speed a setting allows).
const SPEED_STEP_MPS: f64 = 0.1;
const SPEEDS: usize = 30;

#[derive(Debug, Clone)]
pub(crate) struct LqrLaw {
    /// The gains at (i + 1) SPEED_STEP_MPS, near the row and far from it; None where the
    /// design failed (the law then holds the wheel where the row's curvature wants it).
    near: [Option<Gain>; SPEEDS],
    far: [Option<Gain>; SPEEDS],
    wheelbase_m: f64,
    max_wheel_angle_rad: f64,
    tool_x_m: f64,
    lookahead_m: f64,
    /// The last update's time, for the distance the integral adds over.
    last_t_s: Option<f64>,
    /// The integral of the tool's offset over distance, as a curvature, 1/m, and its
    /// gain and limit ([steer] ki_per_m2, integral_max_deg).
    integral_per_m: f64,
    ki_per_m2: f64,
    integral_max_per_m: f64,
}

impl LqrLaw {
    /// The law for `s`, its gains designed for the steer thread's period.
    pub fn new(s: &Settings) -> LqrLaw {
        // The same model as the benchmark's bound (bench/bound.rs), of this robot.
        let model = SteeringModel::new(&s.sim, &s.pid_steer, s.robot.wheelbase_m);
        let period_s = 1.0 / s.steer.rate_hz;
        let tool_x_m = s.robot.tool_offset_m;
        let table = |rate_price| {
            std::array::from_fn(|i| {
                let (a, b) = continuous(&model, (i + 1) as f64 * SPEED_STEP_MPS);
                let (a, b) = discrete(&a, &b, period_s);
                priced_gain(&a, &b, tool_x_m, ANGLE_PRICE, rate_price)
            })
        };
        LqrLaw {
            near: table(NEAR_RATE_PRICE),
            far: table(FAR_RATE_PRICE),
            wheelbase_m: s.robot.wheelbase_m,
            max_wheel_angle_rad: s.robot.max_wheel_angle_deg.to_radians(),
            tool_x_m,
            lookahead_m: s.steer.lookahead_m,
            last_t_s: None,
            integral_per_m: 0.0,
            ki_per_m2: s.steer.ki_per_m2,
            integral_max_per_m: s.steer.integral_max_deg.to_radians().tan() / s.robot.wheelbase_m,
        }
    }

    /// New [steer] settings taken in Halt: the look-ahead and the integral change; the
    /// gains do not (they come from the model this thread keeps from its start, and its
    /// rate), so nothing is solved in the steer thread.
    pub fn retune(&mut self, s: &Settings) {
        self.lookahead_m = s.steer.lookahead_m;
        self.ki_per_m2 = s.steer.ki_per_m2;
        self.integral_max_per_m = s.steer.integral_max_deg.to_radians().tan() / s.robot.wheelbase_m;
        self.reset();
    }

    /// Start afresh (entering autonomous mode).
    pub fn reset(&mut self) {
        self.last_t_s = None;
        self.integral_per_m = 0.0;
    }

    /// The gain at `speed_mps` with the tool `tool_offset_m` off the row: between the
    /// tables' two nearest speeds (their ends beyond them), and between the near and the
    /// far design.
    fn gain(&self, speed_mps: f64, tool_offset_m: f64) -> Option<Gain> {
        let at = (speed_mps.abs() / SPEED_STEP_MPS - 1.0).clamp(0.0, (SPEEDS - 1) as f64);
        let (below, share) = (at.floor() as usize, at.fract());
        let above = (below + 1).min(SPEEDS - 1);
        let at_speed = |table: &[Option<Gain>; SPEEDS]| {
            Some(table[below]? * (1.0 - share) + table[above]? * share)
        };
        let far_share = ((tool_offset_m.abs() - NEAR_M) / (FAR_M - NEAR_M)).clamp(0.0, 1.0);
        Some(at_speed(&self.near)? * (1.0 - far_share) + at_speed(&self.far)? * far_share)
    }

    /// The wheel angle for the filter's `row` now, at `now_s`.
    pub fn update(&mut self, row: &RowState, now_s: f64, motion: &Motion) -> LawOutput {
        let wheel_rad = motion.wheel_angle_rad;
        let dt_s = self.last_t_s.map_or(0.0, |t_s| (now_s - t_s).max(0.0));
        self.last_t_s = Some(now_s);
        // The row's offset `x_m` ahead of the rear axle, on a row of `curvature_per_m`.
        let at = |x_m: f64, curvature_per_m: f64| {
            row.offset_m + row.heading_rad * x_m + curvature_per_m * x_m * x_m / 2.0
        };
        // 5. What the model leaves on an arc or a slope, the tool's mean offset, goes by
        //    an integral over distance, as pure pursuit's does.
        let tool_offset_m = at(self.tool_x_m, row.curvature_per_m);
        // Only near the row: an offset still being steered away is the regulator's, and
        // integrated it would carry the robot past the row.
        let near = tool_offset_m.abs() < INTEGRATE_WITHIN_M;
        let travelled_m = if near {
            motion.speed_mps.abs() * dt_s
        } else {
            0.0
        };
        self.integral_per_m = (self.integral_per_m + self.ki_per_m2 * tool_offset_m * travelled_m)
            .clamp(-self.integral_max_per_m, self.integral_max_per_m);
        let curvature_per_m = row.curvature_per_m + self.integral_per_m;
        let held_rad = (self.wheelbase_m * curvature_per_m).atan();
        let correction_rad = self.gain(motion.speed_mps, tool_offset_m).map_or(0.0, |k| {
            let x = [
                (Y, -row.offset_m),
                (HEADING, -row.heading_rad),
                (WHEEL, wheel_rad - held_rad),
                (CRAB, row.slip_rad),
            ];
            -x.iter().map(|&(i, value)| k[i] * value).sum::<f64>()
        });
        LawOutput {
            wheel_angle_rad: (held_rad + correction_rad)
                .clamp(-self.max_wheel_angle_rad, self.max_wheel_angle_rad),
            lookahead_offset_m: at(self.lookahead_m, curvature_per_m),
            tool_offset_m,
            row_curvature_per_m: row.curvature_per_m,
            integral_per_m: self.integral_per_m,
        }
    }
}

#[cfg(test)]
#[path = "law_lqr_tests.rs"]
mod tests;
