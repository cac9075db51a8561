//! The robot's flows turned into the `View` the panels draw: the status (10 per
//! second: mode, power, fault, camera link, loop figures) and the newest tick (every
//! input, output, reference and measured value, the steering law's workings, the
//! simulated truth), with the names and units of the run record.

use mechweed_hw::Side;
use mechweed_hw::camproto::RowEstimate;
use mechweed_hw::sim::Truth;
use serde_json::Value;

use super::view::View;
use crate::rt::LoopSummary;
use crate::state::cross_track::CrossTrackMeaning;
use crate::state::modes::Mode;
use crate::state::status::{PowerState, Status};
use crate::state::steering::Steering;
use crate::steer::{FilterFigures, RowFigures, SteerCommand};

fn num(json: &Value, key: &str) -> f64 {
    json[key].as_f64().unwrap_or(f64::NAN)
}

fn int(json: &Value, key: &str) -> i64 {
    json[key].as_i64().unwrap_or(0)
}

fn flag(json: &Value, key: &str) -> bool {
    json[key].as_i64() == Some(1) || json[key].as_bool() == Some(true)
}

pub fn mode(word: &str) -> Option<Mode> {
    Some(match word {
        "halt" => Mode::Halt,
        "joystick" => Mode::Joystick,
        "autonomous" => Mode::Autonomous,
        "test" => Mode::Test,
        "fault" => Mode::Fault,
        _ => return None,
    })
}

fn power(word: &str) -> PowerState {
    match word {
        "on" => PowerState::On,
        "closing" => PowerState::Closing { since_s: f64::NAN },
        _ => PowerState::Off,
    }
}

/// What `ROBOT/status` carries: time, mode, power, the camera link, the loops.
pub(crate) fn fill_from_status(view: &mut View, status: &Value) -> Result<(), String> {
    // Checked before anything is written: a bad status changes nothing.
    let word = status["mode"].as_str().unwrap_or_default();
    let new_mode = mode(word).ok_or_else(|| format!("\"mode\": '{word}' is not a mode"))?;
    let t_s = status["t_s"]
        .as_f64()
        .ok_or("\"t_s\" is not a number of seconds")?;
    view.cross_track = CrossTrackMeaning::from_word(status["cross_track"].as_str());
    let st = &mut view.status;
    st.mode = new_mode;
    st.t_s = t_s;
    st.tick = status["tick"].as_u64().unwrap_or(st.tick);
    st.power = power(status["power"].as_str().unwrap_or_default());
    st.measured.speed_mps = num(status, "speed_mps");
    st.measured.wheel_angle_rad = num(status, "wheel_angle_rad");
    st.measured.distance_m = num(status, "distance_m");
    st.inputs.battery_v = num(status, "battery_v");
    let camera = &status["camera"];
    let link = &mut view.link;
    link.connected = flag(camera, "connected");
    link.streaming = flag(camera, "streaming");
    link.last_usable_s = st.t_s - num(camera, "age_s");
    link.last_usable.offset_m = num(camera, "offset_m");
    link.last_usable.angle_rad = num(camera, "angle_rad");
    link.last_usable.quality = int(camera, "quality").clamp(0, 255) as u8;
    // The flows carry the estimate in use, not every frame: it stands for the last one.
    link.last_row = link.last_usable;
    link.last_row_s = link.last_usable_s;
    let counters = &camera["counters"];
    let c = &mut link.counters;
    for (key, field) in [
        ("frames_ok", &mut c.frames_ok),
        ("crc_errors", &mut c.crc_errors),
        ("resyncs", &mut c.resyncs),
        ("seq_gaps", &mut c.seq_gaps),
        ("bytes_skipped", &mut c.bytes_skipped),
        ("pongs", &mut c.pongs),
        ("bad_values", &mut c.bad_values),
        ("unknown_kinds", &mut c.unknown_kinds),
        ("duplicates", &mut c.duplicates),
    ] {
        *field = counters[key].as_u64().unwrap_or(0);
    }
    for (i, name) in ["supervisor", "steer"].into_iter().enumerate() {
        let figures = status["loops"][name].clone();
        view.loops[i] = serde_json::from_value::<LoopSummary>(figures).unwrap_or_default();
    }
    Ok(())
}

/// What `ROBOT/tick` carries beyond the status: every input and output, the
/// regulators' references, the steer thread's command, the simulated truth.
pub(crate) fn fill_from_tick(view: &mut View, tick: &Value) {
    fill_status(&mut view.status, tick);
    let tick_t_s = num(tick, "t_s");
    fill_steer(&mut view.steer, tick, tick_t_s);
    view.link.last_usable = RowEstimate {
        seq: int(tick, "cam_seq").clamp(0, 255) as u8,
        ..view.link.last_usable
    };
    view.link.last_row = view.link.last_usable;
    // Simulated: the truth's columns are numbers (empty on the real robot).
    view.simulated = tick["sim_distance_m"].is_number();
    view.truth = if view.simulated {
        Truth {
            t_s: tick_t_s,
            tool_cross_track_m: num(tick, "sim_tool_cross_track_m"),
            distance_m: num(tick, "sim_distance_m"),
            row_done: flag(tick, "sim_row_done"),
            ..Truth::default()
        }
    } else {
        Truth::default()
    };
}

