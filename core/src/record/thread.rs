//! The recorder thread: takes ticks and events off the queues and writes them into
//! the record's files, in tick order. It flushes at least every half second, after
//! every fault and at the end, so a crash loses at most the last second. A file that
//! cannot be written is given up with one warning; the thread keeps emptying the
//! queues, so the supervisor never notices.

use std::collections::VecDeque;
use std::io;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, TryRecvError};
use serde::Serialize;

use super::event::{EventKind, RecordEvent};
use super::received::{ReceivedEvent, ReceivedTick};
use super::row::TickSample;
use super::space::SpaceWatch;
use super::tap::Counters;

/// One format's files. Implementations write to a buffer; `flush` puts it on disk.
pub trait Sink: Send {
    fn tick(&mut self, sample: &TickSample) -> io::Result<()>;
    fn event(&mut self, event: &RecordEvent) -> io::Result<()>;
    /// Write what is buffered through to the disk.
    fn flush(&mut self) -> io::Result<()>;
    /// Complete the files (the MCAP summary and footer) and flush.
    fn finish(&mut self) -> io::Result<()>;
    /// The files written, for messages and the report.
    fn files(&self) -> Vec<String>;
    /// A tick as another computer received it from the bus (`mechweed record --bus`).
    fn received_tick(&mut self, _tick: &ReceivedTick) -> io::Result<()> {
        Err(io::Error::other(
            "this record does not take ticks from the bus",
        ))
    }
    /// An event as another computer received it from the bus.
    fn received_event(&mut self, _event: &ReceivedEvent) -> io::Result<()> {
        Err(io::Error::other(
            "this record does not take events from the bus",
        ))
    }
}

/// Flush at least this often, so that a crash loses less than a second.
const FLUSH_EVERY: Duration = Duration::from_millis(500);
/// The recorder looks at its queues this often (5 ticks at 100 Hz).
const POLL: Duration = Duration::from_millis(50);

/// What a record holds at the end of the run, for the run report.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RecordOutcome {
    /// The record's files (empty: no record was made).
    pub files: Vec<String>,
    /// Ticks handed to the files.
    pub ticks_recorded: u64,
    /// Ticks the queue had no room for: the disk was slower than the robot.
    pub ticks_dropped: u64,
    /// Faults, mode changes and notices recorded.
    pub events_recorded: u64,
    pub events_dropped: u64,
    /// Why the record is missing or incomplete, if it is.
    pub problems: Vec<String>,
}

/// The handle of a running recorder: `finish` waits for it once the tap is dropped.
pub struct Recorder {
    thread: Option<JoinHandle<RecordOutcome>>,
    files: Vec<String>,
    counters: Arc<Counters>,
    /// Why there is no recorder thread (recording off, or the files could not be made).
    without: Option<RecordOutcome>,
}

impl Recorder {
    /// No recording: the outcome says why.
    pub fn without(outcome: RecordOutcome) -> Recorder {
        Recorder {
            thread: None,
            files: Vec::new(),
            counters: Arc::default(),
            without: Some(outcome),
        }
    }

    /// The record's files.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// Wait for the recorder to write everything and close the files. Call it after
    /// the tap is dropped (the supervisor thread has ended), or it waits for ever.
    pub fn finish(mut self) -> RecordOutcome {
        let mut outcome = match (self.thread.take(), self.without.take()) {
            (Some(thread), _) => thread.join().unwrap_or_else(|_| RecordOutcome {
                files: self.files.clone(),
                problems: vec!["the recorder thread panicked: the record may be incomplete".into()],
                ..RecordOutcome::default()
            }),
            (None, without) => without.unwrap_or_default(),
        };
        outcome.ticks_dropped = self.counters.ticks_dropped.load(Ordering::Relaxed);
        outcome.events_dropped = self.counters.events_dropped.load(Ordering::Relaxed);
        outcome
    }
}

pub(super) fn spawn(
    sinks: Vec<Box<dyn Sink>>,
    ticks: Receiver<TickSample>,
    events: Receiver<RecordEvent>,
    every_n_ticks: u64,
    counters: Arc<Counters>,
    space: Option<SpaceWatch>,
) -> io::Result<Recorder> {
    let mut writer = Writer {
        sinks: sinks.into_iter().map(Some).collect(),
        space,
        outcome: RecordOutcome::default(),
        every_n_ticks: every_n_ticks.max(1),
        last_tick: None,
        last_flush: Instant::now(),
        unflushed: false,
    };
    let files: Vec<String> = writer
        .sinks
        .iter()
        .flatten()
        .flat_map(|s| s.files())
        .collect();
    writer.outcome.files = files.clone();
    let thread = std::thread::Builder::new()
        .name("recorder".to_string())
        .spawn(move || writer.run(&ticks, &events))?;
    Ok(Recorder {
        thread: Some(thread),
        files,
        counters,
        without: None,
    })
}

