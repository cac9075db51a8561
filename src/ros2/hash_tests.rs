//! The type hashes computed again from the `.msg` definitions of types.rs, by ROS 2's
//! rules (rosidl's `calculate_type_hash`): SHA-256 of a one-line JSON description of
//! the type's fields and of every type it uses, sorted by name, with no default values
//! or constants. The expected values are rosidl's own output, as published: generated
//! type-description files of a Kilted micro-ROS build, and other projects' tests that
//! read them from a Jazzy install (share/PKG/msg/TYPE.json). A definition with a field
//! wrong here, or a hash wrong in the table, fails.

use super::types::{self, MsgType, TOPIC_TYPES};
use mechweed_core::config::Distro;

const EXPECTED: [(&str, &str); 25] = [
    (
        "builtin_interfaces/msg/Time",
        "b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197",
    ),
    (
        "std_msgs/msg/Header",
        "f49fb3ae2cf070f793645ff749683ac6b06203e41c891e17701b1cb597ce6a01",
    ),
    (
        "std_msgs/msg/Float64",
        "705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a",
    ),
    (
        "std_msgs/msg/String",
        "df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
    ),
    (
        "geometry_msgs/msg/Point",
        "6963084842a9b04494d6b2941d11444708d892da2f4b09843b9c43f42a7f6881",
    ),
    (
        "geometry_msgs/msg/Vector3",
        "cc12fe83e4c02719f1ce8070bfd14aecd40f75a96696a67a2a1f37f7dbb0765d",
    ),
    (
        "geometry_msgs/msg/Quaternion",
        "8a765f66778c8ff7c8ab94afcc590a2ed5325a1d9a076ffff38fbce36f458684",
    ),
    (
        "geometry_msgs/msg/Pose",
        "d501954e9476cea2996984e812054b68026ae0bfae789d9a10b23daf35cc90fa",
    ),
    (
        "geometry_msgs/msg/PoseWithCovariance",
        "9a7c0fd234b7f45c6098745ecccd773ca1085670e64107135397aee31c02e1bb",
    ),
    (
        "geometry_msgs/msg/PoseWithCovarianceStamped",
        "26432f9803e43727d3c8f668d1fdb3c630f548af631e2f4e31382371bfea3b6e",
    ),
    (
        "geometry_msgs/msg/Twist",
        "9c45bf16fe0983d80e3cfe750d6835843d265a9a6c46bd2e609fcddde6fb8d2a",
    ),
    (
        "geometry_msgs/msg/TwistWithCovariance",
        "49f574f033f095d8b6cd1beaca5ca7925e296e84af1716d16c89d38b059c8c18",
    ),
    (
        "geometry_msgs/msg/Transform",
        "beb83fbe698636351461f6f35d1abb20010c43d55374d81bd041f1ba2581fddc",
    ),
    (
        "geometry_msgs/msg/TransformStamped",
        "0a241f87d04668d94099cbb5ba11691d5ad32c2f29682e4eb5653424bd275206",
    ),
    (
        "nav_msgs/msg/Odometry",
        "3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0",
    ),
    (
        "sensor_msgs/msg/NavSatStatus",
        "d1ed3befa628e09571bd273b888ba1c1fd187c9a5e0006b385d7e5e9095a3204",
    ),
    (
        "sensor_msgs/msg/NavSatFix",
        "62223ab3fe210a15976021da7afddc9e200dc9ec75231c1b6a557fc598a65404",
    ),
    (
        "sensor_msgs/msg/JointState",
        "a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
    ),
    (
        "diagnostic_msgs/msg/KeyValue",
        "d68081eaa540288c5440753baecef0c4e16e81a5f78ad68902ded5100413bb42",
    ),
    (
        "diagnostic_msgs/msg/DiagnosticStatus",
        "b0e3e692ea2d54a8af2f4ef1930e81556a2db55216b771f8a7d2724ed47bf0e4",
    ),
    (
        "diagnostic_msgs/msg/DiagnosticArray",
        "5a8a36efb05fb25070fa0fb3810290c0e6cd4862b54a8fb975a1ee8dc55a333e",
    ),
    (
        "tf2_msgs/msg/TFMessage",
        "e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
    ),
    (
        "rcl_interfaces/msg/Log",
        "e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac",
    ),
    // rosidl's generated C description of sensor_msgs (its constants differ between
    // releases, which the hash leaves out; its fields do not).
    (
        "sensor_msgs/msg/BatteryState",
        "4bee5dfce981c98faa6828b868307a0a73f992ed0789f374ee96c8f840e69741",
    ),
    // Not sent; a check of the rule for a message with no fields.
    (
        "std_msgs/msg/Empty",
        "20b625256f32d5dbc0d04fee44f43c41e51c70d3502f84b4a08e7a9c26a96312",
    ),
];

/// rosidl's field type ids; arrays add 48, unbounded sequences 144.
fn type_id(primitive: &str) -> Option<u32> {
    Some(match primitive {
        "int8" => 2,
        "uint8" | "char" => 3,
        "int16" => 4,
        "uint16" => 5,
        "int32" => 6,
        "uint32" => 7,
        "int64" => 8,
        "uint64" => 9,
        "float32" => 10,
        "float64" => 11,
        "bool" => 15,
        "byte" => 16,
        "string" => 17,
        _ => return None,
    })
}

