//! Teaching a row by driving it: the pure logic behind `mechweed teach`. The caller
//! feeds the tool point's GNSS position, the receiver's fix quality and the distance
//! driven; the teacher keeps a point every `spacing_m` while the fix is trusted, and
//! refuses the row (saying where, in metres along it) if a stretch had no trusted fix,
//! the machine went back, or the row breaks a rule of the map file.

use std::collections::BTreeSet;

use crate::gnss::rowmap::format::{
    MAX_STEP_M, latitude_problem, longitude_problem, name_problem, row_problems,
};
use crate::gnss::rowmap::map::MapRow;
use mechweed_hw::geo::{Geodetic, LocalFrame};

/// GGA fix quality of an RTK fixed position.
pub(crate) const RTK_FIXED: u8 = 4;
/// GGA fix quality of an RTK float position.
pub(crate) const RTK_FLOAT: u8 = 5;
/// The distance driven may go back this much without the row being refused, m:
/// odometry jitters by millimetres while the machine stands.
const REVERSE_TOLERANCE_M: f64 = 0.02;
/// A point this close to its due place is due, m: distances added up in steps miss by
/// ulps.
const SPACING_SLACK_M: f64 = 1e-6;

/// How a row is taught.
#[derive(Debug, Clone, PartialEq)]
pub struct TeachSettings {
    /// A point is kept every this much travel, m: the first sample at or past each
    /// multiple of it, so that the points keep their places along the row whatever
    /// the sample rate.
    pub spacing_m: f64,
    /// A longer stretch without a trusted fix refuses the row, m.
    pub max_gap_m: f64,
    /// A shorter row is refused, m.
    pub min_length_m: f64,
    /// GGA fix qualities (0..=8) whose positions are good enough for the map.
    pub trusted_fix: BTreeSet<u8>,
}

impl Default for TeachSettings {
    fn default() -> TeachSettings {
        TeachSettings {
            spacing_m: 0.25,
            max_gap_m: 1.0,
            min_length_m: 2.0,
            trusted_fix: BTreeSet::from([RTK_FIXED]),
        }
    }
}

/// One position of the tool point while teaching.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeachSample {
    pub lat_deg: f64,
    pub lon_deg: f64,
    /// GGA fix quality: 0 invalid, 1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float, ...
    pub fix_quality: u8,
    /// Distance driven since some start (odometry), m; only differences matter.
    pub distance_m: f64,
}

/// Why a row was not taught. Distances are metres along the row from its first sample.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TeachError {
    #[error("teach setting {setting} = {value}: {what}")]
    BadSetting {
        setting: &'static str,
        value: String,
        what: String,
    },
    #[error("no {trusted} position from {from_m:.1} m to {to_m:.1} m of the row: drive it again")]
    NoTrustedFix {
        /// The trusted fix qualities, named: "RTK fixed".
        trusted: String,
        from_m: f64,
        to_m: f64,
    },
    #[error(
        "the machine went back from {from_m:.2} m to {to_m:.2} m of the row: a row is taught \
         driving forward in one go: drive it again"
    )]
    Reversed { from_m: f64, to_m: f64 },
    #[error("the distance driven is not a number after {after_m:.2} m of the row")]
    BadDistance { after_m: f64 },
    #[error("{what}")]
    BadName { what: String },
    #[error("{count} points were taught with a trusted fix: a row needs at least 2")]
    TooFewPoints { count: usize },
    #[error("the taught row is {length_m:.2} m long, shorter than {min_m} m: drive it again")]
    TooShort { length_m: f64, min_m: f64 },
    #[error("at {at_m:.2} m of the row: {what}: drive it again")]
    Geometry { at_m: f64, what: String },
}

