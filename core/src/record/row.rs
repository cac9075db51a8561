//! One tick of a record: what the supervisor thread hands over, and the table of
//! columns that both formats write. The CSV header and the MCAP JSON schema are made
//! from `COLUMNS`, so a name, its unit and its meaning are written down only here.

use mechweed_hw::Side;
use mechweed_hw::sim::Truth;

use crate::camlink::LinkStatus;
use crate::rt::health::ThreadHealth;
use crate::state::status::PowerState;
use crate::state::status::Status;
use crate::steer::{EndSwitchState, SteerCommand};

/// What the supervisor thread hands to the recorder for one tick: plain copies, so
/// handing it over never allocates.
#[derive(Debug, Clone, Copy, Default)]
pub struct TickSample {
    /// The supervisor's status as published at the end of the tick.
    pub status: Status,
    /// The steer thread's latest command (with the steering law's workings).
    pub steer: SteerCommand,
    /// The camera link's latest status (with the estimate in use).
    pub link: LinkStatus,
    /// The simulated robot's truth at this tick; None on the real robot.
    pub truth: Option<Truth>,
    /// What else the tick was given, so that a replay can give it again.
    pub given: Given,
}

/// What a supervisor tick is given besides the inputs, the steer command and the link
/// status: the other threads' health, and a card that failed in this tick.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Given {
    pub health: ThreadHealth,
    pub hw_failed: Option<HwFailure>,
}

/// A card that did not answer: in the tick's read or its write.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HwFailure {
    /// "read" or "write".
    pub during: &'static str,
    pub card: &'static str,
}

/// One cell. Numbers that are not finite (no camera estimate yet, not simulated) are
/// written as an empty CSV cell and a JSON null: MATLAB and pandas read both as NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    Num(f64),
    Int(i64),
    /// A fixed word (mode, power state, end switch side): no commas, no quotes.
    Text(&'static str),
}

/// A column of the record: its name (with the unit in it), unit, meaning, and how to
/// get its value from a tick.
pub struct Column {
    pub name: &'static str,
    pub unit: &'static str,
    pub meaning: &'static str,
    pub value: fn(&TickSample) -> Value,
}

const fn col(
    name: &'static str,
    unit: &'static str,
    meaning: &'static str,
    value: fn(&TickSample) -> Value,
) -> Column {
    Column {
        name,
        unit,
        meaning,
        value,
    }
}

fn num(x: f64) -> Value {
    Value::Num(x)
}

/// One of the row filter's figures; empty when the camera steered alone.
fn filter(r: &TickSample, figure: fn(&crate::steer::FilterFigures) -> f64) -> Value {
    num(r.steer.row.filter.as_ref().map_or(f64::NAN, figure))
}

/// On/off signals as 0 and 1, which every plotting tool draws.
fn flag(on: bool) -> Value {
    Value::Int(on as i64)
}

fn power(p: PowerState) -> Value {
    Value::Text(match p {
        PowerState::Off => "off",
        PowerState::Closing { .. } => "closing",
        PowerState::On => "on",
    })
}

fn side(s: Option<Side>) -> Value {
    Value::Text(match s {
        None => "",
        Some(Side::Left) => "left",
        Some(Side::Right) => "right",
    })
}

fn sim(r: &TickSample, get: fn(&Truth) -> f64) -> Value {
    num(r.truth.as_ref().map_or(f64::NAN, get))
}

