//! The robot's flows made into ROS messages, from the JSON the robot itself writes
//! (`tick_json`, `status_json`): stamps on the robot's clock, /fix only when the fix
//! changes, /rosout levels, STALE diagnostics, and bad messages refused with why.

use std::time::{Duration, Instant};

use mechweed_core::record::{TickSample, tick_json};

use super::cdr::decode;
use super::diagnostics::{ERROR, OK, STALE, WARN};
use super::flows::Converter;
use super::model::RobotModel;
use super::msgs::{BatteryState, DiagnosticArray, JointState, Log, NavSatFix, Odometry};
use super::topics::Topic;
use crate::bus::payload::status_json;
use crate::state::modes::Mode;
use crate::state::status::Notice;
use crate::state::steering::Steering;
use mechweed_core::config::Settings;
use mechweed_core::rt::LoopSummary;

pub(super) fn tick(t_s: f64, distance_m: f64) -> Vec<u8> {
    let mut sample = TickSample::default();
    sample.status.t_s = t_s;
    sample.status.mode = Mode::Autonomous;
    let m = &mut sample.status.measured;
    (m.v_left_mps, m.v_right_mps, m.speed_mps) = (0.9, 1.1, 1.0);
    (m.distance_m, m.wheel_angle_rad, m.yaw_rate_rps) = (distance_m, 0.05, 0.0);
    let mut json = String::new();
    tick_json(&sample, &mut json);
    json.into_bytes()
}

/// A status of the robot at `t_s`, published at `wall_s`, with the GNSS quality `q`.
pub(super) fn status(t_s: f64, wall_s: f64, q: u8, lat_deg: f64) -> Vec<u8> {
    let mut s = TickSample::default();
    s.status.t_s = t_s;
    s.steer.row.gnss_quality = q;
    s.steer.row.gnss_position = (q > 0).then_some((lat_deg, 5.0));
    s.steer.row.gnss_sd_m = (q > 0).then_some(0.02);
    let mut json = status_json(&s.status, &s.link, &s.steer, &[Default::default(); 2]);
    json["wall_s"] = wall_s.into();
    json["cross_track"] = "estimated".into();
    json["bus"] =
        serde_json::json!({"secured": false, "security": "not secured", "identities": ""});
    json.to_string().into_bytes()
}

pub(super) fn topics(out: &[super::flows::Outgoing]) -> Vec<Topic> {
    out.iter().map(|o| o.topic).collect()
}

#[test]
fn ticks_are_stamped_on_the_robots_clock_once_a_status_gives_it() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    c.status(&status(10.0, 1_000_010.5, 0, 0.0), Instant::now())
        .unwrap();
    // Published later after its tick: the least offset is the robot's clock.
    c.status(&status(10.1, 1_000_010.9, 0, 0.0), Instant::now())
        .unwrap();
    let out = c.tick(&tick(10.25, 3.0)).unwrap();
    assert_eq!(
        topics(&out),
        [
            Topic::JointStates,
            Topic::Odom,
            Topic::Tf,
            Topic::CrossTrack
        ]
    );
    let stamp = out[0].stamp;
    assert_eq!(stamp.sec, 1_000_010);
    assert!(
        (i64::from(stamp.nanosec) - 750_000_000).abs() < 1000,
        "{stamp:?}"
    );
    let joints: JointState = decode(&out[0].bytes).unwrap();
    assert_eq!(joints.header.stamp, stamp);
    // 0.9 and 1.1 m/s on 0.2 m wheels; the wheel angle as it is.
    assert_eq!(joints.velocity[..2], [4.5, 5.5]);
    assert_eq!(joints.position[2], 0.05);
    let later = c.tick(&tick(10.35, 3.1)).unwrap();
    let odom: Odometry = decode(&later[1].bytes).unwrap();
    assert!((odom.pose.pose.position.x - 0.1).abs() < 1e-9, "{odom:?}");
    assert_eq!(odom.twist.twist.linear.x, 1.0);
    // The robot program started again a minute later: its run clock is back near 0.
    c.status(&status(0.5, 1_000_071.0, 0, 0.0), Instant::now())
        .unwrap();
    let again = c.tick(&tick(0.6, 0.1)).unwrap();
    assert_eq!(again[0].stamp.sec, 1_000_071, "{:?}", again[0].stamp);
}

#[test]
fn the_battery_goes_out_once_a_second_of_the_robots_time_with_its_voltage() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()))
        .with_frame_prefix("robot2/");
    let mut sent = Vec::new();
    // Statuses at 10 a second for 2.5 s, the voltage falling; then the robot starts again.
    for (i, t_s) in (0..25).map(|i| (i, f64::from(i) * 0.1)).chain([(25, 0.2)]) {
        let mut json: serde_json::Value =
            serde_json::from_slice(&status(t_s, 100.0 + t_s, 0, 0.0)).unwrap();
        json["battery_v"] = (25.0 - 0.01 * f64::from(i)).into();
        let out = c
            .status(json.to_string().as_bytes(), Instant::now())
            .unwrap();
        let battery = out.iter().filter(|o| o.topic == Topic::Battery);
        sent.extend(battery.map(|o| decode::<BatteryState>(&o.bytes).unwrap()));
    }
    let volts: Vec<f32> = sent.iter().map(|b| b.voltage).collect();
    assert_eq!(
        volts,
        [25.0, 24.9, 24.8, 24.75],
        "at 0, 1, 2 s and after the restart"
    );
    let b = &sent[0];
    assert_eq!(b.header.frame_id, "robot2/base_link");
    assert!(
        b.present && b.current.is_nan() && b.percentage.is_nan(),
        "{b:?}"
    );
    assert_eq!((b.power_supply_status, b.power_supply_health), (0, 0));
}