struct Writer {
    /// None once a sink has failed.
    sinks: Vec<Option<Box<dyn Sink>>>,
    /// The free space of the record's disk (None: not watched, a test's sinks).
    space: Option<SpaceWatch>,
    outcome: RecordOutcome,
    every_n_ticks: u64,
    last_tick: Option<u64>,
    last_flush: Instant,
    /// Something was written since the last flush.
    unflushed: bool,
}

impl Writer {
    /// Polls the queues rather than waiting on them: a waiting receiver would make
    /// every `try_send` wake it with a system call, inside the supervisor's tick.
    fn run(
        mut self,
        ticks: &Receiver<TickSample>,
        events: &Receiver<RecordEvent>,
    ) -> RecordOutcome {
        let mut pending: VecDeque<RecordEvent> = VecDeque::new();
        let mut ended = false;
        while !ended {
            std::thread::sleep(POLL);
            self.stop_if_disk_nearly_full();
            let mut fault = false;
            loop {
                let sample = match ticks.try_recv() {
                    Ok(sample) => sample,
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => {
                        ended = true;
                        break;
                    }
                };
                // A tick's events are sent before it: write them first.
                pending.extend(events.try_iter());
                let tick = sample.status.tick;
                while let Some(event) = pending.pop_front_if(|e| e.tick <= tick) {
                    fault |= self.event(&event);
                }
                self.note_dropped(&sample);
                self.each_sink(|sink| sink.tick(&sample));
                self.outcome.ticks_recorded += 1;
                self.unflushed = true;
            }
            // Events of ticks not recorded (every Nth), or whose tick is on its way.
            pending.extend(events.try_iter());
            while let Some(event) = pending.pop_front() {
                fault |= self.event(&event);
            }
            if fault || (self.unflushed && self.last_flush.elapsed() >= FLUSH_EVERY) {
                self.each_sink(|sink| sink.flush());
                self.last_flush = Instant::now();
                self.unflushed = false;
            }
        }
        self.each_sink(|sink| sink.finish());
        self.outcome
    }

    /// Close every file, said once, when the disk is nearly full: the queues are still
    /// emptied, so the supervisor never notices.
    fn stop_if_disk_nearly_full(&mut self) {
        let Some(why) = self.space.as_mut().and_then(SpaceWatch::nearly_full) else {
            return;
        };
        self.each_sink(|sink| sink.finish());
        self.sinks.iter_mut().for_each(|slot| *slot = None);
        self.space = None;
        tracing::warn!("{why}");
        self.outcome.problems.push(why);
    }

    /// Write one event; true if it is a fault (the files are flushed at once).
    fn event(&mut self, event: &RecordEvent) -> bool {
        self.each_sink(|sink| sink.event(event));
        self.outcome.events_recorded += 1;
        self.unflushed = true;
        matches!(event.kind, EventKind::Fault(_))
    }

    /// A gap in the tick numbers is ticks the queue dropped: say so where it happened.
    fn note_dropped(&mut self, sample: &TickSample) {
        let tick = sample.status.tick;
        if let Some(last) = self.last_tick.replace(tick) {
            let missing = tick.saturating_sub(last) / self.every_n_ticks;
            if missing > 1 {
                let event = RecordEvent {
                    t_s: sample.status.t_s,
                    tick,
                    kind: EventKind::Dropped { ticks: missing - 1 },
                };
                self.event(&event);
            }
        }
    }

    /// Do `work` on every sink still working; give up a sink that fails, with a warning
    /// that names its files. The robot runs on without it.
    fn each_sink(&mut self, mut work: impl FnMut(&mut dyn Sink) -> io::Result<()>) {
        for slot in &mut self.sinks {
            let Some(sink) = slot else { continue };
            if let Err(e) = work(sink.as_mut()) {
                let problem = format!(
                    "cannot write the run record {}: {e}; recording stopped, the robot runs on",
                    sink.files().join(", ")
                );
                tracing::warn!("{problem}");
                self.outcome.problems.push(problem);
                *slot = None;
            }
        }
    }
}
