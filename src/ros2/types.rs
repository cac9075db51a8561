//! The message types the bridge sends: each one's ROS name, its `.msg` definition (the
//! fields, in wire order, and the constants a reader needs) and the types it uses,
//! and the RIHS01 type hash of each topic's type for each ROS 2 release.
//!
//! A subscriber hears a publisher only when both name the same hash, and a wrong hash
//! is silence, not an error: the hashes are checked by the tests, which compute them
//! again from these definitions by ROS 2's own rules (hash_tests.rs).

use mechweed_core::config::Distro;

/// One ROS 2 message type.
#[derive(Debug)]
pub struct MsgType {
    /// `package/msg/Name`.
    pub name: &'static str,
    /// The `.msg` text: nested types are written `package/Name`.
    pub definition: &'static str,
    /// The message types its fields use, directly.
    pub uses: &'static [&'static MsgType],
}

impl MsgType {
    /// `package/Name`, as `.msg` files and MCAP schemas name a dependency.
    pub fn short_name(&self) -> String {
        self.name.replacen("/msg/", "/", 1)
    }

    /// The DDS name that keys and tokens carry: `package::msg::dds_::Name_`.
    pub fn dds_name(&self) -> String {
        let (package, name) = self.name.split_once("/msg/").unwrap_or(("", self.name));
        format!("{package}::msg::dds_::{name}_")
    }

    /// Every type this one uses, directly or through another, each once, in the order
    /// first met.
    pub fn all_uses(&self) -> Vec<&'static MsgType> {
        let mut found: Vec<&'static MsgType> = Vec::new();
        let mut todo: Vec<&'static MsgType> = self.uses.to_vec();
        while !todo.is_empty() {
            let next = todo.remove(0);
            if !found.iter().any(|t| t.name == next.name) {
                found.push(next);
                todo.extend(next.uses.iter().copied());
            }
        }
        found
    }

    /// The type's RIHS01 hash in `distro`, as keys and tokens write it.
    pub fn hash(&self, distro: Distro) -> &'static str {
        hashes(distro)
            .iter()
            .find(|(name, _)| *name == self.name)
            .map_or("TypeHashNotSupported", |(_, hash)| *hash)
    }
}

pub static TIME: MsgType = MsgType {
    name: "builtin_interfaces/msg/Time",
    definition: "int32 sec\nuint32 nanosec\n",
    uses: &[],
};

pub static HEADER: MsgType = MsgType {
    name: "std_msgs/msg/Header",
    definition: "builtin_interfaces/Time stamp\nstring frame_id\n",
    uses: &[&TIME],
};

pub static FLOAT64: MsgType = MsgType {
    name: "std_msgs/msg/Float64",
    definition: "float64 data\n",
    uses: &[],
};

pub static STRING: MsgType = MsgType {
    name: "std_msgs/msg/String",
    definition: "string data\n",
    uses: &[],
};

/// std_srvs/srv/Trigger, the HALT service's type: its DDS name and rosidl's hash of the
/// service (of its request, response and event types), the same in Jazzy, Kilted and
/// Rolling. The hash is the published one, as several projects' tests read it from a
/// ROS install; the hash tests here compute messages', not services'.
pub const TRIGGER_DDS: &str = "std_srvs::srv::dds_::Trigger_";
pub const TRIGGER_HASH: &str =
    "RIHS01_eeff2cd6fa5ad9d27cdf4dec64818317839b62f212a91e6b5304b634b2062c5f";

pub static POINT: MsgType = MsgType {
    name: "geometry_msgs/msg/Point",
    definition: "float64 x\nfloat64 y\nfloat64 z\n",
    uses: &[],
};

pub static VECTOR3: MsgType = MsgType {
    name: "geometry_msgs/msg/Vector3",
    definition: "float64 x\nfloat64 y\nfloat64 z\n",
    uses: &[],
};

pub static QUATERNION: MsgType = MsgType {
    name: "geometry_msgs/msg/Quaternion",
    definition: "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
    uses: &[],
};

pub static POSE: MsgType = MsgType {
    name: "geometry_msgs/msg/Pose",
    definition: "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    uses: &[&POINT, &QUATERNION],
};

