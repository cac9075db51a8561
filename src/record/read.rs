//! Reading a record back, from either format, as a table of cells by column name: for
//! `mechweed record summary` and for the tests that compare the two formats. Every
//! error names the file and, where it can, the line or message.
//!
//! The format is told by the file's first bytes (MCAP's magic), not by its name. A
//! record whose run ended abruptly (no MCAP footer, half a CSV line) is read up to
//! where it ends, with a note saying so.

use std::fmt;
use std::path::{Path, PathBuf};

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
    /// Where each row came from, for messages: "line 12", "message 12".
    pub places: Vec<String>,
}

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

#[derive(Debug, Clone, PartialEq)]
pub struct ReadError {
    pub file: PathBuf,
    pub what: String,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file.display(), self.what)
    }
}

impl Table {
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The number in `row`, `col`: None for an empty cell, an error for text.
    pub fn number(&self, row: usize, col: usize) -> Result<Option<f64>, String> {
        match &self.rows[row][col] {
            Cell::Num(x) if x.is_nan() => Ok(None),
            Cell::Num(x) => Ok(Some(*x)),
            Cell::Empty => Ok(None),
            Cell::Text(t) => Err(format!(
                "{}: {} = '{t}' is not a number",
                self.places[row], self.columns[col]
            )),
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
pub fn read(path: &Path, wanted: &[&str]) -> Result<Record, ReadError> {
    let error = |what: String| ReadError {
        file: path.to_path_buf(),
        what,
    };
    let bytes = std::fs::read(path).map_err(|e| error(format!("cannot read it: {e}")))?;
    if bytes.is_empty() {
        return Err(error("the file is empty".to_string()));
    }
    if bytes.starts_with(MCAP_MAGIC) {
        return read_mcap(path, &bytes, wanted).map_err(error);
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| error("neither a CSV record (not text) nor an MCAP file".to_string()))?;
    let name = path.to_string_lossy();
    if name.ends_with(".events.csv") {
        return Err(error(
            "this is the events file of a record: give the tick file beside it (NAME.csv)"
                .to_string(),
        ));
    }
    let mut notes = Vec::new();
    let ticks = parse_csv(&text, wanted, &mut notes).map_err(error)?;
    let events_path = with_suffix(&path.with_extension(""), ".events.csv");
    let events = match std::fs::read_to_string(&events_path) {
        Ok(text) => Some(
            parse_csv(&text, &EVENT_COLUMNS, &mut notes).map_err(|what| ReadError {
                file: events_path.clone(),
                what,
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
fn fields(line: &str) -> Result<Vec<String>, String> {
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
    if quoted {
        return Err("a quoted field is not closed".to_string());
    }
    Ok(out)
}

fn parse_csv(text: &str, wanted: &[&str], notes: &mut Vec<String>) -> Result<Table, String> {
    let mut lines = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l));
    let header = fields(lines.next().unwrap_or_default()).map_err(|e| format!("line 1: {e}"))?;
    let mut picks = Vec::new();
    for name in wanted {
        match header.iter().position(|h| h.trim() == *name) {
            Some(i) => picks.push(i),
            None => {
                return Err(format!(
                    "not a mechweed record: the first line has no column {name}"
                ));
            }
        }
    }
    let mut table = Table {
        columns: wanted.iter().map(|s| s.to_string()).collect(),
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
        let cells = fields(line).map_err(|e| format!("line {number}: {e}"));
        let cells = match cells {
            Ok(cells) if cells.len() == header.len() => cells,
            Ok(_) | Err(_) if last && !ends_whole => {
                notes.push(format!(
                    "line {number} is incomplete (the run ended abruptly?): left out"
                ));
                break;
            }
            Ok(cells) => {
                return Err(format!(
                    "line {number} has {} fields, the first line {}",
                    cells.len(),
                    header.len()
                ));
            }
            Err(e) => return Err(e),
        };
        table
            .rows
            .push(picks.iter().map(|&k| cell(&cells[k])).collect());
        table.places.push(format!("line {number}"));
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

fn read_mcap(path: &Path, bytes: &[u8], wanted: &[&str]) -> Result<Record, String> {
    let stream =
        ::mcap::MessageStream::new(bytes).map_err(|e| format!("not a readable MCAP file: {e}"))?;
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
                return Err(format!("not a readable MCAP file: {e}"));
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
        let place = format!("message {} ({})", i + 1, message.channel.topic);
        let object: serde_json::Map<String, serde_json::Value> =
            serde_json::from_slice(&message.data)
                .map_err(|e| format!("{place}: not a JSON object: {e}"))?;
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
                None => return Err(format!("{place}: not a mechweed record: no {name}")),
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
        assert!(fields("1,\"open").is_err());
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
        let t = parse_csv("t_s,x\n0.1,abc\n", &["x"], &mut notes).unwrap();
        assert_eq!(
            t.number(0, 0),
            Err("line 2: x = 'abc' is not a number".to_string())
        );
        let e = parse_csv("t_s,x\n0.1\n0.2,1\n", &["x"], &mut notes).unwrap_err();
        assert_eq!(e, "line 2 has 1 fields, the first line 2");
        let e = parse_csv("hello\n", &["t_s"], &mut notes).unwrap_err();
        assert!(e.contains("no column t_s"), "{e}");
    }
}
