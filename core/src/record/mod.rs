//! Run records: every run leaves a record a scientist can open in MATLAB, pandas,
//! Foxglove or PlotJuggler, flushed often enough that a fault or a crash loses at most
//! the last second.
//!
//! The supervisor thread hands each tick to a `RecordTap` (tap.rs): a copy into a
//! bounded queue that never blocks and never allocates. The recorder thread
//! (thread.rs) writes the ticks and events into the formats asked for: CSV (csv.rs)
//! and MCAP (mcap.rs), both made from the one table of columns in row.rs. A record
//! that cannot be written is a warning; the robot runs on.
//!
//! `mechweed record summary FILE` (summary.rs, reading with read.rs) prints a record's
//! duration, distance, faults and cross-track figures; `latest` is the newest record
//! in the folder (keep.rs), which also deletes the oldest records beyond `[record] keep`.

mod csv;
mod error;
mod event;
mod files;
pub mod header;
pub mod keep;
mod mcap;
pub mod off_board;
pub mod read;
pub mod received;
pub mod request_text;
mod row;
pub mod space;
pub mod summary;
mod tap;
mod thread;

#[cfg(test)]
mod tests;

use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};

use crossbeam_channel::bounded;
use mechweed_hw::sim::TruthHandle;

use crate::config::{RecordSettings, Settings};
use header::{HEADER_SUFFIX, RunHeader};

pub use self::mcap::{EVENT_TOPIC, TICK_TOPIC};
pub use error::{Place, ReadProblem, RecordError};
pub use event::{EVENT_COLUMNS, EventKind, RecordEvent};
pub use files::utc_stamp;
pub use row::{COLUMNS, Column, Given, HwFailure, TickSample, Value, column_names, tick_json};
pub use tap::{Delivery, RecordTap};
pub use thread::{RecordOutcome, Recorder, Sink};

/// Ticks the queue holds: 10 s at 100 Hz, more than a healthy disk ever stalls.
const QUEUE_TICKS: usize = 1024;
/// Events the queue holds; they are rare (a few per run).
const QUEUE_EVENTS: usize = 256;

/// Start recording into new files in `[record] folder`, named by the time now.
/// `truth` is the simulated robot's, read on each recorded tick by `after_tick`.
/// The error names the folder and what is wrong.
/// Beside the ticks and events, NAME.run.json holds the settings in force, for a replay.
pub fn start(
    run_settings: &Settings,
    truth: Option<TruthHandle>,
    delivery: Delivery,
) -> Result<(RecordTap, Recorder), RecordError> {
    let started = SystemTime::now();
    let start_unix_ns = started
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let name = utc_stamp(started);
    start_named(run_settings, &name, start_unix_ns, truth, delivery)
}

/// As `start`, into files named `name` (a what-if beside the record it replays).
pub fn start_named(
    run_settings: &Settings,
    name: &str,
    start_unix_ns: u64,
    truth: Option<TruthHandle>,
    delivery: Delivery,
) -> Result<(RecordTap, Recorder), RecordError> {
    let settings = &run_settings.record;
    let header = RunHeader::of(run_settings);
    let every_n = settings.every_n_ticks;
    let sinks = new_sinks(settings, name, start_unix_ns, every_n, Some(&header))?;
    let space = Some(space::SpaceWatch::of(&settings.folder));
    start_watched(sinks, settings.every_n_ticks, delivery, truth, space).map_err(|e| {
        RecordError::Begin {
            folder: settings.folder.clone(),
            error: e.kind(),
        }
    })
}

/// New files in `[record] folder`, in its formats, named by the time `now`; the run they
/// record began at `start_unix_ns` and keeps every `every_n_ticks`th tick.
fn new_sinks(
    settings: &RecordSettings,
    stamp: &str,
    start_unix_ns: u64,
    every_n_ticks: u64,
    header: Option<&RunHeader>,
) -> Result<Vec<Box<dyn Sink>>, RecordError> {
    let folder = &settings.folder;
    let why = |e: std::io::Error| RecordError::Begin {
        folder: folder.clone(),
        error: e.kind(),
    };
    let (csv, mcap) = (settings.formats.csv(), settings.formats.mcap());
    let mut extensions = Vec::new();
    if csv {
        extensions.extend([".csv", ".events.csv"]);
    }
    if mcap {
        extensions.push(".mcap");
    }
    if header.is_some() {
        extensions.push(HEADER_SUFFIX);
    }
    let mut made = files::create(folder, stamp, &extensions)?.files.into_iter();
    let mut sinks: Vec<Box<dyn Sink>> = Vec::new();
    // The files come in the order of `extensions`.
    if csv && let (Some(ticks), Some(events)) = (made.next(), made.next()) {
        sinks.push(Box::new(csv::CsvSink::new(ticks, events).map_err(why)?));
    }
    if mcap && let Some(file) = made.next() {
        let about = self::mcap::About {
            started_utc: stamp,
            every_n_ticks,
        };
        sinks.push(Box::new(
            self::mcap::McapSink::new(file, start_unix_ns, &about).map_err(why)?,
        ));
    }
    if let (Some(header), Some((_, mut file))) = (header, made.next()) {
        header.write(&mut file).map_err(why)?;
    }
    Ok(sinks)
}