pub static POSE_WITH_COVARIANCE: MsgType = MsgType {
    name: "geometry_msgs/msg/PoseWithCovariance",
    definition: "geometry_msgs/Pose pose\nfloat64[36] covariance\n",
    uses: &[&POSE],
};

pub static POSE_WITH_COVARIANCE_STAMPED: MsgType = MsgType {
    name: "geometry_msgs/msg/PoseWithCovarianceStamped",
    definition: "std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n",
    uses: &[&HEADER, &POSE_WITH_COVARIANCE],
};

pub static TWIST: MsgType = MsgType {
    name: "geometry_msgs/msg/Twist",
    definition: "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
    uses: &[&VECTOR3],
};

pub static TWIST_WITH_COVARIANCE: MsgType = MsgType {
    name: "geometry_msgs/msg/TwistWithCovariance",
    definition: "geometry_msgs/Twist twist\nfloat64[36] covariance\n",
    uses: &[&TWIST],
};

pub static ODOMETRY: MsgType = MsgType {
    name: "nav_msgs/msg/Odometry",
    definition: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
    uses: &[&HEADER, &POSE_WITH_COVARIANCE, &TWIST_WITH_COVARIANCE],
};

pub static TRANSFORM: MsgType = MsgType {
    name: "geometry_msgs/msg/Transform",
    definition: "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
    uses: &[&VECTOR3, &QUATERNION],
};

pub static TRANSFORM_STAMPED: MsgType = MsgType {
    name: "geometry_msgs/msg/TransformStamped",
    definition: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n",
    uses: &[&HEADER, &TRANSFORM],
};

pub static TF_MESSAGE: MsgType = MsgType {
    name: "tf2_msgs/msg/TFMessage",
    definition: "geometry_msgs/TransformStamped[] transforms\n",
    uses: &[&TRANSFORM_STAMPED],
};

pub static NAV_SAT_STATUS: MsgType = MsgType {
    name: "sensor_msgs/msg/NavSatStatus",
    definition: "int8 STATUS_UNKNOWN=-2\nint8 STATUS_NO_FIX=-1\nint8 STATUS_FIX=0\nint8 STATUS_SBAS_FIX=1\n\
int8 STATUS_GBAS_FIX=2\nint8 status -2\nuint16 SERVICE_UNKNOWN=0\nuint16 SERVICE_GPS=1\n\
uint16 SERVICE_GLONASS=2\nuint16 SERVICE_COMPASS=4\nuint16 SERVICE_GALILEO=8\nuint16 service\n",
    uses: &[],
};

pub static NAV_SAT_FIX: MsgType = MsgType {
    name: "sensor_msgs/msg/NavSatFix",
    definition: "std_msgs/Header header\nsensor_msgs/NavSatStatus status\nfloat64 latitude\n\
float64 longitude\nfloat64 altitude\nfloat64[9] position_covariance\n\
uint8 COVARIANCE_TYPE_UNKNOWN=0\nuint8 COVARIANCE_TYPE_APPROXIMATED=1\n\
uint8 COVARIANCE_TYPE_DIAGONAL_KNOWN=2\nuint8 COVARIANCE_TYPE_KNOWN=3\n\
uint8 position_covariance_type\n",
    uses: &[&HEADER, &NAV_SAT_STATUS],
};

pub static JOINT_STATE: MsgType = MsgType {
    name: "sensor_msgs/msg/JointState",
    definition: "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n",
    uses: &[&HEADER],
};

pub static KEY_VALUE: MsgType = MsgType {
    name: "diagnostic_msgs/msg/KeyValue",
    definition: "string key\nstring value\n",
    uses: &[],
};

pub static DIAGNOSTIC_STATUS: MsgType = MsgType {
    name: "diagnostic_msgs/msg/DiagnosticStatus",
    definition: "byte OK=0\nbyte WARN=1\nbyte ERROR=2\nbyte STALE=3\nbyte level\nstring name\n\
string message\nstring hardware_id\ndiagnostic_msgs/KeyValue[] values\n",
    uses: &[&KEY_VALUE],
};

