//! One row in metres east and north of a reference point, and where a point (the
//! tool's position from GNSS) lies relative to it: arclength along the row, signed
//! cross-track offset, the row's heading and curvature there.
//!
//! The row is the polyline through its points, extended straight before its first
//! point and after its last, so that the robot gets an offset while it lines up and
//! while it leaves the row.

use crate::gnss::rowmap::format::{latitude_problem, longitude_problem};
use crate::gnss::rowmap::map::MapRow;
use mechweed_hw::geo::{Geodetic, LocalFrame};

/// Beyond this distance from the hint's segment the walk is not trusted, m: a hint
/// that far off belongs to another row or an old position, and walking downhill from
/// it may stop in a dip of a curved row.
const FAR_M: f64 = 2.0;
/// Points closer than this to the one before are dropped, m: a segment without length
/// has no direction.
const SAME_POINT_M: f64 = 1e-6;
/// Curvature is the heading change over this much row, m: long enough to average a
/// few taught points' noise, short enough to follow a headland bend.
const CURVATURE_WINDOW_M: f64 = 1.0;

/// Why a row cannot be put in the local frame.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("row '{row}': {what}")]
pub struct RowError {
    pub row: String,
    pub what: String,
}

/// Where a point lies relative to a row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foot {
    /// Arclength of the foot point from the row's first point, m: negative before it,
    /// beyond the row's length after its last.
    pub s_m: f64,
    /// Distance of the point from the row, m; positive = the point is LEFT of the row
    /// looking along the row's direction.
    pub offset_m: f64,
    /// Heading of the row's segment at the foot, rad, counter-clockwise from east.
    pub heading_rad: f64,
    /// Curvature of the row at the foot, 1/m; positive = the row turns left.
    pub curvature_per_m: f64,
}

/// A row as a polyline in metres east and north of a frame's origin.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalRow {
    name: String,
    /// (east, north) of each point, m; consecutive points are distinct.
    points_m: Vec<(f64, f64)>,
    /// Arclength of each point from the first, m.
    s_m: Vec<f64>,
    /// Unit direction (east, north) of each segment.
    dirs: Vec<(f64, f64)>,
    /// Heading of each segment, rad, unwrapped so that differences are turns.
    turned_rad: Vec<f64>,
    /// Arclength of each segment's middle, m.
    mid_s_m: Vec<f64>,
}

/// One segment of the polyline.
struct Segment {
    a: (f64, f64),
    s_m: f64,
    length_m: f64,
    dir: (f64, f64),
}

impl Segment {
    /// Squared distance from `p` to the segment (not its extension).
    fn distance2(&self, p: (f64, f64)) -> f64 {
        let (dx, dy) = (p.0 - self.a.0, p.1 - self.a.1);
        let t = (dx * self.dir.0 + dy * self.dir.1).clamp(0.0, self.length_m);
        let (ex, ey) = (dx - self.dir.0 * t, dy - self.dir.1 * t);
        ex * ex + ey * ey
    }
}

fn cross(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.1 - a.1 * b.0
}

/// Before a row's first point and after its last, a position still counts as on the
/// row within this distance along it, m: the tool reaches the row's end a little
/// before the taught line does, and the robot lines up before the first point.
pub(crate) const ROW_END_MARGIN_M: f64 = 1.0;

