//! The robot's model for ROS: a URDF made from robot.ini's geometry, on
//! `robot_description`, and the fixed frames on `/tf_static`, so that rviz2 places the
//! tool, the camera's row point and the GNSS antenna, and navsat_transform finds the
//! antenna of /fix. The moving joints (the drive wheels and the steering, named as on
//! /joint_states) go on /tf with each tick (odom.rs), so that rviz2's RobotModel shows
//! the robot moving with no robot_state_publisher.
//!
//! `base_link` is the rear axle's centre on the ground: x forward, y left, z up. The
//! steered front wheel is drawn with the drive wheels' radius, which robot.ini does
//! not give for it; the antenna at ground height, as robot.ini gives no height.

use mechweed_core::config::{Ros2Settings, Settings};

use super::msgs::{Quaternion, TfMessage, Time, Transform, TransformStamped, Vector3};
use super::odom::{BASE_FRAME, Frames, GNSS_FRAME, JOINTS, header};

/// The fixed frames: the tool's point, the camera's row point and the antenna.
pub const TOOL_FRAME: &str = "tool";
pub const CAMERA_FRAME: &str = "camera_lookahead";
/// The moving links, one per joint of /joint_states, in that order.
pub const JOINT_LINKS: [&str; 3] = ["wheel_left_link", "wheel_right_link", "steering_link"];

/// The wheels' width as drawn, m (robot.ini does not give it).
const WHEEL_WIDTH_M: f64 = 0.08;

/// What the URDF, the fixed frames and the odometry's covariances are made from.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotModel {
    pub wheelbase_m: f64,
    pub track_m: f64,
    pub wheel_radius_m: f64,
    pub max_wheel_angle_rad: f64,
    pub wheel_angle_rate_rps: f64,
    /// Ahead of the rear axle (- = behind), m.
    pub tool_ahead_m: f64,
    pub camera_ahead_m: f64,
    pub antenna_ahead_m: f64,
    pub antenna_left_m: f64,
    /// Encoder counts per metre of a drive wheel's travel.
    pub enc_counts_per_m: f64,
    /// Steering encoder counts per radian of wheel angle.
    pub steer_counts_per_rad: f64,
    /// The heading's random walk from wheel slip, rad per sqrt(m) ([filter]).
    pub slip_sd_rad_per_sqrt_m: f64,
    /// The supervisor's period, over which a wheel's speed is counted, s.
    pub period_s: f64,
}

impl RobotModel {
    /// The model of robot.ini's robot; the wheel radius is [ros2]'s.
    pub fn of(settings: &Settings) -> RobotModel {
        let r = &settings.robot;
        let ros = settings.ros2.clone().unwrap_or_else(Ros2Settings::shipped);
        RobotModel {
            wheelbase_m: r.wheelbase_m,
            track_m: r.track_m,
            wheel_radius_m: ros.wheel_radius_m,
            max_wheel_angle_rad: r.max_wheel_angle_deg.to_radians(),
            wheel_angle_rate_rps: settings.supervisor.wheel_angle_rate_dps.to_radians(),
            tool_ahead_m: r.tool_offset_m,
            camera_ahead_m: r.camera_lookahead_m,
            antenna_ahead_m: settings.gnss.antenna_ahead_m,
            antenna_left_m: settings.gnss.antenna_left_m,
            enc_counts_per_m: r.enc_counts_per_m,
            steer_counts_per_rad: r.steer_counts_per_deg.to_degrees(),
            slip_sd_rad_per_sqrt_m: settings.filter.slip_sd_per_sqrt_m,
            period_s: 1.0 / settings.supervisor.rate_hz,
        }
    }

