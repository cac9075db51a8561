//! /diagnostics from the robot's status: one status per part (supervisor, steering,
//! camera link, GNSS, bus), each with a level and the figures an operator reads on
//! the GUI, as key/value text. The levels inform; they never stop anything (the
//! supervisor does that on the robot). A level says what the part's state means: OK
//! when it works as configured (a notice goes in the message), WARN only when it is
//! degraded (a sensor lost and another steering in its place, a float fix, loops
//! running late), ERROR for a fault; STALE is the converter's (flows.rs).

use serde_json::Value;

use super::msgs::{DiagnosticArray, DiagnosticStatus, KeyValue, Time};
use super::odom::header;

pub const OK: u8 = 0;
pub const WARN: u8 = 1;
pub const ERROR: u8 = 2;
pub const STALE: u8 = 3;

/// The parts, as their statuses are named: `mechweed: PART`.
pub const PARTS: [&str; 5] = ["supervisor", "steering", "camera link", "GNSS", "bus"];

/// A field of the status as text: numbers as JSON writes them, null as "none".
fn text(v: &Value) -> String {
    match v {
        Value::Null => "none".to_string(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

fn part(
    name: &str,
    robot: &str,
    level: u8,
    message: String,
    values: Vec<KeyValue>,
) -> DiagnosticStatus {
    DiagnosticStatus {
        level,
        name: format!("mechweed: {name}"),
        message,
        hardware_id: hardware_id(robot, name),
        values,
    }
}

/// The part on the robot, as `ROBOT/part` ("mechweed/camera_link").
fn hardware_id(robot: &str, name: &str) -> String {
    format!("{robot}/{}", name.to_lowercase().replace(' ', "_"))
}

/// What the diagnostics need besides the status.
pub struct Context<'a> {
    /// The robot's name on the bus.
    pub robot: &'a str,
    /// The bridge's own figures.
    pub bridge: &'a str,
    /// The loops' overruns rose since the status before.
    pub overruns_rising: bool,
}

/// Whether a notice tells of a sensor lost and another steering in its place: a
/// steering notice with its reason ("steering by GNSS alone: no usable camera row").
pub fn is_fallback(notice: &str) -> bool {
    notice.starts_with("steering by ") && notice.contains(": ")
}

/// Both loops' overruns so far in `status`.
pub fn overruns(status: &Value) -> u64 {
    ["supervisor", "steer"]
        .iter()
        .filter_map(|lp| status["loops"][lp]["overruns"].as_u64())
        .sum()
}

/// Key/values of `object`'s fields `keys`, under their own names.
fn fields(object: &Value, keys: &[&str]) -> Vec<KeyValue> {
    keys.iter()
        .map(|k| KeyValue {
            key: k.to_string(),
            value: text(&object[*k]),
        })
        .collect()
}

fn kv(key: &str, value: String) -> KeyValue {
    KeyValue {
        key: key.to_string(),
        value,
    }
}

/// The five statuses of one robot status.
pub fn from_status(status: &Value, context: &Context, stamp: Time) -> DiagnosticArray {
    let (robot, bridge) = (context.robot, context.bridge);
    let mode = text(&status["mode"]);
    let fault = &status["fault"];
    let notice = &status["notice"];

    let supervisor = {
        let running = format!("{mode}, motor power {}", text(&status["power"]));
        let (level, message) = match fault {
            Value::String(f) => (ERROR, format!("fault: {f}")),
            _ if context.overruns_rising => (WARN, format!("{running}; loops running late")),
            _ => (OK, running),
        };
        let mut values = fields(
            status,
            &[
                "mode",
                "power",
                "fault",
                "speed_mps",
                "wheel_angle_rad",
                "distance_m",
                "battery_v",
            ],
        );
        for (name, lp) in [
            ("supervisor", &status["loops"]["supervisor"]),
            ("steer", &status["loops"]["steer"]),
        ] {
            values.push(kv(&format!("{name} loop rate_hz"), text(&lp["rate_hz"])));
            values.push(kv(&format!("{name} loop overruns"), text(&lp["overruns"])));
            values.push(kv(
                &format!("{name} loop late_us p99"),
                text(&lp["late_us"]["p99"]),
            ));
            values.push(kv(
                &format!("{name} loop exec_us p99"),
                text(&lp["exec_us"]["p99"]),
            ));
        }
        part("supervisor", robot, level, message, values)
    };

    let steering_by = text(&status["steering"]);
    let steering = {
        let said = match notice {
            Value::String(n) => n.clone(),
            _ => format!("steering by {steering_by}"),
        };
        let fallback = is_fallback(&said);
        let (level, message) = match steering_by.as_str() {
            "nothing" if mode == "autonomous" => (ERROR, "nothing to steer by".to_string()),
            "camera_alone" => (WARN, said),
            "gnss_alone" if fallback => (WARN, said),
            _ => (OK, said),
        };
        let mut values = vec![
            kv("steering", steering_by.clone()),
            kv("notice", text(notice)),
        ];
        let filter = &status["filter"];
        if filter.is_object() {
            values.extend(fields(
                filter,
                &[
                    "offset_m",
                    "offset_sd_m",
                    "heading_rad",
                    "curvature_per_m",
                    "map_bias_m",
                    "camera_rejected",
                    "gnss_rejected",
                ],
            ));
        }
        values.push(kv("cross_track", text(&status["cross_track"])));
        part("steering", robot, level, message, values)
    };

    let camera = {
        let c = &status["camera"];
        let (level, message) = match (c["connected"].as_bool(), c["streaming"].as_bool()) {
            (Some(true), Some(true)) => (OK, "streaming rows".to_string()),
            (Some(true), _) => (WARN, "connected, no rows".to_string()),
            _ => (ERROR, "not connected".to_string()),
        };
        let mut values = fields(
            c,
            &[
                "connected",
                "streaming",
                "age_s",
                "offset_m",
                "angle_rad",
                "quality",
            ],
        );
        if let Value::Object(counters) = &c["counters"] {
            values.extend(counters.iter().map(|(k, v)| kv(k, text(v))));
        }
        part("camera link", robot, level, message, values)
    };

    let gnss = {
        let g = &status["gnss"];
        let by_gnss = matches!(steering_by.as_str(), "fused" | "gnss_alone");
        let (level, message) = match g["quality"].as_u64() {
            Some(4) => (OK, "RTK fixed".to_string()),
            Some(5) => (WARN, "RTK float".to_string()),
            Some(q) if q > 0 => (WARN, format!("fix quality {q}, not RTK")),
            _ if by_gnss => (ERROR, "no fix".to_string()),
            _ => (OK, "no fix (not steering by GNSS)".to_string()),
        };
        part(
            "GNSS",
            robot,
            level,
            message,
            fields(g, &["quality", "satellites", "sd_m", "lat_deg", "lon_deg"]),
        )
    };

    let bus = {
        let b = &status["bus"];
        let mut values = fields(b, &["secured", "security", "identities"]);
        values.push(kv("bridge", bridge.to_string()));
        part("bus", robot, OK, text(&b["security"]), values)
    };

    DiagnosticArray {
        header: header(stamp, ""),
        status: vec![supervisor, steering, camera, gnss, bus],
    }
}

/// Every part STALE: no status from the robot for `silent_s`.
pub fn stale(robot: &str, stamp: Time, silent_s: f64) -> DiagnosticArray {
    DiagnosticArray {
        header: header(stamp, ""),
        status: PARTS
            .iter()
            .map(|p| {
                let message = format!("no status from the robot for {silent_s:.0} s");
                part(p, robot, STALE, message, Vec::new())
            })
            .collect(),
    }
}
