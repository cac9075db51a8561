//! `mechweed teach`: a row's line for the row map, from a drive along the row in
//! joystick mode with the weeding tool on it. The drive is an ordinary run (its record
//! keeps every fix); this reads the record back, turns each fix of the antenna into the
//! tool's position (the robot's heading from the antenna's own track), and hands them to
//! the teacher (core/src/gnss/rowmap/teach.rs), which keeps a point every 25 cm of
//! trusted RTK fixes and refuses a row with a stretch it could not trust. The row goes into the map file,
//! replacing a row of the same name.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use mechweed_hw::geo::{Enu, Geodetic, LocalFrame};

use crate::config::Settings;
use crate::gnss::rowmap::{
    MapRow, RowMap, TeachSample, TeachSettings, Teacher, read_map, write_map,
};
use crate::programs::run::{RunArgs, StartMode};
use crate::programs::{load_settings, print_errors, said};
use crate::record::read::{Table, read};

/// The record's columns teaching reads.
const COLUMNS: [&str; 8] = [
    "mode",
    "distance_m",
    "gnss_quality",
    "gnss_lat_deg",
    "gnss_lon_deg",
    "cam_offset_m",
    "cam_angle_rad",
    "cam_quality",
];

/// The heading is taken from the antenna's track over the last metre or so: over less,
/// RTK's centimetre of noise turns it by degrees, which the 0.9 m from the antenna to
/// the tool makes centimetres.
const HEADING_BASE_M: f64 = 1.0;

/// What teaching found, for the closing lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Taught {
    pub row: MapRow,
    /// Driven in joystick mode with a trusted fix, m.
    pub length_m: f64,
    pub fixes_used: usize,
    /// The row the camera saw, from the tool, over the drive: the median, m (positive:
    /// the row left of the tool); None: the camera saw no row of [camera] min_quality.
    pub camera_row_from_tool_m: Option<f64>,
}

/// The tool's path along the row `name`, from the joystick driving in `record`.
pub(crate) fn taught_row(record: &Path, name: &str, s: &Settings) -> Result<Taught, String> {
    let rec = read(record, &COLUMNS).map_err(|e| e.to_string())?;
    let t = &rec.ticks;
    let col = |c: &str| {
        t.column(c).ok_or_else(|| {
            format!(
                "{}: no column {c} (recorded by an older mechweed?)",
                record.display()
            )
        })
    };
    let (mode, distance, quality, lat, lon) = (
        col("mode")?,
        col("distance_m")?,
        col("gnss_quality")?,
        col("gnss_lat_deg")?,
        col("gnss_lon_deg")?,
    );
    let camera = [
        col("cam_offset_m")?,
        col("cam_angle_rad")?,
        col("cam_quality")?,
    ];
    let num = |row: usize, c: usize| t.number(row, c).map_err(|e| e.to_string());
    let settings = TeachSettings::default();
    let trusted = settings.trusted_fix.clone();
    let mut teacher = Teacher::new(settings).map_err(|e| e.to_string())?;
    let mut track = Track::new(s);
    let (mut fixes_used, mut first_m, mut last_m) = (0, None, 0.0);
    let mut camera_row_m = Vec::new();
    for row in 0..t.rows.len() {
        if t.text(row, mode) != "joystick" {
            continue;
        }
        if let Some(from_tool_m) = camera_row_at_tool(t, row, camera, s)? {
            camera_row_m.push(from_tool_m);
        }
        let (Some(lat_deg), Some(lon_deg), Some(distance_m)) =
            (num(row, lat)?, num(row, lon)?, num(row, distance)?)
        else {
            continue;
        };
        let code = num(row, quality)?.unwrap_or(0.0) as u8;
        // Only trusted fixes give the heading that places the tool (a float fix 15 cm
        // off, 1 m back, turns it by 8 degrees). The teacher sees an untrusted one too,
        // to judge the gap it makes.
        let (tool_lat_deg, tool_lon_deg) = if trusted.contains(&code) {
            let Some(tool) = track.tool(lat_deg, lon_deg) else {
                continue;
            };
            tool
        } else {
            (lat_deg, lon_deg)
        };
        teacher
            .feed(TeachSample {
                lat_deg: tool_lat_deg,
                lon_deg: tool_lon_deg,
                fix_quality: code,
                distance_m,
            })
            .map_err(|e| e.to_string())?;
        fixes_used += 1;
        first_m.get_or_insert(distance_m);
        last_m = distance_m;
    }
    if fixes_used == 0 {
        return Err(no_drive(record, t));
    }
    let row = teacher.finish(name).map_err(|e| e.to_string())?;
    camera_row_m.sort_by(f64::total_cmp);
    Ok(Taught {
        row,
        length_m: last_m - first_m.unwrap_or(last_m),
        fixes_used,
        camera_row_from_tool_m: camera_row_m.get(camera_row_m.len() / 2).copied(),
    })
}