impl LocalRow {
    /// The row in `frame`. Points repeated within a micrometre are dropped; a row
    /// needs two distinct points on the earth.
    pub fn new(row: &MapRow, frame: &LocalFrame) -> Result<LocalRow, RowError> {
        let error = |what: String| RowError {
            row: row.name.clone(),
            what,
        };
        // The map holds no heights. The ground is near the frame's origin height, and
        // GNSS positions come with their heights: at the ellipsoid instead, a field at
        // 500 m would shrink by about 3 mm per 40 m against them.
        let height_m = frame.origin().height_m;
        let mut points_m: Vec<(f64, f64)> = Vec::with_capacity(row.points_deg.len());
        for (index, &(lat_deg, lon_deg)) in row.points_deg.iter().enumerate() {
            let problem = latitude_problem(lat_deg, &lat_deg.to_string())
                .or_else(|| longitude_problem(lon_deg, &lon_deg.to_string()));
            if let Some(what) = problem {
                return Err(error(format!("point {}: {what}", index + 1)));
            }
            let enu = frame.to_enu(Geodetic {
                lat_deg,
                lon_deg,
                height_m,
            });
            let point = (enu.east_m, enu.north_m);
            let repeated = points_m
                .last()
                .is_some_and(|last| (point.0 - last.0).hypot(point.1 - last.1) < SAME_POINT_M);
            if !repeated {
                points_m.push(point);
            }
        }
        if points_m.len() < 2 {
            return Err(error("has fewer than 2 distinct points".to_string()));
        }
        let mut s_m = vec![0.0];
        let mut dirs = Vec::with_capacity(points_m.len() - 1);
        let mut turned_rad: Vec<f64> = Vec::with_capacity(points_m.len() - 1);
        let mut mid_s_m = Vec::with_capacity(points_m.len() - 1);
        let mut length_m = 0.0;
        for pair in points_m.windows(2) {
            let [a, b] = pair else { continue };
            let step_m = (b.0 - a.0).hypot(b.1 - a.1);
            let dir = ((b.0 - a.0) / step_m, (b.1 - a.1) / step_m);
            let heading_rad = match (turned_rad.last(), dirs.last()) {
                (Some(&before_rad), Some(&before)) => {
                    before_rad + cross(before, dir).atan2(before.0 * dir.0 + before.1 * dir.1)
                }
                _ => dir.1.atan2(dir.0),
            };
            turned_rad.push(heading_rad);
            dirs.push(dir);
            mid_s_m.push(length_m + step_m / 2.0);
            length_m += step_m;
            s_m.push(length_m);
        }
        Ok(LocalRow {
            name: row.name.clone(),
            points_m,
            s_m,
            dirs,
            turned_rad,
            mid_s_m,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// Arclength from the first point to the last, m.
    pub fn length_m(&self) -> f64 {
        self.s_m.last().copied().unwrap_or(0.0)
    }

    /// A point `s_m` along the row (from its first point) lies beside it: within
    /// ROW_END_MARGIN_M of its ends. Past that (the headland) the map tells nothing,
    /// however far the last segment would reach.
    pub(crate) fn is_beside(&self, s_m: f64) -> bool {
        (-ROW_END_MARGIN_M..=self.length_m() + ROW_END_MARGIN_M).contains(&s_m)
    }

    /// (east, north) of the row's points, m, without repeated points.
    pub fn points_m(&self) -> &[(f64, f64)] {
        &self.points_m
    }

    pub(crate) fn segment_count(&self) -> usize {
        self.dirs.len()
    }

    fn segment(&self, i: usize) -> Option<Segment> {
        let (&a, &dir) = (self.points_m.get(i)?, self.dirs.get(i)?);
        let (&start_m, &end_m) = (self.s_m.get(i)?, self.s_m.get(i + 1)?);
        Some(Segment {
            a,
            s_m: start_m,
            length_m: end_m - start_m,
            dir,
        })
    }

    fn distance2(&self, i: usize, p: (f64, f64)) -> Option<f64> {
        Some(self.segment(i)?.distance2(p))
    }

    /// Where the point (east, north, m) lies relative to the row. `hint` is a segment
    /// index near the answer: keep one per tracked point and pass it every time. The
    /// search walks downhill from it, costing O(distance moved); when the hint's
    /// segment is more than 2 m from the point it scans every segment instead. At a
    /// corner the nearer of the two segments wins. `None` for a non-finite point.
    pub fn project(&self, east_m: f64, north_m: f64, hint: &mut usize) -> Option<Foot> {
        if !(east_m.is_finite() && north_m.is_finite()) {
            return None;
        }
        let p = (east_m, north_m);
        let mut i = (*hint).min(self.segment_count().saturating_sub(1));
        let mut best = self.distance2(i, p)?;
        if best > FAR_M * FAR_M {
            (i, _) = self.nearest_segment(p)?;
        } else {
            while let Some(d) = self.distance2(i + 1, p).filter(|&d| d < best) {
                (i, best) = (i + 1, d);
            }
            while let Some(d) = i
                .checked_sub(1)
                .and_then(|j| self.distance2(j, p))
                .filter(|&d| d < best)
            {
                (i, best) = (i - 1, d);
            }
        }
        *hint = i;
        self.foot(i, p)
    }

    /// As `project`, by scanning every segment: for a point with no good hint.
    pub(crate) fn project_scan(&self, east_m: f64, north_m: f64) -> Option<Foot> {
        if !(east_m.is_finite() && north_m.is_finite()) {
            return None;
        }
        let (i, _) = self.nearest_segment((east_m, north_m))?;
        self.foot(i, (east_m, north_m))
    }

    /// The segment nearest to `p` and its squared distance (the first of equals).
    fn nearest_segment(&self, p: (f64, f64)) -> Option<(usize, f64)> {
        (0..self.segment_count())
            .filter_map(|i| Some((i, self.distance2(i, p)?)))
            .fold(None, |best: Option<(usize, f64)>, (i, d)| match best {
                Some((_, best_d)) if best_d <= d => best,
                _ => Some((i, d)),
            })
    }

    /// The foot of `p` on segment `i`, the segment nearest to it.
    fn foot(&self, i: usize, p: (f64, f64)) -> Option<Foot> {
        let seg = self.segment(i)?;
        let last = self.segment_count().saturating_sub(1);
        let d = (p.0 - seg.a.0, p.1 - seg.a.1);
        let t_m = d.0 * seg.dir.0 + d.1 * seg.dir.1;
        // Inside the row a foot beyond a segment's end is the corner point itself, and
        // the offset is the distance to it; at the row's ends the line goes on straight.
        let (along_m, offset_m) = if t_m < 0.0 && i > 0 {
            (0.0, self.corner_offset_m(i, p)?)
        } else if t_m > seg.length_m && i < last {
            (seg.length_m, self.corner_offset_m(i + 1, p)?)
        } else {
            (t_m, cross(seg.dir, d))
        };
        let s_m = seg.s_m + along_m;
        Some(Foot {
            s_m,
            offset_m,
            heading_rad: seg.dir.1.atan2(seg.dir.0),
            curvature_per_m: self.curvature_per_m(s_m),
        })
    }

    /// Signed distance from `p` to the inner point `k`: the side is taken across the
    /// mean of the two segments' directions, which is right for either segment.
    fn corner_offset_m(&self, k: usize, p: (f64, f64)) -> Option<f64> {
        let (&v, &before, &after) = (
            self.points_m.get(k)?,
            self.dirs.get(k.checked_sub(1)?)?,
            self.dirs.get(k)?,
        );
        let d = (p.0 - v.0, p.1 - v.1);
        let mean = (before.0 + after.0, before.1 + after.1);
        // A row that doubles back has no mean direction; the segment before decides.
        let across = if mean.0.hypot(mean.1) > 1e-9 {
            cross(mean, d)
        } else {
            cross(before, d)
        };
        Some(d.0.hypot(d.1).copysign(across))
    }

    /// The heading change over `CURVATURE_WINDOW_M` centred on `s_m`, divided by it.
    /// The heading runs linearly between the segments' middles (so an evenly sampled
    /// arc gives exactly its curvature) and stays constant beyond the first and last
    /// middles, like the straight extensions.
    fn curvature_per_m(&self, s_m: f64) -> f64 {
        let half_m = CURVATURE_WINDOW_M / 2.0;
        (self.heading_at(s_m + half_m) - self.heading_at(s_m - half_m)) / CURVATURE_WINDOW_M
    }

    fn heading_at(&self, s_m: f64) -> f64 {
        let k = self.mid_s_m.partition_point(|&mid_m| mid_m <= s_m);
        let before = k
            .checked_sub(1)
            .and_then(|j| Some((*self.mid_s_m.get(j)?, *self.turned_rad.get(j)?)));
        let after = self
            .mid_s_m
            .get(k)
            .and_then(|&mid_m| Some((mid_m, *self.turned_rad.get(k)?)));
        match (before, after) {
            (Some((s0_m, h0_rad)), Some((s1_m, h1_rad))) => {
                h0_rad + (h1_rad - h0_rad) * (s_m - s0_m) / (s1_m - s0_m)
            }
            (Some((_, h_rad)), None) | (None, Some((_, h_rad))) => h_rad,
            (None, None) => 0.0,
        }
    }
}

#[cfg(test)]
#[path = "local_row_tests.rs"]
mod tests;