/// Every column of a tick, in file order. Names are valid MATLAB and Python
/// identifiers; SI units as in the program (angles in rad, speeds in m/s).
#[rustfmt::skip]
pub const COLUMNS: &[Column] = &[
    // Time and state.
    col("t_s", "s", "supervisor time since the run started", |r| num(r.status.t_s)),
    col("tick", "count", "supervisor tick number", |r| Value::Int(r.status.tick as i64)),
    col("mode", "text", "halt, joystick, autonomous, test or fault", |r| Value::Text(r.status.mode.name())),
    col("power", "text", "motor power: off, closing or on", |r| power(r.status.power)),
    // Every input, as read.
    col("pot_v", "V", "steering potentiometer", |r| num(r.status.inputs.pot_v)),
    col("joystick_steer_v", "V", "joystick steer axis, + = right", |r| num(r.status.inputs.joystick_steer_v)),
    col("joystick_speed_v", "V", "joystick speed axis, + = forward", |r| num(r.status.inputs.joystick_speed_v)),
    col("battery_v", "V", "battery voltage", |r| num(r.status.inputs.battery_v)),
    col("estop_front_released", "0/1", "1 = front e-stop released", |r| flag(r.status.inputs.estop_front_released)),
    col("estop_back_released", "0/1", "1 = back e-stop released", |r| flag(r.status.inputs.estop_back_released)),
    col("motor_power_present", "0/1", "1 = motor contactor closed", |r| flag(r.status.inputs.motor_power_present)),
    col("end_switch_left", "0/1", "1 = left steering end switch closed", |r| flag(r.status.inputs.end_switch_left)),
    col("end_switch_right", "0/1", "1 = right steering end switch closed", |r| flag(r.status.inputs.end_switch_right)),
    col("joystick_enable", "0/1", "1 = dead-man button held", |r| flag(r.status.inputs.joystick_enable)),
    col("enc_left_counts", "counts", "left wheel encoder", |r| Value::Int(r.status.inputs.enc_left_counts)),
    col("enc_right_counts", "counts", "right wheel encoder", |r| Value::Int(r.status.inputs.enc_right_counts)),
    col("enc_steer_counts", "counts", "steering encoder, 0 at power-up", |r| Value::Int(r.status.inputs.enc_steer_counts)),
    // Every output, as written.
    col("amp_left_v", "V", "left drive amplifier, + = forward", |r| num(r.status.outputs.amp_left_v)),
    col("amp_right_v", "V", "right drive amplifier, + = forward", |r| num(r.status.outputs.amp_right_v)),
    col("amp_steer_v", "V", "steering amplifier, + = turn left", |r| num(r.status.outputs.amp_steer_v)),
    col("main_power_on", "0/1", "1 = contactor commanded closed", |r| flag(r.status.outputs.main_power_on)),
    col("brake_release_left", "0/1", "1 = left brake released", |r| flag(r.status.outputs.brake_release_left)),
    col("brake_release_right", "0/1", "1 = right brake released", |r| flag(r.status.outputs.brake_release_right)),
    col("tool_on", "0/1", "1 = weeding tool on", |r| flag(r.status.outputs.tool_on)),
    // Measured.
    col("v_left_mps", "m/s", "left wheel speed, filtered", |r| num(r.status.measured.v_left_mps)),
    col("v_right_mps", "m/s", "right wheel speed, filtered", |r| num(r.status.measured.v_right_mps)),
    col("speed_mps", "m/s", "speed of the rear axle centre", |r| num(r.status.measured.speed_mps)),
    col("wheel_angle_rad", "rad", "wheel angle, + = left", |r| num(r.status.measured.wheel_angle_rad)),
    col("pot_angle_filtered_rad", "rad", "wheel angle from the potentiometer, filtered",
        |r| num(r.status.measured.pot_angle_filtered_rad)),
    col("wheel_angle_filtered_rad", "rad", "wheel angle from the encoder, same filter",
        |r| num(r.status.measured.wheel_angle_filtered_rad)),
    col("yaw_rate_rps", "rad/s", "heading rate, + = turning left", |r| num(r.status.measured.yaw_rate_rps)),
    col("distance_m", "m", "odometry: distance driven", |r| num(r.status.measured.distance_m)),
    col("calibrated", "0/1", "1 = steering encoder calibrated", |r| flag(r.status.measured.calibrated)),
    // Regulators: references, and errors = reference - measured (the regulators run
    // only in joystick and autonomous).
    col("speed_ref_mps", "m/s", "speed reference after the ramp", |r| num(r.status.speed_ref_mps)),
    col("v_left_ref_mps", "m/s", "left wheel speed reference", |r| num(r.status.v_left_ref_mps)),
    col("v_right_ref_mps", "m/s", "right wheel speed reference", |r| num(r.status.v_right_ref_mps)),
    col("wheel_angle_ref_rad", "rad", "wheel angle reference after the ramp", |r| num(r.status.wheel_angle_ref_rad)),
    col("v_left_err_mps", "m/s", "left wheel speed error",
        |r| num(r.status.v_left_ref_mps - r.status.measured.v_left_mps)),
    col("v_right_err_mps", "m/s", "right wheel speed error",
        |r| num(r.status.v_right_ref_mps - r.status.measured.v_right_mps)),
    col("wheel_angle_err_rad", "rad", "wheel angle error",
        |r| num(r.status.wheel_angle_ref_rad - r.status.measured.wheel_angle_rad)),
    col("endswitch_hit", "text", "end switch hit latched: left, right or empty", |r| side(r.status.endswitch_hit)),
    // The steer thread's command and the steering law's workings.
    col("steer_speed_mps", "m/s", "speed asked by the steer thread", |r| num(r.steer.speed_mps)),
    col("steer_wheel_angle_rad", "rad", "wheel angle asked by the steer thread", |r| num(r.steer.wheel_angle_rad)),
    col("steer_age_s", "s", "age of the steer command at this tick", |r| num(r.status.t_s - r.steer.t_s)),
    col("law_lookahead_offset_m", "m", "row offset at the look-ahead point, + = left",
        |r| num(r.steer.law.lookahead_offset_m)),
    col("law_tool_offset_m", "m", "row offset at the tool, as the law sees it", |r| num(r.steer.law.tool_offset_m)),
    col("law_row_curvature_per_m", "1/m", "row curvature used, + = left", |r| num(r.steer.law.row_curvature_per_m)),
    col("law_integral_per_m", "1/m", "curvature added by the tool integral", |r| num(r.steer.law.integral_per_m)),
    // The GNSS fix and the row filter (source gnss or fused; empty otherwise).
    col("gnss_quality", "code", "the last fix's GGA quality: 0 none, 1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float",
        |r| Value::Int(r.steer.row.gnss_quality as i64)),
    col("gnss_satellites", "count", "satellites in the last fix", |r| Value::Int(r.steer.row.gnss_satellites as i64)),
    col("gnss_sd_m", "m", "the receiver's own s.d. of that position (GST)",
        |r| num(r.steer.row.gnss_sd_m.unwrap_or(f64::NAN))),
    col("gnss_heard_s", "s", "when the GNSS receiver last sent an epoch, fix or not (empty: never)",
        |r| num(r.steer.row.gnss_heard_s.unwrap_or(f64::NAN))),
    col("gnss_lat_deg", "deg", "the antenna's latitude in the last fix (WGS-84)",
        |r| num(r.steer.row.gnss_position.map_or(f64::NAN, |p| p.0))),
    col("gnss_lon_deg", "deg", "the antenna's longitude in the last fix",
        |r| num(r.steer.row.gnss_position.map_or(f64::NAN, |p| p.1))),
    col("filter_offset_m", "m", "the row filter's row offset at the rear axle, + = left", |r| filter(r, |f| f.offset_m)),
    col("filter_offset_sd_m", "m", "its s.d.", |r| filter(r, |f| f.offset_sd_m)),
    col("filter_heading_rad", "rad", "the row's heading relative to the robot, + = left", |r| filter(r, |f| f.heading_rad)),
    col("filter_curvature_per_m", "1/m", "the row's curvature, + = left", |r| filter(r, |f| f.curvature_per_m)),
    col("filter_map_bias_m", "m", "how far the map's line lies left of the row", |r| filter(r, |f| f.map_bias_m)),
    col("filter_camera_rejected", "count", "camera rows the filter's gate rejected so far",
        |r| Value::Int(r.steer.row.filter.map_or(0, |f| f.camera_rejected) as i64)),
    col("filter_gnss_rejected", "count", "GNSS fixes the filter's gate rejected so far",
        |r| Value::Int(r.steer.row.filter.map_or(0, |f| f.gnss_rejected) as i64)),
    // The camera estimate in use (the last usable one) and the link's counters.
    col("cam_offset_m", "m", "row offset at the camera point, + = left", |r| num(r.link.last_usable.offset_m)),
    col("cam_angle_rad", "rad", "row angle, + = row turns left", |r| num(r.link.last_usable.angle_rad)),
    col("cam_quality", "0-100", "camera confidence of that estimate",
        |r| Value::Int(r.link.last_usable.quality as i64)),
    col("cam_seq", "count", "sequence number of that estimate", |r| Value::Int(r.link.last_usable.seq as i64)),
    col("cam_age_s", "s", "time since that estimate arrived (empty: none yet)",
        |r| num(r.status.t_s - r.link.last_usable_s)),
    col("cam_frames_ok", "count", "valid frames so far", |r| Value::Int(r.link.counters.frames_ok as i64)),
    col("cam_crc_errors", "count", "frames with a bad CRC so far", |r| Value::Int(r.link.counters.crc_errors as i64)),
    col("cam_seq_gaps", "count", "frames lost (sequence gaps) so far", |r| Value::Int(r.link.counters.seq_gaps as i64)),
    col("cam_duplicates", "count", "frames received twice (ignored) so far",
        |r| Value::Int(r.link.counters.duplicates as i64)),
    col("cam_connected", "0/1", "1 = camera port open", |r| flag(r.link.connected)),
    col("link_streaming_since_s", "s", "when the camera link began this spell of streaming rows (empty: not streaming)",
        |r| num(if r.link.streaming { r.link.streaming_since_s } else { f64::NAN })),
    col("link_heard_s", "s", "when the camera computer last sent a valid frame, a row or a PONG (empty: never)",
        |r| num(r.link.heard_s)),
    // The rest of what the tick was given (for `mechweed replay`): the steer command's
    // time, mode and end-switch procedure, the link's times, the threads' health.
    col("steer_t_s", "s", "when the steer command was made", |r| num(r.steer.t_s)),
    col("steer_mode", "text", "the mode the steer command was made for", |r| Value::Text(r.steer.mode.name())),
    col("steer_endswitch", "text", "end-switch procedure under way: left, right or empty",
        |r| side(match r.steer.endswitch { EndSwitchState::Active { side: s, .. } => Some(s), _ => None })),
    col("steer_endswitch_since_s", "s", "when that procedure began (empty: none)",
        |r| num(match r.steer.endswitch { EndSwitchState::Active { since_s, .. } => since_s, _ => f64::NAN })),
    col("steer_endswitch_done", "count", "end-switch procedures finished so far",
        |r| Value::Int(r.steer.endswitch_done_count as i64)),
    col("steer_endswitch_last", "text", "side of the last one finished", |r| side(r.steer.endswitch_last_side)),
    col("steering", "text", "which sensors steer: camera, fused, camera_alone, gnss_alone or nothing",
        |r| Value::Text(r.steer.sources.steering.name())),
    col("steer_camera_good_s", "s", "when the camera last had a usable row, as the steer thread saw it",
        |r| num(r.steer.sources.camera_good_s)),
    col("steer_gnss_good_s", "s", "when the last trusted GNSS fix came, as the steer thread saw it",
        |r| num(r.steer.sources.gnss_good_s)),
    col("link_last_row_s", "s", "when the last valid row frame came (empty: none yet)", |r| num(r.link.last_row_s)),
    col("link_last_usable_s", "s", "when the last usable estimate came (empty: none yet)",
        |r| num(r.link.last_usable_s)),
    col("link_beat_s", "s", "the camera-link thread's last beat", |r| num(r.link.beat_s)),
    col("gui_beat_s", "s", "the GUI's last heartbeat (empty: no GUI)",
        |r| num(r.given.health.gui_beat_s.unwrap_or(f64::NAN))),
    col("thread_panicked", "text", "a thread that panicked, or empty",
        |r| Value::Text(r.given.health.panicked.map_or("", |t| t.label()))),
    col("supervisor_overruns", "count", "supervisor deadline overruns so far",
        |r| Value::Int(r.given.health.supervisor_overruns as i64)),
    col("hw_failed", "text", "a card that did not answer in this tick: read or write, or empty",
        |r| Value::Text(r.given.hw_failed.map_or("", |f| f.during))),
    col("hw_failed_card", "text", "which card", |r| Value::Text(r.given.hw_failed.map_or("", |f| f.card))),
    // The simulated robot's truth (empty on the real robot).
    col("sim_tool_cross_track_m", "m", "tool offset from the row, + = tool left", |r| sim(r, |t| t.tool_cross_track_m)),
    col("sim_distance_m", "m", "true distance driven by the rear axle", |r| sim(r, |t| t.distance_m)),
    col("sim_row_done", "0/1", "1 = the tool has passed the row's end",
        |r| r.truth.map_or(Value::Num(f64::NAN), |t| flag(t.row_done))),
];