/// Collects one row while it is driven. Feed every position, then `finish`.
#[derive(Debug, Clone)]
pub struct Teacher {
    settings: TeachSettings,
    /// `distance_m` of the first sample: distances in errors count from it.
    start_m: Option<f64>,
    furthest_m: f64,
    /// The last trusted sample and where it was.
    last_trusted: Option<((f64, f64), f64)>,
    points_deg: Vec<(f64, f64)>,
    points_at_m: Vec<f64>,
    /// Where the next point is due, m.
    next_due_m: f64,
    /// The first reason the row is refused: teaching it further cannot mend it.
    fault: Option<TeachError>,
}

impl Teacher {
    pub fn new(settings: TeachSettings) -> Result<Teacher, TeachError> {
        let bad = |setting: &'static str, value: String, what: &str| TeachError::BadSetting {
            setting,
            value,
            what: what.to_string(),
        };
        let spacing_m = settings.spacing_m;
        if !(spacing_m > 0.0 && spacing_m <= MAX_STEP_M) {
            let what = format!("must be more than 0 and at most {MAX_STEP_M} m");
            return Err(bad("spacing_m", spacing_m.to_string(), &what));
        }
        if !(settings.max_gap_m > 0.0 && settings.max_gap_m.is_finite()) {
            let value = settings.max_gap_m.to_string();
            return Err(bad("max_gap_m", value, "must be a number more than 0"));
        }
        if !(settings.min_length_m >= 0.0 && settings.min_length_m.is_finite()) {
            let value = settings.min_length_m.to_string();
            return Err(bad("min_length_m", value, "must be a number, 0 or more"));
        }
        let codes = format!("{:?}", settings.trusted_fix);
        if settings.trusted_fix.is_empty() {
            return Err(bad(
                "trusted_fix",
                codes,
                "must name at least one fix quality",
            ));
        }
        if settings.trusted_fix.iter().any(|&code| code > 8) {
            return Err(bad("trusted_fix", codes, "GGA fix qualities are 0 to 8"));
        }
        Ok(Teacher {
            settings,
            start_m: None,
            furthest_m: 0.0,
            last_trusted: None,
            points_deg: Vec::new(),
            points_at_m: Vec::new(),
            next_due_m: 0.0,
            fault: None,
        })
    }

    /// Takes one position. An error means the row is refused; it is returned again for
    /// every later sample and by `finish`, so the operator can be told at once.
    pub fn feed(&mut self, sample: TeachSample) -> Result<(), TeachError> {
        if let Some(fault) = &self.fault {
            return Err(fault.clone());
        }
        match self.take(sample) {
            Ok(()) => Ok(()),
            Err(fault) => {
                self.fault = Some(fault.clone());
                Err(fault)
            }
        }
    }

    fn take(&mut self, sample: TeachSample) -> Result<(), TeachError> {
        if !sample.distance_m.is_finite() {
            return Err(TeachError::BadDistance {
                after_m: self.furthest_m,
            });
        }
        let start_m = *self.start_m.get_or_insert(sample.distance_m);
        let at_m = sample.distance_m - start_m;
        if at_m < self.furthest_m - REVERSE_TOLERANCE_M {
            return Err(TeachError::Reversed {
                from_m: self.furthest_m,
                to_m: at_m,
            });
        }
        self.furthest_m = self.furthest_m.max(at_m);
        let on_earth = latitude_problem(sample.lat_deg, "").is_none()
            && longitude_problem(sample.lon_deg, "").is_none();
        if !(on_earth && self.settings.trusted_fix.contains(&sample.fix_quality)) {
            // Judged when a trusted fix comes back, or at `finish`.
            return Ok(());
        }
        self.check_gap(at_m)?;
        let position_deg = (sample.lat_deg, sample.lon_deg);
        self.last_trusted = Some((position_deg, at_m));
        if at_m >= self.next_due_m - SPACING_SLACK_M {
            self.points_deg.push(position_deg);
            self.points_at_m.push(at_m);
            let spacing_m = self.settings.spacing_m;
            self.next_due_m = (((at_m + SPACING_SLACK_M) / spacing_m).floor() + 1.0) * spacing_m;
        }
        Ok(())
    }

    /// Refuses the row if the stretch since the last trusted fix (or the start) up to
    /// `at_m` is longer than allowed.
    fn check_gap(&self, at_m: f64) -> Result<(), TeachError> {
        let from_m = self.last_trusted.map_or(0.0, |(_, at_m)| at_m);
        if at_m - from_m > self.settings.max_gap_m {
            return Err(TeachError::NoTrustedFix {
                trusted: trusted_names(&self.settings.trusted_fix),
                from_m,
                to_m: at_m,
            });
        }
        Ok(())
    }

    /// Points kept so far.
    pub fn point_count(&self) -> usize {
        self.points_deg.len()
    }

    /// Distance driven since the last trusted fix (or the start), m: for a live warning
    /// before the stretch refuses the row.
    pub fn untrusted_m(&self) -> f64 {
        self.furthest_m - self.last_trusted.map_or(0.0, |(_, at_m)| at_m)
    }

    /// The taught row, called `name`, or why it is refused.
    pub fn finish(mut self, name: &str) -> Result<MapRow, TeachError> {
        if let Some(fault) = self.fault {
            return Err(fault);
        }
        if let Some(what) = name_problem(name) {
            return Err(TeachError::BadName { what });
        }
        if self.start_m.is_some() {
            self.check_gap(self.furthest_m)?;
        }
        // The row ends where the last trusted fix was, not up to a spacing before it.
        if let (Some((position_deg, at_m)), Some(&last_m)) =
            (self.last_trusted, self.points_at_m.last())
            && at_m - last_m >= self.settings.spacing_m / 2.0
        {
            self.points_deg.push(position_deg);
            self.points_at_m.push(at_m);
        }
        if self.points_deg.len() < 2 {
            return Err(TeachError::TooFewPoints {
                count: self.points_deg.len(),
            });
        }
        let at = |point: usize| self.points_at_m.get(point).copied().unwrap_or(0.0);
        if let Some(problem) = row_problems(&self.points_deg).first() {
            let what = problem.describe(name, &|point| format!("at {:.2} m", at(point)));
            return Err(TeachError::Geometry {
                at_m: at(problem.point()),
                what,
            });
        }
        let length_m = polyline_length_m(&self.points_deg);
        if length_m < self.settings.min_length_m {
            return Err(TeachError::TooShort {
                length_m,
                min_m: self.settings.min_length_m,
            });
        }
        Ok(MapRow {
            name: name.to_string(),
            points_deg: self.points_deg,
        })
    }
}

