//! What travels on the bus, as JSON: the status the robot publishes, and the requests
//! and row estimates it takes, each checked with a reason that names what is wrong.
//! Names and units are the run record's (record/row.rs), so a flow, a record and the
//! GUI say the same thing in the same words.

use mechweed_hw::camproto::{MAX_ANGLE_RAD, MAX_OFFSET_M, RowEstimate};
use serde_json::{Value, json};

use crate::camlink::LinkStatus;
use crate::rt::LoopSummary;
use crate::state::modes::{Mode, Request};
use crate::state::status::{PowerState, Status};
use crate::steer::SteerCommand;

/// `ROBOT/status`, about ten times a second.
pub(crate) fn status_json(
    status: &Status,
    link: &LinkStatus,
    steer: &SteerCommand,
    loops: &[LoopSummary; 2],
) -> Value {
    let power = match status.power {
        PowerState::Off => "off",
        PowerState::Closing { .. } => "closing",
        PowerState::On => "on",
    };
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    json!({
        "t_s": status.t_s,
        // Wall-clock time of publishing, s since 1970: a receiver on a machine with the
        // same clock (NTP, or the same computer) sees how old the status is.
        "wall_s": wall_s(),
        "tick": status.tick,
        "mode": status.mode.name(),
        "power": power,
        "fault": status.fault.map(|f| f.cause.to_string()),
        "fault_check": status.fault.map(|f| f.cause.what_to_check()),
        "fault_came_back_after_s": status.fault.and_then(|f| f.came_back_after_s),
        "notice": status.notice.map(|n| n.to_string()),
        "speed_mps": status.measured.speed_mps,
        "wheel_angle_rad": status.measured.wheel_angle_rad,
        "distance_m": status.measured.distance_m,
        "battery_v": status.inputs.battery_v,
        "camera": {
            "connected": link.connected,
            "streaming": link.streaming,
            "age_s": finite(status.t_s - link.last_usable_s),
            "offset_m": link.last_usable.offset_m,
            "angle_rad": link.last_usable.angle_rad,
            "quality": link.last_usable.quality,
            "counters": link.counters,
        },
        "steering": steer.sources.steering.name(),
        "gnss": gnss_json(steer),
        "filter": steer.row.filter.map(|f| json!({
            "offset_m": f.offset_m,
            "offset_sd_m": f.offset_sd_m,
            "heading_rad": f.heading_rad,
            "heading_sd_rad": f.heading_sd_rad,
            "curvature_per_m": f.curvature_per_m,
            "map_bias_m": f.map_bias_m,
            "camera_rejected": f.camera_rejected,
            "gnss_rejected": f.gnss_rejected,
        })),
        "loops": { "supervisor": loops[0], "steer": loops[1] },
    })
}

/// The last GNSS fix as the steer thread saw it (quality 0 and nulls: no fix).
fn gnss_json(steer: &SteerCommand) -> Value {
    let row = &steer.row;
    let (lat_deg, lon_deg) = row.gnss_position.unzip();
    json!({
        "quality": row.gnss_quality,
        "satellites": row.gnss_satellites,
        "sd_m": row.gnss_sd_m,
        "lat_deg": lat_deg,
        "lon_deg": lon_deg,
    })
}

/// Now, s since 1970 (the system clock).
pub fn wall_s() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// A payload as a JSON object with no field but `known`, or why not: a misspelt field
/// is named, never ignored.
fn object(bytes: &[u8], known: &[&str]) -> Result<serde_json::Map<String, Value>, String> {
    let text =
        std::str::from_utf8(bytes).map_err(|_| "the payload is not UTF-8 text".to_string())?;
    match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(map)) => match map.keys().find(|k| !known.contains(&k.as_str())) {
            Some(unknown) => Err(format!(
                "\"{}\" is not a field here (the fields are {})",
                clip(unknown),
                known.join(", ")
            )),
            // serde_json keeps the last of a field given twice: a second one is no guess.
            None => match given_twice(text) {
                Some(twice) => Err(format!(
                    "\"{}\" is given twice: give each field once",
                    clip(&twice)
                )),
                None => Ok(map),
            },
        },
        Ok(other) => Err(format!(
            "the payload is JSON but not an object: {}",
            clip(&other.to_string())
        )),
        Err(e) => Err(format!("the payload is not JSON ({e}): {}", clip(text))),
    }
}

