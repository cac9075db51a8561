//! `mechweed record --ros2` of a run on a secured bus, as the cluster's viewer: a ROS 2
//! bag that this program's reader and `record summary` read back.

use crate::bus::secured::{Keys, secured_robot};
use crate::common::{mechweed, text};
use mechweed::ros2::bag_read::{RosMsg, read};

#[test]
fn a_ros_2_bag_of_a_secured_run_is_recorded_as_a_viewer_and_read_back() {
    let _machine = crate::shared_machine();
    let keys = Keys::new();
    let robot = secured_robot(&keys, &["--mode", "autonomous", "--duration", "20"]);
    let folder = tempfile::tempdir().unwrap();
    let out = mechweed()
        .args([
            "record",
            "--ros2",
            "--connect",
            &robot.endpoint,
            "--seconds",
            "6",
        ])
        .arg("--set")
        .arg(format!("record.folder={}", folder.path().display()))
        .args(keys.as_("viewer"))
        .output()
        .unwrap();
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(said.contains("ROS 2 bag "), "{said}");
    let bag = std::fs::read_dir(folder.path())
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.to_string_lossy().ends_with(".mcap"))
        .expect("a bag");
    let name = bag.file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("mechweed-ros2-"), "{name}");

    let messages = read(&bag).unwrap();
    let xs: Vec<f64> = messages
        .iter()
        .filter_map(|m| match &m.msg {
            RosMsg::Odom(o) => Some(o.pose.pose.position.x),
            _ => None,
        })
        .collect();
    assert!(xs.len() > 20, "{} odometry messages", xs.len());
    // The robot's model first, as `ros2 bag play` latches it for rviz2.
    assert!(
        matches!(&messages[0].msg, RosMsg::Text(urdf) if urdf.data.contains("<robot name=\"mechweed\">")),
        "{:?}",
        messages[0]
    );
    assert!(xs.last().unwrap() - xs[0] > 1.0, "{xs:?}");
    let summary = mechweed()
        .args(["record", "summary"])
        .arg(&bag)
        .output()
        .unwrap();
    let said = text(&summary.stdout);
    assert!(summary.status.success(), "{said}{}", text(&summary.stderr));
    for line in [
        "ROS 2 bag ",
        "  /diagnostics: ",
        "  /mechweed/odom: ",
        "  /tf: ",
        "  /tf_static: 1",
        "  /mechweed/robot_description: 1",
        "odometry: ended ",
    ] {
        assert!(said.contains(line), "{line:?} not in {said}");
    }
}
