//! `mechweed record --bus`: an off-board recorder. On another computer (a laptop at the
//! field's edge) it writes the same CSV and MCAP files as the robot's own record, from
//! the ticks and events the robot publishes, and counts what the network dropped: a gap
//! in the tick numbers is written into the record as a `dropped` event, where it
//! happened. The robot publishes every `[bus] tick_every_n`th tick, so the record has
//! that many fewer rows than the robot's own.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use zenoh::Wait;

use crate::bus_tools::Tool;
use crate::config::RecordSettings;
use crate::record::received::{BusRecord, ReceivedEvent, ReceivedTick, parse_event, parse_tick};

/// Messages waiting for the recorder's thread; beyond this they are dropped here and
/// counted (this computer fell behind).
const QUEUE: usize = 4096;
/// Bad messages are counted; the first few are also said.
const SAY_BAD: u64 = 5;

pub struct Options {
    pub connect: String,
    pub robot: String,
    /// Stop after this long (None: at Ctrl-C).
    pub seconds: Option<f64>,
    pub record: RecordSettings,
}

/// What an off-board record holds, said at the end.
#[derive(Default)]
struct Counts {
    ticks: u64,
    events: u64,
    /// Ticks missing between those received: the network or the robot's queue.
    missing: u64,
    bad: u64,
    files: Vec<String>,
}

/// Record until `stop` (Ctrl-C) or `seconds`; returns the closing summary.
pub fn record(opts: &Options, stop: &AtomicBool) -> Result<String, String> {
    let tool = Tool::connect(&opts.connect, &opts.robot, true)?;
    let (tx, rx) = crossbeam_channel::bounded::<(bool, Vec<u8>)>(QUEUE);
    let dropped_here = Arc::new(AtomicU64::new(0));
    let mut subscribers = Vec::new();
    for (is_tick, key) in [(true, "tick"), (false, "event")] {
        let (tx, dropped) = (tx.clone(), dropped_here.clone());
        let subscriber = tool
            .session()
            .declare_subscriber(tool.key(key))
            .callback(move |sample| {
                let bytes = sample.payload().to_bytes().into_owned();
                if tx.try_send((is_tick, bytes)).is_err() {
                    dropped.fetch_add(1, Ordering::Relaxed);
                }
            })
            .wait()
            .map_err(|e| e.to_string())?;
        subscribers.push(subscriber);
    }
    let _alive = tool
        .session()
        .liveliness()
        .declare_token(tool.key(&format!("alive/record-{}", std::process::id())))
        .wait()
        .map_err(|e| e.to_string())?;
    println!(
        "off-board recorder: waiting for the ticks of {} at {}",
        opts.robot, opts.connect
    );
    let end = opts
        .seconds
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let mut stride = || {
        tool.ask("config/bus/tick_every_n", None)
            .ok()
            .and_then(|answer| {
                let json: serde_json::Value = serde_json::from_str(&answer).ok()?;
                json["value"].as_str()?.parse().ok()
            })
            .unwrap_or(1)
    };
    let mut recording = Recording {
        stride: &mut stride,
        settings: &opts.record,
        record: None,
        last_tick: None,
        every_n: 1,
        waiting_events: Vec::new(),
        counts: Counts::default(),
        broken: None,
    };
    while !stop.load(Ordering::Relaxed) && end.is_none_or(|end| Instant::now() < end) {
        let Ok((is_tick, bytes)) = rx.recv_timeout(Duration::from_millis(100)) else {
            continue;
        };
        let parsed = if is_tick {
            parse_tick(&bytes).map(|tick| recording.received_tick(&tick))
        } else {
            parse_event(&bytes).map(|event| recording.received_event(event))
        };
        if let Err(why) = parsed {
            recording.counts.bad += 1;
            if recording.counts.bad <= SAY_BAD {
                let what = if is_tick { "a tick" } else { "an event" };
                eprintln!("off-board recorder: {what} that cannot be recorded: {why}");
            }
        }
        if let Some(why) = recording.broken.take() {
            recording.close();
            return Err(format!("off-board recorder: {why}"));
        }
    }
    recording.close();
    let c = &recording.counts;
    let files = if c.files.is_empty() {
        "no record (no tick arrived)".to_string()
    } else {
        c.files.join(", ")
    };
    Ok(format!(
        "off-board record of {}: {} ticks and {} events into {files}; {} ticks missing between those received (the network or the robot's bus queue dropped them), {} dropped on this computer, {} messages refused",
        opts.robot,
        c.ticks,
        c.events,
        c.missing,
        dropped_here.load(Ordering::Relaxed),
        c.bad
    ))
}

