//! A record read back as what each supervisor tick was given and what it wrote, with
//! every reason it cannot be replayed exactly: no settings beside it, a column missing,
//! a tick missing, a cell that is not what its column holds.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use mechweed_hw::{Inputs, Outputs};

use super::row::{Row, WANTED};
use crate::camlink::LinkStatus;
use crate::record::header::RunHeader;
use crate::record::read::{self, Table};
use crate::record::request_text::parse_event_text;
use crate::record::{Given, Place};
use crate::state::modes::{Mode, Request};
use crate::steer::SteerCommand;

/// One tick as the record has it.
#[derive(Debug, Clone)]
pub struct RecordedTick {
    pub tick: u64,
    pub t_s: f64,
    pub inputs: Inputs,
    pub steer: SteerCommand,
    pub link: LinkStatus,
    pub given: Given,
    /// What the tick wrote, and the mode it ended in.
    pub outputs: Outputs,
    pub mode: Mode,
    pub place: Place,
}

/// A request as the record has it: given before `tick`, and the answer in words.
#[derive(Debug, Clone)]
pub struct RecordedRequest {
    pub request: Request,
    pub answer: String,
}

pub struct Recorded {
    pub file: PathBuf,
    pub header: RunHeader,
    pub ticks: Vec<RecordedTick>,
    pub requests: BTreeMap<u64, Vec<RecordedRequest>>,
    /// Faults as the record has them: (tick, words).
    pub faults: Vec<(u64, String)>,
    /// What a reader should know (a file that ends abruptly).
    pub notes: Vec<String>,
}

/// Read `file` (a record's .csv or .mcap) for a replay, or say why it cannot be one.
pub fn read_for_replay(file: &Path) -> Result<Recorded, String> {
    let header_file = RunHeader::beside(file).ok_or_else(|| {
        format!(
            "{}: not a record's file (NAME.csv or NAME.mcap)",
            file.display()
        )
    })?;
    // The file itself first: a missing record is not a missing header.
    if !file.exists() {
        return Err(format!("{}: no such file", file.display()));
    }
    if !header_file.exists() {
        return Err(format!(
            "{}: no {} beside it, with the settings the run had: a record made before replays existed, by `record --bus`, or with that file removed cannot be replayed exactly",
            file.display(),
            header_file.display()
        ));
    }
    let header = RunHeader::read(&header_file)?;
    if header.off_board {
        return Err(format!(
            "{}: recorded off-board (`record --bus`) from the robot's flows, which do not carry its settings: it cannot be replayed exactly; replay the robot's own record of that run",
            file.display()
        ));
    }
    if !header.settings_as_read {
        return Err(format!(
            "{}: the run's settings were changed inside the program after its settings file was read (a test's own settings): they are not known, so it cannot be replayed exactly",
            header_file.display()
        ));
    }
    let record = read::read(file, WANTED).map_err(|e| {
        format!("{e} (a record made before replays existed lacks the columns a replay needs)")
    })?;
    let events = record.events.as_ref().ok_or_else(|| {
        format!(
            "{}: its events file is missing: the operator's requests are in it",
            file.display()
        )
    })?;
    let mut ticks = Vec::with_capacity(record.ticks.rows.len());
    for row in 0..record.ticks.rows.len() {
        let tick = (Row {
            table: &record.ticks,
            row,
        })
        .tick()
        .map_err(|e| format!("{}: {e}", record.file.display()))?;
        let expected = ticks.last().map_or(1, |t: &RecordedTick| t.tick + 1);
        if tick.tick != expected {
            return Err(format!(
                "{}: tick {} follows tick {} ({}): the ticks between are missing (the recorder fell behind, a record of every n-th tick, or an edited file); a replay needs every tick",
                record.file.display(),
                tick.tick,
                expected - 1,
                tick.place
            ));
        }
        ticks.push(tick);
    }
    if ticks.is_empty() {
        return Err(format!("{}: the record holds no ticks", file.display()));
    }
    let (requests, faults) = events_of(events, &record.file)?;
    Ok(Recorded {
        file: file.to_path_buf(),
        header,
        ticks,
        requests,
        faults,
        notes: record.notes,
    })
}

type Requests = BTreeMap<u64, Vec<RecordedRequest>>;

fn events_of(events: &Table, file: &Path) -> Result<(Requests, Vec<(u64, String)>), String> {
    let mut requests: Requests = BTreeMap::new();
    let mut faults = Vec::new();
    let (kind, text, tick) = (2, 3, 1);
    for row in 0..events.rows.len() {
        let at = || format!("{} (events, {})", file.display(), events.places[row]);
        let n =
            (events.number(row, tick)).map_err(|e| format!("{} (events): {e}", file.display()))?;
        let n = n.ok_or_else(|| format!("{}: no tick", at()))?;
        if n < 1.0 || n.fract() != 0.0 || n > 1e15 {
            return Err(format!("{}: tick {n} is not a tick number", at()));
        }
        let n = n as u64;
        match events.text(row, kind).as_str() {
            "request" => {
                let (request, answer) = parse_event_text(&events.text(row, text))
                    .map_err(|e| format!("{}: {e}", at()))?;
                requests
                    .entry(n)
                    .or_default()
                    .push(RecordedRequest { request, answer });
            }
            "fault" => faults.push((n, events.text(row, text))),
            "dropped" => {
                return Err(format!(
                    "{}: {}: a replay needs every tick",
                    at(),
                    events.text(row, text)
                ));
            }
            _ => {}
        }
    }
    Ok((requests, faults))
}
