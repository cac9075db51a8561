//! A fused run of the simulated robot seen from the ROS side, as `ros2 node list`,
//! `ros2 topic list` and `ros2 topic echo` would see it. The keys, tokens and hashes
//! are written out here by rmw_zenoh's rules, not taken from the program.

use std::collections::HashMap;
use std::time::{Duration, Instant};

use mechweed::ros2::cdr::decode;
use mechweed::ros2::msgs::{Log, StringMsg, TfMessage};
use mechweed::ros2::wire::read_attachment;
use zenoh::Wait;

use super::heard::check_the_run;
use super::{Bridge, Router, tokens};
use crate::bus::Robot;

/// (topic, its entity id, its type, its hash, its QoS in a token)
const TOPICS: [(&str, u32, &str, &str, &str); 11] = [
    (
        "/diagnostics",
        1,
        "diagnostic_msgs::msg::dds_::DiagnosticArray_",
        "RIHS01_5a8a36efb05fb25070fa0fb3810290c0e6cd4862b54a8fb975a1ee8dc55a333e",
        "::,10:,:,:,,",
    ),
    (
        "/rosout",
        2,
        "rcl_interfaces::msg::dds_::Log_",
        "RIHS01_e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac",
        ":1:,1000:,:10,0:,,",
    ),
    (
        "/tf",
        3,
        "tf2_msgs::msg::dds_::TFMessage_",
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
        "::,100:,:,:,,",
    ),
    (
        "/mechweed/joint_states",
        4,
        "sensor_msgs::msg::dds_::JointState_",
        "RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/odom",
        5,
        "nav_msgs::msg::dds_::Odometry_",
        "RIHS01_3cc97dc7fb7502f8714462c526d369e35b603cfc34d946e3f2eda2766dfec6e0",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/fix",
        6,
        "sensor_msgs::msg::dds_::NavSatFix_",
        "RIHS01_62223ab3fe210a15976021da7afddc9e200dc9ec75231c1b6a557fc598a65404",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/row",
        7,
        "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_",
        "RIHS01_26432f9803e43727d3c8f668d1fdb3c630f548af631e2f4e31382371bfea3b6e",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/cross_track",
        8,
        "std_msgs::msg::dds_::Float64_",
        "RIHS01_705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/battery_state",
        9,
        "sensor_msgs::msg::dds_::BatteryState_",
        "RIHS01_4bee5dfce981c98faa6828b868307a0a73f992ed0789f374ee96c8f840e69741",
        "::,10:,:,:,,",
    ),
    (
        "/mechweed/robot_description",
        10,
        "std_msgs::msg::dds_::String_",
        "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
        ":1:,1:,:,:,,",
    ),
    (
        "/tf_static",
        11,
        "tf2_msgs::msg::dds_::TFMessage_",
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
        ":1:,1:,:,:,,",
    ),
];

/// A sample as heard: payload and attachment.
pub(super) type Heard = HashMap<&'static str, Vec<(Vec<u8>, Vec<u8>)>>;

fn wall_ns() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos() as i64
}

