//! The row-following benchmark: three row shapes at three speeds,
//! every disturbance on, in lockstep simulation; the tool's cross-track error after
//! the first 5 m of each row.
//!
//! Two tiers: the clean field (0.3, 0.5, 1.0 m/s) and the realistic field (0.5, 1.0,
//! 2.0 m/s), which adds what real fields add ([sim] field_*, from the settings). Its
//! robot's drive is geared for 2 m/s, and its speed regulators are scaled to match.

use mechweed_hw::sim::{CrossTrackSummary, FieldKind, RowShape, SimParams};
use serde::Serialize;

use crate::bench::achievable::{achievable, late, wheel_rate_limit_dps};
use crate::bench::bound::bound;
use crate::bench::floor::{Geometry, floor_cm};
use crate::config::{CameraPort, GnssPort, Settings, SteerSource, override_parts};
use crate::state::modes::Mode;
use crate::threads::lockstep::Lockstep;

pub(crate) const ROWS: [RowShape; 3] = [RowShape::Straight, RowShape::SCurve, RowShape::Arc];

/// The speeds of each tier, m/s.
pub(crate) fn speeds_mps(field: FieldKind) -> [f64; 3] {
    match field {
        FieldKind::Clean => [0.3, 0.5, 1.0],
        FieldKind::Realistic => [0.5, 1.0, 2.0],
    }
}

/// The realistic tier's drive: 2.4 m/s at 10 V (the clean plant's 0.12 m/s per V gives
/// 1.2 m/s, short of the tier's 2 m/s).
pub(crate) const REALISTIC_MOTOR_GAIN_MPS_PER_V: f64 = 0.24;

pub(crate) fn field_name(field: FieldKind) -> &'static str {
    match field {
        FieldKind::Clean => "clean",
        FieldKind::Realistic => "realistic",
    }
}

pub(crate) fn source_name(source: SteerSource) -> &'static str {
    match source {
        SteerSource::Camera => "camera",
        SteerSource::Gnss => "gnss",
        SteerSource::Fused => "fused",
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct RowRun {
    pub field: String,
    /// Which sensors steered ([steer] source).
    pub source: String,
    pub row: String,
    pub speed_mps: f64,
    pub cross_track_cm: CrossTrackSummary,
    /// How far the row filter's estimate of the tool's offset was from the truth over the
    /// same stretch (None when the camera steers alone): the part of the tool's error no
    /// steering law could remove, the rest being what the steering did not correct.
    pub filter_error_cm: Option<CrossTrackSummary>,
    /// On the realistic field: the s.d. at the tool that an exact Kalman filter of the
    /// field's error model leaves over a stretch this long with these sensors, on
    /// average over such fields, cm (bench_floor.rs): what the sensors allow before any
    /// steering. One field's draw can fall either side of it.
    pub filter_floor_cm: Option<f64>,
    /// On the realistic field: the tool's s.d. that the best linear (LQG) steering of a
    /// linear model of the field, the robot and these sensors leaves over a stretch this
    /// long, its mean taken out, cm (bench_bound.rs). Like the floor, an expectation
    /// over such fields.
    pub steering_bound_cm: Option<f64>,
    /// The same bound as an RMS, the stretch's mean kept, as `cross_track_cm.rms_cm` is
    /// measured, cm: the one the tool's RMS is compared with.
    pub steering_bound_rms_cm: Option<f64>,
    /// On the realistic field: the tool's RMS that the best linear steering reaches with
    /// the loop's delay and the wheel's rate limit added to the bound's model, cm
    /// (bench_achievable.rs), and that steering's RMS wheel rate, deg/s.
    pub achievable_rms_cm: Option<f64>,
    pub achievable_wheel_rate_dps: Option<f64>,
    pub faults: Vec<String>,
    pub sim_time_s: f64,
}

pub fn row_name(row: RowShape) -> &'static str {
    match row {
        RowShape::Straight => "straight",
        RowShape::SCurve => "scurve",
        RowShape::Arc => "arc",
    }
}

