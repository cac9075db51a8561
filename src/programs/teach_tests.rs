//! Tests of teach.rs.

use super::*;

#[test]
fn a_float_fix_in_mid_row_does_not_turn_the_heading_that_places_the_tool() {
    // Driving east along latitude 52 at 0.5 m/s, a fix every 5 cm; from 3.0 to 3.3 m
    // the receiver is in RTK float (quality 5) and 15 cm north.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drive.csv");
    let frame = LocalFrame::new(Geodetic {
        lat_deg: 52.0,
        lon_deg: 5.66,
        height_m: 0.0,
    });
    // Every record has the camera's columns; empty here (no row seen).
    let mut csv = String::from(
        "mode,distance_m,gnss_quality,gnss_lat_deg,gnss_lon_deg,cam_offset_m,cam_angle_rad,cam_quality\n",
    );
    for i in 0..=120 {
        let at_m = 0.05 * f64::from(i);
        let float = (3.0..3.3).contains(&at_m);
        let p = frame.to_geodetic(Enu {
            east_m: at_m,
            north_m: if float { 0.15 } else { 0.0 },
            up_m: 0.0,
        });
        let quality = if float { 5 } else { 4 };
        csv += &format!("joystick,{at_m},{quality},{},{},,,\n", p.lat_deg, p.lon_deg);
    }
    std::fs::write(&path, csv).unwrap();
    let taught = taught_row(&path, "1", &Settings::shipped()).unwrap();
    for &(lat_deg, lon_deg) in &taught.row.points_deg {
        let p = frame.to_enu(Geodetic {
            lat_deg,
            lon_deg,
            height_m: 0.0,
        });
        assert!(
            p.north_m.abs() < 0.01,
            "a point {:.3} m off the row",
            p.north_m
        );
    }
}
