//! Each message's bytes against a layout worked out by hand from the CDR rules: the
//! header 00 01 00 00; then each field in order, a number aligned to its own size
//! (at most 8) from the first byte after the header; a string as a u32 length that
//! counts its closing NUL, its bytes and the NUL; a sequence as a u32 count and its
//! items; a fixed array as its items alone. The comments give each field's offset.

use super::cdr::{decode, encode};
use super::msgs::*;

fn le32(x: u32) -> Vec<u8> {
    x.to_le_bytes().to_vec()
}

fn f64s(xs: &[f64]) -> Vec<u8> {
    xs.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn stamp(sec: i32, nanosec: u32) -> Time {
    Time { sec, nanosec }
}

/// The bytes of `parts` after the header, checked and read back.
fn check<T>(message: &T, parts: &[&[u8]])
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
{
    let mut expected = vec![0x00, 0x01, 0x00, 0x00];
    for part in parts {
        expected.extend_from_slice(part);
    }
    let bytes = encode(message).unwrap();
    assert_eq!(bytes, expected, "{message:?}");
    assert_eq!(&decode::<T>(&bytes).unwrap(), message);
}

#[test]
fn float64_is_eight_bytes_after_the_header() {
    check(&Float64 { data: 1.5 }, &[&[0, 0, 0, 0, 0, 0, 0xf8, 0x3f]]);
}

#[test]
fn nav_sat_fix_pads_before_its_first_double() {
    let fix = NavSatFix {
        header: Header {
            stamp: stamp(1, 2),
            frame_id: "gnss".into(),
        },
        status: NavSatStatus {
            status: -1,
            service: 1,
        },
        latitude: 52.0,
        longitude: 5.5,
        altitude: -3.0,
        position_covariance: [1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0],
        position_covariance_type: 2,
    };
    check(
        &fix,
        &[
            &[1, 0, 0, 0, 2, 0, 0, 0],                // 0 sec, 4 nanosec
            &[5, 0, 0, 0, b'g', b'n', b's', b's', 0], // 8 "gnss" and NUL: to 17
            &[0xff],                                  // 17 status -1
            &[1, 0],                                  // 18 service, aligned to 2
            &[0, 0, 0, 0],                            // 20 to 24: the double's alignment
            &f64s(&[52.0, 5.5, -3.0]),                // 24 latitude, longitude, altitude
            &f64s(&fix.position_covariance),          // 48 the 9 covariances: to 120
            &[2],                                     // 120 the covariance's type
        ],
    );
}

#[test]
fn joint_state_counts_its_sequences() {
    let joints = JointState {
        header: Header::default(),
        name: vec!["a".into()],
        position: vec![0.25],
        velocity: vec![],
        effort: vec![],
    };
    check(
        &joints,
        &[
            &[0; 8],                // 0 the stamp
            &[1, 0, 0, 0, 0],       // 8 "" is its NUL alone: to 13
            &[0, 0, 0],             // 13 to 16
            &le32(1),               // 16 one name
            &[2, 0, 0, 0, b'a', 0], // 20 "a": to 26
            &[0, 0],                // 26 to 28
            &le32(1),               // 28 one position
            &f64s(&[0.25]),         // 32 already aligned to 8
            &le32(0),               // 40 no velocity
            &le32(0),               // 44 no effort
        ],
    );
}

#[test]
fn log_aligns_each_string_and_its_line() {
    let log = Log {
        stamp: stamp(7, 0),
        level: 40,
        name: "n".into(),
        msg: "m".into(),
        file: String::new(),
        function: String::new(),
        line: 9,
    };
    check(
        &log,
        &[
            &[7, 0, 0, 0, 0, 0, 0, 0], // 0 the stamp
            &[40, 0, 0, 0],            // 8 level, then 3 bytes to 12
            &[2, 0, 0, 0, b'n', 0],    // 12 name: to 18
            &[0, 0],                   // 18 to 20
            &[2, 0, 0, 0, b'm', 0],    // 20 msg: to 26
            &[0, 0],                   // 26 to 28
            &[1, 0, 0, 0, 0],          // 28 file: to 33
            &[0, 0, 0],                // 33 to 36
            &[1, 0, 0, 0, 0],          // 36 function: to 41
            &[0, 0, 0],                // 41 to 44
            &le32(9),                  // 44 line
        ],
    );
}

#[test]
fn diagnostic_array_nests_statuses_and_their_key_values() {
    let array = DiagnosticArray {
        header: Header {
            stamp: stamp(0, 0),
            frame_id: String::new(),
        },
        status: vec![DiagnosticStatus {
            level: 1,
            name: "s".into(),
            message: String::new(),
            hardware_id: String::new(),
            values: vec![KeyValue {
                key: "k".into(),
                value: "v".into(),
            }],
        }],
    };
    check(
        &array,
        &[
            &[0; 8],                      // 0 the stamp
            &[1, 0, 0, 0, 0, 0, 0, 0],    // 8 "": to 13, then to 16
            &le32(1),                     // 16 one status
            &[1, 0, 0, 0],                // 20 level (a byte), then to 24
            &[2, 0, 0, 0, b's', 0, 0, 0], // 24 name: to 30, then to 32
            &[1, 0, 0, 0, 0, 0, 0, 0],    // 32 message: to 37, then to 40
            &[1, 0, 0, 0, 0, 0, 0, 0],    // 40 hardware_id: to 45, then to 48
            &le32(1),                     // 48 one key/value
            &[2, 0, 0, 0, b'k', 0, 0, 0], // 52 key: to 58, then to 60
            &[2, 0, 0, 0, b'v', 0],       // 60 value: to 66
        ],
    );
}

fn pose(x: f64) -> Pose {
    Pose {
        position: Vector3 { x, y: 2.0, z: 0.0 },
        orientation: Quaternion::yaw(0.0),
    }
}

#[test]
fn pose_with_covariance_stamped_holds_36_covariances_with_no_count() {
    let mut covariance = [0.0; 36];
    covariance[7] = 0.01;
    let row = PoseWithCovarianceStamped {
        header: Header {
            stamp: stamp(3, 4),
            frame_id: "row".into(),
        },
        pose: PoseWithCovariance {
            pose: pose(1.0),
            covariance,
        },
    };
    check(
        &row,
        &[
            &[3, 0, 0, 0, 4, 0, 0, 0],          // 0 the stamp
            &[4, 0, 0, 0, b'r', b'o', b'w', 0], // 8 "row": to 16, aligned already
            &f64s(&[1.0, 2.0, 0.0]),            // 16 position
            &f64s(&[0.0, 0.0, 0.0, 1.0]),       // 40 orientation
            &f64s(&covariance),                 // 72 to 360
        ],
    );
}

#[test]
fn odometry_and_tf_are_laid_out_field_by_field() {
    let odometry = Odometry {
        header: Header {
            stamp: stamp(0, 0),
            frame_id: "odom".into(),
        },
        child_frame_id: "base_link".into(),
        pose: PoseWithCovariance {
            pose: pose(5.0),
            covariance: [0.0; 36],
        },
        twist: TwistWithCovariance {
            twist: Twist {
                linear: Vector3 {
                    x: 1.0,
                    y: 0.0,
                    z: 0.0,
                },
                angular: Vector3 {
                    x: 0.0,
                    y: 0.0,
                    z: 0.5,
                },
            },
            covariance: [0.0; 36],
        },
    };
    check(
        &odometry,
        &[
            &[0; 8],
            &[5, 0, 0, 0, b'o', b'd', b'o', b'm', 0], // 8 "odom": to 17
            &[0, 0, 0],                               // 17 to 20
            &le32(10),                                // 20 "base_link"
            b"base_link\0",                           // 24 to 34
            &[0; 6],                                  // 34 to 40
            &f64s(&[5.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0]), // 40 the pose: to 96
            &[0; 288],                                // 96 its covariance: to 384
            &f64s(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.5]),   // 384 the twist: to 432
            &[0; 288],                                // 432 its covariance: to 720
        ],
    );
    let tf = TfMessage {
        transforms: vec![TransformStamped {
            header: Header {
                stamp: stamp(0, 0),
                frame_id: "odom".into(),
            },
            child_frame_id: "base_link".into(),
            transform: Transform {
                translation: Vector3 {
                    x: 5.0,
                    y: 2.0,
                    z: 0.0,
                },
                rotation: Quaternion::yaw(0.0),
            },
        }],
    };
    check(
        &tf,
        &[
            &le32(1),                                 // 0 one transform
            &[0; 8],                                  // 4 the stamp
            &[5, 0, 0, 0, b'o', b'd', b'o', b'm', 0], // 12 "odom": to 21
            &[0, 0, 0],                               // 21 to 24
            &le32(10),
            b"base_link\0",                              // 28 to 38
            &[0, 0],                                     // 38 to 40
            &f64s(&[5.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0]), // 40 to 96
        ],
    );
}

#[test]
fn bytes_that_are_not_little_endian_cdr_of_the_type_are_refused_with_why() {
    let why = decode::<Float64>(&[0x00, 0x00, 0x00, 0x00, 1, 2, 3, 4, 5, 6, 7, 8]).unwrap_err();
    assert!(why.contains("[00 00 00 00]"), "{why}");
    let why = decode::<Float64>(&[0x00, 0x01, 0x00, 0x00, 1, 2]).unwrap_err();
    assert!(why.starts_with("not this message's CDR"), "{why}");
    let mut long = encode(&Float64 { data: 1.0 }).unwrap();
    long.extend_from_slice(&[0; 8]);
    let why = decode::<Float64>(&long).unwrap_err();
    assert!(why.contains("8 bytes left over"), "{why}");
}