/// Start a recorder thread writing into `sinks` (tests give their own sinks).
pub fn start_with_sinks(
    sinks: Vec<Box<dyn Sink>>,
    every_n_ticks: u64,
    delivery: Delivery,
    truth: Option<TruthHandle>,
) -> std::io::Result<(RecordTap, Recorder)> {
    start_watched(sinks, every_n_ticks, delivery, truth, None)
}

/// As `start_with_sinks`, stopping when `space` says the disk is nearly full.
pub fn start_watched(
    sinks: Vec<Box<dyn Sink>>,
    every_n_ticks: u64,
    delivery: Delivery,
    truth: Option<TruthHandle>,
    space: Option<space::SpaceWatch>,
) -> std::io::Result<(RecordTap, Recorder)> {
    let (tick_tx, tick_rx) = bounded(QUEUE_TICKS);
    let (event_tx, event_rx) = bounded(QUEUE_EVENTS);
    let counters = Arc::default();
    let recorder = thread::spawn(
        sinks,
        tick_rx,
        event_rx,
        every_n_ticks,
        Arc::clone(&counters),
        space,
    )?;
    let tap = RecordTap::new(tick_tx, event_tx, every_n_ticks, delivery, counters, truth);
    Ok((tap, recorder))
}

/// The ticks and events of a run for another reader than the recorder (the bus
/// thread): every `every_n_ticks`th tick and every event, through queues that drop and
/// count when the reader falls behind, exactly as the recorder's.
pub fn flow(every_n_ticks: u64, capacity: usize, truth: TruthHandle) -> (RecordTap, TickFlow) {
    let (tick_tx, ticks) = bounded(capacity.max(1));
    let (event_tx, events) = bounded(QUEUE_EVENTS);
    let counters: Arc<tap::Counters> = Arc::default();
    let tap = RecordTap::new(
        tick_tx,
        event_tx,
        every_n_ticks,
        Delivery::NeverWait,
        Arc::clone(&counters),
        Some(truth),
    );
    let flow = TickFlow {
        ticks,
        events,
        counters,
    };
    (tap, flow)
}

/// The reading end of `flow`.
pub struct TickFlow {
    pub ticks: crossbeam_channel::Receiver<TickSample>,
    pub events: crossbeam_channel::Receiver<RecordEvent>,
    counters: Arc<tap::Counters>,
}

impl TickFlow {
    /// Ticks and events the queues had no room for so far.
    pub fn dropped(&self) -> (u64, u64) {
        use std::sync::atomic::Ordering::Relaxed;
        (
            self.counters.ticks_dropped.load(Relaxed),
            self.counters.events_dropped.load(Relaxed),
        )
    }
}

/// For `mechweed run`: record as robot.ini says, and say where. If the record cannot
/// be made, warn (naming the folder) and run on without one.
pub fn start_for_run(run_settings: &Settings, truth: TruthHandle) -> (RecordTap, Recorder) {
    let settings = &run_settings.record;
    if !settings.enabled {
        let outcome = RecordOutcome {
            problems: vec!["recording is off ([record] enabled = no)".to_string()],
            ..RecordOutcome::default()
        };
        return (RecordTap::off(), Recorder::without(outcome));
    }
    match start(run_settings, Some(truth), Delivery::NeverWait) {
        Ok((tap, recorder)) => {
            crate::say!("recording into {}", recorder.files().join(", "));
            // The record just made is never deleted, even if the clock went back.
            let current = (recorder.files().first())
                .and_then(|f| keep::record_of(std::path::Path::new(f)))
                .unwrap_or_default();
            if let Some(keep) = settings.keep_records {
                for line in keep::remove_oldest(&settings.folder, keep, &current) {
                    crate::say!("{line}");
                }
            }
            if let Some(keep_gb) = settings.keep_gb {
                for line in keep::remove_beyond_size(&settings.folder, keep_gb, &current) {
                    crate::say!("{line}");
                }
            }
            (tap, recorder)
        }
        Err(why) => {
            let why = format!("{why}; the robot runs on without a record");
            tracing::warn!("{why}");
            let outcome = RecordOutcome {
                problems: vec![why],
                ..RecordOutcome::default()
            };
            (RecordTap::off(), Recorder::without(outcome))
        }
    }
}
