//! What goes wrong making a record or reading one back, as values that name the file
//! and what failed: the system's reason, the line of a CSV file, the column by name.
//! Nothing decides on the words: they are made only when the error is shown.

use std::fmt;
use std::io::ErrorKind;
use std::path::PathBuf;

/// Where in a record a row came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Place {
    /// A line of a CSV file, counted from 1 (the column names are line 1).
    Line(usize),
    /// A message of an MCAP file, counted from 1, on its topic.
    Message { number: usize, topic: String },
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::Line(line) => write!(f, "line {line}"),
            Place::Message { number, topic } => write!(f, "message {number} ({topic})"),
        }
    }
}

/// What is wrong with a record that is read back (the file is named around it).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadProblem {
    #[error("cannot read it: {0}")]
    CannotRead(ErrorKind),
    #[error("the file is empty")]
    Empty,
    #[error("neither a CSV record (not text) nor an MCAP file")]
    NeitherCsvNorMcap,
    #[error("this is the events file of a record: give the tick file beside it (NAME.csv)")]
    EventsFile,
    #[error("line {line}: a quoted field is not closed")]
    UnclosedQuote { line: usize },
    #[error("not a mechweed record: the first line has no column {name}")]
    MissingColumn { name: String },
    #[error("line {line} has {fields} fields, the first line {header}")]
    FieldCount {
        line: usize,
        fields: usize,
        header: usize,
    },
    /// The MCAP library's reason.
    #[error("not a readable MCAP file: {reason}")]
    NotMcap { reason: String },
    /// The JSON library's reason.
    #[error("{place}: not a JSON object: {reason}")]
    NotJson { place: Place, reason: String },
    #[error("{place}: not a mechweed record: no {name}")]
    MissingField { place: Place, name: String },
    #[error("{place}: {column} = '{text}' is not a number")]
    NotANumber {
        place: Place,
        column: String,
        text: String,
    },
    #[error("{place}: {column} is empty")]
    EmptyCell { place: Place, column: String },
    #[error("the record holds no ticks")]
    NoTicks,
}

/// Why a record could not be made, or read back.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RecordError {
    /// The record's folder could not be made.
    #[error("cannot record this run in {}: {error}", folder.display())]
    CreateFolder { folder: PathBuf, error: ErrorKind },
    /// A file of the record could not be created in its folder.
    #[error("cannot record this run in {}: cannot create {}: {error}", folder.display(), path.display())]
    CreateFile {
        folder: PathBuf,
        path: PathBuf,
        error: ErrorKind,
    },
    /// Every name of this second is taken (`stamp`, `stamp-2` .. `stamp-100`).
    #[error("cannot record this run in {}: 100 records named {stamp} exist already", folder.display())]
    NamesTaken { folder: PathBuf, stamp: String },
    /// The files' first lines could not be written, or the recorder thread not started.
    #[error("cannot record this run in {}: {error}", folder.display())]
    Begin { folder: PathBuf, error: ErrorKind },
    /// A record read back is not what it should be.
    #[error("{}: {problem}", file.display())]
    Read { file: PathBuf, problem: ReadProblem },
}
