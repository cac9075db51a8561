//! Reads a row map file (laid out as `format` describes) into a `RowMap`, collecting
//! every error of the file with its line, so that one pass over the spreadsheet fixes
//! them all.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use crate::gnss::rowmap::format::{
    HEADER, HEADER_WITH_NOTE, MapFileError, MapFileErrors, Place, latitude_problem,
    longitude_problem, name_problem, physical_lines, row_problems, shown, split_fields,
};
use crate::gnss::rowmap::map::{MapRow, RowMap};

/// Why a row map could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("{file}: cannot read the row map: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Invalid(MapFileErrors),
}

/// Reads the row map at `path`; errors name the path as given.
pub fn read_map(path: &Path) -> Result<RowMap, ReadError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
        file: file.clone(),
        source,
    })?;
    parse_map_bytes(&file, &bytes).map_err(ReadError::Invalid)
}

/// Reads a row map from the bytes of a file named `file` in messages.
pub fn parse_map_bytes(file: &str, bytes: &[u8]) -> Result<RowMap, MapFileErrors> {
    match std::str::from_utf8(bytes) {
        Ok(text) => parse_map(file, text),
        Err(error) => {
            let valid = bytes.get(..error.valid_up_to()).unwrap_or_default();
            let line = line_breaks(valid) + 1;
            Err(MapFileErrors::new(vec![MapFileError {
                place: Place::Line {
                    file: file.to_string(),
                    line,
                },
                what: "this line is not UTF-8 text: save the file as 'CSV UTF-8'".to_string(),
            }]))
        }
    }
}

/// Line breaks the way `physical_lines` counts them: CRLF, LF or a lone CR.
fn line_breaks(bytes: &[u8]) -> usize {
    let mut breaks = 0;
    let mut after_cr = false;
    for &byte in bytes {
        if byte == b'\r' || (byte == b'\n' && !after_cr) {
            breaks += 1;
        }
        after_cr = byte == b'\r';
    }
    breaks
}

/// Reads a row map from the text of a file named `file` in messages.
pub fn parse_map(file: &str, text: &str) -> Result<RowMap, MapFileErrors> {
    // Spreadsheets on Windows start UTF-8 CSV with a byte order mark.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut parse = Parse {
        file,
        errors: Vec::new(),
        header: None,
        rows: Vec::new(),
        row_of_name: HashMap::new(),
        refused_name: None,
        incomplete: HashSet::new(),
        data_lines: 0,
    };
    for (index, line) in physical_lines(text).into_iter().enumerate() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        match parse.header {
            None => parse.header_line(index + 1, line),
            Some(with_note) => parse.data_line(index + 1, line, with_note),
        }
    }
    parse.finish()
}

/// A row as it is read: its points and the line each came from.
struct RowLines {
    name: String,
    points_deg: Vec<(f64, f64)>,
    lines: Vec<usize>,
}

struct Parse<'a> {
    file: &'a str,
    errors: Vec<MapFileError>,
    /// Once the header is read: whether it has the note column.
    header: Option<bool>,
    rows: Vec<RowLines>,
    row_of_name: HashMap<String, usize>,
    /// The row whose lines after another row were just refused: one error for the
    /// whole stretch, not one per line.
    refused_name: Option<String>,
    /// Rows with a refused line: their points are not all there, so the checks of a
    /// whole row (enough points, distances, turns) would report what is not so.
    incomplete: HashSet<String>,
    data_lines: usize,
}