/// The `--set` overrides of [sim] that the benchmark would not use, each as a message:
/// it drives its own plant and takes of [sim] only the realistic field's field_*.
/// Refused by name, since a setting that silently changes nothing misleads.
pub fn unused_overrides(set: &[String], field: FieldKind) -> Vec<String> {
    let sim_keys = set.iter().filter_map(|item| match override_parts(item)? {
        ("sim", name, _) => Some(name),
        _ => None,
    });
    sim_keys
        .filter_map(|name| match (name.starts_with("field_"), field) {
            (true, FieldKind::Realistic) => None,
            (true, FieldKind::Clean) => Some(format!(
                "--set sim.{name}: the clean field has none of the realistic field's \
                 disturbances: add --field realistic"
            )),
            (false, _) => Some(format!(
                "--set sim.{name}: bench rows drives its own simulated robot; of [sim] it \
                 takes only the realistic field's field_* settings{}",
                match name {
                    "seed" => " (its seed: --seed N)",
                    "field" => " (its field: --field clean|realistic)",
                    _ => "",
                }
            )),
        })
        .collect()
}

/// Drive one benchmark row in autonomous mode to its end; the controller's settings
/// are `settings`' (its [sim] section is replaced by the benchmark's plant, but for
/// the realistic field's [sim] field_*, field_gnss_* among them).
pub fn run_row(
    settings: &Settings,
    field: FieldKind,
    source: SteerSource,
    row: RowShape,
    speed_mps: f64,
    seed: u64,
) -> RowRun {
    let mut s = settings.clone();
    s.sources.source = source;
    if source != SteerSource::Camera {
        // The simulated robot's receiver, on the simulated field's map.
        s.gnss.port = GnssPort::Link(CameraPort::Sim);
    }
    s.sim = SimParams {
        field,
        tier: settings.sim.tier,
        ..SimParams::benchmark(row, seed)
    };
    if field == FieldKind::Realistic {
        gear_for_the_field(&mut s);
        // The receiver's float episodes are the field's too ([sim] field_gnss_float_*).
        s.sim.gnss.float_every_m = settings.sim.gnss.float_every_m;
        s.sim.gnss.float_s = settings.sim.gnss.float_s;
    }
    s.steer.speed_mps = speed_mps;
    let limit_s = s.sim.row_length_m / speed_mps.max(0.05) + 30.0;
    let mut sim = Lockstep::new(&s, Mode::Autonomous);
    if source != SteerSource::Camera {
        sim.track_filter_error(s.robot.tool_offset_m, s.sim.cross_track_from_m);
    }
    // The run ends where the tool passes the row's end, or where the supervisor stopped
    // the robot (its own end of row, or a fault) after it started driving.
    let mut driving = false;
    while !sim.robot.truth().row_done && sim.now_s() < limit_s {
        sim.tick();
        let autonomous = sim.supervisor.mode() == Mode::Autonomous;
        if driving && !autonomous {
            break;
        }
        driving |= autonomous;
    }
    let cross_track_cm = sim.robot.cross_track().summary();
    let at = Geometry {
        tool_x_m: s.robot.tool_offset_m,
        camera_x_m: s.robot.camera_lookahead_m,
        antenna_x_m: s.gnss.antenna_ahead_m,
    };
    let measured_m = cross_track_cm.distance_m;
    let realistic = field == FieldKind::Realistic;
    let filter_floor_cm = realistic
        .then(|| floor_cm(&s.sim, at, source, speed_mps, measured_m))
        .flatten();
    let steering_bound = realistic
        .then(|| bound(&s.sim, at, &s.pid_steer, source, speed_mps, measured_m))
        .flatten();
    let reachable = realistic
        .then(|| {
            let run = (source, speed_mps, measured_m);
            let delayed = late(&s.sim, source);
            achievable(&s, at, run, wheel_rate_limit_dps(&s), delayed)
        })
        .flatten();
    RowRun {
        field: field_name(field).to_string(),
        source: source_name(source).to_string(),
        row: row_name(row).to_string(),
        speed_mps,
        cross_track_cm,
        filter_error_cm: sim.filter_error().map(|e| e.summary()),
        filter_floor_cm,
        steering_bound_cm: steering_bound.map(|b| b.sd_cm),
        steering_bound_rms_cm: steering_bound.map(|b| b.rms_cm),
        achievable_rms_cm: reachable.map(|(r, _)| r.rms_cm),
        achievable_wheel_rate_dps: reachable.map(|(r, _)| r.wheel_rate_rms_dps),
        faults: sim
            .supervisor
            .faults()
            .iter()
            .map(|f| format!("{:.2} s: {}", f.t_s, f.cause))
            .collect(),
        sim_time_s: sim.now_s(),
    }
}

