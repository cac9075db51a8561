//! The CSV form of a record, for MATLAB (`readtable`) and pandas (`read_csv`): one
//! header line of column names with their units in them (`t_s,tick,mode,...`), then one
//! line per tick. Events go to a small second file beside it, `NAME.events.csv`
//! (`t_s,tick,kind,text`), so that the tick file stays a plain table of numbers.
//! Missing numbers are empty cells (NaN in both tools); on/off signals are 0 and 1.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use super::event::{EVENT_COLUMNS, RecordEvent};
use super::received::{Cell, ReceivedEvent, ReceivedTick};
use super::row::{COLUMNS, TickSample, Value, number_text};
use super::thread::Sink;

pub(crate) struct CsvSink {
    ticks: BufWriter<File>,
    events: BufWriter<File>,
    paths: [PathBuf; 2],
    /// One line, reused so that writing a tick does not allocate.
    line: String,
}

impl CsvSink {
    /// Write the header lines into the two (new, empty) files.
    pub fn new(ticks: (PathBuf, File), events: (PathBuf, File)) -> io::Result<CsvSink> {
        let mut sink = CsvSink {
            ticks: BufWriter::with_capacity(1 << 16, ticks.1),
            events: BufWriter::new(events.1),
            paths: [ticks.0, events.0],
            line: String::with_capacity(2048),
        };
        let header: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        writeln!(sink.ticks, "{}", header.join(","))?;
        writeln!(sink.events, "{}", EVENT_COLUMNS.join(","))?;
        Ok(sink)
    }
}

/// A CSV field in double quotes, quotes doubled (RFC 4180), for free text.
pub fn quoted(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\""))
}

impl Sink for CsvSink {
    fn tick(&mut self, sample: &TickSample) -> io::Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        for (i, column) in COLUMNS.iter().enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            match (column.value)(sample) {
                Value::Num(x) => {
                    number_text(x, &mut self.line);
                }
                Value::Int(n) => {
                    let _ = write!(self.line, "{n}");
                }
                Value::Text(t) => self.line.push_str(t),
            }
        }
        self.line.push('\n');
        self.ticks.write_all(self.line.as_bytes())
    }

    fn event(&mut self, event: &RecordEvent) -> io::Result<()> {
        let mut t = String::new();
        number_text(event.t_s, &mut t);
        writeln!(
            self.events,
            "{t},{},{},{}",
            event.tick,
            event.kind_name(),
            quoted(&event.text())
        )
    }

    fn flush(&mut self) -> io::Result<()> {
        self.ticks.flush()?;
        self.events.flush()?;
        // Through the operating system's cache too: a power cut then loses at most
        // what came since the last flush.
        self.ticks.get_ref().sync_data()?;
        self.events.get_ref().sync_data()
    }

    fn finish(&mut self) -> io::Result<()> {
        self.flush()
    }

    fn files(&self) -> Vec<String> {
        self.paths.iter().map(|p| p.display().to_string()).collect()
    }

    fn received_tick(&mut self, tick: &ReceivedTick) -> io::Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        for (i, cell) in tick.cells.iter().enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            match cell {
                Cell::Num(x) => {
                    number_text(*x, &mut self.line);
                }
                Cell::Int(n) => {
                    let _ = write!(self.line, "{n}");
                }
                // Checked on arrival to be one of the record's fixed words.
                Cell::Word(word) => self.line.push_str(word),
            }
        }
        self.line.push('\n');
        self.ticks.write_all(self.line.as_bytes())
    }

    fn received_event(&mut self, event: &ReceivedEvent) -> io::Result<()> {
        let mut t = String::new();
        number_text(event.t_s, &mut t);
        writeln!(
            self.events,
            "{t},{},{},{}",
            event.tick,
            event.kind,
            quoted(&event.text)
        )
    }
}
