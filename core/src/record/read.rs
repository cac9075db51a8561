//! Reading a record back, from either format, as a table of cells by column name: for
//! `mechweed record summary` and for the tests that compare the two formats. Every
//! error names the file and, where it can, the line or message.
//!
//! The format is told by the file's first bytes (MCAP's magic), not by its name. A
//! record whose run ended abruptly (no MCAP footer, half a CSV line) is read up to
//! where it ends, with a note saying so.

use std::path::{Path, PathBuf};

use super::error::{Place, ReadProblem, RecordError};
use super::event::EVENT_COLUMNS;
use super::files::with_suffix;
use super::mcap::{EVENT_TOPIC, TICK_TOPIC};

#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    Num(f64),
    Text(String),
    /// An empty CSV cell or a JSON null: a number that was not there (NaN).
    Empty,
}

/// The columns asked for, one row per tick (or event).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<Cell>>,
    /// Where each row came from, for messages: line 12, message 12.
    pub places: Vec<Place>,
    /// Columns of ADDED_LATER asked for that this record lacks (read as empty).
    pub absent: Vec<String>,
}

/// Columns added to the records after replays existed: a record made before one was
/// added lacks it, and reads as empty there (the reader says which in `Table::absent`)
/// rather than being refused.
pub const ADDED_LATER: &[&str] = &["gnss_heard_s", "link_streaming_since_s", "link_heard_s"];

/// A record read back.
#[derive(Debug, Clone)]
pub struct Record {
    pub file: PathBuf,
    pub ticks: Table,
    /// None: a CSV record without its events file beside it.
    pub events: Option<Table>,
    /// What a reader should know: a file that ends abruptly, a missing events file.
    pub notes: Vec<String>,
}

impl Table {
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The number in `row`, `col`: None for an empty cell, an error for text.
    pub fn number(&self, row: usize, col: usize) -> Result<Option<f64>, ReadProblem> {
        match &self.rows[row][col] {
            Cell::Num(x) if x.is_nan() => Ok(None),
            Cell::Num(x) => Ok(Some(*x)),
            Cell::Empty => Ok(None),
            Cell::Text(t) => Err(ReadProblem::NotANumber {
                place: self.places[row].clone(),
                column: self.columns[col].clone(),
                text: t.clone(),
            }),
        }
    }

    /// The text in `row`, `col` (numbers as written).
    pub fn text(&self, row: usize, col: usize) -> String {
        match &self.rows[row][col] {
            Cell::Num(x) => x.to_string(),
            Cell::Text(t) => t.clone(),
            Cell::Empty => String::new(),
        }
    }
}

/// MCAP files start with these bytes.
const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Read the columns `wanted` of every tick, and the events, from a record.
pub fn read(path: &Path, wanted: &[&str]) -> Result<Record, RecordError> {
    let error = |problem: ReadProblem| RecordError::Read {
        file: path.to_path_buf(),
        problem,
    };
    let bytes = std::fs::read(path).map_err(|e| error(ReadProblem::CannotRead(e.kind())))?;
    if bytes.is_empty() {
        return Err(error(ReadProblem::Empty));
    }
    if bytes.starts_with(MCAP_MAGIC) {
        return read_mcap(path, &bytes, wanted).map_err(error);
    }
    let text = String::from_utf8(bytes).map_err(|_| error(ReadProblem::NeitherCsvNorMcap))?;
    let name = path.to_string_lossy();
    if name.ends_with(".events.csv") {
        return Err(error(ReadProblem::EventsFile));
    }
    let mut notes = Vec::new();
    let ticks = parse_csv(&text, wanted, &mut notes).map_err(error)?;
    let events_path = with_suffix(&path.with_extension(""), ".events.csv");
    let events = match std::fs::read_to_string(&events_path) {
        Ok(text) => Some(
            parse_csv(&text, &EVENT_COLUMNS, &mut notes).map_err(|problem| RecordError::Read {
                file: events_path.clone(),
                problem,
            })?,
        ),
        Err(e) => {
            notes.push(format!(
                "no events (faults, modes, notices): cannot read {} ({e})",
                events_path.display()
            ));
            None
        }
    };
    Ok(Record {
        file: path.to_path_buf(),
        ticks,
        events,
        notes,
    })
}

