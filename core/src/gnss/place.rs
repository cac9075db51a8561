//! Where the row map's line lies from the robot, from a GNSS fix.
//!
//! The map's rows are turned into metres east and north of [gnss] origin, or the map's
//! first point (the local frame: the fixes go into the same frame). A fix is the antenna's position; the
//! rear axle is `antenna_ahead_m` behind it and `antenna_left_m` to its right, along the
//! robot's heading. GNSS gives no heading of its own at a standstill, so the heading is
//! the map line's, less the row filter's estimate of the row's heading relative to the
//! robot. The answer is what the row filter's GNSS update wants: the map line's offset
//! from the rear axle in the robot's frame (positive: the line lies to the left).
//!
//! The row is chosen at the first fix of a run (the nearest one) and kept until
//! `choose_again`, so that a neighbouring row never takes over mid-row.
//!
//! A row may be driven either way. A map's points run one way, and from one fix at a
//! standstill nothing tells which way the robot faces: taken the wrong way round, every
//! offset comes out on the wrong side and the robot steers away from its row. So the
//! direction is found from the fixes themselves: over the first `DIRECTION_AFTER_M` driven,
//! the place along the row grows (along the map's order) or shrinks (against it), and from
//! then on the line is followed the way the robot drives it. Until then the fixes steer
//! nothing (sources_fuse.rs).

use mechweed_hw::geo::{Geodetic, LocalFrame};
use mechweed_hw::nmea::Fix;

use crate::gnss::rowmap::{LocalMap, MapRow, RowMap};

/// The row map's line seen from the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MapView {
    /// The map line's offset from the rear axle, robot frame, m (positive: left).
    pub offset_m: f64,
    /// Where along the row the rear axle is, m from the row's first point.
    pub along_m: f64,
    /// The row's index in the map.
    pub row: usize,
    /// Which way the robot drives the row is known: until then `offset_m` may be on the
    /// wrong side.
    pub direction_known: bool,
}

/// Driven this far, the place along the row has moved by several times the fixes' noise,
/// and the steering, on the wrong side for that long, has barely turned the robot, m.
const DIRECTION_AFTER_M: f64 = 0.3;

/// Which way the robot drives its row.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Direction {
    /// Not yet known: the first fix's place along the row and the distance driven then.
    Unknown(Option<(f64, f64)>),
    Along,
    Against,
}

pub struct RowPlace {
    frame: LocalFrame,
    map: LocalMap,
    antenna_ahead_m: f64,
    antenna_left_m: f64,
    row: Option<usize>,
    hint: usize,
    direction: Direction,
}

impl RowPlace {
    /// The map's rows in the local frame at `origin` (None: the map's first point);
    /// `label` names the map in errors.
    pub fn new(
        map: &RowMap,
        label: &str,
        (antenna_ahead_m, antenna_left_m): (f64, f64),
        origin: Option<Geodetic>,
    ) -> Result<RowPlace, String> {
        let Some(&(lat_deg, lon_deg)) = map.rows.first().and_then(|r| r.points_deg.first()) else {
            return Err(format!("{label}: the map has no rows"));
        };
        let frame = LocalFrame::new(origin.unwrap_or(Geodetic {
            lat_deg,
            lon_deg,
            height_m: 0.0,
        }));
        let local = map
            .to_local(&frame)
            .map_err(|e| format!("{label}: row {}: {}", e.row, e.what))?;
        Ok(RowPlace {
            frame,
            map: local,
            antenna_ahead_m,
            antenna_left_m,
            row: None,
            hint: 0,
            direction: Direction::Unknown(None),
        })
    }

    /// The simulated field's own map: one row, named 1.
    pub fn from_points(
        points: &[Geodetic],
        antenna_ahead_m: f64,
        antenna_left_m: f64,
    ) -> Result<RowPlace, String> {
        let row = MapRow {
            name: "1".to_string(),
            points_deg: points.iter().map(|p| (p.lat_deg, p.lon_deg)).collect(),
        };
        let map = RowMap { rows: vec![row] };
        let antenna = (antenna_ahead_m, antenna_left_m);
        RowPlace::new(&map, "the simulated field's map", antenna, None)
    }

    /// Choose the row afresh at the next fix (a new autonomous run).
    pub(crate) fn choose_again(&mut self) {
        self.row = None;
        self.direction = Direction::Unknown(None);
    }

    /// The robot drives its row against the map's point order.
    pub(crate) fn against_map(&self) -> bool {
        self.direction == Direction::Against
    }