/// The supervisor's inputs, outputs, measurements and references of a tick.
fn fill_status(st: &mut Status, tick: &Value) {
    let i = &mut st.inputs;
    i.pot_v = num(tick, "pot_v");
    i.joystick_steer_v = num(tick, "joystick_steer_v");
    i.joystick_speed_v = num(tick, "joystick_speed_v");
    i.estop_front_released = flag(tick, "estop_front_released");
    i.estop_back_released = flag(tick, "estop_back_released");
    i.motor_power_present = flag(tick, "motor_power_present");
    i.end_switch_left = flag(tick, "end_switch_left");
    i.end_switch_right = flag(tick, "end_switch_right");
    i.joystick_enable = flag(tick, "joystick_enable");
    i.enc_left_counts = int(tick, "enc_left_counts");
    i.enc_right_counts = int(tick, "enc_right_counts");
    i.enc_steer_counts = int(tick, "enc_steer_counts");
    let o = &mut st.outputs;
    o.amp_left_v = num(tick, "amp_left_v");
    o.amp_right_v = num(tick, "amp_right_v");
    o.amp_steer_v = num(tick, "amp_steer_v");
    o.main_power_on = flag(tick, "main_power_on");
    o.brake_release_left = flag(tick, "brake_release_left");
    o.brake_release_right = flag(tick, "brake_release_right");
    o.tool_on = flag(tick, "tool_on");
    let m = &mut st.measured;
    m.v_left_mps = num(tick, "v_left_mps");
    m.v_right_mps = num(tick, "v_right_mps");
    m.pot_angle_filtered_rad = num(tick, "pot_angle_filtered_rad");
    m.wheel_angle_filtered_rad = num(tick, "wheel_angle_filtered_rad");
    m.yaw_rate_rps = num(tick, "yaw_rate_rps");
    m.calibrated = flag(tick, "calibrated");
    st.speed_ref_mps = num(tick, "speed_ref_mps");
    st.v_left_ref_mps = num(tick, "v_left_ref_mps");
    st.v_right_ref_mps = num(tick, "v_right_ref_mps");
    st.wheel_angle_ref_rad = num(tick, "wheel_angle_ref_rad");
    st.endswitch_hit = match tick["endswitch_hit"].as_str() {
        Some("left") => Some(Side::Left),
        Some("right") => Some(Side::Right),
        _ => None,
    };
}

/// The steer thread's command of a tick: speed, angle, the law's and the row's figures.
fn fill_steer(steer: &mut SteerCommand, tick: &Value, tick_t_s: f64) {
    steer.speed_mps = num(tick, "steer_speed_mps");
    steer.wheel_angle_rad = num(tick, "steer_wheel_angle_rad");
    steer.t_s = tick_t_s - num(tick, "steer_age_s");
    steer.law.lookahead_offset_m = num(tick, "law_lookahead_offset_m");
    steer.law.tool_offset_m = num(tick, "law_tool_offset_m");
    steer.law.row_curvature_per_m = num(tick, "law_row_curvature_per_m");
    steer.law.integral_per_m = num(tick, "law_integral_per_m");
    if let Some(steering) = tick["steering"].as_str().and_then(Steering::from_name) {
        steer.sources.steering = steering;
    }
    steer.row = RowFigures {
        gnss_quality: int(tick, "gnss_quality").clamp(0, 255) as u8,
        gnss_satellites: int(tick, "gnss_satellites").clamp(0, 255) as u8,
        gnss_sd_m: tick["gnss_sd_m"].as_f64(),
        // Not in the tick: the robot's supervisor judges its receiver by it.
        gnss_heard_s: None,
        gnss_position: tick["gnss_lat_deg"]
            .as_f64()
            .zip(tick["gnss_lon_deg"].as_f64()),
        // The filter's columns are numbers only where it runs.
        filter: tick["filter_offset_m"].is_number().then(|| FilterFigures {
            offset_m: num(tick, "filter_offset_m"),
            offset_sd_m: num(tick, "filter_offset_sd_m"),
            heading_rad: num(tick, "filter_heading_rad"),
            // A tick does not carry it (a status does), and the view does not show it.
            heading_sd_rad: f64::NAN,
            curvature_per_m: num(tick, "filter_curvature_per_m"),
            map_bias_m: num(tick, "filter_map_bias_m"),
            camera_rejected: int(tick, "filter_camera_rejected").max(0) as u64,
            gnss_rejected: int(tick, "filter_gnss_rejected").max(0) as u64,
        }),
    };
}