/// Split one CSV line into fields; double quotes may hold commas ("" is a quote).
/// None: a quoted field is not closed.
fn fields(line: &str) -> Option<Vec<String>> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(ch) = chars.next() {
        let field = out.last_mut().expect("never empty");
        match (ch, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            (ch, _) => field.push(ch),
        }
    }
    (!quoted).then_some(out)
}

fn parse_csv(text: &str, wanted: &[&str], notes: &mut Vec<String>) -> Result<Table, ReadProblem> {
    let mut lines = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l));
    let header =
        fields(lines.next().unwrap_or_default()).ok_or(ReadProblem::UnclosedQuote { line: 1 })?;
    let mut picks = Vec::new();
    let mut absent = Vec::new();
    for name in wanted {
        match header.iter().position(|h| h.trim() == *name) {
            Some(i) => picks.push(Some(i)),
            None if ADDED_LATER.contains(name) => {
                picks.push(None);
                absent.push(name.to_string());
            }
            None => {
                return Err(ReadProblem::MissingColumn {
                    name: name.to_string(),
                });
            }
        }
    }
    let mut table = Table {
        columns: wanted.iter().map(|s| s.to_string()).collect(),
        absent,
        ..Table::default()
    };
    let ends_whole = text.ends_with('\n');
    let all: Vec<&str> = lines.collect();
    for (i, line) in all.iter().enumerate() {
        let number = i + 2;
        let last = i + 1 == all.len();
        if line.is_empty() && last {
            break;
        }
        // A last line without its newline was cut while written, even where it has every
        // column: its last value may be cut short ("0.125" read as "0.1").
        let cut_short = last && !ends_whole;
        let cells = match fields(line) {
            Some(cells) if cells.len() == header.len() && !cut_short => cells,
            _ if cut_short => {
                notes.push(format!(
                    "line {number} is incomplete (the run ended abruptly?): left out"
                ));
                break;
            }
            Some(cells) => {
                return Err(ReadProblem::FieldCount {
                    line: number,
                    fields: cells.len(),
                    header: header.len(),
                });
            }
            None => return Err(ReadProblem::UnclosedQuote { line: number }),
        };
        table.rows.push(
            picks
                .iter()
                .map(|&k| k.map_or(Cell::Empty, |k| cell(&cells[k])))
                .collect(),
        );
        table.places.push(Place::Line(number));
    }
    Ok(table)
}

fn cell(text: &str) -> Cell {
    let text = text.trim();
    if text.is_empty() {
        Cell::Empty
    } else {
        text.parse()
            .map_or_else(|_| Cell::Text(text.to_string()), Cell::Num)
    }
}