/// A type's own description: `{"type_name": ..., "fields": [...]}`, and the names of
/// the types its fields use.
fn describe(name: &str, definition: &str) -> (String, Vec<String>) {
    let mut fields = Vec::new();
    let mut uses = Vec::new();
    for line in definition.lines() {
        let mut words = line.split_whitespace();
        let (Some(kind), Some(field)) = (words.next(), words.next()) else {
            continue;
        };
        if line.contains('=') {
            continue; // a constant
        }
        let (base, capacity, offset) = match kind.split_once('[') {
            Some((base, "]")) => (base, 0, 144),
            Some((base, n)) => (base, n.trim_end_matches(']').parse::<u32>().unwrap(), 48),
            None => (kind, 0, 0),
        };
        let (id, nested) = match type_id(base) {
            Some(id) => (id, String::new()),
            None => {
                let (package, short) = base.split_once('/').unwrap();
                let full = format!("{package}/msg/{short}");
                uses.push(full.clone());
                (1, full)
            }
        };
        fields.push(format!(
            "{{\"name\": \"{field}\", \"type\": {{\"type_id\": {}, \"capacity\": {capacity}, \"string_capacity\": 0, \"nested_type_name\": \"{nested}\"}}}}",
            id + offset
        ));
    }
    if fields.is_empty() {
        fields.push("{\"name\": \"structure_needs_at_least_one_member\", \"type\": {\"type_id\": 3, \"capacity\": 0, \"string_capacity\": 0, \"nested_type_name\": \"\"}}".to_string());
    }
    let text = format!(
        "{{\"type_name\": \"{name}\", \"fields\": [{}]}}",
        fields.join(", ")
    );
    (text, uses)
}

fn definition_of(name: &str) -> &'static str {
    if name == "std_msgs/msg/Empty" {
        return "";
    }
    every_type()
        .into_iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| panic!("{name} is used but not defined"))
        .definition
}

/// Every type the topics use, each once.
fn every_type() -> Vec<&'static MsgType> {
    let mut all: Vec<&'static MsgType> = Vec::new();
    for t in TOPIC_TYPES {
        for t in std::iter::once(t).chain(t.all_uses()) {
            if !all.iter().any(|a| a.name == t.name) {
                all.push(t);
            }
        }
    }
    all
}

fn rihs01(name: &str) -> String {
    let (own, mut todo) = describe(name, definition_of(name));
    let mut referenced: Vec<String> = Vec::new();
    while let Some(next) = todo.pop() {
        if !referenced.contains(&next) {
            todo.extend(describe(&next, definition_of(&next)).1);
            referenced.push(next);
        }
    }
    referenced.sort();
    let described: Vec<String> = referenced
        .iter()
        .map(|r| describe(r, definition_of(r)).0)
        .collect();
    let json = format!(
        "{{\"type_description\": {own}, \"referenced_type_descriptions\": [{}]}}",
        described.join(", ")
    );
    let digest = ring::digest::digest(&ring::digest::SHA256, json.as_bytes());
    let hex: String = digest.as_ref().iter().map(|b| format!("{b:02x}")).collect();
    format!("RIHS01_{hex}")
}

fn expected(name: &str) -> String {
    let (_, hash) = EXPECTED
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no expected hash of {name}"));
    format!("RIHS01_{hash}")
}

#[test]
fn each_definition_hashes_to_the_hash_ros_2_gives_its_type() {
    assert_eq!(rihs01("std_msgs/msg/Empty"), expected("std_msgs/msg/Empty"));
    let all = every_type();
    assert_eq!(all.len(), 24, "every type of the table but Empty");
    for t in all {
        assert_eq!(rihs01(t.name), expected(t.name), "{}", t.name);
    }
}

#[test]
fn each_release_names_the_hash_of_each_topics_type() {
    for distro in Distro::ALL {
        for t in TOPIC_TYPES {
            assert_eq!(
                t.hash(distro),
                expected(t.name),
                "{} in {}",
                t.name,
                distro.name()
            );
        }
    }
    // A type the table does not know is written as rmw_zenoh writes an unhashed one.
    assert_eq!(types::TIME.hash(Distro::Jazzy), "TypeHashNotSupported");
}

#[test]
fn dds_names_and_schemas_are_written_as_ros_writes_them() {
    assert_eq!(
        types::NAV_SAT_FIX.dds_name(),
        "sensor_msgs::msg::dds_::NavSatFix_"
    );
    assert_eq!(types::TF_MESSAGE.short_name(), "tf2_msgs/TFMessage");
    let schema = types::schema_text(&types::POSE_WITH_COVARIANCE_STAMPED);
    let sep = "=".repeat(80);
    assert!(schema.starts_with("std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n"));
    for used in [
        "std_msgs/Header",
        "geometry_msgs/PoseWithCovariance",
        "builtin_interfaces/Time",
        "geometry_msgs/Pose",
        "geometry_msgs/Point",
        "geometry_msgs/Quaternion",
    ] {
        assert_eq!(
            schema.matches(&format!("{sep}\nMSG: {used}\n")).count(),
            1,
            "{used}:\n{schema}"
        );
    }
}
