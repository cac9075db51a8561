//! The robot's motion for ROS: its pose in the `odom` frame, its twist and its joints,
//! from the ticks it publishes. The pose is dead reckoning from the robot's own
//! odometry (distance driven and heading rate), begun at 0 when the bridge hears its
//! first tick: continuous and drifting, as REP 105 wants of `odom`. `base_link` is the
//! rear axle's centre, x forward, y left, z up.

use super::covariance::Move;
use super::msgs::{
    Header, JointState, Odometry, Pose, PoseWithCovariance, Quaternion, TfMessage, Time, Transform,
    TransformStamped, Twist, TwistWithCovariance, Vector3,
};

pub const ODOM_FRAME: &str = "odom";
pub const BASE_FRAME: &str = "base_link";
pub const GNSS_FRAME: &str = "gnss";

/// The frame ids as ROS sees them: each with `[ros2] frame_prefix` before it, so that
/// several robots' frames stay apart on one ROS network (`robot2/` gives robot2/odom).
#[derive(Debug, Clone, Default)]
pub struct Frames {
    prefix: String,
}

impl Frames {
    pub fn new(prefix: &str) -> Frames {
        Frames {
            prefix: prefix.to_string(),
        }
    }

    /// `frame` (odom, base_link, row, gnss) with the prefix.
    pub fn id(&self, frame: &str) -> String {
        format!("{}{frame}", self.prefix)
    }
}

/// The joints on /joint_states, in this order.
pub const JOINTS: [&str; 3] = ["wheel_left", "wheel_right", "steering"];

/// What the bridge reads from one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickMotion {
    pub t_s: f64,
    pub distance_m: f64,
    pub speed_mps: f64,
    pub yaw_rate_rps: f64,
    pub v_left_mps: f64,
    pub v_right_mps: f64,
    /// + = left.
    pub wheel_angle_rad: f64,
}

/// The pose and joints so far.
#[derive(Debug, Clone, Default)]
pub struct Odometer {
    pub x_m: f64,
    pub y_m: f64,
    pub yaw_rad: f64,
    /// Wheel turns so far, rad, from their speeds.
    pub wheel_left_rad: f64,
    pub wheel_right_rad: f64,
    /// The steering's rate between the last two ticks, rad/s.
    pub steer_rate_rps: f64,
    /// The last step taken (for the covariances), until taken from here.
    pub last_move: Option<Move>,
    last: Option<TickMotion>,
}

impl Odometer {
    /// Move on to `tick`. A tick older than the last (a robot that started again) begins
    /// the pose from where it is; a gap of dropped ticks is bridged by the distance. A
    /// tick without a time is skipped; a rate the robot could not give (JSON null) adds
    /// nothing, so that one gap never makes the pose NaN for good.
    pub fn step(&mut self, tick: TickMotion, wheel_radius_m: f64) {
        if !tick.t_s.is_finite() {
            return;
        }
        let Some(last) = self.last.replace(tick) else {
            return;
        };
        let dt_s = tick.t_s - last.t_s;
        // The robot's distance only grows (it counts reversing too): the step takes its
        // direction from the speed.
        let backwards = tick.speed_mps + last.speed_mps < 0.0;
        let ds_m = (tick.distance_m - last.distance_m).abs() * if backwards { -1.0 } else { 1.0 };
        if dt_s <= 0.0 || !ds_m.is_finite() {
            return;
        }
        let mean = |a: f64, b: f64| {
            let m = 0.5 * (a + b);
            if m.is_finite() { m } else { 0.0 }
        };
        // The heading turned at about the mean of the two rates; the step is taken
        // along the mean heading.
        let dyaw_rad = mean(tick.yaw_rate_rps, last.yaw_rate_rps) * dt_s;
        let mid_rad = self.yaw_rad + 0.5 * dyaw_rad;
        self.x_m += ds_m * mid_rad.cos();
        self.y_m += ds_m * mid_rad.sin();
        self.last_move = Some(Move {
            ds_m,
            mid_rad,
            dt_s,
        });
        self.yaw_rad = wrap(self.yaw_rad + dyaw_rad);
        let turned = |v1: f64, v0: f64| mean(v1, v0) * dt_s / wheel_radius_m;
        self.wheel_left_rad += turned(tick.v_left_mps, last.v_left_mps);
        self.wheel_right_rad += turned(tick.v_right_mps, last.v_right_mps);
        self.steer_rate_rps = (tick.wheel_angle_rad - last.wheel_angle_rad) / dt_s;
    }

    /// nav_msgs/Odometry: the pose in `odom`, the twist in `base_link`, without their
    /// covariances (covariance.rs gives them).
    pub fn odometry(&self, stamp: Time, tick: &TickMotion, frames: &Frames) -> Odometry {
        Odometry {
            header: header(stamp, &frames.id(ODOM_FRAME)),
            child_frame_id: frames.id(BASE_FRAME),
            pose: PoseWithCovariance {
                pose: Pose {
                    position: Vector3 {
                        x: self.x_m,
                        y: self.y_m,
                        z: 0.0,
                    },
                    orientation: Quaternion::yaw(self.yaw_rad),
                },
                covariance: [0.0; 36],
            },
            twist: TwistWithCovariance {
                twist: Twist {
                    linear: Vector3 {
                        x: tick.speed_mps,
                        ..Vector3::default()
                    },
                    angular: Vector3 {
                        z: tick.yaw_rate_rps,
                        ..Vector3::default()
                    },
                },
                covariance: [0.0; 36],
            },
        }
    }

