//! The field tier: what a real field adds to the clean benchmark ([sim] field = realistic).
//!
//! The clean plant's camera noise is independent from frame to frame, so the steering
//! averages it away, and its rows are perfect. A real field is not kind like that. This
//! file lays out, from the seed, everything of a field that the robot meets at a place:
//! - gaps in the row (stretches with no plants, where the camera repeats its last
//!   estimate at a low quality) and weed patches (stretches where the camera locks onto
//!   weeds beside the row: its offset is off by 5-10 cm), both along the row's arclength;
//! - a side slope whose slip changes along the way, and loose soil whose wheel slip makes
//!   the odometry over-read, both smooth profiles over the distance driven;
//! - bumps (clods, ruts) that kick the robot's heading and position at points of the way.
//!
//! The camera's correlated error is the camera's own (camera.rs, a Gauss-Markov process
//! over distance).
//! With the clean tier nothing here acts: no gaps, no weeds, the constant side slip of
//! [sim] side_slip_deg, no wheel slip, no bumps.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Exp, StandardNormal};

use super::params::{FieldKind, FieldTierParams, SimParams};

/// A stretch of the row, by arclength from the row's start, m.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Stretch {
    from_m: f64,
    to_m: f64,
    /// How far the camera's offset is off in a weed patch, m (positive: to the left).
    offset_m: f64,
}

/// A kick to the robot's body at a point of its way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bump {
    /// Distance driven where it happens, m.
    pub at_m: f64,
    pub heading_rad: f64,
    /// Sideways, positive to the left of the robot, m.
    pub side_m: f64,
}

/// What the camera sees at a point of the row, besides the row itself.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct RowAt {
    /// No plants here: the camera has nothing to measure.
    pub gap: bool,
    /// The camera's offset is off by this much (a weed patch), m.
    pub weed_offset_m: f64,
}

pub(crate) struct FieldTier {
    realistic: bool,
    constant_slip_rad: f64,
    gaps: Vec<Stretch>,
    weeds: Vec<Stretch>,
    slope: Profile,
    wheel_slip: Profile,
    bumps: Vec<Bump>,
    next_bump: usize,
}

impl FieldTier {
    /// `params` must be sanitized. The layout reaches `length_m` past the row's start.
    pub fn new(params: &SimParams, length_m: f64) -> FieldTier {
        let t = &params.tier;
        let realistic = params.field == FieldKind::Realistic;
        let mut rng = ChaCha8Rng::seed_from_u64(params.seed.wrapping_add(super::SEED_FIELD));
        // Every stream is drawn whichever tier runs, so that the clean tier's other
        // random numbers never depend on the field kind.
        let gaps = stretches(&mut rng, length_m, t.gap_every_m, t.gap_min_m, t.gap_max_m);
        let mut weeds = stretches(
            &mut rng,
            length_m,
            t.weed_every_m,
            t.weed_length_m,
            t.weed_length_m,
        );
        for weed in &mut weeds {
            let size_m = rng.random_range(t.weed_offset_min_m..=t.weed_offset_max_m);
            weed.offset_m = if rng.random::<bool>() {
                size_m
            } else {
                -size_m
            };
        }
        let slope_deg = Profile::new(&mut rng, length_m, t.slope_length_m, t.slope_max_deg);
        let wheel_slip = Profile::new(&mut rng, length_m, t.wheel_slip_length_m, t.wheel_slip_max);
        let bumps = bumps(&mut rng, length_m, t);
        let keep = |list: Vec<Stretch>| if realistic { list } else { Vec::new() };
        FieldTier {
            realistic,
            constant_slip_rad: params.side_slip_deg.to_radians(),
            gaps: keep(gaps),
            weeds: keep(weeds),
            slope: slope_deg.scaled(1f64.to_radians()),
            wheel_slip,
            bumps: if realistic { bumps } else { Vec::new() },
            next_bump: 0,
        }
    }

    /// The body's side slip where the robot has driven `distance_m`, rad.
    pub(crate) fn side_slip_rad(&self, distance_m: f64) -> f64 {
        if self.realistic {
            self.slope.at(distance_m)
        } else {
            self.constant_slip_rad
        }
    }

