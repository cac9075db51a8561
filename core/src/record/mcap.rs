//! The MCAP form of a record, for Foxglove and PlotJuggler: JSON messages on channels
//! with a JSON schema, which both tools plot with no plugin.
//!
//! - `/mechweed/tick`: one message per recorded tick, an object with the CSV's column
//!   names as keys (missing numbers are null);
//! - `/mechweed/event`: `{t_s, tick, kind, text}` for faults, mode changes, notices.
//!
//! A message's log time is the run's start (wall clock) plus its `t_s`. Chunks are
//! zstd-compressed on this thread (JSON repeats its keys; it compresses tenfold).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::PathBuf;

use ::mcap::records::{MessageHeader, Metadata};
use ::mcap::{Compression, McapError, WriteOptions, Writer};
use serde_json::json;

use super::event::RecordEvent;
use super::received::{ReceivedEvent, ReceivedTick};
use super::row::{COLUMNS, TickSample, Value, tick_json};
use super::thread::Sink;

pub const TICK_TOPIC: &str = "/mechweed/tick";
pub const EVENT_TOPIC: &str = "/mechweed/event";

pub(crate) struct McapSink {
    /// None once finished.
    writer: Option<Writer<BufWriter<File>>>,
    path: PathBuf,
    /// The same file as the writer's, to sync it to the disk.
    file: File,
    tick_channel: u16,
    event_channel: u16,
    start_unix_ns: u64,
    sequence: u32,
    /// One message, reused.
    json: String,
}

/// What the record is, for the file's metadata record.
pub struct About<'a> {
    pub started_utc: &'a str,
    pub every_n_ticks: u64,
}

fn io_error(e: McapError) -> io::Error {
    match e {
        McapError::Io(e) => e,
        other => io::Error::other(other.to_string()),
    }
}

/// The JSON schema of a tick, from the column table.
fn tick_schema() -> String {
    let sample = TickSample::default();
    let properties: serde_json::Map<String, serde_json::Value> = COLUMNS
        .iter()
        .map(|c| {
            let kind = match (c.value)(&sample) {
                Value::Num(_) => json!(["number", "null"]),
                Value::Int(_) => json!("integer"),
                Value::Text(_) => json!("string"),
            };
            let about = format!("{}, {}", c.meaning, c.unit);
            (
                c.name.to_string(),
                json!({"type": kind, "description": about}),
            )
        })
        .collect();
    json!({"title": "mechweed tick", "type": "object", "properties": properties}).to_string()
}

fn event_schema() -> String {
    json!({
        "title": "mechweed event",
        "type": "object",
        "properties": {
            "t_s": {"type": "number", "description": "supervisor time since the run started, s"},
            "tick": {"type": "integer", "description": "supervisor tick number"},
            "kind": {"type": "string", "description": "mode, fault, notice or dropped"},
            "text": {"type": "string", "description": "what happened"}
        }
    })
    .to_string()
}

impl McapSink {
    pub fn new(
        (path, file): (PathBuf, File),
        start_unix_ns: u64,
        about: &About,
    ) -> io::Result<McapSink> {
        let options = WriteOptions::new()
            .compression(Some(Compression::Zstd))
            // Compress on the recorder thread alone: no helper threads beside the robot's.
            .compression_threads(0)
            .profile("");
        let sync_handle = file.try_clone()?;
        let mut writer = options
            .create(BufWriter::with_capacity(1 << 16, file))
            .map_err(io_error)?;
        let no_metadata = BTreeMap::new();
        let tick_schema = writer
            .add_schema("mechweed.Tick", "jsonschema", tick_schema().as_bytes())
            .map_err(io_error)?;
        let event_schema = writer
            .add_schema("mechweed.Event", "jsonschema", event_schema().as_bytes())
            .map_err(io_error)?;
        let tick_channel = writer
            .add_channel(tick_schema, TICK_TOPIC, "json", &no_metadata)
            .map_err(io_error)?;
        let event_channel = writer
            .add_channel(event_schema, EVENT_TOPIC, "json", &no_metadata)
            .map_err(io_error)?;
        let metadata = BTreeMap::from([
            ("program".to_string(), "mechweed".to_string()),
            ("version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
            ("started_utc".to_string(), about.started_utc.to_string()),
            ("every_n_ticks".to_string(), about.every_n_ticks.to_string()),
        ]);
        writer
            .write_metadata(&Metadata {
                name: "mechweed record".to_string(),
                metadata,
            })
            .map_err(io_error)?;
        Ok(McapSink {
            writer: Some(writer),
            path,
            file: sync_handle,
            tick_channel,
            event_channel,
            start_unix_ns,
            sequence: 0,
            json: String::with_capacity(4096),
        })
    }

    fn write(&mut self, channel_id: u16, t_s: f64, data: &[u8]) -> io::Result<()> {
        let Some(writer) = &mut self.writer else {
            return Err(io::Error::other("the record is already finished"));
        };
        // A time before the start (impossible) or beyond 500 years is kept at the start.
        let since_ns = if (0.0..1.6e10).contains(&t_s) {
            (t_s * 1e9).round() as u64
        } else {
            0
        };
        let time_ns = self.start_unix_ns.saturating_add(since_ns);
        self.sequence = self.sequence.wrapping_add(1);
        let header = MessageHeader {
            channel_id,
            sequence: self.sequence,
            log_time: time_ns,
            publish_time: time_ns,
        };
        writer
            .write_to_known_channel(&header, data)
            .map_err(io_error)
    }
}

impl Sink for McapSink {
    fn tick(&mut self, sample: &TickSample) -> io::Result<()> {
        let mut json = std::mem::take(&mut self.json);
        tick_json(sample, &mut json);
        let result = self.write(self.tick_channel, sample.status.t_s, json.as_bytes());
        self.json = json;
        result
    }

    fn event(&mut self, event: &RecordEvent) -> io::Result<()> {
        let message = event.to_json();
        self.write(
            self.event_channel,
            event.t_s,
            message.to_string().as_bytes(),
        )
    }

    /// Ends the open chunk, so that everything so far is readable from the file.
    fn flush(&mut self) -> io::Result<()> {
        let Some(writer) = &mut self.writer else {
            return Ok(());
        };
        writer.flush().map_err(io_error)?;
        // Also through the operating system's cache: a power cut then loses at most
        // what came since the last flush.
        self.file.sync_data()
    }

    fn finish(&mut self) -> io::Result<()> {
        let Some(mut writer) = self.writer.take() else {
            return Ok(());
        };
        writer.finish().map_err(io_error)?;
        let file = writer
            .into_inner()
            .into_inner()
            .map_err(|e| e.into_error())?;
        file.sync_all()
    }

    fn files(&self) -> Vec<String> {
        vec![self.path.display().to_string()]
    }

    fn received_tick(&mut self, tick: &ReceivedTick) -> io::Result<()> {
        self.write(self.tick_channel, tick.t_s, tick.json.as_bytes())
    }

    fn received_event(&mut self, event: &ReceivedEvent) -> io::Result<()> {
        let message = json!({
            "t_s": event.t_s,
            "tick": event.tick,
            "kind": event.kind,
            "text": event.text,
        });
        self.write(
            self.event_channel,
            event.t_s,
            message.to_string().as_bytes(),
        )
    }
}
