//! The standard ROS 2 messages the bridge sends, as Rust structs whose fields are in
//! the order of their `.msg` definitions (types.rs): CDR writes fields in declaration
//! order, so this order is the wire format. Units and frames follow REP 103 and 105:
//! SI units, x forward, y left, z up, angles in rad.

use serde::{Deserialize, Serialize};
use serde_big_array::BigArray;

/// builtin_interfaces/Time: seconds and nanoseconds since 1970.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// From seconds since 1970 (the robot's wall clock).
    pub fn from_unix_s(t_s: f64) -> Time {
        let t_s = t_s.max(0.0);
        let mut sec = t_s.floor();
        let mut nanosec = ((t_s - sec) * 1e9).round();
        if nanosec >= 1e9 {
            sec += 1.0;
            nanosec = 0.0;
        }
        Time {
            sec: sec.min(i32::MAX as f64) as i32,
            nanosec: nanosec as u32,
        }
    }

    pub fn unix_ns(self) -> u64 {
        self.sec.max(0) as u64 * 1_000_000_000 + u64::from(self.nanosec)
    }
}

/// std_msgs/Header.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}

/// std_msgs/Float64.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Float64 {
    pub data: f64,
}

/// std_msgs/String (the robot's model on robot_description).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StringMsg {
    pub data: String,
}

/// std_srvs/srv/Trigger's request: no fields, so rosidl gives it one byte.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TriggerRequest {
    pub structure_needs_at_least_one_member: u8,
}

/// std_srvs/srv/Trigger's response.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TriggerResponse {
    pub success: bool,
    pub message: String,
}

/// geometry_msgs/Point and geometry_msgs/Vector3 have the same fields.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// geometry_msgs/Quaternion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

impl Quaternion {
    /// A turn of `yaw_rad` about z (left positive).
    pub fn yaw(yaw_rad: f64) -> Quaternion {
        let half = yaw_rad / 2.0;
        Quaternion {
            x: 0.0,
            y: 0.0,
            z: half.sin(),
            w: half.cos(),
        }
    }
}

impl Default for Quaternion {
    fn default() -> Quaternion {
        Quaternion::yaw(0.0)
    }
}

/// geometry_msgs/Pose.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    pub position: Vector3,
    pub orientation: Quaternion,
}

/// A 6x6 covariance, row by row: x, y, z, rotation about x, y, z.
pub type Covariance6 = [f64; 36];

/// geometry_msgs/PoseWithCovariance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    pub pose: Pose,
    #[serde(with = "BigArray")]
    pub covariance: Covariance6,
}

/// geometry_msgs/PoseWithCovarianceStamped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovarianceStamped {
    pub header: Header,
    pub pose: PoseWithCovariance,
}

/// geometry_msgs/Twist.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Twist {
    pub linear: Vector3,
    pub angular: Vector3,
}

/// geometry_msgs/TwistWithCovariance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    pub twist: Twist,
    #[serde(with = "BigArray")]
    pub covariance: Covariance6,
}

/// nav_msgs/Odometry: the pose in `header.frame_id`, the twist in `child_frame_id`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    pub header: Header,
    pub child_frame_id: String,
    pub pose: PoseWithCovariance,
    pub twist: TwistWithCovariance,
}

/// geometry_msgs/Transform.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Transform {
    pub translation: Vector3,
    pub rotation: Quaternion,
}

/// geometry_msgs/TransformStamped.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TransformStamped {
    pub header: Header,
    pub child_frame_id: String,
    pub transform: Transform,
}

/// tf2_msgs/TFMessage.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TfMessage {
    pub transforms: Vec<TransformStamped>,
}

/// sensor_msgs/NavSatStatus: status -1 no fix, 0 fix, 1 SBAS, 2 GBAS (RTK); service 1 GPS.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct NavSatStatus {
    pub status: i8,
    pub service: u16,
}

/// sensor_msgs/NavSatFix.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct NavSatFix {
    pub header: Header,
    pub status: NavSatStatus,
    pub latitude: f64,
    pub longitude: f64,
    pub altitude: f64,
    /// East, north, up, m², row by row.
    pub position_covariance: [f64; 9],
    /// 0 unknown, 1 approximated, 2 diagonal known, 3 known.
    pub position_covariance_type: u8,
}

/// sensor_msgs/BatteryState: NaN for what is not measured; status, health and
/// technology 0, unknown.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BatteryState {
    pub header: Header,
    pub voltage: f32,
    pub temperature: f32,
    pub current: f32,
    pub charge: f32,
    pub capacity: f32,
    pub design_capacity: f32,
    pub percentage: f32,
    pub power_supply_status: u8,
    pub power_supply_health: u8,
    pub power_supply_technology: u8,
    pub present: bool,
    pub cell_voltage: Vec<f32>,
    pub cell_temperature: Vec<f32>,
    pub location: String,
    pub serial_number: String,
}

/// sensor_msgs/JointState.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JointState {
    pub header: Header,
    pub name: Vec<String>,
    pub position: Vec<f64>,
    pub velocity: Vec<f64>,
    pub effort: Vec<f64>,
}

/// diagnostic_msgs/KeyValue.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct KeyValue {
    pub key: String,
    pub value: String,
}

/// diagnostic_msgs/DiagnosticStatus: level 0 OK, 1 WARN, 2 ERROR, 3 STALE.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DiagnosticStatus {
    pub level: u8,
    pub name: String,
    pub message: String,
    pub hardware_id: String,
    pub values: Vec<KeyValue>,
}

/// diagnostic_msgs/DiagnosticArray.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DiagnosticArray {
    pub header: Header,
    pub status: Vec<DiagnosticStatus>,
}

/// rcl_interfaces/Log: level 10 debug, 20 info, 30 warn, 40 error, 50 fatal.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Log {
    pub stamp: Time,
    pub level: u8,
    pub name: String,
    pub msg: String,
    pub file: String,
    pub function: String,
    pub line: u32,
}
