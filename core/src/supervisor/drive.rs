//! The supervisor while driving (Joystick and Autonomous): the steer thread's references,
//! ramped, and the PI wheel-speed and PD steering regulators (pid.rs) that turn them
//! into amplifier voltages.

use mechweed_hw::{Inputs, Outputs};

use super::Supervisor;
use super::endswitch::guard_steering;
use crate::state::modes::Mode;
use crate::steer::SteerCommand;

/// Move `value` towards `target` by at most `step`.
fn ramp(value: f64, target: f64, step: f64) -> f64 {
    value + (target - value).clamp(-step, step)
}

impl Supervisor {
    /// Joystick and Autonomous: references from the steer thread, ramped; the
    /// regulators turn them into amplifier voltages.
    pub(super) fn drive(
        &mut self,
        now_s: f64,
        steer: &SteerCommand,
        inputs: &Inputs,
        gap_s: f64,
    ) -> Outputs {
        if self.status.mode == Mode::Joystick && !inputs.joystick_enable {
            // The dead-man let go: stop as HALT does, brakes on at once. A person who
            // lets go may have fallen; the spring brakes stop the robot in the shortest
            // distance, where a ramp would roll on for up to a metre. Pressed again, the
            // robot starts from rest.
            self.start_driving();
            self.status.v_left_ref_mps = 0.0;
            self.status.v_right_ref_mps = 0.0;
            return self.standing_outputs();
        }
        // Ramps and integrators take at most two periods at once: after a stall (itself
        // a fault) none of them jumps by the whole gap.
        let dt_s = gap_s.min(MAX_STEP_PERIODS * self.period_s);
        let s = &self.settings;
        let m = self.status.measured;
        let end_switch = inputs.end_switch_left
            || inputs.end_switch_right
            || self.status.endswitch_hit.is_some();
        // A command the steer thread made for another mode, or one it stopped renewing,
        // asks for nothing: stand, and hold the wheel where its reference is.
        let steer_age_s = now_s - steer.t_s;
        let fresh = steer.mode == self.status.mode
            && steer_age_s <= STEER_MAX_AGE_PERIODS / s.steer.rate_hz;
        let max_speed_mps = s.supervisor.max_speed_mps;
        let target_speed_mps = if end_switch || !fresh {
            0.0
        } else {
            steer.speed_mps.clamp(-max_speed_mps, max_speed_mps)
        };
        // One limit in every mode; the end-switch procedure's angle lies within it
        // (check-config refuses one that does not).
        let max_angle_rad = s.robot.max_wheel_angle_deg.to_radians();
        let target_angle_rad = if fresh {
            steer.wheel_angle_rad.clamp(-max_angle_rad, max_angle_rad)
        } else {
            self.status.wheel_angle_ref_rad
        };

        let st = &mut self.status;
        st.speed_ref_mps = ramp(
            st.speed_ref_mps,
            target_speed_mps,
            s.supervisor.accel_mps2 * dt_s,
        );
        st.wheel_angle_ref_rad = ramp(
            st.wheel_angle_ref_rad,
            target_angle_rad,
            s.supervisor.wheel_angle_rate_dps.to_radians() * dt_s,
        );
        // Ackermann: on a turn the inner rear wheel runs slower than the outer one.
        let half_track_curvature =
            0.5 * s.robot.track_m * m.wheel_angle_rad.tan() / s.robot.wheelbase_m;
        st.v_left_ref_mps = st.speed_ref_mps * (1.0 - half_track_curvature);
        st.v_right_ref_mps = st.speed_ref_mps * (1.0 + half_track_curvature);

        let outputs = Outputs {
            amp_left_v: self.left.update(st.v_left_ref_mps, m.v_left_mps, dt_s),
            amp_right_v: self.right.update(st.v_right_ref_mps, m.v_right_mps, dt_s),
            // A derivative is a rate: over the true interval, not the capped one.
            amp_steer_v: self
                .steering
                .update(st.wheel_angle_ref_rad, m.wheel_angle_rad, gap_s),
            main_power_on: true,
            brake_release_left: true,
            brake_release_right: true,
            tool_on: st.mode == Mode::Autonomous && st.speed_ref_mps > TOOL_MIN_SPEED_MPS,
        };
        guard_steering(outputs, inputs)
    }
}

/// The weeding tool runs only while the robot moves along the row, m/s.
const TOOL_MIN_SPEED_MPS: f64 = 0.05;

/// The longest interval ramps and integrators take in one tick, in supervisor periods.
const MAX_STEP_PERIODS: f64 = 2.0;

/// A steer command older than this many steer periods is stale: target speed 0.
const STEER_MAX_AGE_PERIODS: f64 = 2.0;
