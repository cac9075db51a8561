//! The robot's flows (ROBOT/tick, ROBOT/status and ROBOT/event, JSON) made into ROS 2
//! messages, each with its topic and stamp. The bridge publishes them (bridge.rs) and
//! `mechweed record --ros2` writes them to a bag (bag.rs): the same bytes both ways.
//!
//! Stamps are the robot's own times: a tick's supervisor time `t_s` on the robot's
//! wall clock, which its status gives (`wall_s` when published, less its `t_s`).

use std::time::Instant;

use serde_json::{Map, Value};

use super::cdr::{RosMessage, encode};
use super::clock::RobotClock;
use super::diagnostics;
use super::msgs::{
    BatteryState, Float64, Log, NavSatFix, NavSatStatus, Pose, PoseWithCovariance,
    PoseWithCovarianceStamped, Quaternion, Time, Vector3,
};
use super::odom::{BASE_FRAME, Frames, GNSS_FRAME, Odometer, TickMotion, header};
use super::topics::Topic;

/// One message for one topic.
#[derive(Debug, Clone)]
pub struct Outgoing {
    pub topic: Topic,
    pub stamp: Time,
    /// Encapsulation header and CDR.
    pub bytes: Vec<u8>,
}

/// The frame of /row: x along the row at the robot, y to the row's left.
pub const ROW_FRAME: &str = "row";
/// No status for this long and /diagnostics says every part STALE, s.
pub const STALE_AFTER_S: f64 = 3.0;

/// What the bridge has converted, and refused.
#[derive(Debug, Clone, Copy, Default)]
pub struct Counts {
    pub ticks: u64,
    pub statuses: u64,
    pub events: u64,
    /// Messages that could not be read (named when said).
    pub bad: u64,
}

pub struct Converter {
    robot: String,
    wheel_radius_m: f64,
    frames: Frames,
    odometer: Odometer,
    clock: RobotClock,
    /// The last status, and when it arrived.
    last_status: Option<(Value, Instant)>,
    /// The loops' overruns in the status before the last: rising, they are a WARN.
    overruns_before: Option<u64>,
    /// When the converter began: STALE comes only after STALE_AFTER_S without a status,
    /// counted from here until the first status comes.
    started: Instant,
    /// The last fix sent on /fix: quality, latitude and longitude.
    last_fix: Option<(u64, Option<f64>, Option<f64>)>,
    /// The robot's time of the last /battery_state, s.
    last_battery_t_s: Option<f64>,
    pub counts: Counts,
}

fn object(bytes: &[u8]) -> Result<Map<String, Value>, String> {
    match serde_json::from_slice::<Value>(bytes) {
        Ok(Value::Object(map)) => Ok(map),
        Ok(_) => Err("JSON but not an object".to_string()),
        Err(e) => Err(format!("not JSON ({e})")),
    }
}

/// A number the message must have (JSON null: not a number now, NaN).
fn number(map: &Map<String, Value>, key: &str) -> Result<f64, String> {
    match map.get(key) {
        Some(Value::Number(n)) => n.as_f64().ok_or_else(|| format!("{key} is not a number")),
        Some(Value::Null) => Ok(f64::NAN),
        Some(other) => Err(format!("{key} is {other}, not a number")),
        None => Err(format!("{key} is missing")),
    }
}

fn message<T: RosMessage>(topic: Topic, stamp: Time, msg: &T) -> Result<Outgoing, String> {
    Ok(Outgoing {
        topic,
        stamp,
        bytes: encode(msg)?,
    })
}

impl Converter {
    pub fn new(robot: &str, wheel_radius_m: f64) -> Converter {
        Converter {
            robot: robot.to_string(),
            wheel_radius_m,
            frames: Frames::default(),
            odometer: Odometer::default(),
            clock: RobotClock::default(),
            last_status: None,
            overruns_before: None,
            started: Instant::now(),
            last_fix: None,
            last_battery_t_s: None,
            counts: Counts::default(),
        }
    }

    /// Every frame id with `prefix` before it (`[ros2] frame_prefix`).
    pub fn with_frame_prefix(mut self, prefix: &str) -> Converter {
        self.frames = Frames::new(prefix);
        self
    }

    /// The robot's time `t_s` on its wall clock; before a status of the run, this
    /// computer's now.
    fn stamp(&self, t_s: f64) -> Time {
        let wall_s = self.clock.wall_s(t_s);
        Time::from_unix_s(wall_s.unwrap_or_else(crate::bus::payload::wall_s))
    }