    /// The map line from the robot at `fix`, the row heading `row_heading_rad` to the
    /// left of the robot's (the row filter's estimate), the robot having driven `driven_m`
    /// (odometry, forward). None when no row is near.
    pub(crate) fn locate(
        &mut self,
        fix: &Fix,
        row_heading_rad: f64,
        driven_m: f64,
    ) -> Option<MapView> {
        let antenna = self.frame.to_enu(Geodetic {
            lat_deg: fix.lat_deg,
            lon_deg: fix.lon_deg,
            height_m: 0.0,
        });
        let row = match self.row {
            Some(row) => row,
            None => {
                let (row, _) = self.map.nearest_row(antenna.east_m, antenna.north_m)?;
                self.row = Some(row);
                self.hint = 0;
                row
            }
        };
        let line = self.map.rows.get(row)?;
        // The robot's heading is the line's beside the rear axle less the row's heading
        // from the robot (the filter's, at the axle); the axle is found from the antenna
        // with it. Start from the line beside the antenna; a second round moves to the
        // line beside the axle, which on a 20 m arc turns 1.4 degrees in 0.5 m.
        let mut foot = line.project(antenna.east_m, antenna.north_m, &mut self.hint)?;
        let against = self.direction == Direction::Against;
        let facing_rad = if against { std::f64::consts::PI } else { 0.0 };
        for _ in 0..2 {
            let heading_rad = foot.heading_rad + facing_rad - row_heading_rad;
            let (sin, cos) = heading_rad.sin_cos();
            let axle_east_m =
                antenna.east_m - self.antenna_ahead_m * cos + self.antenna_left_m * sin;
            let axle_north_m =
                antenna.north_m - self.antenna_ahead_m * sin - self.antenna_left_m * cos;
            foot = line.project(axle_east_m, axle_north_m, &mut self.hint)?;
        }
        if !line.is_beside(foot.s_m) {
            return None;
        }
        self.find_direction(foot.s_m, driven_m);
        let against = self.direction == Direction::Against;
        Some(MapView {
            // The axle left of the line is the line to the axle's right (facing the
            // map's way; facing against it, to its left).
            offset_m: if against {
                foot.offset_m
            } else {
                -foot.offset_m
            },
            along_m: foot.s_m,
            row,
            direction_known: !matches!(self.direction, Direction::Unknown(_)),
        })
    }

    /// The direction, from the place along the row `along_m` with `driven_m` driven.
    fn find_direction(&mut self, along_m: f64, driven_m: f64) {
        let Direction::Unknown(first) = self.direction else {
            return;
        };
        let Some((first_along_m, first_driven_m)) = first else {
            self.direction = Direction::Unknown(Some((along_m, driven_m)));
            return;
        };
        if driven_m - first_driven_m >= DIRECTION_AFTER_M {
            self.direction = match along_m < first_along_m {
                true => Direction::Against,
                false => Direction::Along,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::geo::Enu;
    use mechweed_hw::nmea::FixQuality;

    const ORIGIN: Geodetic = Geodetic {
        lat_deg: 52.0,
        lon_deg: 5.66,
        height_m: 0.0,
    };

    /// A straight row 20 m due north, a point every metre; the antenna on the centre line.
    fn place() -> RowPlace {
        let frame = LocalFrame::new(ORIGIN);
        let points: Vec<Geodetic> = (0..=20)
            .map(|i| {
                frame.to_geodetic(Enu {
                    east_m: 0.0,
                    north_m: f64::from(i),
                    up_m: 0.0,
                })
            })
            .collect();
        RowPlace::from_points(&points, 0.0, 0.0).unwrap()
    }

    /// A fix of the antenna `north_m` along the row and `east_m` beside it.
    fn fix(north_m: f64, east_m: f64) -> Fix {
        let at = LocalFrame::new(ORIGIN).to_geodetic(Enu {
            east_m,
            north_m,
            up_m: 0.0,
        });
        Fix {
            utc_s_of_day: 0.0,
            lat_deg: at.lat_deg,
            lon_deg: at.lon_deg,
            altitude_m: None,
            quality: FixQuality::RtkFixed,
            satellites: None,
            hdop: None,
            correction_age_s: None,
            sd_east_m: None,
            sd_north_m: None,
            speed_mps: None,
            course_deg: None,
        }
    }

    #[test]
    fn the_direction_is_found_only_once_the_robot_has_driven_and_found_again_each_run() {
        let mut place = place();
        // Standing 10 cm east of the line, the fixes wandering along it by a centimetre:
        // nothing says which way the robot faces, however many fixes come.
        for (k, north_m) in [10.0, 9.99, 10.01, 9.98].into_iter().enumerate() {
            let view = place
                .locate(&fix(north_m, 0.1), 0.0, 12.0 + 0.01 * k as f64)
                .unwrap();
            assert!(!view.direction_known, "known at fix {k}");
        }
        // Driven 0.4 m with the place along the row shrinking: against the map's order,
        // the robot facing south, and the line, west of it, on its right.
        let view = place.locate(&fix(9.6, 0.1), 0.0, 12.4).unwrap();
        assert!(view.direction_known && place.against_map());
        assert!((view.offset_m + 0.1).abs() < 0.01, "{view:?}");
        // A new run finds it again, here along the map's order: facing north, the line on
        // the robot's left.
        place.choose_again();
        let view = place.locate(&fix(5.0, 0.1), 0.0, 20.0).unwrap();
        assert!(!view.direction_known && !place.against_map());
        let view = place.locate(&fix(5.4, 0.1), 0.0, 20.4).unwrap();
        assert!(view.direction_known && !place.against_map());
        assert!((view.offset_m - 0.1).abs() < 0.01, "{view:?}");
    }
}