#[test]
fn a_ros_client_finds_the_node_and_its_topics_and_decodes_the_run_on_each() {
    let _machine = crate::shared_machine();
    let router = Router::start();
    let robot = Robot::start(&[
        "--mode",
        "autonomous",
        "--duration",
        "30",
        "--set",
        "gnss.port=sim",
        "--set",
        "steer.source=fused",
    ]);
    let client = router.client();
    let (tx, rx) = crossbeam_channel::unbounded();
    let mut subscribers = Vec::new();
    for (topic, _, dds, hash, _) in TOPICS {
        let key = format!("0/{}/{dds}/{hash}", topic.trim_start_matches('/'));
        let tx = tx.clone();
        subscribers.push(
            client
                .declare_subscriber(key)
                .callback(move |s| {
                    let payload = s.payload().to_bytes().into_owned();
                    let attachment = s.attachment().map(|a| a.to_bytes().into_owned());
                    tx.send((topic, payload, attachment.unwrap_or_default()))
                        .unwrap();
                })
                .wait()
                .unwrap(),
        );
    }
    let bridge = Bridge::start(&router.endpoint, &robot.endpoint, 14.0);

    // What `ros2 node list` and `ros2 topic list` read: one node token, a publisher's each.
    let found = tokens(&client, 12);
    let node = found
        .iter()
        .find(|t| t.contains("/NN/"))
        .expect("a node token");
    let zid = node.split('/').nth(2).unwrap().to_string();
    assert_eq!(
        *node,
        format!("@ros2_lv/0/{zid}/0/0/NN/%/%mechweed/ros2_bridge")
    );
    let mut expected: Vec<String> = TOPICS
        .iter()
        .map(|(topic, eid, dds, hash, qos)| {
            format!(
                "@ros2_lv/0/{zid}/0/{eid}/MP/%/%mechweed/ros2_bridge/{}/{dds}/{hash}/{qos}",
                topic.replace('/', "%")
            )
        })
        .collect();
    expected.push(node.clone());
    expected.sort();
    assert_eq!(found, expected);

    // Six seconds of the run, then HALT from the bus: a mode change on /rosout.
    let mut heard: Heard = HashMap::new();
    let listen = |seconds: u64, heard: &mut Heard| {
        let end = Instant::now() + Duration::from_secs(seconds);
        while let Ok((topic, payload, attachment)) = rx.recv_deadline(end) {
            heard.entry(topic).or_default().push((payload, attachment));
        }
    };
    listen(6, &mut heard);
    assert!(robot.bus(&["request", "halt"]).status.success());
    listen(2, &mut heard);
    drop(subscribers);
    // A console started after the HALT, as rqt_console subscribes to /rosout (transient
    // local, so with rmw_zenoh's history query): it is given what came before it.
    let late = late_subscriber(&client, 1);
    let late_model = late_subscriber(&client, 9);
    let late_frames = late_subscriber(&client, 10);
    let (ok, stdout, stderr) = bridge.finish();
    assert!(ok, "{stdout}{stderr}");
    assert!(
        stdout.contains("ros2: node /mechweed/ros2_bridge publishes /diagnostics, /rosout, /tf"),
        "{stdout}"
    );

    // Every sample has rmw_zenoh's attachment: its sequence goes up by one per
    // publisher, its time is now and its id is XXH3-128 of the publisher's token.
    for (topic, eid, ..) in TOPICS {
        let samples = heard
            .get(topic)
            .unwrap_or_else(|| panic!("nothing on {topic}"));
        let token = &expected[expected
            .iter()
            .position(|t| t.contains(&format!("/0/{eid}/MP/")))
            .unwrap()];
        let gid = xxhash_rust::xxh3::xxh3_128(token.as_bytes()).to_le_bytes();
        let mut last = None;
        for (_, attachment) in samples {
            assert_eq!(attachment.len(), 33, "{topic}");
            let (sequence, time_ns, id) = read_attachment(attachment).unwrap();
            // Loopback and reliable: none is lost after the first heard.
            if let Some(last) = last {
                assert_eq!(sequence, last + 1, "{topic}");
            }
            last = Some(sequence);
            assert!((wall_ns() - time_ns).abs() < 60_000_000_000, "{topic}");
            assert_eq!(id, gid, "{topic}");
        }
    }
    check_the_run(&heard);
    let logs: Vec<Log> = late.iter().map(|(p, _)| decode(p).unwrap()).collect();
    assert!(
        logs.iter()
            .any(|l| l.msg.starts_with("mode: ") && l.msg.contains("halt")),
        "a late console heard {logs:?}"
    );
    assert!(late.iter().all(|(_, a)| a.len() == 33), "{late:?}");
    // rviz2 started late still gets the robot's model and its fixed frames: the last one.
    assert_eq!(late_model.len(), 1);
    let urdf: StringMsg = decode(&late_model[0].0).unwrap();
    assert!(
        urdf.data
            .contains("<joint name=\"steering\" type=\"revolute\">")
    );
    let fixed: TfMessage = decode(&late_frames[0].0).unwrap();
    let children: Vec<&str> = (fixed.transforms.iter())
        .map(|t| t.child_frame_id.as_str())
        .collect();
    assert_eq!(children, ["tool", "camera_lookahead", "gnss"]);
}

/// What a transient-local subscriber of `TOPICS[k]` started now hears in 2 s: as
/// rmw_zenoh's, it asks the publishers it detects for their cache.
fn late_subscriber(client: &zenoh::Session, k: usize) -> Vec<(Vec<u8>, Vec<u8>)> {
    use zenoh_ext::{AdvancedSubscriberBuilderExt, HistoryConfig};
    let (topic, _, dds, hash, _) = TOPICS[k];
    let (tx, rx) = crossbeam_channel::unbounded();
    let _console = client
        .declare_subscriber(format!("0/{}/{dds}/{hash}", topic.trim_start_matches('/')))
        .history(HistoryConfig::default().detect_late_publishers())
        .callback(move |s| {
            let attachment = s.attachment().map(|a| a.to_bytes().into_owned());
            let _ = tx.send((
                s.payload().to_bytes().into_owned(),
                attachment.unwrap_or_default(),
            ));
        })
        .wait()
        .unwrap();
    let end = Instant::now() + Duration::from_secs(2);
    std::iter::from_fn(|| rx.recv_deadline(end).ok()).collect()
}