fn read_mcap(path: &Path, bytes: &[u8], wanted: &[&str]) -> Result<Record, ReadProblem> {
    let not_mcap = |e: ::mcap::McapError| ReadProblem::NotMcap {
        reason: e.to_string(),
    };
    let stream = ::mcap::MessageStream::new(bytes).map_err(not_mcap)?;
    let mut ticks = Table {
        columns: wanted.iter().map(|s| s.to_string()).collect(),
        ..Table::default()
    };
    let mut events = Table {
        columns: EVENT_COLUMNS.iter().map(|s| s.to_string()).collect(),
        ..Table::default()
    };
    let mut notes = Vec::new();
    for (i, message) in stream.enumerate() {
        let message = match message {
            Ok(m) => m,
            Err(e) if ticks.rows.is_empty() && events.rows.is_empty() => {
                return Err(not_mcap(e));
            }
            Err(e) => {
                notes.push(format!(
                    "the file ends abruptly after {} ticks ({e}): the run did not finish?",
                    ticks.rows.len()
                ));
                break;
            }
        };
        let (table, names): (&mut Table, &[&str]) = match message.channel.topic.as_str() {
            TICK_TOPIC => (&mut ticks, wanted),
            EVENT_TOPIC => (&mut events, &EVENT_COLUMNS),
            _ => continue,
        };
        let place = Place::Message {
            number: i + 1,
            topic: message.channel.topic.clone(),
        };
        let object: serde_json::Map<String, serde_json::Value> =
            serde_json::from_slice(&message.data).map_err(|e| ReadProblem::NotJson {
                place: place.clone(),
                reason: e.to_string(),
            })?;
        let mut row = Vec::with_capacity(names.len());
        for name in names {
            row.push(match object.get(*name) {
                Some(serde_json::Value::Number(n)) => n.as_f64().map_or(Cell::Empty, Cell::Num),
                // An empty word (no end switch hit) reads as in the CSV: an empty cell.
                Some(serde_json::Value::String(s)) if s.is_empty() => Cell::Empty,
                Some(serde_json::Value::String(s)) => Cell::Text(s.clone()),
                Some(serde_json::Value::Bool(b)) => Cell::Num(f64::from(u8::from(*b))),
                Some(serde_json::Value::Null) => Cell::Empty,
                Some(other) => Cell::Text(other.to_string()),
                None if ADDED_LATER.contains(name) => {
                    if !table.absent.iter().any(|a| a == name) {
                        table.absent.push(name.to_string());
                    }
                    Cell::Empty
                }
                None => {
                    return Err(ReadProblem::MissingField {
                        place,
                        name: name.to_string(),
                    });
                }
            });
        }
        table.rows.push(row);
        table.places.push(place);
    }
    Ok(Record {
        file: path.to_path_buf(),
        ticks,
        events: Some(events),
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_quotes_and_commas() {
        assert_eq!(
            fields("1,a,\"b, \"\"c\"\"\"").unwrap(),
            ["1", "a", "b, \"c\""]
        );
        assert_eq!(fields("").unwrap(), [""]);
        assert_eq!(fields("1,\"open"), None);
    }

    #[test]
    fn csv_tables_and_their_mistakes() {
        let mut notes = Vec::new();
        let t = parse_csv(
            "t_s,mode,x\n0.1,halt,\n0.2,fault,3\n0.3,fa",
            &["x", "t_s"],
            &mut notes,
        )
        .unwrap();
        assert_eq!(t.rows.len(), 2, "the half-written last line is left out");
        assert_eq!(t.rows[0], [Cell::Empty, Cell::Num(0.1)]);
        assert_eq!(t.number(1, 0), Ok(Some(3.0)));
        assert_eq!(notes.len(), 1);
        // Cut inside its last value, a line has every column: still cut, left out.
        let t = parse_csv("t_s,x\n0.1,2\n0.2,0.12", &["x"], &mut notes).unwrap();
        assert_eq!(t.rows.len(), 1, "0.125 cut to 0.12 is not a value");
        assert_eq!(notes.len(), 2);
        let t = parse_csv("t_s,x\n0.1,abc\n", &["x"], &mut notes).unwrap();
        let e = t.number(0, 0).unwrap_err();
        assert_eq!(
            e,
            ReadProblem::NotANumber {
                place: Place::Line(2),
                column: "x".into(),
                text: "abc".into()
            }
        );
        assert_eq!(e.to_string(), "line 2: x = 'abc' is not a number");
        let e = parse_csv("t_s,x\n0.1\n0.2,1\n", &["x"], &mut notes).unwrap_err();
        assert_eq!(e.to_string(), "line 2 has 1 fields, the first line 2");
        let e = parse_csv("hello\n", &["t_s"], &mut notes).unwrap_err();
        assert!(e.to_string().contains("no column t_s"), "{e}");
        let e = parse_csv("t_s\n\"1\n2\n", &["t_s"], &mut notes).unwrap_err();
        assert_eq!(e, ReadProblem::UnclosedQuote { line: 2 });
    }
}
