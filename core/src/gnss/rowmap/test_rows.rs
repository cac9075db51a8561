//! Rows drawn in metres for the tests, put on the earth through a local frame as a
//! map file would have them.

use crate::gnss::rowmap::map::MapRow;
use mechweed_hw::geo::{Enu, Geodetic, LocalFrame};

/// A field in Bavaria at 500 m: a height well off the ellipsoid catches a frame that
/// puts the map's points at the wrong height.
pub(crate) fn field_frame() -> LocalFrame {
    LocalFrame::new(Geodetic {
        lat_deg: 48.137_154,
        lon_deg: 11.575_49,
        height_m: 500.0,
    })
}

/// The row through (east, north) points in `frame`, m.
pub(crate) fn row_from_m(frame: &LocalFrame, name: &str, points_m: &[(f64, f64)]) -> MapRow {
    MapRow {
        name: name.to_string(),
        points_deg: points_m
            .iter()
            .map(|&(east_m, north_m)| {
                let g = frame.to_geodetic(Enu {
                    east_m,
                    north_m,
                    up_m: 0.0,
                });
                (g.lat_deg, g.lon_deg)
            })
            .collect(),
    }
}

/// A left-turning arc of `radius_m` starting at the origin heading east, a point every
/// `step_m` of arclength up to `length_m`.
pub(crate) fn arc_m(radius_m: f64, step_m: f64, length_m: f64) -> Vec<(f64, f64)> {
    let count = (length_m / step_m).round() as usize;
    (0..=count)
        .map(|i| {
            let angle_rad = i as f64 * step_m / radius_m;
            (
                radius_m * angle_rad.sin(),
                radius_m * (1.0 - angle_rad.cos()),
            )
        })
        .collect()
}