/// Where the camera's row was at the tool in record line `row`, m (positive: the row
/// left of the tool); None without an estimate of [camera] min_quality. `camera` are
/// the columns cam_offset_m, cam_angle_rad and cam_quality.
fn camera_row_at_tool(
    t: &Table,
    row: usize,
    camera: [usize; 3],
    s: &Settings,
) -> Result<Option<f64>, String> {
    let cell = |col: usize| t.number(row, col).map_err(|e| e.to_string());
    let (Some(offset_m), Some(angle_rad), Some(quality)) =
        (cell(camera[0])?, cell(camera[1])?, cell(camera[2])?)
    else {
        return Ok(None);
    };
    if quality < f64::from(s.camera.min_quality) {
        return Ok(None);
    }
    // The row's line, seen at the camera point, carried back to the tool.
    let back_m = s.robot.tool_offset_m - s.robot.camera_lookahead_m;
    Ok(Some(offset_m + angle_rad.tan() * back_m))
}

/// Why nothing could be taught from the record.
fn no_drive(record: &Path, t: &Table) -> String {
    format!(
        "{}: no joystick driving with a GNSS position in its {} ticks: drive the row in joystick mode with [gnss] port set",
        record.display(),
        t.rows.len()
    )
}

/// Teach row `name` from `record` and put it into the map file `map`: the line to say,
/// or why nothing was written.
pub(crate) fn teach_into_map(
    record: &Path,
    name: &str,
    map: &Path,
    s: &Settings,
) -> Result<String, String> {
    let taught = taught_row(record, name, s)
        .map_err(|why| format!("{why}; nothing written to {}", map.display()))?;
    let points = taught.row.points_deg.len();
    let comment = format!(
        "row {name} taught by mechweed teach from {}",
        record.display()
    );
    let wrote = write_into_map(map, taught.row, &comment)?;
    let mut said = format!(
        "row {name}: {points} points over {:.1} m driven, {wrote}",
        taught.length_m
    );
    let limit_m = s.gnss.teach_warn_off_row_m;
    match taught.camera_row_from_tool_m {
        Some(row_m) if row_m.abs() > limit_m => {
            let side = if row_m > 0.0 { "left" } else { "right" };
            said += &format!(
                "\nWARNING: the tool ran {:.1} cm from the row the camera saw (the plants {side} of it; the median over the drive, more than [gnss] teach_warn_off_row_m = {:.1} cm): the map now has the row where the tool went, so autonomous runs by GNSS will weed beside the plants. Drive it again along the plants, or keep it if that offset is meant.",
                row_m.abs() * 100.0,
                limit_m * 100.0
            );
        }
        Some(_) => {}
        None => {
            said += "\nnote: the camera saw no row while driving: whether the tool went along the plants is not known"
        }
    }
    Ok(said)
}

/// The simulated field's own map (its planting record, with the planting error of
/// [sim] gnss_map_error_*) as row `name` of the map file `map`: the line to say.
pub(crate) fn field_into_map(s: &Settings, name: &str, map: &Path) -> Result<String, String> {
    let (camera, _) = mechweed_hw::sim::byte_pipe(16);
    let robot = mechweed_hw::sim::SimRobot::new(&s.sim, camera);
    let points = robot.planted_map();
    let row = MapRow {
        name: name.to_string(),
        points_deg: points.iter().map(|p| (p.lat_deg, p.lon_deg)).collect(),
    };
    let comment = format!(
        "row {name}: the simulated field's planting record (seed {})",
        s.sim.seed
    );
    let wrote = write_into_map(map, row, &comment)?;
    Ok(format!(
        "row {name}: the simulated field's map, {} points, {wrote}",
        points.len()
    ))
}

/// Put `row` into the map file at `path` (made if missing), replacing a row of the same
/// name; says what it did. A file that was there is kept beside it as FILE.bak first:
/// the map is written anew, without the old file's notes and comments.
pub(crate) fn write_into_map(path: &Path, row: MapRow, comment: &str) -> Result<String, String> {
    let (mut map, backup) = if path.exists() {
        let map = read_map(path).map_err(|e| e.to_string())?;
        let mut backup = path.as_os_str().to_owned();
        backup.push(".bak");
        let backup = PathBuf::from(backup);
        std::fs::copy(path, &backup).map_err(|e| {
            format!(
                "cannot keep {} as {}: {e}",
                path.display(),
                backup.display()
            )
        })?;
        (map, Some(backup))
    } else {
        (RowMap { rows: Vec::new() }, None)
    };
    let replaced = match map.rows.iter_mut().find(|r| r.name == row.name) {
        Some(old) => {
            *old = row;
            true
        }
        None => {
            map.rows.push(row);
            false
        }
    };
    write_map(path, &map, Some(comment)).map_err(|e| e.to_string())?;
    let verb = if replaced {
        "replacing the row of that name in"
    } else {
        "written to"
    };
    Ok(match backup {
        Some(backup) => format!(
            "{verb} {} (the file as it was, with its notes and comments, kept as {})",
            path.display(),
            backup.display()
        ),
        None => format!("{verb} {}", path.display()),
    })
}

