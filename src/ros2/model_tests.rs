//! The robot's URDF read by ROS's own parser (Python's urdf_parser_py, where it is
//! installed), its joints those of /joint_states, its fixed frames those of /tf_static.

use super::*;
use crate::ros2::msgs::Time;

fn model() -> RobotModel {
    RobotModel::of(&Settings::shipped())
}

/// What urdf_parser_py reads: each link's name, then each joint as
/// "name type parent child x y z"; None (said) where Python or the parser is missing.
fn parsed(urdf: &str) -> Option<Vec<String>> {
    use std::io::Write;
    let script = "import sys\nfrom urdf_parser_py.urdf import URDF\n\
        r = URDF.from_xml_string(sys.stdin.read().encode())\n\
        for l in r.links: print('link', l.name)\n\
        for j in r.joints: print('joint', j.name, j.type, j.parent, j.child, *j.origin.xyz)\n";
    let child = std::process::Command::new("python3")
        .args(["-c", script])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn();
    let Ok(mut child) = child else {
        eprintln!("skipped: no python3 to read the URDF with urdf_parser_py");
        return None;
    };
    child
        .stdin
        .take()
        .unwrap()
        .write_all(urdf.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if stderr.contains("No module named 'urdf_parser_py'") {
        eprintln!("skipped: Python's urdf_parser_py is not installed (pip install urdf-parser-py)");
        return None;
    }
    assert!(
        out.status.success(),
        "urdf_parser_py refused the URDF: {stderr}\n{urdf}"
    );
    let text = String::from_utf8(out.stdout).unwrap();
    Some(text.lines().map(str::to_string).collect())
}

#[test]
fn rosss_urdf_parser_reads_the_model_with_the_joints_of_joint_states_and_the_fixed_frames() {
    let m = model();
    let frames = Frames::new("robot2/");
    let urdf = m.urdf(&frames);
    let Some(lines) = parsed(&urdf) else { return };
    let links: Vec<&str> = (lines.iter())
        .filter_map(|l| l.strip_prefix("link "))
        .collect();
    assert_eq!(
        links,
        [
            "robot2/base_link",
            "robot2/wheel_left_link",
            "robot2/wheel_right_link",
            "robot2/steering_link",
            "robot2/tool",
            "robot2/camera_lookahead",
            "robot2/gnss"
        ]
    );
    let joints: Vec<Vec<&str>> = (lines.iter())
        .filter_map(|l| l.strip_prefix("joint "))
        .map(|l| l.split(' ').collect())
        .collect();
    // The moving joints are named as on /joint_states, in its order.
    let moving: Vec<&str> = joints.iter().take(3).map(|j| j[0]).collect();
    assert_eq!(moving, JOINTS);
    assert_eq!(joints[2][1], "revolute");
    let at = |j: &Vec<&str>| -> [f64; 3] { [j[4], j[5], j[6]].map(|v| v.parse::<f64>().unwrap()) };
    // The steering at the front axle, the wheels a half track either side.
    assert_eq!(at(&joints[2]), [m.wheelbase_m, 0.0, m.wheel_radius_m]);
    assert_eq!(at(&joints[0])[1], m.track_m / 2.0);
    // Each fixed joint is a transform of /tf_static: same parent, child and place.
    let fixed = m.static_transforms(Time::default(), &frames);
    assert_eq!(fixed.transforms.len(), 3);
    for (joint, t) in joints[3..].iter().zip(&fixed.transforms) {
        assert_eq!(joint[1], "fixed");
        assert_eq!(
            (joint[2], joint[3]),
            (t.header.frame_id.as_str(), t.child_frame_id.as_str())
        );
        let v = t.transform.translation;
        assert_eq!(at(joint), [v.x, v.y, v.z]);
    }
    assert_eq!(at(&joints[3])[0], m.tool_ahead_m);
    assert_eq!(at(&joints[5])[..2], [m.antenna_ahead_m, m.antenna_left_m]);
}

#[test]
fn the_model_follows_the_settings_and_the_moving_links_turn_with_their_joints() {
    let mut settings = Settings::shipped();
    settings.robot.wheelbase_m = 1.7;
    settings.gnss.antenna_left_m = -0.2;
    let m = RobotModel::of(&settings);
    let frames = Frames::default();
    let urdf = m.urdf(&frames);
    assert!(urdf.contains("<origin xyz=\"1.7 0 0.2\""), "{urdf}");
    let gnss = &m.static_transforms(Time::default(), &frames).transforms[2];
    assert_eq!(
        (gnss.child_frame_id.as_str(), gnss.transform.translation.y),
        ("gnss", -0.2)
    );
    // A quarter turn of the left wheel about y; the steering 0.3 rad about z.
    let t = m.joint_transforms(
        Time::default(),
        [std::f64::consts::FRAC_PI_2, 0.0, 0.3],
        &frames,
    );
    let q = t[0].transform.rotation;
    assert!((q.y - (std::f64::consts::FRAC_PI_4).sin()).abs() < 1e-12 && q.z == 0.0);
    assert!((t[2].transform.rotation.z - 0.15f64.sin()).abs() < 1e-12);
    assert_eq!(t[2].transform.translation.x, 1.7);
    assert_eq!(t[1].child_frame_id, "wheel_right_link");
}
