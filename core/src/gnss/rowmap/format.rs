//! The row map file: its layout, the errors found in one, and the rules every row must
//! meet. The rules live here, shared by the reader, the writer and teaching, so that
//! whatever is written or taught reads back.
//!
//! A row map is CSV as a spreadsheet writes and reads it:
//!
//! ```text
//! # mechweed row map - one line per point: the row's name then its WGS-84 ...
//! # taught on 2026-11-25 by mechweed teach
//! row,lat_deg,lon_deg
//! 1,48.137154000,11.575490000
//! 1,48.137154000,11.575830000
//! north-3,48.137160750,11.575490000
//! north-3,48.137160750,11.575830000
//! ```
//!
//! - Lines whose first non-blank character is `#` are comments; blank lines are ignored.
//! - The first other line is the header: `row,lat_deg,lon_deg`, or with a fourth column
//!   `row,lat_deg,lon_deg,note` whose text is read over (a place for the user's remarks).
//! - Then one point per line: the row's name, WGS-84 latitude and longitude in degrees
//!   with `.` as the decimal point. Fields may be quoted (`"1"`) as spreadsheets write
//!   them; a UTF-8 byte order mark and CRLF or CR line ends are accepted.
//! - A row's points are on consecutive lines, in driving order.
//! - A row name is text without commas, double quotes or control characters that does
//!   not start with `#` (the line would be a comment).

use std::fmt;

use mechweed_hw::geo::{Enu, Geodetic, LocalFrame};

/// The header line of a row map without the optional note column.
pub(crate) const HEADER: &str = "row,lat_deg,lon_deg";
/// The header line of a row map with the note column.
pub(crate) const HEADER_WITH_NOTE: &str = "row,lat_deg,lon_deg,note";
/// Consecutive points closer than this are a repeated line, m.
pub(crate) const MIN_STEP_M: f64 = 0.001;
/// Consecutive points farther apart than this are a typo in a digit, m: rows are taught
/// at a point every 0.25 m and planting records log one every few metres.
pub(crate) const MAX_STEP_M: f64 = 100.0;
/// A row turning more than this at one point has a point out of order, degrees.
pub(crate) const MAX_TURN_DEG: f64 = 90.0;
/// Decimals of a degree written: 1e-9 degree is about 0.1 mm on the ground.
pub(crate) const DECIMALS: usize = 9;
/// More errors than this in one file are counted, not listed: the first ones show what
/// is wrong, and a wholly wrong file should not flood the screen.
pub(crate) const MAX_ERRORS_SHOWN: usize = 20;
/// Text quoted from the file is cut to this many characters in messages.
const SHOWN_CHARS: usize = 40;

/// Where in a row map a problem is.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A line of the file, counted from 1.
    Line { file: String, line: usize },
    /// A point of a row about to be written, counted from 1.
    Point {
        file: String,
        row: String,
        point: usize,
    },
    /// The file as a whole.
    File(String),
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::Line { file, line } => write!(f, "{file} line {line}"),
            Place::Point { file, row, point } => write!(f, "{file} row '{row}' point {point}"),
            Place::File(file) => f.write_str(file),
        }
    }
}

/// One thing wrong with a row map, said so that a person can fix it.
#[derive(Debug, Clone, PartialEq)]
pub struct MapFileError {
    pub place: Place,
    pub what: String,
}

impl fmt::Display for MapFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.place, self.what)
    }
}

/// Everything wrong with one row map: the first `MAX_ERRORS_SHOWN`, and how many more.
#[derive(Debug, Clone, PartialEq)]
pub struct MapFileErrors {
    pub errors: Vec<MapFileError>,
    /// Errors found beyond those listed.
    pub more: usize,
}

impl MapFileErrors {
    /// Keeps the first `MAX_ERRORS_SHOWN` of `all` (in the order given).
    pub fn new(mut all: Vec<MapFileError>) -> MapFileErrors {
        let more = all.len().saturating_sub(MAX_ERRORS_SHOWN);
        all.truncate(MAX_ERRORS_SHOWN);
        MapFileErrors { errors: all, more }
    }
}

impl fmt::Display for MapFileErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for error in &self.errors {
            if !first {
                f.write_str("\n")?;
            }
            first = false;
            write!(f, "{error}")?;
        }
        if self.more > 0 {
            let plural = if self.more == 1 { "" } else { "s" };
            write!(f, "\nand {} more error{plural}", self.more)?;
        }
        Ok(())
    }
}

impl std::error::Error for MapFileErrors {}