/// The fix qualities, as an operator knows them: "RTK fixed or RTK float".
fn trusted_names(codes: &BTreeSet<u8>) -> String {
    let names: Vec<String> = codes
        .iter()
        .map(|&code| match code {
            0 => "invalid".to_string(),
            1 => "GPS".to_string(),
            2 => "DGPS".to_string(),
            3 => "PPS".to_string(),
            RTK_FIXED => "RTK fixed".to_string(),
            RTK_FLOAT => "RTK float".to_string(),
            6 => "dead reckoning".to_string(),
            7 => "manual input".to_string(),
            8 => "simulated".to_string(),
            other => format!("quality {other}"),
        })
        .collect();
    names.join(" or ")
}

/// Length of the line through the points on the ground, m.
fn polyline_length_m(points_deg: &[(f64, f64)]) -> f64 {
    let at = |&(lat_deg, lon_deg): &(f64, f64)| Geodetic {
        lat_deg,
        lon_deg,
        height_m: 0.0,
    };
    let Some(first) = points_deg.first() else {
        return 0.0;
    };
    let frame = LocalFrame::new(at(first));
    let points_m: Vec<(f64, f64)> = points_deg
        .iter()
        .map(|p| {
            let enu = frame.to_enu(at(p));
            (enu.east_m, enu.north_m)
        })
        .collect();
    points_m
        .windows(2)
        .map(|pair| match pair {
            [a, b] => (b.0 - a.0).hypot(b.1 - a.1),
            _ => 0.0,
        })
        .sum()
}

#[cfg(test)]
#[path = "teach_tests.rs"]
mod tests;
