//! The field: one crop row's centre line and its plants.
//!
//! The centre line is a polyline with a point every centimetre of arclength (for the
//! S-curve, every centimetre of x, with the true arclength stored), starting at the
//! origin heading +x, and running 5 m past the row's end so the camera can look past it.
//! The plants go on `PLANTED_BEYOND_M` past the measured length of the row, as in a
//! field where the benchmark measures a stretch of a longer row: the camera still sees
//! plants while the tool covers the last metres of the stretch.
//! Cross-track errors are measured against this interpolated line, not the plants.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::params::{RowShape, SimParams};

/// Spacing of the polyline's points, m.
const SAMPLE_M: f64 = 0.01;
/// The line goes on this far past the row's end, m.
const EXTRA_M: f64 = 5.0;
/// The plants go on this far past the row's measured length, m.
pub(crate) const PLANTED_BEYOND_M: f64 = 2.0;
/// Beyond this distance from the line the local search is not trusted, m.
const FAR_M: f64 = 2.0;

/// Where a point lies relative to the row.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Projection {
    /// Arclength of the foot point from the row's start, m (negative before the start).
    pub s_m: f64,
    /// Lateral offset of the point from the centre line, m; positive = point is LEFT of the row.
    pub signed_offset_m: f64,
    /// Heading of the row at the foot point, rad.
    pub heading_rad: f64,
}

pub struct Field {
    points: Vec<(f64, f64)>,
    /// Arclength of each point from the start, m.
    s_m: Vec<f64>,
    row_length_m: f64,
    plants: Vec<(f64, f64)>,
}

impl Field {
    pub fn new(params: &SimParams) -> Field {
        let p = params.sanitized();
        let n_points = ((p.row_length_m + EXTRA_M) / SAMPLE_M).ceil() as usize + 1;
        let mut points = Vec::with_capacity(n_points);
        for i in 0..n_points {
            let u = i as f64 * SAMPLE_M;
            points.push(match p.row {
                RowShape::Straight => (u, 0.0),
                RowShape::SCurve => {
                    let phase = std::f64::consts::TAU * u / p.scurve_wavelength_m;
                    (u, p.scurve_amplitude_m * phase.sin())
                }
                RowShape::Arc => {
                    let r = p.arc_radius_m;
                    ((u / r).sin() * r, (1.0 - (u / r).cos()) * r)
                }
            });
        }
        let mut s_m = Vec::with_capacity(n_points);
        let mut s = 0.0;
        s_m.push(s);
        for pair in points.windows(2) {
            s += (pair[1].0 - pair[0].0).hypot(pair[1].1 - pair[0].1);
            s_m.push(s);
        }
        let mut field = Field {
            points,
            s_m,
            row_length_m: p.row_length_m,
            plants: Vec::new(),
        };
        field.plants = field.scatter_plants(&p);
        field
    }

    /// A plant every `plant_spacing_m` along the row, pushed sideways by Gaussian scatter.
    fn scatter_plants(&self, p: &SimParams) -> Vec<(f64, f64)> {
        let mut rng = ChaCha8Rng::seed_from_u64(p.seed.wrapping_add(super::SEED_PLANTS));
        let count = (self.planted_length_m() / p.plant_spacing_m).floor() as usize + 1;
        let mut plants = Vec::with_capacity(count);
        for k in 0..count {
            let (x, y, heading) = self.point_at(k as f64 * p.plant_spacing_m);
            let side_m: f64 = StandardNormal.sample(&mut rng);
            let side_m = side_m * p.plant_scatter_m;
            plants.push((x - heading.sin() * side_m, y + heading.cos() * side_m));
        }
        plants
    }

    /// Length of the planted row, past which the camera sees no plants, m.
    pub(crate) fn planted_length_m(&self) -> f64 {
        self.row_length_m + PLANTED_BEYOND_M
    }

    /// Length of the row (without the extra line past its end), m.
    pub fn length_m(&self) -> f64 {
        self.row_length_m
    }

    /// Positions of the plants in the field frame, m.
    pub fn plants(&self) -> &[(f64, f64)] {
        &self.plants
    }

    /// The centre line's points in the field frame, m (for drawing).
    pub(crate) fn centre_line(&self) -> &[(f64, f64)] {
        &self.points
    }

    pub(crate) fn segment_count(&self) -> usize {
        self.points.len() - 1
    }

    /// Start point, arclength and unit direction of segment i (i < segment_count).
    pub(crate) fn segment(&self, i: usize) -> Segment {
        let a = self.points[i];
        let b = self.points[i + 1];
        let length_m = self.s_m[i + 1] - self.s_m[i];
        Segment {
            a,
            s_m: self.s_m[i],
            length_m,
            dir: ((b.0 - a.0) / length_m, (b.1 - a.1) / length_m),
        }
    }

    /// Point and heading of the line at arclength s (clamped to the line). Construction only.
    pub(crate) fn point_at(&self, s_m: f64) -> (f64, f64, f64) {
        let i = self
            .s_m
            .partition_point(|&s| s <= s_m)
            .clamp(1, self.segment_count())
            - 1;
        let seg = self.segment(i);
        let t = (s_m - seg.s_m).clamp(0.0, seg.length_m);
        (
            seg.a.0 + seg.dir.0 * t,
            seg.a.1 + seg.dir.1 * t,
            seg.heading_rad(),
        )
    }