pub static DIAGNOSTIC_ARRAY: MsgType = MsgType {
    name: "diagnostic_msgs/msg/DiagnosticArray",
    definition: "std_msgs/Header header\ndiagnostic_msgs/DiagnosticStatus[] status\n",
    uses: &[&HEADER, &DIAGNOSTIC_STATUS],
};

pub static LOG: MsgType = MsgType {
    name: "rcl_interfaces/msg/Log",
    definition: "uint8 DEBUG=10\nuint8 INFO=20\nuint8 WARN=30\nuint8 ERROR=40\nuint8 FATAL=50\n\
builtin_interfaces/Time stamp\nuint8 level\nstring name\nstring msg\nstring file\n\
string function\nuint32 line\n",
    uses: &[&TIME],
};

pub static BATTERY_STATE: MsgType = MsgType {
    name: "sensor_msgs/msg/BatteryState",
    definition: "uint8 POWER_SUPPLY_STATUS_UNKNOWN=0\nuint8 POWER_SUPPLY_HEALTH_UNKNOWN=0\n\
uint8 POWER_SUPPLY_TECHNOLOGY_UNKNOWN=0\nstd_msgs/Header header\nfloat32 voltage\n\
float32 temperature\nfloat32 current\nfloat32 charge\nfloat32 capacity\n\
float32 design_capacity\nfloat32 percentage\nuint8 power_supply_status\n\
uint8 power_supply_health\nuint8 power_supply_technology\nbool present\n\
float32[] cell_voltage\nfloat32[] cell_temperature\nstring location\nstring serial_number\n",
    uses: &[&HEADER],
};

/// The types a topic may carry: the ones with a hash.
pub static TOPIC_TYPES: [&MsgType; 10] = [
    &FLOAT64,
    &STRING,
    &POSE_WITH_COVARIANCE_STAMPED,
    &ODOMETRY,
    &TF_MESSAGE,
    &NAV_SAT_FIX,
    &JOINT_STATE,
    &DIAGNOSTIC_ARRAY,
    &LOG,
    &BATTERY_STATE,
];

/// The hashes of the topics' types in Jazzy (rosidl 4.6), unchanged in Kilted and
/// Rolling: none of these definitions changed between them. A release that changes
/// one gets its own table.
const JAZZY: [(&str, &str); 10] = [
    (
        "std_msgs/msg/Float64",
        "RIHS01_705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a",
    ),
    (
        "std_msgs/msg/String",
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
    ),
    (
        "geometry_msgs/msg/PoseWithCovarianceStamped",
        "RIHS01_26432f9803e43727d3c8f668d1fdb3c630f548af631e2f4e31382371bfea3b6e",
    ),
    (
        "nav_msgs/msg/Odometry",
        "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0",
    ),
    (
        "tf2_msgs/msg/TFMessage",
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
    ),
    (
        "sensor_msgs/msg/NavSatFix",
        "RIHS01_62223ab3fe210a15976021da7afddc9e200dc9ec75231c1b6a557fc598a65404",
    ),
    (
        "sensor_msgs/msg/JointState",
        "RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
    ),
    (
        "diagnostic_msgs/msg/DiagnosticArray",
        "RIHS01_5a8a36efb05fb25070fa0fb3810290c0e6cd4862b54a8fb975a1ee8dc55a333e",
    ),
    (
        "rcl_interfaces/msg/Log",
        "RIHS01_e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac",
    ),
    (
        "sensor_msgs/msg/BatteryState",
        "RIHS01_4bee5dfce981c98faa6828b868307a0a73f992ed0789f374ee96c8f840e69741",
    ),
];

/// The hash table of `distro`.
pub fn hashes(distro: Distro) -> &'static [(&'static str, &'static str)] {
    match distro {
        Distro::Jazzy | Distro::Kilted | Distro::Rolling => &JAZZY,
    }
}

/// The `.msg` text of `t` with the text of every type it uses, as an MCAP `ros2msg`
/// schema carries it: each dependency after a line of 80 `=` and `MSG: package/Name`.
pub fn schema_text(t: &MsgType) -> String {
    let mut text = t.definition.to_string();
    for used in t.all_uses() {
        text += &"=".repeat(80);
        text += &format!("\nMSG: {}\n{}", used.short_name(), used.definition);
    }
    text
}
