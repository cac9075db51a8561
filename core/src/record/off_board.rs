//! The off-board recorder's bookkeeping (`mechweed record --bus`, src/programs/bus/record.rs):
//! the ticks and events received from the robot's bus into record files, a gap in the
//! tick numbers written as a `dropped` event where it happened, a new record when the
//! robot program starts again. It holds no bus and runs in no real-time thread: the
//! recorder hands it what its subscribers received.

use std::time::{SystemTime, UNIX_EPOCH};

use super::received::{BusRecord, ReceivedEvent, ReceivedTick};
use crate::config::RecordSettings;
use crate::state::cross_track::CrossTrackMeaning;

/// What the robot says of itself when a record begins: its `[bus] tick_every_n`, and
/// whether its cross-track means anything (its record header keeps that).
#[derive(Debug, Clone, Copy)]
pub struct RobotSays {
    pub every_n: u64,
    pub cross_track: CrossTrackMeaning,
}

/// What an off-board record holds, said at the end.
#[derive(Default)]
pub struct Counts {
    pub ticks: u64,
    pub events: u64,
    /// Ticks missing between those received: the network or the robot's queue.
    pub missing: u64,
    pub bad: u64,
    pub files: Vec<String>,
}

/// The received ticks and events into record files.
pub struct Recording<'a> {
    /// The robot's `[bus] tick_every_n`, asked when a record begins.
    ask: &'a mut dyn FnMut() -> RobotSays,
    settings: &'a RecordSettings,
    record: Option<BusRecord>,
    last_tick: Option<u64>,
    /// The robot's `[bus] tick_every_n`: a gap larger than this is ticks missing.
    every_n: u64,
    /// Events before the first tick, written when the record begins.
    waiting_events: Vec<ReceivedEvent>,
    pub counts: Counts,
    /// Why no record can be made (the folder cannot be written): the recorder ends.
    pub broken: Option<String>,
}

impl<'a> Recording<'a> {
    /// Nothing recorded yet; `ask` asks the robot what a record needs of it when one
    /// begins.
    pub fn new(ask: &'a mut dyn FnMut() -> RobotSays, settings: &'a RecordSettings) -> Self {
        Recording {
            ask,
            settings,
            record: None,
            last_tick: None,
            every_n: 1,
            waiting_events: Vec::new(),
            counts: Counts::default(),
            broken: None,
        }
    }

    pub fn received_tick(&mut self, tick: &ReceivedTick) {
        if self.last_tick.is_some_and(|last| tick.tick <= last) {
            crate::say!(
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

    pub fn received_event(&mut self, event: ReceivedEvent) {
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
        let says = (self.ask)();
        self.every_n = says.every_n.max(1);
        let now_ns = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        let start_ns = now_ns.saturating_sub((first.t_s.max(0.0) * 1e9) as u64);
        match BusRecord::create(self.settings, start_ns, self.every_n, says.cross_track) {
            Ok(record) => {
                crate::say!(
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

    /// Finish the record's files, if one is open.
    pub fn close(&mut self) {
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
    use crate::record::received::parse_tick;
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
        let mut ask = || RobotSays {
            every_n: 10,
            cross_track: CrossTrackMeaning::Meaningful,
        };
        let mut recording = Recording::new(&mut ask, &settings);
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