    /// A tick: /joint_states, /odom, /tf and /cross_track.
    pub fn tick(&mut self, bytes: &[u8]) -> Result<Vec<Outgoing>, String> {
        let map = object(bytes)?;
        let tick = TickMotion {
            t_s: number(&map, "t_s")?,
            distance_m: number(&map, "distance_m")?,
            speed_mps: number(&map, "speed_mps")?,
            yaw_rate_rps: number(&map, "yaw_rate_rps")?,
            v_left_mps: number(&map, "v_left_mps")?,
            v_right_mps: number(&map, "v_right_mps")?,
            wheel_angle_rad: number(&map, "wheel_angle_rad")?,
        };
        let tool_offset_m = number(&map, "law_tool_offset_m")?;
        self.counts.ticks += 1;
        self.clock.tick(tick.t_s);
        self.odometer.step(tick, self.wheel_radius_m);
        let stamp = self.stamp(tick.t_s);
        let o = &self.odometer;
        let mut out = vec![
            message(
                Topic::JointStates,
                stamp,
                &o.joints(stamp, &tick, self.wheel_radius_m, &self.frames),
            )?,
            message(Topic::Odom, stamp, &o.odometry(stamp, &tick, &self.frames))?,
            message(Topic::Tf, stamp, &o.transform(stamp, &self.frames))?,
        ];
        if tool_offset_m.is_finite() {
            // The law's offset is the row's from the tool; cross-track is the tool's.
            let cross_track = Float64 {
                data: -tool_offset_m,
            };
            out.push(message(Topic::CrossTrack, stamp, &cross_track)?);
        }
        Ok(out)
    }

    /// A status that arrived at `arrived`: /row when the row filter runs, /fix when the
    /// fix changed.
    pub fn status(&mut self, bytes: &[u8], arrived: Instant) -> Result<Vec<Outgoing>, String> {
        let map = object(bytes)?;
        let (t_s, wall_s) = (number(&map, "t_s")?, number(&map, "wall_s")?);
        if !(t_s.is_finite() && wall_s.is_finite()) {
            return Err("t_s and wall_s must be numbers".to_string());
        }
        self.counts.statuses += 1;
        self.clock.status(t_s, wall_s);
        let stamp = self.stamp(t_s);
        let status = Value::Object(map);
        let mut out = Vec::new();
        if let Some(row) = row(&status["filter"], stamp, &self.frames.id(ROW_FRAME)) {
            out.push(message(Topic::Row, stamp, &row)?);
        }
        if let Some(fix) = self.fix(&status["gnss"], stamp) {
            out.push(message(Topic::Fix, stamp, &fix)?);
        }
        if let Some(battery) = self.battery(&status, t_s, stamp) {
            out.push(message(Topic::Battery, stamp, &battery)?);
        }
        let overruns = |s: &Value| diagnostics::overruns(s);
        self.overruns_before = self.last_status.as_ref().map(|(s, _)| overruns(s));
        self.last_status = Some((status, arrived));
        Ok(out)
    }

    /// An event: /rosout, at the level its kind deserves.
    pub fn event(&mut self, bytes: &[u8]) -> Result<Vec<Outgoing>, String> {
        let map = object(bytes)?;
        let t_s = number(&map, "t_s")?;
        let word = |key: &str| match map.get(key) {
            Some(Value::String(s)) => Ok(s.clone()),
            _ => Err(format!("{key} is not text")),
        };
        let (kind, text) = (word("kind")?, word("text")?);
        // A notice is news (INFO), but for one of something degraded or stopped: a
        // sensor lost, an end switch hit.
        let warns = diagnostics::is_fallback(&text) || text.contains("end switch");
        let level = match kind.as_str() {
            "fault" => 40,
            "dropped" => 30,
            "notice" if warns => 30,
            _ => 20,
        };
        self.counts.events += 1;
        let stamp = self.stamp(t_s);
        let log = Log {
            stamp,
            level,
            name: self.robot.replace('/', "."),
            msg: format!("{kind}: {text}"),
            ..Log::default()
        };
        Ok(vec![message(Topic::Rosout, stamp, &log)?])
    }

    /// /diagnostics from the last status; each part STALE once no status came for
    /// STALE_AFTER_S (since the converter began, before the first), and nothing before.
    pub fn diagnostics(&self, now: Instant, bridge: &str) -> Result<Option<Outgoing>, String> {
        let wall = Time::from_unix_s(crate::bus::payload::wall_s());
        let since = |at: Instant| now.saturating_duration_since(at).as_secs_f64();
        let array = match &self.last_status {
            Some((status, at)) if since(*at) < STALE_AFTER_S => {
                let t_s = status["t_s"].as_f64().unwrap_or(f64::NAN);
                let rising =
                    (self.overruns_before).is_some_and(|o| diagnostics::overruns(status) > o);
                let part = diagnostics::Context {
                    robot: &self.robot,
                    bridge,
                    overruns_rising: rising,
                };
                diagnostics::from_status(status, &part, self.stamp(t_s))
            }
            Some((_, at)) => diagnostics::stale(&self.robot, wall, since(*at)),
            None if since(self.started) >= STALE_AFTER_S => {
                diagnostics::stale(&self.robot, wall, since(self.started))
            }
            None => return Ok(None),
        };
        message(Topic::Diagnostics, array.header.stamp, &array).map(Some)
    }