/// The names of every column, in file order.
pub fn column_names() -> impl Iterator<Item = &'static str> {
    COLUMNS.iter().map(|c| c.name)
}

/// A number as text that reads back to the same f64 (shortest round trip), or None
/// for NaN and infinities.
pub(crate) fn number_text(x: f64, out: &mut String) -> bool {
    use std::fmt::Write;
    if x.is_finite() {
        let _ = write!(out, "{x:?}");
        true
    } else {
        false
    }
}

/// One tick as a JSON object, a key per column (MCAP messages and the bus's
/// ROBOT/tick); `json` is cleared first and reused, so a tick does not allocate.
pub fn tick_json(sample: &TickSample, json: &mut String) {
    use std::fmt::Write as _;
    json.clear();
    json.push('{');
    for (i, column) in COLUMNS.iter().enumerate() {
        if i > 0 {
            json.push(',');
        }
        let _ = write!(json, "\"{}\":", column.name);
        match (column.value)(sample) {
            Value::Num(x) => {
                if !number_text(x, json) {
                    json.push_str("null");
                }
            }
            Value::Int(n) => {
                let _ = write!(json, "{n}");
            }
            // Fixed words: no character needs escaping (checked in the tests below).
            Value::Text(t) => {
                let _ = write!(json, "\"{t}\"");
            }
        }
    }
    json.push('}');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_identifiers_and_unique() {
        let mut seen = std::collections::BTreeSet::new();
        for c in COLUMNS {
            let ok = c
                .name
                .chars()
                .next()
                .is_some_and(|ch| ch.is_ascii_lowercase())
                && c.name
                    .chars()
                    .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_');
            assert!(ok, "{} is not a MATLAB/Python identifier", c.name);
            assert!(seen.insert(c.name), "{} twice", c.name);
            assert!(!c.unit.is_empty() && !c.meaning.is_empty(), "{}", c.name);
        }
    }

    #[test]
    fn texts_need_no_quoting_and_missing_numbers_are_not_finite() {
        let sample = TickSample::default();
        for c in COLUMNS {
            if let Value::Text(t) = (c.value)(&sample) {
                assert!(!t.contains([',', '"', '\n']), "{}", c.name);
            }
        }
        let value = |name: &str| {
            let c = COLUMNS.iter().find(|c| c.name == name).unwrap();
            (c.value)(&sample)
        };
        // No estimate yet, not simulated: empty cells, not zeros that look real.
        assert!(matches!(value("cam_age_s"), Value::Num(x) if x.is_nan() || x.is_infinite()));
        assert!(matches!(value("sim_tool_cross_track_m"), Value::Num(x) if x.is_nan()));
        let mut text = String::new();
        assert!(!number_text(f64::INFINITY, &mut text) && text.is_empty());
        assert!(number_text(0.1 + 0.2, &mut text));
        assert_eq!(text.parse::<f64>().unwrap(), 0.1 + 0.2);
    }
}