/// What the realistic field's robot is, for the benchmark's first line.
pub fn field_line(field: FieldKind) -> Option<String> {
    (field == FieldKind::Realistic).then(|| {
        format!(
            "field: realistic ([sim] field_*); the drive geared for 2 m/s ({REALISTIC_MOTOR_GAIN_MPS_PER_V} m/s per V), the speed regulators' gains scaled to match"
        )
    })
}

/// Every row at every speed of `field`, once per source, saying each run as it starts
/// (stderr).
pub fn run_all(
    settings: &Settings,
    field: FieldKind,
    sources: &[SteerSource],
    seed: u64,
) -> Vec<RowRun> {
    let mut runs = Vec::new();
    for &source in sources {
        for row in ROWS {
            for speed in speeds_mps(field) {
                eprintln!(
                    "running {} row at {speed} m/s, steering by {} ...",
                    row_name(row),
                    source_name(source)
                );
                runs.push(run_row(settings, field, source, row, speed, seed));
            }
        }
    }
    runs
}

/// The realistic tier's robot: a drive geared for its 2 m/s, and the speed regulators'
/// gains (volts per m/s) scaled by the gear, so that the loops behave as the clean
/// robot's do.
fn gear_for_the_field(s: &mut Settings) {
    let ratio = s.sim.motor_gain_mps_per_v / REALISTIC_MOTOR_GAIN_MPS_PER_V;
    s.sim.motor_gain_mps_per_v = REALISTIC_MOTOR_GAIN_MPS_PER_V;
    for pid in [&mut s.pid_left, &mut s.pid_right] {
        pid.kp *= ratio;
        pid.ki *= ratio;
        pid.kff *= ratio;
    }
    let top_mps = 10.0 * REALISTIC_MOTOR_GAIN_MPS_PER_V;
    s.supervisor.max_speed_mps = s.supervisor.max_speed_mps.max(top_mps);
}

/// The table `mechweed bench rows` prints.
pub fn table(runs: &[RowRun]) -> String {
    let mut out = String::from(
        "source  row       speed   mean    s.d.    RMS   bound  reach     p95     max    >2cm  filter  floor  faults\n",
    );
    out += "                  m/s     cm      cm      cm     cm     cm      cm      cm     %     s.d. cm   cm\n";
    out += "(bound and reach: the RMS that the best linear steering leaves on the field's model, and \
             with the loop's delay and the wheel's rate limit added, to compare with RMS; \
             n/c, not comparable, for a run that stopped before its row's end)\n";
    for r in runs {
        let c = &r.cross_track_cm;
        // A stopped run's figures cover part of its row: no reference compares with it.
        let reference = |cm: Option<f64>| match (cm, r.faults.is_empty()) {
            (None, _) => "-".to_string(),
            (Some(_), false) => "n/c".to_string(),
            (Some(cm), true) => format!("{cm:.2}"),
        };
        out += &format!(
            "{:<7} {:<9} {:4.1} {:7.2} {:7.2} {:7.2} {:>6} {:>6} {:7.2} {:7.2} {:6.1} {:>7} {:>6}  {}\n",
            r.source,
            r.row,
            r.speed_mps,
            c.mean_cm,
            c.sd_cm,
            c.rms_cm,
            reference(r.steering_bound_rms_cm),
            reference(r.achievable_rms_cm),
            c.p95_cm,
            c.max_cm,
            c.share_over_2cm * 100.0,
            r.filter_error_cm
                .map_or("-".to_string(), |e| format!("{:.2}", e.sd_cm)),
            r.filter_floor_cm
                .map_or("-".to_string(), |f| format!("{f:.2}")),
            if r.faults.is_empty() {
                "none".to_string()
            } else {
                r.faults.join("; ")
            }
        );
    }
    out
}
