//! A ROS 2 bag written and read back: by this program's reader (every message decoded
//! as its schema says) and by the mcap crate (its summary, statistics, schemas and
//! channels, as rosbag2 and Foxglove read them).

use std::time::Instant;

use mechweed_core::config::Distro;

use super::bag::{Bag, offered_qos_profiles};
use super::bag_read::{RosMsg, read, summary};
use super::flows::Converter;
use super::model::RobotModel;
use super::topics::Topic;
use super::types::schema_text;
use mechweed_core::config::Settings;

fn messages() -> Vec<super::flows::Outgoing> {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let mut out = Vec::new();
    let status = serde_json::json!({"t_s": 0.0, "wall_s": 100.0, "gnss": {"quality": 4, "lat_deg": 52.0, "lon_deg": 5.0, "sd_m": 0.02}, "filter": {"offset_m": 0.01, "heading_rad": 0.0, "offset_sd_m": 0.005}});
    out.extend(
        c.status(status.to_string().as_bytes(), Instant::now())
            .unwrap(),
    );
    for i in 0..20 {
        let t_s = f64::from(i) * 0.1;
        let tick = serde_json::json!({"t_s": t_s, "distance_m": t_s, "speed_mps": 1.0, "yaw_rate_rps": 0.0, "v_left_mps": 1.0, "v_right_mps": 1.0, "wheel_angle_rad": 0.0, "law_tool_offset_m": -0.01});
        out.extend(c.tick(tick.to_string().as_bytes()).unwrap());
    }
    let event =
        serde_json::json!({"t_s": 2.0, "tick": 200, "kind": "fault", "text": "e-stop pressed"});
    out.extend(c.event(event.to_string().as_bytes()).unwrap());
    // A status came a moment ago: its diagnostics are there.
    out.extend(c.diagnostics(Instant::now(), "").unwrap());
    out
}

#[test]
fn a_bag_is_read_back_whole_by_our_reader_and_by_the_mcap_crate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let written = messages();
    let mut bag = Bag::create(&path, "/mechweed", Distro::Jazzy).unwrap();
    for m in &written {
        bag.write(m).unwrap();
    }
    bag.finish().unwrap();

    let back = read(&path).unwrap();
    assert_eq!(back.len(), written.len());
    for (m, b) in written.iter().zip(&back) {
        assert_eq!(b.topic, m.topic.name("/mechweed"));
    }
    let odometry: Vec<_> = back
        .iter()
        .filter_map(|b| match &b.msg {
            RosMsg::Odom(o) => Some(o),
            _ => None,
        })
        .collect();
    assert_eq!(odometry.len(), 20);
    assert!((odometry[19].pose.pose.position.x - 1.9).abs() < 1e-9);
    assert!(
        back.iter()
            .any(|b| matches!(&b.msg, RosMsg::Log(l) if l.msg == "fault: e-stop pressed"))
    );
    assert!(
        back.iter()
            .any(|b| matches!(&b.msg, RosMsg::Fix(f) if f.latitude == 52.0))
    );

    // The mcap crate: the ros2 profile, a ros2msg schema per type with its whole
    // definition, a cdr channel per topic with rosbag2's metadata, and statistics.
    let bytes = std::fs::read(&path).unwrap();
    let mcap_summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a summary section");
    let stats = mcap_summary.stats.expect("statistics");
    assert_eq!(stats.message_count, written.len() as u64);
    assert_eq!(mcap_summary.channels.len(), Topic::ALL.len());
    for channel in mcap_summary.channels.values() {
        let topic = Topic::ALL
            .into_iter()
            .find(|t| t.name("/mechweed") == channel.topic)
            .unwrap();
        let schema = channel.schema.as_ref().unwrap();
        assert_eq!(
            (schema.encoding.as_str(), channel.message_encoding.as_str()),
            ("ros2msg", "cdr")
        );
        assert_eq!(schema.name, topic.msg_type().name);
        assert_eq!(&schema.data[..], schema_text(topic.msg_type()).as_bytes());
        assert_eq!(
            channel.metadata["topic_type_hash"],
            topic.msg_type().hash(Distro::Jazzy)
        );
        assert_eq!(
            channel.metadata["offered_qos_profiles"],
            offered_qos_profiles(topic.offered())
        );
    }
    let mut header = mcap::read::LinearReader::new(&bytes).unwrap();
    match header.next() {
        Some(Ok(mcap::records::Record::Header(h))) => assert_eq!(h.profile, "ros2"),
        other => panic!("no header: {other:?}"),
    }
    let said = summary(&path).unwrap();
    assert!(
        said.contains("/mechweed/odom: 20") && said.contains("fault: e-stop pressed"),
        "{said}"
    );
    assert!(said.contains("odometry: ended 1.90 m ahead"), "{said}");
}

#[test]
fn the_offered_qos_is_rosbag2s_yaml() {
    assert_eq!(
        offered_qos_profiles(Topic::Odom.offered()),
        "- history: keep_last\n  depth: 10\n  reliability: reliable\n  durability: volatile\n  deadline:\n    sec: 9223372036\n    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  liveliness: automatic\n  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  avoid_ros_namespace_conventions: false"
    );
    // /rosout as rcl offers it (rcl_qos_profile_rosout_default), as rosbag2 writes it.
    assert_eq!(
        offered_qos_profiles(Topic::Rosout.offered()),
        "- history: keep_last\n  depth: 1000\n  reliability: reliable\n  durability: transient_local\n  deadline:\n    sec: 9223372036\n    nsec: 854775807\n  lifespan:\n    sec: 10\n    nsec: 0\n  liveliness: automatic\n  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  avoid_ros_namespace_conventions: false"
    );
}

#[test]
fn a_file_that_is_not_a_ros_2_bag_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.mcap");
    std::fs::write(&path, b"not an mcap file").unwrap();
    let why = read(&path).unwrap_err();
    assert!(
        why.contains("other.mcap") && why.contains("not a ROS 2 bag"),
        "{why}"
    );
}