impl Parse<'_> {
    fn error(&mut self, line: usize, what: String) {
        self.errors.push(MapFileError {
            place: Place::Line {
                file: self.file.to_string(),
                line,
            },
            what,
        });
    }

    fn header_line(&mut self, line: usize, text: &str) {
        let fields = match split_fields(text) {
            Ok(fields) => without_trailing_empty(fields),
            Err(_) => Vec::new(),
        };
        let names: Vec<String> = fields.iter().map(|f| f.to_ascii_lowercase()).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        match names.as_slice() {
            ["row", "lat_deg", "lon_deg"] => self.header = Some(false),
            ["row", "lat_deg", "lon_deg", "note"] => self.header = Some(true),
            _ => {
                let mut what = format!(
                    "the header must be '{HEADER}' (or '{HEADER_WITH_NOTE}'), found '{}'",
                    shown(text)
                );
                if text.contains(';') && !text.contains(',') {
                    what.push_str(
                        "; the fields are separated by ';': save with ',' between fields \
                         and '.' as the decimal point",
                    );
                }
                self.error(line, what);
                // Read on as if the header were right, to find the other errors too.
                let with_note = fields.len() == 4;
                self.header = Some(with_note);
                // A file without its header starts with a point: keep it, or its row
                // would be reported as one point short.
                if let LineRead::Point { name, point_deg } = read_point(text, with_note) {
                    self.data_lines += 1;
                    self.point(line, name, point_deg);
                }
            }
        }
    }

    fn data_line(&mut self, line: usize, text: &str, with_note: bool) {
        match read_point(text, with_note) {
            LineRead::Blank => {}
            LineRead::Point { name, point_deg } => {
                self.data_lines += 1;
                self.point(line, name, point_deg);
            }
            LineRead::Refused { name, problems } => {
                self.data_lines += 1;
                self.incomplete.extend(name);
                for what in problems {
                    self.error(line, what);
                }
            }
        }
    }

    fn point(&mut self, line: usize, name: String, point_deg: (f64, f64)) {
        if let Some(current) = self.rows.last_mut().filter(|row| row.name == name) {
            current.points_deg.push(point_deg);
            current.lines.push(line);
            self.refused_name = None;
            return;
        }
        let Some(&earlier) = self.row_of_name.get(&name) else {
            self.row_of_name.insert(name.clone(), self.rows.len());
            self.rows.push(RowLines {
                name,
                points_deg: vec![point_deg],
                lines: vec![line],
            });
            self.refused_name = None;
            return;
        };
        if self.refused_name.as_ref() == Some(&name) {
            return;
        }
        let (first, last) = self.rows.get(earlier).map_or((0, 0), |row| {
            (
                row.lines.first().copied().unwrap_or(0),
                row.lines.last().copied().unwrap_or(0),
            )
        });
        let between = self.rows.last().map_or("", |row| row.name.as_str());
        let lines = if first == last {
            format!("line {first}")
        } else {
            format!("lines {first} to {last}")
        };
        let what = format!(
            "row '{}' comes back after row '{}': a row's points must be on consecutive \
             lines (row '{}' is on {lines})",
            shown(&name),
            shown(between),
            shown(&name)
        );
        self.error(line, what);
        self.incomplete.insert(name.clone());
        self.refused_name = Some(name);
    }

    fn finish(mut self) -> Result<RowMap, MapFileErrors> {
        if self.header.is_none() {
            self.errors.push(MapFileError {
                place: Place::File(self.file.to_string()),
                what: format!("is empty: a row map starts with the header line '{HEADER}'"),
            });
        } else if self.data_lines == 0 {
            self.errors.push(MapFileError {
                place: Place::File(self.file.to_string()),
                what: format!("has no rows: after the header, one line per point ('{HEADER}')"),
            });
        }
        let rows = std::mem::take(&mut self.rows);
        let incomplete = std::mem::take(&mut self.incomplete);
        for row in rows.iter().filter(|row| !incomplete.contains(&row.name)) {
            for problem in row_problems(&row.points_deg) {
                let at = |point: usize| match row.lines.get(point) {
                    Some(line) => format!("line {line}"),
                    None => "the row's end".to_string(),
                };
                let line = row.lines.get(problem.point()).copied().unwrap_or(0);
                let what = problem.describe(&row.name, &at);
                self.error(line, what);
            }
        }
        if !self.errors.is_empty() {
            self.errors.sort_by_key(|error| match error.place {
                Place::Line { line, .. } => line,
                Place::Point { point, .. } => point,
                Place::File(_) => 0,
            });
            return Err(MapFileErrors::new(self.errors));
        }
        Ok(RowMap {
            rows: rows
                .into_iter()
                .map(|row| MapRow {
                    name: row.name,
                    points_deg: row.points_deg,
                })
                .collect(),
        })
    }
}

/// What one line that is not a comment says.
enum LineRead {
    /// A spreadsheet writes an empty row of cells as a line of commas.
    Blank,
    Point {
        name: String,
        point_deg: (f64, f64),
    },
    /// With the row's name when the line has one, and everything wrong with the line.
    Refused {
        name: Option<String>,
        problems: Vec<String>,
    },
}

fn read_point(text: &str, with_note: bool) -> LineRead {
    let fields = match split_fields(text) {
        Ok(fields) => without_trailing_empty(fields),
        Err(what) => {
            return LineRead::Refused {
                name: None,
                problems: vec![what],
            };
        }
    };
    // Trailing empty cells are dropped, so an empty note leaves 3 fields.
    let (name, lat_text, lon_text) = match fields.as_slice() {
        [] => return LineRead::Blank,
        [name, lat, lon] => (name, lat, lon),
        [name, lat, lon, _note] if with_note => (name, lat, lon),
        _ => {
            let (expected, header) = if with_note {
                (4, HEADER_WITH_NOTE)
            } else {
                (3, HEADER)
            };
            let mut what = format!(
                "expected {expected} fields ({header}), found {}",
                fields.len()
            );
            if fields.len() > expected {
                what.push_str(": numbers must use '.', not ',', as the decimal point");
            }
            return LineRead::Refused {
                name: fields.first().cloned(),
                problems: vec![what],
            };
        }
    };
    let mut problems = Vec::new();
    problems.extend(name_problem(name));
    let lat_deg = number(&mut problems, "latitude", lat_text);
    let lon_deg = number(&mut problems, "longitude", lon_text);
    if let Some(lat_deg) = lat_deg {
        problems.extend(latitude_problem(lat_deg, lat_text));
    }
    if let Some(lon_deg) = lon_deg {
        problems.extend(longitude_problem(lon_deg, lon_text));
    }
    match (lat_deg, lon_deg) {
        (Some(lat_deg), Some(lon_deg)) if problems.is_empty() => LineRead::Point {
            name: name.clone(),
            point_deg: (lat_deg, lon_deg),
        },
        _ => LineRead::Refused {
            name: Some(name.clone()),
            problems,
        },
    }
}

/// Spreadsheets pad every line with empty cells to the widest line of the sheet.
fn without_trailing_empty(mut fields: Vec<String>) -> Vec<String> {
    while fields.last().is_some_and(String::is_empty) {
        fields.pop();
    }
    fields
}

/// `text` as a number, or a problem saying why not.
fn number(problems: &mut Vec<String>, what: &str, text: &str) -> Option<f64> {
    if text.is_empty() {
        problems.push(format!("{what} is missing"));
        return None;
    }
    match text.parse::<f64>() {
        Ok(value) => Some(value),
        Err(_) => {
            problems.push(format!("{what} '{}' is not a number", shown(text)));
            None
        }
    }
}

#[cfg(test)]
#[path = "read_tests.rs"]
mod tests;
