//! The [sim] section: the simulated robot, field and camera computer.
//! These are the plant's true values; the controller's own model is in [robot].

use mechweed_hw::sim::gnss::SimGnssParams;
use mechweed_hw::sim::miswire::miswire_names;
use mechweed_hw::sim::{
    CROSS_TRACK_FROM_M, FieldKind, FieldTierParams, Miswire, RowShape, SimParams, parse_events,
};

use super::reader::Reader;

const ROWS: [(&str, RowShape); 3] = [
    ("straight", RowShape::Straight),
    ("scurve", RowShape::SCurve),
    ("arc", RowShape::Arc),
];

pub(super) fn load(r: &mut Reader) -> SimParams {
    let s = "sim";
    let names: Vec<&str> = ROWS.iter().map(|(name, _)| *name).collect();
    SimParams {
        seed: r.u64(s, "seed", 0, u64::MAX),
        step_s: r.f64(s, "step_s", 1e-5, 0.002),
        wheelbase_m: r.f64(s, "wheelbase_m", 0.2, 5.0),
        track_m: r.f64(s, "track_m", 0.2, 5.0),
        motor_gain_mps_per_v: r.f64(s, "motor_gain_mps_per_v", 0.001, 10.0),
        motor_tau_s: r.f64(s, "motor_tau_s", 0.001, 10.0),
        motor_deadband_v: r.f64(s, "motor_deadband_v", 0.0, 5.0),
        motor_mismatch: r.f64(s, "motor_mismatch", -0.5, 0.5),
        steer_rate_dps_per_v: r.f64(s, "steer_rate_dps_per_v", 0.1, 100.0),
        steer_lag_s: r.f64(s, "steer_lag_s", 0.0, 1.0),
        steer_limit_deg: r.f64(s, "steer_limit_deg", 1.0, 60.0),
        end_switch_deg: r.f64(s, "end_switch_deg", 1.0, 60.0),
        pot_noise_v: r.f64(s, "pot_noise_v", 0.0, 1.0),
        enc_counts_per_m: r.f64(s, "enc_counts_per_m", 1.0, 1e7),
        steer_counts_per_deg: r.f64(s, "steer_counts_per_deg", 1.0, 1e6),
        tool_offset_m: r.f64(s, "tool_offset_m", -3.0, 3.0),
        brake_stop_s: r.f64(s, "brake_stop_s", 0.01, 10.0),
        side_slip_deg: r.f64(s, "side_slip_deg", -20.0, 20.0),
        battery_v: r.f64(s, "battery_v", 0.0, 60.0),
        initial_wheel_angle_deg: r.f64(s, "initial_wheel_angle_deg", -30.0, 30.0),
        field: [FieldKind::Clean, FieldKind::Realistic]
            [r.choice(s, "field", &["clean", "realistic"])],
        tier: field_tier(r),
        row: ROWS[r.choice(s, "row", &names)].1,
        row_length_m: r.f64(s, "row_length_m", 1.0, 10000.0),
        start_offset_m: r.f64(s, "start_offset_m", -0.5, 0.5),
        scurve_amplitude_m: r.f64(s, "scurve_amplitude_m", 0.0, 2.0),
        scurve_wavelength_m: r.f64(s, "scurve_wavelength_m", 0.5, 1000.0),
        arc_radius_m: r.f64(s, "arc_radius_m", 2.0, 10000.0),
        plant_spacing_m: r.f64(s, "plant_spacing_m", 0.01, 10.0),
        plant_scatter_m: r.f64(s, "plant_scatter_m", 0.0, 0.5),
        camera_lookahead_m: r.f64(s, "camera_lookahead_m", 0.0, 5.0),
        camera_rate_hz: r.f64(s, "camera_rate_hz", 0.5, 100.0),
        camera_latency_s: r.f64(s, "camera_latency_s", 0.0, 2.0),
        camera_jitter_s: r.f64(s, "camera_jitter_s", 0.0, 1.0),
        camera_noise_offset_m: r.f64(s, "camera_noise_offset_m", 0.0, 0.5),
        camera_noise_angle_deg: r.f64(s, "camera_noise_angle_deg", 0.0, 30.0),
        camera_drop: r.f64(s, "camera_drop", 0.0, 1.0),
        camera_corrupt: r.f64(s, "camera_corrupt", 0.0, 1.0),
        camera_reboot_s: r.f64(s, "camera_reboot_s", 0.0, 600.0),
        gnss: gnss(r),
        events: r.parsed(s, "events", parse_events).unwrap_or_default(),
        miswire: miswire(r),
        // Not a setting: the simulated plant's rule, which `run --from-m` changes for one run.
        cross_track_from_m: CROSS_TRACK_FROM_M,
    }
}

