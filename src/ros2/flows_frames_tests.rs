//! The converter's frames and the robot's model: the latched model and fixed frames,
//! the odometry's covariances, and the frame prefix on every frame id.

use std::time::Instant;

use mechweed_core::config::Settings;

use super::cdr::decode;
use super::flows::Converter;
use super::flows_tests::{status, tick, topics};
use super::model::RobotModel;
use super::msgs::{JointState, NavSatFix, Odometry, StringMsg, TfMessage};
use super::topics::Topic;

#[test]
fn the_model_is_latched_first_and_odometry_has_covariances_that_grow_with_the_drive() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let latched = c.latched().unwrap();
    assert_eq!(topics(&latched), [Topic::RobotDescription, Topic::TfStatic]);
    // Ten metres straight on: the heading's spread is slip over 10 m; sideways it has
    // grown far beyond the first step's; every variance is finite and none negative.
    let odometry = |c: &mut Converter, t_s: f64, m: f64| -> Odometry {
        decode(&c.tick(&tick(t_s, m)).unwrap()[1].bytes).unwrap()
    };
    odometry(&mut c, 0.0, 0.0);
    let first = odometry(&mut c, 0.1, 0.1);
    let mut last = first.clone();
    for k in 2..=100 {
        last = odometry(&mut c, 0.1 * k as f64, 0.1 * k as f64);
    }
    let slip = Settings::shipped().filter.slip_sd_per_sqrt_m;
    let yaw_var = last.pose.covariance[35];
    assert!(
        (yaw_var / (slip * slip * 10.0) - 1.0).abs() < 0.01,
        "{yaw_var}"
    );
    assert!(last.pose.covariance[7] > 100.0 * first.pose.covariance[7]);
    assert!(last.twist.covariance[0] > 0.0 && last.twist.covariance[35] > 0.0);
    for cov in [last.pose.covariance, last.twist.covariance] {
        assert!(cov.iter().all(|v| v.is_finite()));
        assert!((0..6).all(|k| cov[7 * k] >= 0.0));
    }
}

#[test]
fn a_frame_prefix_goes_before_every_frame_id_and_none_leaves_them_as_they_are() {
    for (prefix, odom_frame, base_frame, gnss_frame) in [
        ("", "odom", "base_link", "gnss"),
        ("robot2/", "robot2/odom", "robot2/base_link", "robot2/gnss"),
    ] {
        let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()))
            .with_frame_prefix(prefix);
        let out = c.tick(&tick(1.0, 0.5)).unwrap();
        let joints: JointState = decode(&out[0].bytes).unwrap();
        let odom: Odometry = decode(&out[1].bytes).unwrap();
        let tf: TfMessage = decode(&out[2].bytes).unwrap();
        assert_eq!(joints.header.frame_id, base_frame);
        assert_eq!(
            (odom.header.frame_id.as_str(), odom.child_frame_id.as_str()),
            (odom_frame, base_frame)
        );
        let t = &tf.transforms[0];
        assert_eq!(
            (t.header.frame_id.as_str(), t.child_frame_id.as_str()),
            (odom_frame, base_frame)
        );
        // The moving links too, and every link of the model and its fixed frames.
        assert!(
            tf.transforms[1..]
                .iter()
                .all(|t| t.header.frame_id == base_frame && t.child_frame_id.starts_with(prefix))
        );
        let latched = c.latched().unwrap();
        let fixed: TfMessage = decode(&latched[1].bytes).unwrap();
        assert!(
            fixed
                .transforms
                .iter()
                .any(|t| t.child_frame_id == gnss_frame)
        );
        let urdf: StringMsg = decode(&latched[0].bytes).unwrap();
        assert!(urdf.data.contains(&format!("<link name=\"{base_frame}\">")));
        let out = c.status(&status(1.1, 101.1, 4, 52.0), Instant::now());
        let fix = out.unwrap().into_iter().find(|o| o.topic == Topic::Fix);
        let fix: NavSatFix = decode(&fix.expect("a fix").bytes).unwrap();
        assert_eq!(fix.header.frame_id, gnss_frame);
    }
}

#[test]
fn the_rows_frame_is_placed_from_base_link_and_its_pose_carries_the_filters_spread() {
    use mechweed_core::record::TickSample;
    use mechweed_core::steer::FilterFigures;
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let mut s = TickSample::default();
    s.status.t_s = 1.0;
    s.steer.row.filter = Some(FilterFigures {
        offset_m: 0.1,
        offset_sd_m: 0.02,
        heading_rad: std::f64::consts::FRAC_PI_2,
        heading_sd_rad: 0.01,
        curvature_per_m: 0.0,
        map_bias_m: 0.0,
        camera_rejected: 0,
        gnss_rejected: 0,
    });
    let json =
        crate::bus::payload::status_json(&s.status, &s.link, &s.steer, &[Default::default(); 2]);
    let out = c
        .status(json.to_string().as_bytes(), Instant::now())
        .unwrap();
    let row = out.iter().find(|o| o.topic == Topic::Row).expect("a row");
    let row: super::msgs::PoseWithCovarianceStamped = decode(&row.bytes).unwrap();
    let cov = row.pose.covariance;
    assert!((cov[7] - 0.02 * 0.02).abs() < 1e-12 && (cov[35] - 1e-4).abs() < 1e-12);
    assert!(cov[14] >= 1e6, "up is not known");
    // The row 10 cm off and turned a quarter left: the robot is 10 cm to the right of
    // the row's x axis (its frame's y is base_link's -x), so the origin is 10 cm behind
    // the rear axle.
    let tf = out
        .iter()
        .find(|o| o.topic == Topic::Tf)
        .expect("base_link -> row");
    let tf: TfMessage = decode(&tf.bytes).unwrap();
    let t = &tf.transforms[0];
    assert_eq!(
        (t.header.frame_id.as_str(), t.child_frame_id.as_str()),
        ("base_link", "row")
    );
    let v = t.transform.translation;
    assert!((v.x + 0.1).abs() < 1e-12 && v.y.abs() < 1e-12, "{v:?}");
}