    /// The fixed frames from base_link, and where they are: (frame, x, y).
    fn fixed(&self) -> [(&'static str, f64, f64); 3] {
        [
            (TOOL_FRAME, self.tool_ahead_m, 0.0),
            (CAMERA_FRAME, self.camera_ahead_m, 0.0),
            (GNSS_FRAME, self.antenna_ahead_m, self.antenna_left_m),
        ]
    }

    /// Where each moving joint is on base_link: (x, y, z).
    fn joint_origins(&self) -> [[f64; 3]; 3] {
        let (half, r) = (self.track_m / 2.0, self.wheel_radius_m);
        [[0.0, half, r], [0.0, -half, r], [self.wheelbase_m, 0.0, r]]
    }

    /// The URDF, every link's name with the frame prefix; the joints keep the names of
    /// /joint_states.
    pub fn urdf(&self, frames: &Frames) -> String {
        let base = frames.id(BASE_FRAME);
        let (l, r, track) = (self.wheelbase_m, self.wheel_radius_m, self.track_m);
        let wheel = format!(
            "<visual><origin xyz=\"0 0 0\" rpy=\"1.5708 0 0\"/><geometry><cylinder radius=\"{r}\" length=\"{WHEEL_WIDTH_M}\"/></geometry></visual>"
        );
        let mut text = format!(
            "<?xml version=\"1.0\"?>\n<robot name=\"mechweed\">\n  <link name=\"{base}\">\n    <visual><origin xyz=\"{} 0 {r}\" rpy=\"0 0 0\"/><geometry><box size=\"{l} {} 0.1\"/></geometry></visual>\n  </link>\n",
            l / 2.0,
            (track - 2.0 * WHEEL_WIDTH_M).max(0.05),
        );
        for (k, (joint, link)) in JOINTS.iter().zip(JOINT_LINKS).enumerate() {
            let link = frames.id(link);
            let [x, y, z] = self.joint_origins()[k];
            let (kind, axis, limit) = if *joint == "steering" {
                let a = self.max_wheel_angle_rad;
                let limit = format!(
                    "\n    <limit lower=\"{}\" upper=\"{a}\" effort=\"0\" velocity=\"{}\"/>",
                    -a, self.wheel_angle_rate_rps
                );
                ("revolute", "0 0 1", limit)
            } else {
                ("continuous", "0 1 0", String::new())
            };
            text += &format!(
                "  <link name=\"{link}\">\n    {wheel}\n  </link>\n  <joint name=\"{joint}\" type=\"{kind}\">\n    <parent link=\"{base}\"/>\n    <child link=\"{link}\"/>\n    <origin xyz=\"{x} {y} {z}\" rpy=\"0 0 0\"/>\n    <axis xyz=\"{axis}\"/>{limit}\n  </joint>\n"
            );
        }
        for (frame, x, y) in self.fixed() {
            let link = frames.id(frame);
            text += &format!(
                "  <link name=\"{link}\"/>\n  <joint name=\"{frame}_joint\" type=\"fixed\">\n    <parent link=\"{base}\"/>\n    <child link=\"{link}\"/>\n    <origin xyz=\"{x} {y} 0\" rpy=\"0 0 0\"/>\n  </joint>\n"
            );
        }
        text + "</robot>\n"
    }

    /// /tf_static: base_link to each fixed frame.
    pub fn static_transforms(&self, stamp: Time, frames: &Frames) -> TfMessage {
        let transforms = (self.fixed().into_iter())
            .map(|(frame, x, y)| TransformStamped {
                header: header(stamp, &frames.id(BASE_FRAME)),
                child_frame_id: frames.id(frame),
                transform: Transform {
                    translation: Vector3 { x, y, z: 0.0 },
                    rotation: Quaternion::default(),
                },
            })
            .collect();
        TfMessage { transforms }
    }

    /// The moving joints' transforms at `positions` (wheels' turns and the wheel
    /// angle, rad, as on /joint_states): the wheels about y, the steering about z.
    pub fn joint_transforms(
        &self,
        stamp: Time,
        positions: [f64; 3],
        frames: &Frames,
    ) -> Vec<TransformStamped> {
        let about_y = |rad: f64| Quaternion {
            x: 0.0,
            y: (rad / 2.0).sin(),
            z: 0.0,
            w: (rad / 2.0).cos(),
        };
        let rotations = [
            about_y(positions[0]),
            about_y(positions[1]),
            Quaternion::yaw(positions[2]),
        ];
        (0..3)
            .map(|k| {
                let [x, y, z] = self.joint_origins()[k];
                TransformStamped {
                    header: header(stamp, &frames.id(BASE_FRAME)),
                    child_frame_id: frames.id(JOINT_LINKS[k]),
                    transform: Transform {
                        translation: Vector3 { x, y, z },
                        rotation: rotations[k],
                    },
                }
            })
            .collect()
    }
}

#[cfg(test)]
#[path = "model_tests.rs"]
mod tests;