/// The antenna's track: its heading from where it was a metre back, and the tool's
/// place from the antenna's along that heading.
struct Track {
    frame: Option<LocalFrame>,
    /// The antenna's recent positions, east and north, m: the oldest is at least
    /// `HEADING_BASE_M` back once the robot has driven that far.
    recent: VecDeque<(f64, f64)>,
    /// From the antenna to the tool, along and across the robot, m.
    ahead_m: f64,
    left_m: f64,
}

impl Track {
    fn new(s: &Settings) -> Track {
        Track {
            frame: None,
            recent: VecDeque::new(),
            ahead_m: s.robot.tool_offset_m - s.gnss.antenna_ahead_m,
            left_m: -s.gnss.antenna_left_m,
        }
    }

    /// The tool's latitude and longitude for an antenna fix, once the robot has driven
    /// far enough for a heading.
    fn tool(&mut self, lat_deg: f64, lon_deg: f64) -> Option<(f64, f64)> {
        let place = Geodetic {
            lat_deg,
            lon_deg,
            height_m: 0.0,
        };
        let frame = *self.frame.get_or_insert_with(|| LocalFrame::new(place));
        let here = frame.to_enu(place);
        let far = |p: &(f64, f64)| (here.east_m - p.0).hypot(here.north_m - p.1) >= HEADING_BASE_M;
        // Keep one position at least a base back, and drop the older ones.
        while self.recent.len() > 1 && self.recent.get(1).is_some_and(far) {
            self.recent.pop_front();
        }
        self.recent.push_back((here.east_m, here.north_m));
        let &(back_e, back_n) = self.recent.front().filter(|p| far(p))?;
        let heading_rad = (here.north_m - back_n).atan2(here.east_m - back_e);
        let (sin, cos) = heading_rad.sin_cos();
        let tool = frame.to_geodetic(Enu {
            east_m: here.east_m + self.ahead_m * cos - self.left_m * sin,
            north_m: here.north_m + self.ahead_m * sin + self.left_m * cos,
            up_m: 0.0,
        });
        Some((tool.lat_deg, tool.lon_deg))
    }
}

#[derive(clap::Args)]
pub struct TeachArgs {
    /// The row's name in the map (e.g. 3 or north-3).
    pub row: String,
    /// The row map file to put it in: made if missing; a row of that name is replaced.
    #[arg(long, value_name = "FILE")]
    pub map: PathBuf,
    /// Teach from a record of a drive already made (NAME.csv, NAME.mcap, or latest)
    /// instead of driving now.
    #[arg(long, value_name = "RECORD")]
    pub record: Option<PathBuf>,
    /// Write the simulated field's own map instead (its planting record, [sim]
    /// gnss_map_error_*): no driving.
    #[arg(long, conflicts_with = "record")]
    pub field: bool,
    /// The run to drive the row in, as `mechweed run` takes it (it starts in joystick
    /// mode whatever --mode says).
    #[command(flatten)]
    pub run: RunArgs,
}

/// `mechweed teach`: drive the row (or take a record of the drive), map the tool's path.
pub fn teach(args: TeachArgs) -> ExitCode {
    let Ok(settings) = load_settings(args.run.config.as_deref(), &args.run.set)
        .map_err(|errors| print_errors(&errors))
    else {
        return ExitCode::FAILURE;
    };
    if args.field {
        return said(crate::programs::teach::field_into_map(
            &settings, &args.row, &args.map,
        ));
    }
    if args.record.is_none() {
        crate::say!(
            "teaching row {}: drive it in joystick mode with the weeding tool on the row, then end the run (close the window, Ctrl-C, or --duration)",
            args.row
        );
        let run = RunArgs {
            mode: StartMode::Joystick,
            ..args.run
        };
        if crate::programs::run::run(run) != ExitCode::SUCCESS {
            return ExitCode::FAILURE;
        }
    }
    let record = match args.record {
        Some(record) if record.as_os_str() != "latest" => Ok(record),
        _ => crate::record::keep::latest(&settings.record.folder), // the run just made
    };
    said(record.and_then(|record| {
        crate::say!("teaching row {} from {}", args.row, record.display());
        crate::programs::teach::teach_into_map(&record, &args.row, &args.map, &settings)
    }))
}

#[cfg(test)]
#[path = "teach_tests.rs"]
mod tests;
