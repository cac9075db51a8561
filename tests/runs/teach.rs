//! `mechweed teach` from outside: the simulated robot driven along a straight row in
//! joystick mode by the scripted operator, its tool's path taught into a row map file;
//! a drive without RTK is refused and writes nothing.

use crate::common;

use common::{mechweed, text};
use mechweed::gnss::rowmap::read_map;
use mechweed_hw::geo::{Geodetic, LocalFrame};

/// The joystick pushed half forward, straight, from 2 s; a straight row with no slope.
const DRIVE: &str = "sim.events=1 power_up, 1.5 mode joystick, 2 deadman on, 2 joystick 0 2";

fn teach(dir: &std::path::Path, seconds: &str, extra: &[&str]) -> std::process::Output {
    mechweed()
        .args(["teach", "3", "--map"])
        .arg(dir.join("rows.csv"))
        .args(["--headless", "--duration", seconds])
        .args(common::test_run_settings(dir))
        .args([
            "--set",
            DRIVE,
            "--set",
            "sim.row=straight",
            "--set",
            "sim.side_slip_deg=0",
        ])
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn a_row_driven_in_joystick_mode_is_taught_along_the_tools_path() {
    let dir = tempfile::tempdir().unwrap();
    let out = teach(dir.path(), "12", &["--set", "gnss.port=sim"]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    assert!(stdout.contains("row 3: "), "{stdout}");
    assert!(
        !stdout.contains("WARNING"),
        "driven along the plants: {stdout}"
    );
    let map = read_map(&dir.path().join("rows.csv")).unwrap();
    assert_eq!(map.rows.len(), 1);
    let row = &map.rows[0];
    assert_eq!(row.name, "3");
    // The simulated field starts at 52.0, 5.66 and runs east: the taught points lie
    // along it, north within the tool's own wander and RTK's centimetre.
    let field = LocalFrame::new(Geodetic {
        lat_deg: 52.0,
        lon_deg: 5.66,
        height_m: 0.0,
    });
    let points: Vec<(f64, f64)> = (row.points_deg.iter())
        .map(|&(lat_deg, lon_deg)| {
            let e = field.to_enu(Geodetic {
                lat_deg,
                lon_deg,
                height_m: 0.0,
            });
            (e.east_m, e.north_m)
        })
        .collect();
    // About 4 m at 0.4 m/s from 2 s, the first metre for the heading.
    assert!(points.len() >= 10, "{} points", points.len());
    for pair in points.windows(2) {
        let step_m = (pair[1].0 - pair[0].0).hypot(pair[1].1 - pair[0].1);
        assert!(
            (0.15..0.40).contains(&step_m),
            "a point every 25 cm, not {step_m} m"
        );
        assert!(pair[1].0 > pair[0].0, "in driving order: {pair:?}");
    }
    let worst_m = points.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    assert!(worst_m < 0.05, "a taught point {worst_m} m off the row");
    // The tool is 0.4 m behind the rear axle, the antenna 0.5 m ahead, and the heading
    // needs a metre of the antenna's track: the row begins where the tool was then,
    // 0.6 m along the field.
    assert!((0.4..0.8).contains(&points[0].0), "{:?}", points[0]);

    // Taught again into the same file from the drive's record (no driving): the row of
    // that name is replaced, not doubled.
    let again = mechweed()
        .args(["teach", "3", "--record", "latest", "--map"])
        .arg(dir.path().join("rows.csv"))
        .args(common::test_run_settings(dir.path()))
        .output()
        .unwrap();
    let said = text(&again.stdout);
    assert!(said.contains("replacing the row of that name"), "{said}");
    // The file as it was is kept: teaching writes the map anew, without its notes.
    assert!(said.contains("rows.csv.bak"), "{said}");
    let kept = std::fs::read_to_string(dir.path().join("rows.csv.bak")).unwrap();
    assert!(kept.contains("row,lat_deg,lon_deg"), "{kept}");
    assert_eq!(
        read_map(&dir.path().join("rows.csv")).unwrap().rows.len(),
        1
    );
}

#[test]
fn a_row_driven_beside_its_plants_is_kept_with_a_warning_that_gives_the_offset() {
    // Put down 14 cm beside the row and driven straight: the tool never went along the
    // plants, and every run by the map would weed beside them.
    let dir = tempfile::tempdir().unwrap();
    let out = teach(
        dir.path(),
        "12",
        &["--set", "gnss.port=sim", "--set", "sim.start_offset_m=0.14"],
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    let warning = (stdout.lines())
        .find(|l| l.starts_with("WARNING: the tool ran "))
        .unwrap_or_else(|| panic!("no warning: {stdout}"));
    let cm: f64 = warning["WARNING: the tool ran ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((10.0..18.0).contains(&cm), "{warning}");
    assert!(warning.contains("teach_warn_off_row_m"), "{warning}");
}

#[test]
fn a_drive_without_rtk_fixed_is_refused_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = teach(
        dir.path(),
        "8",
        &[
            "--set",
            "gnss.port=sim",
            "--set",
            &format!("{DRIVE}, 0.5 gnss_float"),
        ],
    );
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(stderr.contains("nothing written to"), "{stderr}");
    assert!(!dir.path().join("rows.csv").exists());
}

#[test]
fn the_simulated_field_writes_its_own_map_with_its_planting_error() {
    let dir = tempfile::tempdir().unwrap();
    let map_file = dir.path().join("field.csv");
    let out = mechweed()
        .args(["teach", "1", "--field", "--map"])
        .arg(&map_file)
        .args(["--set", "sim.row=straight", "--set", "sim.row_length_m=40"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let row = &read_map(&map_file).unwrap().rows[0];
    // A point every 25 cm over the row and the 5 m beyond it.
    assert_eq!(row.points_deg.len(), 181);
    let field = LocalFrame::new(row_origin());
    let north_m: Vec<f64> = (row.points_deg.iter())
        .map(|&(lat_deg, lon_deg)| {
            field
                .to_enu(Geodetic {
                    lat_deg,
                    lon_deg,
                    height_m: 0.0,
                })
                .north_m
        })
        .collect();
    // Off the true row by the planting error (1 cm s.d., slow), never by much more.
    assert!(north_m.iter().all(|n| n.abs() < 0.05), "{north_m:?}");
    assert!(
        north_m.iter().any(|n| n.abs() > 0.001),
        "no planting error at all"
    );
}

fn row_origin() -> Geodetic {
    Geodetic {
        lat_deg: 52.0,
        lon_deg: 5.66,
        height_m: 0.0,
    }
}