    /// How much the drive wheels slip on the soil there (0.05: the ground moves 5 %
    /// less than the wheels' rims, which the encoders count).
    pub(crate) fn wheel_slip(&self, distance_m: f64) -> f64 {
        if self.realistic {
            self.wheel_slip.at(distance_m)
        } else {
            0.0
        }
    }

    /// The next bump the robot has reached by `distance_m`, if any (each once).
    pub(crate) fn bump_reached(&mut self, distance_m: f64) -> Option<Bump> {
        let bump = *self.bumps.get(self.next_bump)?;
        if bump.at_m > distance_m {
            return None;
        }
        self.next_bump += 1;
        Some(bump)
    }

    /// What the camera meets at arclength `s_m` of the row.
    pub fn row_at(&self, s_m: f64) -> RowAt {
        let inside = |list: &[Stretch]| {
            // Stretches are in order and apart: the last one starting before s_m decides.
            let i = list.partition_point(|st| st.from_m <= s_m);
            i.checked_sub(1).map(|i| list[i]).filter(|st| s_m < st.to_m)
        };
        RowAt {
            gap: inside(&self.gaps).is_some(),
            weed_offset_m: inside(&self.weeds).map_or(0.0, |st| st.offset_m),
        }
    }
}

/// Stretches `min_m..max_m` long, their starts apart by exponentially distributed
/// distances of mean `every_m` (measured from one's end to the next's start).
fn stretches(
    rng: &mut ChaCha8Rng,
    length_m: f64,
    every_m: f64,
    min_m: f64,
    max_m: f64,
) -> Vec<Stretch> {
    let mut list = Vec::new();
    let Ok(spacing) = Exp::new(1.0 / every_m) else {
        return list;
    };
    let mut at_m: f64 = spacing.sample(rng);
    while at_m < length_m {
        let long_m = rng.random_range(min_m..=max_m);
        list.push(Stretch {
            from_m: at_m,
            to_m: at_m + long_m,
            offset_m: 0.0,
        });
        at_m += long_m + spacing.sample(rng);
    }
    list
}

fn bumps(rng: &mut ChaCha8Rng, length_m: f64, t: &FieldTierParams) -> Vec<Bump> {
    let mut list = Vec::new();
    let Ok(spacing) = Exp::new(1.0 / t.bump_every_m) else {
        return list;
    };
    let mut at_m: f64 = spacing.sample(rng);
    while at_m < length_m {
        let heading: f64 = StandardNormal.sample(rng);
        let side: f64 = StandardNormal.sample(rng);
        list.push(Bump {
            at_m,
            heading_rad: heading * t.bump_heading_sd_deg.to_radians(),
            side_m: side * t.bump_side_sd_m,
        });
        at_m += spacing.sample(rng);
    }
    list
}

/// A value between 0 and `max` that changes smoothly over distance: a new level drawn
/// every `every_m`, joined by half cosines so that it has no corners.
#[derive(Debug, Clone)]
struct Profile {
    every_m: f64,
    levels: Vec<f64>,
}

impl Profile {
    fn new(rng: &mut ChaCha8Rng, length_m: f64, every_m: f64, max: f64) -> Profile {
        let count = (length_m / every_m).ceil() as usize + 2;
        Profile {
            every_m,
            levels: (0..count).map(|_| rng.random::<f64>() * max).collect(),
        }
    }

    fn scaled(mut self, factor: f64) -> Profile {
        for level in &mut self.levels {
            *level *= factor;
        }
        self
    }

    fn at(&self, distance_m: f64) -> f64 {
        let u = (distance_m / self.every_m).max(0.0);
        let last = self.levels.len() - 1;
        let i = (u.floor() as usize).min(last);
        let (a, b) = (self.levels[i], self.levels[(i + 1).min(last)]);
        let blend = 0.5 - 0.5 * (std::f64::consts::PI * (u - i as f64).min(1.0)).cos();
        a + (b - a) * blend
    }
}

#[cfg(test)]
#[path = "field_tier_tests.rs"]
mod tests;
