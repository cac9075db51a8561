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
use super::covariance::{PoseSpread, twist_covariance};
use super::diagnostics;
use super::model::RobotModel;
use super::msgs::{BatteryState, Float64, Log, NavSatFix, StringMsg, Time};
use super::odom::{BASE_FRAME, Frames, GNSS_FRAME, Odometer, TickMotion, header};
use super::sensors::{nav_sat_fix, row, row_transform};
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
    model: RobotModel,
    frames: Frames,
    odometer: Odometer,
    spread: PoseSpread,
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
    pub fn new(robot: &str, model: RobotModel) -> Converter {
        Converter {
            robot: robot.to_string(),
            model,
            frames: Frames::default(),
            odometer: Odometer::default(),
            spread: PoseSpread::default(),
            clock: RobotClock::default(),
            last_status: None,
            overruns_before: None,
            started: Instant::now(),
            last_fix: None,
            last_battery_t_s: None,
            counts: Counts::default(),
        }
    }

    /// The latched topics, sent once at the start: the robot's model and fixed frames.
    pub fn latched(&self) -> Result<Vec<Outgoing>, String> {
        let stamp = Time::from_unix_s(crate::bus::payload::wall_s());
        let urdf = StringMsg {
            data: self.model.urdf(&self.frames),
        };
        let fixed = self.model.static_transforms(stamp, &self.frames);
        Ok(vec![
            message(Topic::RobotDescription, stamp, &urdf)?,
            message(Topic::TfStatic, stamp, &fixed)?,
        ])
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
        let radius_m = self.model.wheel_radius_m;
        self.odometer.step(tick, radius_m);
        let dt_s = match self.odometer.last_move.take() {
            Some(step) => {
                self.spread.step(step, tick.wheel_angle_rad, &self.model);
                step.dt_s
            }
            None => self.model.period_s,
        };
        let stamp = self.stamp(tick.t_s);
        let (o, frames, model) = (&self.odometer, &self.frames, &self.model);
        let joints = o.joints(stamp, &tick, radius_m, frames);
        let mut odometry = o.odometry(stamp, &tick, frames);
        odometry.pose.covariance = self.spread.pose_covariance(model);
        odometry.twist.covariance =
            twist_covariance(tick.speed_mps, tick.wheel_angle_rad, dt_s, model);
        // odom -> base_link, and base_link -> each moving link: rviz2 draws the model.
        let mut tf = o.transform(stamp, frames);
        let at = [joints.position[0], joints.position[1], joints.position[2]];
        tf.transforms
            .extend(model.joint_transforms(stamp, at, frames));
        let mut out = vec![
            message(Topic::JointStates, stamp, &joints)?,
            message(Topic::Odom, stamp, &odometry)?,
            message(Topic::Tf, stamp, &tf)?,
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
        let (base, row_frame) = (self.frames.id(BASE_FRAME), self.frames.id(ROW_FRAME));
        if let Some(row) = row(&status["filter"], stamp, &row_frame) {
            out.push(message(Topic::Row, stamp, &row)?);
        }
        if let Some(tf) = row_transform(&status["filter"], stamp, &base, &row_frame) {
            out.push(message(Topic::Tf, stamp, &tf)?);
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