#[test]
fn the_fix_is_sent_when_it_changes_and_a_lost_fix_is_said_once() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let now = Instant::now();
    let fixes = |out: Vec<super::flows::Outgoing>| -> Vec<NavSatFix> {
        out.iter()
            .filter(|o| o.topic == Topic::Fix)
            .map(|o| decode(&o.bytes).unwrap())
            .collect()
    };
    // No receiver yet: nothing on /fix.
    assert!(fixes(c.status(&status(1.0, 101.0, 0, 0.0), now).unwrap()).is_empty());
    let first = fixes(c.status(&status(1.1, 101.1, 4, 52.0), now).unwrap());
    assert_eq!(first.len(), 1);
    assert_eq!((first[0].status.status, first[0].latitude), (2, 52.0));
    assert!((first[0].position_covariance[0] - 0.0004).abs() < 1e-12);
    assert!(first[0].altitude.is_nan());
    assert_eq!(
        first[0].position_covariance[8],
        super::sensors::UNKNOWN_VARIANCE_M2
    );
    // The same fix again is not news.
    assert!(fixes(c.status(&status(1.2, 101.2, 4, 52.0), now).unwrap()).is_empty());
    let lost = fixes(c.status(&status(1.3, 101.3, 0, 0.0), now).unwrap());
    assert_eq!((lost.len(), lost[0].status.status), (1, -1));
    assert_eq!(lost[0].position_covariance_type, 0);
    assert!(fixes(c.status(&status(1.4, 101.4, 0, 0.0), now).unwrap()).is_empty());
}

#[test]
fn only_rtk_is_ground_augmented_and_a_fix_not_of_the_sky_is_no_fix() {
    let now = Instant::now();
    for (quality, status_word) in [
        (1, 0),
        (2, 1),
        (3, 0),
        (4, 2),
        (5, 2),
        (6, -1),
        (7, -1),
        (8, -1),
    ] {
        let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
        let out = c.status(&status(1.0, 101.0, quality, 52.0), now).unwrap();
        let fix: NavSatFix =
            decode(&out.iter().find(|o| o.topic == Topic::Fix).unwrap().bytes).unwrap();
        assert_eq!(fix.status.status, status_word, "GGA quality {quality}");
    }
}

#[test]
fn events_go_to_rosout_at_their_levels() {
    let mut c = Converter::new("farm/mechweed", RobotModel::of(&Settings::shipped()));
    let said = |c: &mut Converter, kind: &str, text: &str| -> Log {
        let event = serde_json::json!({"t_s": 1.0, "tick": 100, "kind": kind, "text": text});
        decode(&c.event(event.to_string().as_bytes()).unwrap()[0].bytes).unwrap()
    };
    let level = |c: &mut Converter, kind: &str| said(c, kind, "it");
    let fault = level(&mut c, "fault");
    assert_eq!(
        (fault.level, fault.msg.as_str(), fault.name.as_str()),
        (40, "fault: it", "farm.mechweed")
    );
    // A notice is news; a sensor lost, or an end switch hit, a warning.
    assert_eq!(level(&mut c, "notice").level, 20);
    let fused = said(&mut c, "notice", "steering by camera and GNSS, fused");
    assert_eq!(fused.level, 20);
    let lost = said(
        &mut c,
        "notice",
        "steering by GNSS alone: no usable camera row",
    );
    assert_eq!(lost.level, 30);
    assert_eq!(level(&mut c, "dropped").level, 30);
    assert_eq!(level(&mut c, "mode").level, 20);
}

#[test]
fn diagnostics_say_each_part_and_go_stale_without_statuses() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let t0 = Instant::now();
    let array = |c: &Converter, at: Instant| -> DiagnosticArray {
        decode(&c.diagnostics(at, "bridge figures").unwrap().unwrap().bytes).unwrap()
    };
    // Nothing is stale before the time without a status has passed, also before the
    // first status; then every part is.
    assert!(c.diagnostics(t0, "").unwrap().is_none());
    let silent = array(&c, t0 + Duration::from_secs(4));
    assert_eq!(silent.status.len(), 5);
    assert!(
        silent
            .status
            .iter()
            .all(|s| s.level == STALE && s.message == "no status from the robot for 4 s"),
        "{silent:?}"
    );
    let ids: Vec<&str> = silent
        .status
        .iter()
        .map(|s| s.hardware_id.as_str())
        .collect();
    assert_eq!(
        ids,
        [
            "mechweed/supervisor",
            "mechweed/steering",
            "mechweed/camera_link",
            "mechweed/gnss",
            "mechweed/bus"
        ]
    );
    c.status(&status(2.0, 102.0, 5, 52.0), t0).unwrap();
    let now = array(&c, t0 + Duration::from_secs(1));
    let levels: Vec<u8> = now.status.iter().map(|s| s.level).collect();
    // Halt, no fault; a camera with no rows; RTK float; the bus.
    assert_eq!(levels, [OK, OK, ERROR, WARN, OK], "{now:?}");
    assert_eq!(now.status[3].message, "RTK float");
    let mode = now.status[0]
        .values
        .iter()
        .find(|kv| kv.key == "mode")
        .unwrap();
    assert_eq!(mode.value, "halt");
    let late = array(&c, t0 + Duration::from_secs(4));
    assert!(
        late.status
            .iter()
            .all(|s| s.level == STALE && s.message == "no status from the robot for 4 s")
    );
}