    /// /battery_state about once a second of the robot's time (again at once after it
    /// started again): the voltage is all the robot measures of its battery.
    fn battery(&mut self, status: &Value, t_s: f64, stamp: Time) -> Option<BatteryState> {
        let voltage = status["battery_v"].as_f64()?;
        let due = (self.last_battery_t_s)
            .is_none_or(|last| !(0.0..BATTERY_EVERY_S).contains(&(t_s - last)));
        if !due {
            return None;
        }
        self.last_battery_t_s = Some(t_s);
        Some(BatteryState {
            header: header(stamp, &self.frames.id(BASE_FRAME)),
            voltage: voltage as f32,
            temperature: f32::NAN,
            current: f32::NAN,
            charge: f32::NAN,
            capacity: f32::NAN,
            design_capacity: f32::NAN,
            percentage: f32::NAN,
            present: true,
            ..BatteryState::default()
        })
    }

    /// /fix, when the quality or the position changed since the last sent.
    fn fix(&mut self, gnss: &Value, stamp: Time) -> Option<NavSatFix> {
        let quality = gnss["quality"].as_u64()?;
        let (lat, lon) = (gnss["lat_deg"].as_f64(), gnss["lon_deg"].as_f64());
        let now = (quality, lat, lon);
        if self.last_fix == Some(now) || (self.last_fix.is_none() && quality == 0) {
            return None;
        }
        self.last_fix = Some(now);
        let frame = self.frames.id(GNSS_FRAME);
        Some(nav_sat_fix(
            quality,
            lat,
            lon,
            gnss["sd_m"].as_f64(),
            stamp,
            &frame,
        ))
    }
}

/// How often /battery_state goes out, s of the robot's time.
const BATTERY_EVERY_S: f64 = 1.0;

/// Up's variance when the robot does not know it, m²: so large that nothing trusts it.
pub const UNKNOWN_VARIANCE_M2: f64 = 1e6;

/// The GGA quality as NavSatStatus says it: 1 GPS and 3 PPS a plain fix, 2 DGPS
/// satellite-augmented, 4 and 5 RTK ground-augmented; 0, and 6 dead reckoning, 7 manual,
/// 8 simulation, no fix of the sky.
fn nav_sat_fix(
    quality: u64,
    lat: Option<f64>,
    lon: Option<f64>,
    sd_m: Option<f64>,
    stamp: Time,
    frame: &str,
) -> NavSatFix {
    let status = match quality {
        1 | 3 => 0,
        2 => 1,
        4 | 5 => 2,
        _ => -1,
    };
    // The robot carries the worse of the receiver's east and north s.d. (GST), not the
    // altitude: east and north from it, approximated; up is not known.
    let (covariance, kind) = match sd_m {
        Some(sd) => (
            [
                sd * sd,
                0.0,
                0.0,
                0.0,
                sd * sd,
                0.0,
                0.0,
                0.0,
                UNKNOWN_VARIANCE_M2,
            ],
            1,
        ),
        None => ([0.0; 9], 0),
    };
    NavSatFix {
        header: header(stamp, frame),
        status: NavSatStatus { status, service: 1 },
        latitude: lat.unwrap_or(f64::NAN),
        longitude: lon.unwrap_or(f64::NAN),
        altitude: f64::NAN,
        position_covariance: covariance,
        position_covariance_type: kind,
    }
}

/// The rear axle's place in the row's frame, from the row filter: the row offset `o`
/// (+ = row left of the robot) puts the robot at y = -o, and the row's heading
/// relative to the robot turns it by its negative.
fn row(filter: &Value, stamp: Time, frame: &str) -> Option<PoseWithCovarianceStamped> {
    let offset_m = filter["offset_m"].as_f64()?;
    let heading_rad = filter["heading_rad"].as_f64()?;
    let sd_m = filter["offset_sd_m"].as_f64().unwrap_or(0.0);
    let mut covariance = [0.0; 36];
    covariance[7] = sd_m * sd_m;
    Some(PoseWithCovarianceStamped {
        header: header(stamp, frame),
        pose: PoseWithCovariance {
            pose: Pose {
                position: Vector3 {
                    x: 0.0,
                    y: -offset_m,
                    z: 0.0,
                },
                orientation: Quaternion::yaw(-heading_rad),
            },
            covariance,
        },
    })
}