/// Text from the file as it may appear in a message: cut short, control characters
/// replaced, so that one wild line cannot garble the screen.
pub(crate) fn shown(text: &str) -> String {
    let mut out: String = text
        .chars()
        .take(SHOWN_CHARS)
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    if text.chars().nth(SHOWN_CHARS).is_some() {
        out.push_str("...");
    }
    out
}

/// Why `name` cannot name a row, if it cannot.
pub(crate) fn name_problem(name: &str) -> Option<String> {
    let quoted = shown(name);
    if name.is_empty() {
        Some("the row name is empty".to_string())
    } else if name.trim() != name {
        Some(format!("row name '{quoted}' starts or ends with a space"))
    } else if name.contains(',') {
        Some(format!("row name '{quoted}' contains a comma"))
    } else if name.contains('"') {
        Some(format!("row name '{quoted}' contains a double quote"))
    } else if name.starts_with('#') {
        Some(format!(
            "row name '{quoted}' starts with '#', which would make its lines comments"
        ))
    } else if name.chars().any(char::is_control) {
        Some(format!("row name '{quoted}' contains a control character"))
    } else {
        None
    }
}

/// The lines of a text, split at CRLF, LF or a lone CR (old Mac spreadsheets), so that
/// line numbers match what an editor shows.
pub(crate) fn physical_lines(text: &str) -> Vec<&str> {
    let mut lines = Vec::new();
    let mut rest = text;
    while let Some(end) = rest.find(['\r', '\n']) {
        let (line, tail) = rest.split_at(end);
        lines.push(line);
        rest = tail
            .strip_prefix("\r\n")
            .or_else(|| tail.strip_prefix('\r'))
            .or_else(|| tail.strip_prefix('\n'))
            .unwrap_or("");
    }
    if !rest.is_empty() {
        lines.push(rest);
    }
    lines
}

fn is_blank(c: char) -> bool {
    c == ' ' || c == '\t'
}

/// The fields of one CSV line. Blanks around a field are dropped; a field in double
/// quotes may hold commas, and `""` inside it is one quote. Quoted fields cannot span
/// lines: no row map needs that, and a stray quote is then caught on its own line.
pub(crate) fn split_fields(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.next_if(|&c| is_blank(c)).is_some() {}
        let number = fields.len() + 1;
        let mut field = String::new();
        if chars.next_if_eq(&'"').is_some() {
            loop {
                match chars.next() {
                    None => {
                        return Err(format!("the quote that opens field {number} is not closed"));
                    }
                    Some('"') if chars.next_if_eq(&'"').is_some() => field.push('"'),
                    Some('"') => break,
                    Some(c) => field.push(c),
                }
            }
            while chars.next_if(|&c| is_blank(c)).is_some() {}
            match chars.next() {
                None => {
                    fields.push(field);
                    return Ok(fields);
                }
                Some(',') => fields.push(field),
                Some(c) => {
                    return Err(format!(
                        "field {number} has '{}' after its closing quote",
                        shown(&c.to_string())
                    ));
                }
            }
        } else {
            loop {
                match chars.next() {
                    None => {
                        fields.push(field.trim_end_matches(is_blank).to_string());
                        return Ok(fields);
                    }
                    Some(',') => break,
                    Some(c) => field.push(c),
                }
            }
            fields.push(field.trim_end_matches(is_blank).to_string());
        }
    }
}

/// Why a latitude cannot be used, if it cannot. `text` is how it was written.
pub(crate) fn latitude_problem(lat_deg: f64, text: &str) -> Option<String> {
    coordinate_problem("latitude", lat_deg, text, 90.0)
}

/// Why a longitude cannot be used, if it cannot. `text` is how it was written.
pub(crate) fn longitude_problem(lon_deg: f64, text: &str) -> Option<String> {
    coordinate_problem("longitude", lon_deg, text, 180.0)
}

fn coordinate_problem(what: &str, value_deg: f64, text: &str, limit_deg: f64) -> Option<String> {
    if !value_deg.is_finite() {
        Some(format!("{what} '{}' is not a finite number", shown(text)))
    } else if value_deg.abs() > limit_deg {
        Some(format!(
            "{what} {} is outside -{limit_deg}..{limit_deg}",
            shown(text)
        ))
    } else {
        None
    }
}

/// Something wrong with the points of one row. Points are counted from 0 in the row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RowProblem {
    TooFewPoints { count: usize },
    BadPoint { point: usize, what: String },
    TooClose { point: usize, distance_m: f64 },
    TooFar { point: usize, distance_m: f64 },
    Turn { point: usize, turn_deg: f64 },
}