#[test]
fn a_message_that_is_not_the_robots_is_refused_with_what_is_wrong() {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let why = c.tick(b"{\"t_s\": 1.0}").unwrap_err();
    assert_eq!(why, "distance_m is missing");
    let why = c.tick(b"[1, 2]").unwrap_err();
    assert_eq!(why, "JSON but not an object");
    let why = c
        .status(b"{\"t_s\": \"soon\", \"wall_s\": 1}", Instant::now())
        .unwrap_err();
    assert!(why.contains("t_s is \"soon\""), "{why}");
    let why = c
        .event(b"{\"t_s\": 1, \"kind\": 3, \"text\": \"x\"}")
        .unwrap_err();
    assert_eq!(why, "kind is not text");
    assert!(c.tick(b"\xff").unwrap_err().starts_with("not JSON"));
    assert_eq!(c.counts.ticks + c.counts.statuses + c.counts.events, 0);
}

/// A status of an autonomous run steered by `steering`, its last notice the change to
/// it for `why`, the camera streaming, RTK fixed, the loops with `overruns`.
fn running(steering: Steering, why: Option<&'static str>, overruns: u64) -> Vec<u8> {
    let mut s = TickSample::default();
    s.status.t_s = 20.0;
    s.status.mode = Mode::Autonomous;
    s.status.notice = Some(Notice::Steering {
        steering,
        why,
        t_s: 10.0,
    });
    s.steer.sources.steering = steering;
    (s.link.connected, s.link.streaming) = (true, true);
    s.steer.row.gnss_quality = 4;
    s.steer.row.gnss_position = Some((52.0, 5.0));
    let loops = [LoopSummary {
        overruns,
        ..Default::default()
    }; 2];
    let mut json = status_json(&s.status, &s.link, &s.steer, &loops);
    json["wall_s"] = 1000.0.into();
    json["bus"] =
        serde_json::json!({"secured": false, "security": "not secured", "identities": ""});
    json.to_string().into_bytes()
}

fn levels_after(statuses: &[Vec<u8>]) -> (Vec<u8>, DiagnosticArray) {
    let mut c = Converter::new("mechweed", RobotModel::of(&Settings::shipped()));
    let t0 = Instant::now();
    for status in statuses {
        c.status(status, t0).unwrap();
    }
    let bytes = c.diagnostics(t0, "").unwrap().unwrap().bytes;
    let array: DiagnosticArray = decode(&bytes).unwrap();
    (array.status.iter().map(|s| s.level).collect(), array)
}

#[test]
fn a_healthy_fused_run_is_ok_everywhere_and_its_notice_is_the_steerings_message() {
    let (levels, array) = levels_after(&[running(Steering::Fused, None, 0)]);
    assert_eq!(levels, [OK, OK, OK, OK, OK], "{array:?}");
    assert_eq!(
        array.status[1].message,
        "steering by camera and GNSS, fused"
    );
}

#[test]
fn a_sensor_lost_with_another_steering_in_its_place_is_a_warning() {
    let camera_lost = running(Steering::FilterGnss, Some("no usable camera row"), 0);
    let (levels, array) = levels_after(&[camera_lost]);
    assert_eq!(levels[1], WARN, "{array:?}");
    assert!(array.status[1].message.ends_with(": no usable camera row"));
    let (levels, _) = levels_after(&[running(Steering::FilterCamera, None, 0)]);
    assert_eq!(levels[1], WARN);
    // GNSS alone as configured ([steer] source = gnss) is no fallback.
    let (levels, _) = levels_after(&[running(Steering::FilterGnss, None, 0)]);
    assert_eq!(levels[1], OK);
}

#[test]
fn loops_running_late_warn_while_their_overruns_rise_and_not_after() {
    let (levels, array) = levels_after(&[
        running(Steering::Fused, None, 2),
        running(Steering::Fused, None, 5),
    ]);
    assert_eq!(levels[0], WARN, "{array:?}");
    assert!(array.status[0].message.ends_with("loops running late"));
    let (levels, _) = levels_after(&[
        running(Steering::Fused, None, 5),
        running(Steering::Fused, None, 5),
    ]);
    assert_eq!(levels[0], OK);
}