    /// tf2_msgs/TFMessage: odom -> base_link.
    pub fn transform(&self, stamp: Time, frames: &Frames) -> TfMessage {
        TfMessage {
            transforms: vec![TransformStamped {
                header: header(stamp, &frames.id(ODOM_FRAME)),
                child_frame_id: frames.id(BASE_FRAME),
                transform: Transform {
                    translation: Vector3 {
                        x: self.x_m,
                        y: self.y_m,
                        z: 0.0,
                    },
                    rotation: Quaternion::yaw(self.yaw_rad),
                },
            }],
        }
    }

    /// sensor_msgs/JointState: the wheels' turns (rad) and speeds (rad/s), the
    /// steering's wheel angle (rad, + = left) and its rate.
    pub fn joints(
        &self,
        stamp: Time,
        tick: &TickMotion,
        wheel_radius_m: f64,
        frames: &Frames,
    ) -> JointState {
        JointState {
            header: header(stamp, &frames.id(BASE_FRAME)),
            name: JOINTS.iter().map(|j| j.to_string()).collect(),
            position: vec![
                self.wheel_left_rad,
                self.wheel_right_rad,
                tick.wheel_angle_rad,
            ],
            velocity: vec![
                tick.v_left_mps / wheel_radius_m,
                tick.v_right_mps / wheel_radius_m,
                self.steer_rate_rps,
            ],
            effort: Vec::new(),
        }
    }
}

pub fn header(stamp: Time, frame: &str) -> Header {
    Header {
        stamp,
        frame_id: frame.to_string(),
    }
}

/// An angle in -pi..pi.
fn wrap(rad: f64) -> f64 {
    (rad + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tick(t_s: f64, distance_m: f64, yaw_rate_rps: f64) -> TickMotion {
        TickMotion {
            t_s,
            distance_m,
            speed_mps: 1.0,
            yaw_rate_rps,
            v_left_mps: 1.0,
            v_right_mps: 1.0,
            wheel_angle_rad: 0.0,
        }
    }

    #[test]
    fn a_quarter_circle_ends_a_radius_ahead_and_a_radius_left() {
        // 1 m/s on a 2 m radius for a quarter turn, ticks 0.1 s apart.
        let radius_m = 2.0;
        let mut odo = Odometer::default();
        let quarter_s = std::f64::consts::FRAC_PI_2 * radius_m;
        let steps = (quarter_s / 0.1).round() as usize;
        for i in 0..=steps {
            let t_s = i as f64 * quarter_s / steps as f64;
            odo.step(tick(t_s, t_s, 1.0 / radius_m), 0.2);
        }
        assert!((odo.x_m - radius_m).abs() < 1e-3, "{}", odo.x_m);
        assert!((odo.y_m - radius_m).abs() < 1e-3, "{}", odo.y_m);
        assert!((odo.yaw_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        // 1 m/s for pi s on a 0.2 m wheel.
        let turned = quarter_s / 0.2;
        assert!((odo.wheel_left_rad - turned).abs() < 1e-9);
    }

    #[test]
    fn reversing_moves_the_pose_back_and_a_gap_in_a_rate_leaves_it_whole() {
        let mut odo = Odometer::default();
        let back = |t_s: f64, distance_m: f64| TickMotion {
            speed_mps: -0.5,
            v_left_mps: -0.5,
            v_right_mps: -0.5,
            ..tick(t_s, distance_m, 0.0)
        };
        odo.step(back(0.0, 0.0), 0.2);
        // The robot's distance grows while it reverses.
        odo.step(back(1.0, 0.5), 0.2);
        assert!((odo.x_m + 0.5).abs() < 1e-12, "{}", odo.x_m);
        assert!((odo.wheel_left_rad + 2.5).abs() < 1e-12);
        // A tick whose heading rate and time the robot could not give.
        odo.step(
            TickMotion {
                yaw_rate_rps: f64::NAN,
                ..back(2.0, 1.0)
            },
            0.2,
        );
        odo.step(
            TickMotion {
                t_s: f64::NAN,
                ..back(3.0, 1.5)
            },
            0.2,
        );
        odo.step(back(3.0, 1.5), 0.2);
        assert!(odo.yaw_rad.is_finite() && odo.wheel_left_rad.is_finite());
        assert!((odo.x_m + 1.5).abs() < 1e-12, "{}", odo.x_m);
    }

    #[test]
    fn dropped_ticks_are_bridged_by_the_distance_and_a_restart_moves_nothing() {
        let mut odo = Odometer::default();
        odo.step(tick(0.0, 0.0, 0.0), 0.2);
        odo.step(tick(1.0, 1.0, 0.0), 0.2);
        // Ticks from 1 s to 3 s lost.
        odo.step(tick(3.0, 3.0, 0.0), 0.2);
        assert!((odo.x_m - 3.0).abs() < 1e-12);
        // The robot program started again: its clock and distance are back at 0.
        odo.step(tick(0.1, 0.1, 0.0), 0.2);
        assert!((odo.x_m - 3.0).abs() < 1e-12);
        odo.step(tick(0.2, 0.2, 0.0), 0.2);
        assert!((odo.x_m - 3.1).abs() < 1e-12);
    }
}