    /// Project a point onto the centre line. `hint` is a segment index near the answer
    /// (keep one per moving point and pass it every time): the search walks downhill
    /// from it, so it costs O(distance moved); it falls back to scanning every segment
    /// only when the point is far from the line. Before the start and past the end the
    /// line is extended straight.
    pub fn project(&self, x_m: f64, y_m: f64, hint: &mut usize) -> Projection {
        let n = self.segment_count();
        let mut i = (*hint).min(n - 1);
        let mut best = self.segment(i).distance2((x_m, y_m));
        while i + 1 < n {
            let d = self.segment(i + 1).distance2((x_m, y_m));
            if d >= best {
                break;
            }
            (i, best) = (i + 1, d);
        }
        while i > 0 {
            let d = self.segment(i - 1).distance2((x_m, y_m));
            if d >= best {
                break;
            }
            (i, best) = (i - 1, d);
        }
        if best > FAR_M * FAR_M {
            for j in 0..n {
                let d = self.segment(j).distance2((x_m, y_m));
                if d < best {
                    (i, best) = (j, d);
                }
            }
        }
        *hint = i;
        let seg = self.segment(i);
        let (dx, dy) = (x_m - seg.a.0, y_m - seg.a.1);
        let mut t = dx * seg.dir.0 + dy * seg.dir.1;
        if i > 0 {
            t = t.max(0.0);
        }
        if i + 1 < n {
            t = t.min(seg.length_m);
        }
        Projection {
            s_m: seg.s_m + t,
            signed_offset_m: seg.dir.0 * dy - seg.dir.1 * dx,
            heading_rad: seg.heading_rad(),
        }
    }
}

/// One piece of the polyline.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub a: (f64, f64),
    /// Arclength at `a`, m.
    pub s_m: f64,
    pub length_m: f64,
    /// Unit vector from a to the next point.
    pub dir: (f64, f64),
}

impl Segment {
    pub fn heading_rad(&self) -> f64 {
        self.dir.1.atan2(self.dir.0)
    }

    /// Squared distance from a point to this segment.
    fn distance2(&self, p: (f64, f64)) -> f64 {
        let (dx, dy) = (p.0 - self.a.0, p.1 - self.a.1);
        let t = (dx * self.dir.0 + dy * self.dir.1).clamp(0.0, self.length_m);
        let (ex, ey) = (dx - self.dir.0 * t, dy - self.dir.1 * t);
        ex * ex + ey * ey
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(row: RowShape) -> Field {
        Field::new(&SimParams {
            row,
            row_length_m: 40.0,
            ..SimParams::default()
        })
    }

    #[test]
    fn straight_row_projection_and_sign() {
        let f = field(RowShape::Straight);
        let mut hint = 0;
        let p = f.project(12.345, 0.05, &mut hint);
        assert!((p.s_m - 12.345).abs() < 1e-9);
        assert!(
            (p.signed_offset_m - 0.05).abs() < 1e-12,
            "left of the row is positive"
        );
        assert!(p.heading_rad.abs() < 1e-12);
        assert!(f.project(12.0, -0.03, &mut hint).signed_offset_m < 0.0);
        // Behind the start the line is extended straight.
        let behind = f.project(-0.4, 0.05, &mut 0);
        assert!((behind.s_m + 0.4).abs() < 1e-9 && (behind.signed_offset_m - 0.05).abs() < 1e-12);
        assert_eq!(f.length_m(), 40.0);
        assert!((f.centre_line().last().unwrap().0 - 45.0).abs() < 0.011);
    }

    #[test]
    fn arc_projection_matches_the_circle() {
        let f = field(RowShape::Arc);
        let r = 20.0;
        let theta: f64 = 0.7;
        // A point 3 cm inside the circle (to the left, the arc turns left).
        let (x, y) = ((r - 0.03) * theta.sin(), r - (r - 0.03) * theta.cos());
        let mut hint = 0;
        let p = f.project(x, y, &mut hint);
        assert!((p.s_m - r * theta).abs() < 1e-4, "s {}", p.s_m);
        assert!(
            (p.signed_offset_m - 0.03).abs() < 1e-5,
            "offset {}",
            p.signed_offset_m
        );
        assert!((p.heading_rad - theta).abs() < 1e-3);
        // A hint far away still finds it, and the far fallback works too.
        assert!((f.project(x, y, &mut 3000).s_m - p.s_m).abs() < 1e-6);
        let (xi, yi) = ((r - 3.0) * theta.sin(), r - (r - 3.0) * theta.cos());
        assert!((f.project(xi, yi, &mut 0).signed_offset_m - 3.0).abs() < 1e-3);
    }

    #[test]
    fn scurve_follows_the_sine() {
        let f = field(RowShape::SCurve);
        let mut hint = 0;
        let p = f.project(2.5, 0.05, &mut hint); // the crest: y = A at x = wavelength/4
        assert!(p.signed_offset_m.abs() < 1e-5);
        assert!(p.heading_rad.abs() < 1e-3);
    }

    #[test]
    fn plants_lie_along_the_row_with_the_scatter() {
        let f = field(RowShape::Straight);
        let plants = f.plants();
        // 40 m measured plus the planted stretch beyond, a plant every 0.2 m.
        let expected = ((40.0 + PLANTED_BEYOND_M) / 0.2f64).floor() as usize + 1;
        assert_eq!(plants.len(), expected);
        assert!((plants[100].0 - 20.0).abs() < 1e-9);
        let var = plants.iter().map(|p| p.1 * p.1).sum::<f64>() / plants.len() as f64;
        assert!(
            (0.007..0.013).contains(&var.sqrt()),
            "scatter s.d. {}",
            var.sqrt()
        );
    }
}