/// [sim] miswire: optional, so that a file from before it was a setting reads as
/// wired right.
fn miswire(r: &mut Reader) -> Miswire {
    let Some(text) = r.optional("sim", "miswire") else {
        return Miswire::None;
    };
    Miswire::parse(&text).unwrap_or_else(|| {
        let names = miswire_names().join(", ");
        r.error_at("sim", "miswire", format!("'{text}' is not one of: {names}"));
        Miswire::None
    })
}

/// [sim] field_*: what the realistic field adds (read whichever field is chosen, so
/// that a mistake shows before someone switches to it).
fn field_tier(r: &mut Reader) -> FieldTierParams {
    let s = "sim";
    let t = FieldTierParams {
        camera_bias_sd_m: r.f64(s, "field_camera_bias_sd_m", 0.0, 0.5),
        camera_bias_length_m: r.f64(s, "field_camera_bias_length_m", 0.01, 1000.0),
        gap_every_m: r.f64(s, "field_gap_every_m", 0.1, 10000.0),
        gap_min_m: r.f64(s, "field_gap_min_m", 0.0, 100.0),
        gap_max_m: r.f64(s, "field_gap_max_m", 0.0, 100.0),
        gap_quality: r.u64(s, "field_gap_quality", 0, 100) as u8,
        weed_every_m: r.f64(s, "field_weed_every_m", 0.1, 10000.0),
        weed_length_m: r.f64(s, "field_weed_length_m", 0.0, 100.0),
        weed_offset_min_m: r.f64(s, "field_weed_offset_min_m", 0.0, 1.0),
        weed_offset_max_m: r.f64(s, "field_weed_offset_max_m", 0.0, 1.0),
        slope_max_deg: r.f64(s, "field_slope_max_deg", -20.0, 20.0),
        slope_length_m: r.f64(s, "field_slope_length_m", 0.1, 10000.0),
        bump_every_m: r.f64(s, "field_bump_every_m", 0.01, 10000.0),
        bump_heading_sd_deg: r.f64(s, "field_bump_heading_sd_deg", 0.0, 10.0),
        bump_side_sd_m: r.f64(s, "field_bump_side_sd_m", 0.0, 0.5),
        wheel_slip_max: r.f64(s, "field_wheel_slip_max", 0.0, 0.5),
        wheel_slip_length_m: r.f64(s, "field_wheel_slip_length_m", 0.1, 10000.0),
    };
    for (low, high, lo_v, hi_v) in [
        (
            "field_gap_min_m",
            "field_gap_max_m",
            t.gap_min_m,
            t.gap_max_m,
        ),
        (
            "field_weed_offset_min_m",
            "field_weed_offset_max_m",
            t.weed_offset_min_m,
            t.weed_offset_max_m,
        ),
    ] {
        let keys = [(s, low), (s, high)];
        if lo_v > hi_v && r.all_read(&keys) {
            r.cross_error(
                &keys,
                format!("[sim] {low} = {lo_v} is larger than {high} = {hi_v}"),
            );
        }
    }
    t
}

/// [sim] gnss_*: the simulated receiver, the field's place on the earth and its map.
fn gnss(r: &mut Reader) -> SimGnssParams {
    let s = "sim";
    SimGnssParams {
        rate_hz: r.f64(s, "gnss_rate_hz", 0.1, 100.0),
        latency_s: r.f64(s, "gnss_latency_s", 0.0, 1.0),
        antenna_ahead_m: r.f64(s, "gnss_antenna_ahead_m", -5.0, 5.0),
        antenna_left_m: r.f64(s, "gnss_antenna_left_m", -5.0, 5.0),
        origin_lat_deg: r.f64(s, "gnss_origin_lat_deg", -85.0, 85.0),
        origin_lon_deg: r.f64(s, "gnss_origin_lon_deg", -180.0, 180.0),
        float_every_m: r.f64(s, "field_gnss_float_every_m", 1.0, 1e7),
        float_s: r.f64(s, "field_gnss_float_s", 0.1, 1e5),
        map_error_sd_m: r.f64(s, "gnss_map_error_sd_m", 0.0, 1.0),
        map_error_length_m: r.f64(s, "gnss_map_error_length_m", 0.01, 1e5),
    }
}