impl RowProblem {
    /// The point the problem is at (the row's first for a row too short).
    pub(crate) fn point(&self) -> usize {
        match self {
            RowProblem::TooFewPoints { .. } => 0,
            RowProblem::BadPoint { point, .. }
            | RowProblem::TooClose { point, .. }
            | RowProblem::TooFar { point, .. }
            | RowProblem::Turn { point, .. } => *point,
        }
    }

    /// The message; `at` names a point of the row the way the caller's user knows it
    /// ("line 14", "point 3", "at 12.30 m").
    pub(crate) fn describe(&self, row: &str, at: &dyn Fn(usize) -> String) -> String {
        let row = shown(row);
        match self {
            RowProblem::TooFewPoints { count } => {
                let plural = if *count == 1 { "" } else { "s" };
                format!("row '{row}' has only {count} point{plural}: a row needs at least 2")
            }
            RowProblem::BadPoint { what, .. } => format!("row '{row}': {what}"),
            RowProblem::TooClose { point, distance_m } => format!(
                "this point of row '{row}' is {:.2} mm from the point before it ({}): \
                 a repeated line?",
                distance_m * 1000.0,
                at(point.saturating_sub(1))
            ),
            RowProblem::TooFar { point, distance_m } => format!(
                "this point of row '{row}' is {distance_m:.1} m from the point before it \
                 ({}), more than {MAX_STEP_M} m: a typo in a digit?",
                at(point.saturating_sub(1))
            ),
            RowProblem::Turn { point, turn_deg } => format!(
                "row '{row}' turns by {turn_deg:.0} degrees at this point (between {} and \
                 {}), more than {MAX_TURN_DEG}: a point out of order?",
                at(point.saturating_sub(1)),
                at(point + 1)
            ),
        }
    }
}

/// Everything wrong with a row's points (latitude, longitude in degrees, in driving
/// order).
pub(crate) fn row_problems(points_deg: &[(f64, f64)]) -> Vec<RowProblem> {
    let mut problems = Vec::new();
    for (point, &(lat_deg, lon_deg)) in points_deg.iter().enumerate() {
        let text_lat = lat_deg.to_string();
        let text_lon = lon_deg.to_string();
        if let Some(what) =
            latitude_problem(lat_deg, &text_lat).or_else(|| longitude_problem(lon_deg, &text_lon))
        {
            problems.push(RowProblem::BadPoint { point, what });
        }
    }
    if !problems.is_empty() {
        // Distances between points that are not on the earth mean nothing.
        return problems;
    }
    if points_deg.len() < 2 {
        return vec![RowProblem::TooFewPoints {
            count: points_deg.len(),
        }];
    }
    let points_m = to_local_at_first(points_deg);
    let steps_m: Vec<(f64, f64)> = points_m
        .windows(2)
        .map(|pair| match pair {
            [a, b] => (b.east_m - a.east_m, b.north_m - a.north_m),
            _ => (0.0, 0.0),
        })
        .collect();
    for (i, step) in steps_m.iter().enumerate() {
        let distance_m = step.0.hypot(step.1);
        if distance_m < MIN_STEP_M {
            problems.push(RowProblem::TooClose {
                point: i + 1,
                distance_m,
            });
        } else if distance_m > MAX_STEP_M {
            problems.push(RowProblem::TooFar {
                point: i + 1,
                distance_m,
            });
        }
        if let Some(before) = i.checked_sub(1).and_then(|j| steps_m.get(j)) {
            let usable = |s: &(f64, f64)| s.0.hypot(s.1) >= MIN_STEP_M;
            // A turn next to a repeated point has no direction; that point is reported.
            if usable(before) && usable(step) {
                let cross = before.0 * step.1 - before.1 * step.0;
                let dot = before.0 * step.0 + before.1 * step.1;
                let turn_deg = cross.atan2(dot).abs().to_degrees();
                if turn_deg > MAX_TURN_DEG {
                    problems.push(RowProblem::Turn { point: i, turn_deg });
                }
            }
        }
    }
    problems
}

/// The points in metres east and north of the first, for distances and angles.
fn to_local_at_first(points_deg: &[(f64, f64)]) -> Vec<Enu> {
    let Some(&(lat_deg, lon_deg)) = points_deg.first() else {
        return Vec::new();
    };
    let at = |lat_deg: f64, lon_deg: f64| Geodetic {
        lat_deg,
        lon_deg,
        height_m: 0.0,
    };
    let frame = LocalFrame::new(at(lat_deg, lon_deg));
    points_deg
        .iter()
        .map(|&(lat_deg, lon_deg)| frame.to_enu(at(lat_deg, lon_deg)))
        .collect()
}