/// The received ticks and events into record files: plain bookkeeping of this program's
/// own; it holds no bus (the robot's real-time threads never touch Zenoh either: theirs
/// go to the bus thread through a queue).
struct Recording<'a> {
    /// The robot's `[bus] tick_every_n`, asked when a record begins.
    stride: &'a mut dyn FnMut() -> u64,
    settings: &'a RecordSettings,
    record: Option<BusRecord>,
    last_tick: Option<u64>,
    /// The robot's `[bus] tick_every_n`: a gap larger than this is ticks missing.
    every_n: u64,
    /// Events before the first tick, written when the record begins.
    waiting_events: Vec<ReceivedEvent>,
    counts: Counts,
    /// Why no record can be made (the folder cannot be written): the recorder ends.
    broken: Option<String>,
}

impl Recording<'_> {
    fn received_tick(&mut self, tick: &ReceivedTick) {
        if self.last_tick.is_some_and(|last| tick.tick <= last) {
            println!(
                "off-board recorder: the tick numbers went back (the robot program started again): a new record begins"
            );
            self.close();
        }
        if self.record.is_none() {
            self.begin(tick);
        }
        if let Some(last) = self.last_tick {
            let missing = (tick.tick - last) / self.every_n;
            if missing > 1 {
                self.counts.missing += missing - 1;
                self.received_event(ReceivedEvent {
                    t_s: tick.t_s,
                    tick: tick.tick,
                    kind: "dropped".to_string(),
                    text: format!(
                        "{} ticks not received from the bus: the network or the robot's bus queue dropped them",
                        missing - 1
                    ),
                });
            }
        }
        self.last_tick = Some(tick.tick);
        if let Some(record) = &mut self.record {
            record.tick(tick);
            self.counts.ticks += 1;
        }
    }

    fn received_event(&mut self, event: ReceivedEvent) {
        match &mut self.record {
            Some(record) => {
                record.event(&event);
                self.counts.events += 1;
            }
            None if self.waiting_events.len() < 256 => self.waiting_events.push(event),
            None => self.counts.bad += 1,
        }
    }

    /// New files, at the first tick of a run: its start time and the robot's stride.
    fn begin(&mut self, first: &ReceivedTick) {
        self.every_n = (self.stride)().max(1);
        let now_ns = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        let start_ns = now_ns.saturating_sub((first.t_s.max(0.0) * 1e9) as u64);
        match BusRecord::create(self.settings, start_ns, self.every_n) {
            Ok(record) => {
                println!(
                    "off-board recorder: recording into {} (every {}th tick, as the robot publishes them)",
                    record.files().join(", "),
                    self.every_n
                );
                self.counts.files.extend(record.files().iter().cloned());
                self.record = Some(record);
                for event in std::mem::take(&mut self.waiting_events) {
                    self.received_event(event);
                }
            }
            Err(why) => self.broken = Some(why.to_string()),
        }
    }

    fn close(&mut self) {
        if let Some(record) = self.record.take() {
            for problem in record.finish() {
                eprintln!("off-board recorder: {problem}");
            }
        }
        self.last_tick = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;
    use crate::record::{TickSample, read, tick_json};

    fn tick(n: u64) -> ReceivedTick {
        let mut sample = TickSample::default();
        sample.status.tick = n;
        sample.status.t_s = n as f64 / 100.0;
        let mut json = String::new();
        tick_json(&sample, &mut json);
        parse_tick(json.as_bytes()).unwrap()
    }

    #[test]
    fn a_gap_in_the_ticks_is_counted_and_written_where_it_happened() {
        let folder = tempfile::tempdir().unwrap();
        let mut settings = Settings::shipped().record;
        settings.folder = folder.path().to_path_buf();
        let mut stride = || 10;
        let mut recording = Recording {
            stride: &mut stride,
            settings: &settings,
            record: None,
            last_tick: None,
            every_n: 10,
            waiting_events: Vec::new(),
            counts: Counts::default(),
            broken: None,
        };
        for n in [10, 20, 50, 60] {
            recording.received_tick(&tick(n));
        }
        // The robot program started again: a second record.
        recording.received_tick(&tick(10));
        recording.close();
        let c = &recording.counts;
        assert_eq!((c.ticks, c.missing, c.events), (5, 2, 1));
        let csv = c
            .files
            .iter()
            .find(|f| f.ends_with(".csv") && !f.contains("events"));
        let first = read::read(std::path::Path::new(csv.unwrap()), &["tick"]).unwrap();
        assert_eq!(first.ticks.rows.len(), 4);
        let events = first.events.expect("the events file");
        let kind = events.column("kind").unwrap();
        let text = events.column("text").unwrap();
        assert_eq!(events.text(0, kind), "dropped");
        assert!(
            events
                .text(0, text)
                .starts_with("2 ticks not received from the bus")
        );
        let records = c.files.iter().filter(|f| f.ends_with(".mcap")).count();
        assert_eq!(records, 2, "{:?}", c.files);
    }
}