/// The first field of a JSON object `text` given more than once, if one is.
fn given_twice(text: &str) -> Option<String> {
    struct Names(Vec<String>);
    impl<'de> serde::Deserialize<'de> for Names {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Names, D::Error> {
            struct Each;
            impl<'de> serde::de::Visitor<'de> for Each {
                type Value = Names;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("a JSON object")
                }
                fn visit_map<M: serde::de::MapAccess<'de>>(
                    self,
                    mut m: M,
                ) -> Result<Names, M::Error> {
                    let mut names = Vec::new();
                    while let Some((name, _)) = m.next_entry::<String, serde::de::IgnoredAny>()? {
                        names.push(name);
                    }
                    Ok(Names(names))
                }
            }
            d.deserialize_map(Each)
        }
    }
    let Names(names) = serde_json::from_str(text).ok()?;
    let mut seen = std::collections::BTreeSet::new();
    names.into_iter().find(|name| !seen.insert(name.clone()))
}

/// At most 80 characters of `text`, for a message.
fn clip(text: &str) -> String {
    let mut out: String = text.chars().take(80).collect();
    if out.len() < text.len() {
        out.push_str("...");
    }
    out
}

/// `ROBOT/request`: `{"request": "halt" | "power_up" | "mode", "mode": "..."}`.
pub(crate) fn parse_request(bytes: &[u8]) -> Result<Request, String> {
    let map = object(bytes, &["request", "mode"])?;
    let word = match map.get("request") {
        Some(Value::String(word)) => word.as_str(),
        Some(other) => return Err(format!("\"request\" must be a word, not {other}")),
        None => return Err("no \"request\": say halt, power_up or mode".to_string()),
    };
    if word != "mode" && map.contains_key("mode") {
        return Err(format!(
            "\"mode\" goes only with a mode request, not with {word}"
        ));
    }
    match word {
        "halt" => Ok(Request::Mode(Mode::Halt)),
        "power_up" => Ok(Request::PowerUp),
        "mode" => {
            let mode = match map.get("mode") {
                Some(Value::String(mode)) => mode.as_str(),
                _ => {
                    return Err(
                        "a mode request needs \"mode\": joystick, autonomous, test or halt"
                            .to_string(),
                    );
                }
            };
            let mode = match mode {
                "halt" => Mode::Halt,
                "joystick" => Mode::Joystick,
                "autonomous" => Mode::Autonomous,
                "test" => Mode::Test,
                other => {
                    return Err(format!(
                        "\"{other}\" is not a mode: joystick, autonomous, test or halt"
                    ));
                }
            };
            Ok(Request::Mode(mode))
        }
        other => Err(format!(
            "\"{other}\" is not a request: halt, power_up or mode"
        )),
    }
}

/// `ROBOT/config/SECTION/KEY` set: `{"set": "VALUE"}` (a number may come as a number).
pub(crate) fn parse_set(bytes: &[u8]) -> Result<String, String> {
    let map = object(bytes, &["set"])?;
    match map.get("set") {
        Some(Value::String(text)) => Ok(text.clone()),
        Some(Value::Number(n)) => Ok(n.to_string()),
        Some(other) => Err(format!("\"set\" must be the value as text, not {other}")),
        None => Err("no \"set\": a set is {\"set\": \"VALUE\"}; a get has no payload".to_string()),
    }
}

/// `ROBOT/camera/row`: `{"seq", "angle_rad", "offset_m", "quality", "t_s"}` from a vision
/// program; the ranges are the row camera's (beyond them no camera sees a row).
pub(crate) fn parse_row(bytes: &[u8]) -> Result<(RowEstimate, Option<f64>), String> {
    let map = object(bytes, &["seq", "angle_rad", "offset_m", "quality", "t_s"])?;
    let number = |key: &str| match map.get(key) {
        Some(Value::Number(n)) => n
            .as_f64()
            .ok_or_else(|| format!("\"{key}\" is not a number")),
        Some(other) => Err(format!("\"{key}\" must be a number, not {other}")),
        None => Err(format!("no \"{key}\"")),
    };
    let whole = |key: &str, max: u64| match map.get(key).and_then(Value::as_u64) {
        Some(n) if n <= max => Ok(n),
        _ => Err(format!(
            "\"{key}\" must be a whole number 0 to {max}, not {}",
            map.get(key).map_or("nothing".to_string(), Value::to_string)
        )),
    };
    let angle_rad = number("angle_rad")?;
    let offset_m = number("offset_m")?;
    if angle_rad.abs() > MAX_ANGLE_RAD {
        return Err(format!(
            "angle_rad {angle_rad} is beyond what the camera can see (at most {MAX_ANGLE_RAD} rad either way)"
        ));
    }
    if offset_m.abs() > MAX_OFFSET_M {
        return Err(format!(
            "offset_m {offset_m} is beyond what the camera can see (at most {MAX_OFFSET_M} m either way)"
        ));
    }
    let t_s = match map.get("t_s") {
        None => None,
        Some(t) => match t.as_f64().filter(|t| t.is_finite()) {
            Some(t) => Some(t),
            None => return Err(format!("\"t_s\" must be a number of seconds, not {t}")),
        },
    };
    let estimate = RowEstimate {
        seq: whole("seq", 255)? as u8,
        angle_rad,
        offset_m,
        quality: whole("quality", 100)? as u8,
    };
    Ok((estimate, t_s))
}

