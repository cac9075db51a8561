//! What the bridge test heard, checked against the run: each topic decoded, and its
//! values those of an autonomous, driving, RTK-fixed run on the row.

use mechweed::ros2::cdr::decode;
use mechweed::ros2::msgs::{
    BatteryState, DiagnosticArray, Float64, JointState, Log, NavSatFix, Odometry,
    PoseWithCovarianceStamped, TfMessage,
};

use super::bridge::Heard;

fn all<T: serde::de::DeserializeOwned>(heard: &Heard, topic: &str) -> Vec<T> {
    heard[topic]
        .iter()
        .map(|(p, _)| decode(p).unwrap_or_else(|e| panic!("{topic}: {e}")))
        .collect()
}

/// The values match the run: autonomous, driving, RTK fixed, on the row.
pub(super) fn check_the_run(heard: &Heard) {
    let diagnostics: Vec<DiagnosticArray> = all(heard, "/diagnostics");
    let names: Vec<&str> = diagnostics[0]
        .status
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "mechweed: supervisor",
            "mechweed: steering",
            "mechweed: camera link",
            "mechweed: GNSS",
            "mechweed: bus"
        ]
    );
    let modes: Vec<&str> = diagnostics
        .iter()
        .flat_map(|d| {
            d.status[0]
                .values
                .iter()
                .filter(|kv| kv.key == "mode")
                .map(|kv| kv.value.as_str())
        })
        .collect();
    assert!(modes.contains(&"autonomous"), "{modes:?}");
    assert!(
        diagnostics
            .iter()
            .any(|d| d.status[3].message == "RTK fixed" && d.status[3].level == 0)
    );
    // A healthy fused run: nothing STALE (the robot's statuses came all along, the first
    // within the bridge's first second), and once fused, the steering is OK, its notice
    // the message.
    let levels: Vec<Vec<u8>> = (diagnostics.iter())
        .map(|d| d.status.iter().map(|s| s.level).collect())
        .collect();
    assert!(levels.iter().flatten().all(|&l| l != 3), "{levels:?}");
    let fused: Vec<&DiagnosticArray> = (diagnostics.iter())
        .filter(|d| d.status[1].message.contains("fused"))
        .collect();
    assert!(!fused.is_empty(), "{diagnostics:?}");
    assert!(fused.iter().all(|d| d.status[1].level == 0), "{fused:?}");

    let odometry: Vec<Odometry> = all(heard, "/mechweed/odom");
    let joints: Vec<JointState> = all(heard, "/mechweed/joint_states");
    assert!(
        odometry.len() > 30 && joints.len() == odometry.len(),
        "{} {}",
        odometry.len(),
        joints.len()
    );
    let (first, last) = (
        &odometry[0].pose.pose.position,
        &odometry.last().unwrap().pose.pose.position,
    );
    assert!(
        last.x > first.x + 2.0,
        "the robot went from {first:?} to {last:?}"
    );
    for (o, j) in odometry.iter().zip(&joints) {
        assert_eq!(o.header.frame_id, "odom");
        assert_eq!(o.child_frame_id, "base_link");
        assert_eq!(j.name, ["wheel_left", "wheel_right", "steering"]);
        // Wheel speed in rad/s on a 0.2 m wheel: the robot's speed between the two.
        let wheels_mps = 0.1 * (j.velocity[0] + j.velocity[1]);
        assert!(
            (wheels_mps - o.twist.twist.linear.x).abs() < 0.05,
            "{wheels_mps} {:?}",
            o.twist
        );
        assert!(j.position[2].abs() < 0.6, "steering {} rad", j.position[2]);
    }
    assert!(
        joints.iter().any(|j| j.velocity[0] > 2.0),
        "never faster than 0.4 m/s"
    );

    // Each tick's /tf: odom -> base_link, then the three moving links; each status's
    // while the filter runs: base_link -> row.
    let tf: Vec<TfMessage> = all(heard, "/tf");
    let pairs = |m: &TfMessage| -> Vec<(String, String)> {
        (m.transforms.iter())
            .map(|t| (t.header.frame_id.clone(), t.child_frame_id.clone()))
            .collect()
    };
    let ticks: Vec<&TfMessage> = (tf.iter())
        .filter(|m| m.transforms[0].child_frame_id == "base_link")
        .collect();
    let links = [
        "base_link",
        "wheel_left_link",
        "wheel_right_link",
        "steering_link",
    ];
    let expected: Vec<(String, String)> = (links.iter().enumerate())
        .map(|(k, l)| {
            (
                (if k == 0 { "odom" } else { "base_link" }).to_string(),
                l.to_string(),
            )
        })
        .collect();
    assert_eq!(pairs(ticks.last().unwrap()), expected);
    assert_eq!(
        ticks.last().unwrap().transforms[0].transform.translation,
        *last
    );
    let row = ("base_link".to_string(), "row".to_string());
    assert!(
        tf.iter().any(|m| pairs(m) == [row.clone()]),
        "no base_link -> row"
    );

    let fixes: Vec<NavSatFix> = all(heard, "/mechweed/fix");
    let fix = fixes.last().unwrap();
    assert_eq!(
        fix.status.status, 2,
        "RTK fixed is ground-based augmentation"
    );
    assert!(fix.latitude.abs() <= 90.0 && fix.latitude != 0.0, "{fix:?}");
    assert_eq!(fix.position_covariance_type, 1);
    assert!(fix.position_covariance[0] > 0.0 && fix.position_covariance[0] < 0.05 * 0.05);

    let rows: Vec<PoseWithCovarianceStamped> = all(heard, "/mechweed/row");
    let row = rows.last().unwrap();
    assert_eq!(row.header.frame_id, "row");
    assert!(
        row.pose.pose.position.y.abs() < 0.1 && row.pose.covariance[7] > 0.0,
        "{row:?}"
    );
    let cross_track: Vec<Float64> = all(heard, "/mechweed/cross_track");
    assert!(
        cross_track.iter().all(|c| c.data.abs() < 0.15),
        "{cross_track:?}"
    );

    // The battery once a second, at the simulated battery's voltage.
    let battery: Vec<BatteryState> = all(heard, "/mechweed/battery_state");
    assert!(battery.len() >= 3, "{battery:?}");
    assert!(
        battery
            .iter()
            .all(|b| b.voltage > 20.0 && b.voltage < 30.0 && b.present),
        "{battery:?}"
    );

    let logs: Vec<Log> = all(heard, "/rosout");
    assert!(
        logs.iter()
            .any(|l| l.msg.starts_with("mode: ") && l.msg.contains("halt") && l.level == 20),
        "{logs:?}"
    );
}