/// A row estimate as a vision program publishes it (camsim --bus, tests).
pub(crate) fn row_json(estimate: &RowEstimate, t_s: f64) -> Value {
    json!({
        "seq": estimate.seq,
        "angle_rad": estimate.angle_rad,
        "offset_m": estimate.offset_m,
        "quality": estimate.quality,
        "t_s": t_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_given_twice_is_refused_and_a_huge_one_is_named_short() {
        let twice = parse_request(br#"{"request":"halt","request":"power_up"}"#).unwrap_err();
        assert!(twice.contains("\"request\" is given twice"), "{twice}");
        let huge = format!(r#"{{"{}": 1}}"#, "x".repeat(100_000));
        let why = parse_request(huge.as_bytes()).unwrap_err();
        assert!(why.len() < 300, "{} characters", why.len());
        let array = format!("[{}]", "1,".repeat(50_000) + "1");
        assert!(parse_request(array.as_bytes()).unwrap_err().len() < 300);
    }

    #[test]
    fn requests_parse_and_bad_ones_say_what_is_wrong() {
        assert_eq!(
            parse_request(br#"{"request":"halt"}"#),
            Ok(Request::Mode(Mode::Halt))
        );
        assert_eq!(
            parse_request(br#"{"request":"mode","mode":"autonomous"}"#),
            Ok(Request::Mode(Mode::Autonomous))
        );
        let bad = [
            (&b"halt"[..], "not JSON"),
            (br#"[1,2]"#, "not an object"),
            (br#"{"request":5}"#, "must be a word"),
            (br#"{"request":"dance"}"#, "\"dance\" is not a request"),
            (br#"{"request":"mode"}"#, "needs \"mode\""),
            (
                br#"{"request":"mode","mode":"fault"}"#,
                "\"fault\" is not a mode",
            ),
            (b"\xff\xfe", "not UTF-8"),
        ];
        for (payload, says) in bad {
            let err = parse_request(payload).unwrap_err();
            assert!(err.contains(says), "{err}");
        }
    }

    #[test]
    fn row_estimates_beyond_the_camera_s_view_are_refused() {
        let (ok, t_s) =
            parse_row(br#"{"seq":3,"angle_rad":0.1,"offset_m":-0.02,"quality":90,"t_s":1.5}"#)
                .unwrap();
        assert_eq!((ok.seq, ok.quality, t_s), (3, 90, Some(1.5)));
        let bad = [
            (
                &br#"{"seq":3,"angle_rad":2.0,"offset_m":0,"quality":90}"#[..],
                "angle_rad 2",
            ),
            (
                br#"{"seq":3,"angle_rad":0,"offset_m":9,"quality":90}"#,
                "offset_m 9",
            ),
            (
                br#"{"seq":3,"angle_rad":0,"offset_m":0,"quality":101}"#,
                "\"quality\"",
            ),
            (
                br#"{"seq":-1,"angle_rad":0,"offset_m":0,"quality":1}"#,
                "\"seq\"",
            ),
            (
                br#"{"seq":1,"angle_rad":"0","offset_m":0,"quality":1}"#,
                "must be a number",
            ),
            (br#"{"seq":1,"offset_m":0,"quality":1}"#, "no \"angle_rad\""),
            (
                br#"{"seq":1,"angle_rad":0,"offset_m":0,"quality":1,"t_s":"x"}"#,
                "\"t_s\"",
            ),
        ];
        for (payload, says) in bad {
            let err = parse_row(payload).unwrap_err();
            assert!(err.contains(says), "{err}");
        }
    }

    #[test]
    fn a_set_takes_text_or_a_number() {
        assert_eq!(parse_set(br#"{"set":"1.5"}"#).unwrap(), "1.5");
        assert_eq!(parse_set(br#"{"set":1.5}"#).unwrap(), "1.5");
        let misspelt = parse_set(br#"{"value":1}"#).unwrap_err();
        assert!(
            misspelt.contains("\"value\" is not a field here"),
            "{misspelt}"
        );
        assert!(parse_set(b"{}").unwrap_err().contains("no \"set\""));
    }
}
