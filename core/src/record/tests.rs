//! The promises of the recorder that the robot depends on: the tap never waits for
//! the disk, a record is on disk within a second, and a disk that fails is a warning
//! while the robot runs on.

use std::fs::File;
use std::io;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use super::csv::CsvSink;
use super::event::{EventKind, RecordEvent};
use super::row::{Given, TickSample};
use super::*;
use crate::camlink::LinkStatus;
use crate::config::Settings;
use crate::state::modes::Mode;
use crate::state::status::Status;
use crate::steer::SteerCommand;
use crate::threads::lockstep::Lockstep;

/// A writer on a slow disk: each tick takes 20 ms while `slow` is set.
struct SlowSink {
    slow: Arc<AtomicBool>,
    dropped_events: Arc<AtomicU64>,
}

impl Sink for SlowSink {
    fn tick(&mut self, _: &TickSample) -> io::Result<()> {
        if self.slow.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok(())
    }
    fn event(&mut self, event: &RecordEvent) -> io::Result<()> {
        if let EventKind::Dropped { ticks } = event.kind {
            self.dropped_events.fetch_add(ticks, Ordering::Relaxed);
        }
        Ok(())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
    fn finish(&mut self) -> io::Result<()> {
        Ok(())
    }
    fn files(&self) -> Vec<String> {
        vec!["slow disk".to_string()]
    }
}

#[test]
fn a_slow_disk_drops_and_counts_ticks_and_the_tap_never_waits() {
    let slow = Arc::new(AtomicBool::new(true));
    let dropped_events = Arc::new(AtomicU64::new(0));
    let sink = SlowSink {
        slow: Arc::clone(&slow),
        dropped_events: Arc::clone(&dropped_events),
    };
    let (mut tap, recorder) =
        start_with_sinks(vec![Box::new(sink)], 1, Delivery::NeverWait, None).unwrap();
    let (steer, link) = (SteerCommand::default(), LinkStatus::default());
    let mut status = Status::default();
    const OFFERED: u64 = 5000;
    let started = Instant::now();
    for tick in 1..=OFFERED {
        status.tick = tick;
        status.t_s = tick as f64 * 0.01;
        tap.offer(&status, &steer, &link, None, &Given::default());
    }
    let offering = started.elapsed();
    // The disk writes one tick in 20 ms: a tap that waited for room would have taken
    // (5000 - 1024) x 20 ms = 80 s.
    assert!(
        offering < Duration::from_secs(2),
        "offering took {offering:?}"
    );
    // The disk recovers; the next tick shows in the record where ticks went missing.
    slow.store(false, Ordering::Relaxed);
    std::thread::sleep(Duration::from_millis(500));
    status.tick = OFFERED + 1;
    tap.offer(&status, &steer, &link, None, &Given::default());
    drop(tap);
    let outcome = recorder.finish();
    assert!(outcome.ticks_dropped > 1000, "{outcome:?}");
    assert_eq!(outcome.ticks_recorded + outcome.ticks_dropped, OFFERED + 1);
    let marked = dropped_events.load(Ordering::Relaxed);
    assert_eq!(
        marked, outcome.ticks_dropped,
        "the record says how many are missing"
    );
}

/// A lockstep run on the shipped settings, recorded into `folder`.
fn recorded_run(folder: &std::path::Path, events: &str) -> (Lockstep, Recorder) {
    let mut settings = Settings::shipped();
    settings.sim.events = mechweed_hw::sim::parse_events(events).unwrap();
    settings.record.folder = folder.to_path_buf();
    let (tap, recorder) = start(&settings, None, Delivery::WaitForRoom).unwrap();
    let mut sim = Lockstep::new(&settings, Mode::Autonomous);
    sim.record_into(tap);
    (sim, recorder)
}

#[test]
fn what_was_recorded_is_on_disk_within_a_second() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sim, recorder) = recorded_run(dir.path(), "");
    sim.run_for(3.0);
    // The run goes on (the files stay open); a crash now would leave these files.
    std::thread::sleep(Duration::from_millis(1200));
    let files = recorder.files().to_vec();
    let csv = std::fs::read_to_string(&files[0]).unwrap();
    assert_eq!(csv.lines().count(), 1 + 300, "header and 3 s of ticks");
    let events = std::fs::read_to_string(&files[1]).unwrap();
    assert!(events.contains("halt -> autonomous"), "{events}");
    let mcap = read::read(std::path::Path::new(&files[2]), &["t_s"]).unwrap();
    assert_eq!(mcap.ticks.rows.len(), 300);
    assert!(
        mcap.notes.iter().any(|n| n.contains("ends abruptly")),
        "{:?}",
        mcap.notes
    );
    sim.stop_recording();
    let outcome = recorder.finish();
    assert_eq!((outcome.ticks_recorded, outcome.ticks_dropped), (300, 0));
    assert!(outcome.problems.is_empty(), "{outcome:?}");
    let mcap = read::read(std::path::Path::new(&files[2]), &["t_s"]).unwrap();
    assert!(mcap.notes.is_empty(), "finished: {:?}", mcap.notes);
}

#[test]
fn each_format_alone_and_every_nth_tick() {
    let dir = tempfile::tempdir().unwrap();
    for (formats, endings) in [
        (
            crate::config::RecordFormats::Csv,
            &[".csv", ".events.csv"][..],
        ),
        (crate::config::RecordFormats::Mcap, &[".mcap"][..]),
    ] {
        let mut settings = Settings::shipped();
        settings.record.folder = dir.path().join(format!("{formats:?}"));
        settings.record.formats = formats;
        settings.record.every_n_ticks = 10;
        let (tap, recorder) = start(&settings, None, Delivery::WaitForRoom).unwrap();
        let mut sim = Lockstep::new(&settings, Mode::Autonomous);
        sim.record_into(tap);
        sim.run_for(3.0);
        sim.stop_recording();
        let outcome = recorder.finish();
        assert_eq!(outcome.files.len(), endings.len(), "{outcome:?}");
        for (file, ending) in outcome.files.iter().zip(endings) {
            assert!(file.ends_with(ending), "{file}");
        }
        let record = read::read(std::path::Path::new(&outcome.files[0]), &["tick"]).unwrap();
        let ticks: Vec<Option<f64>> = (0..record.ticks.rows.len())
            .map(|row| record.ticks.number(row, 0).unwrap())
            .collect();
        let expected: Vec<Option<f64>> = (1..=30).map(|k| Some(k as f64 * 10.0)).collect();
        assert_eq!(ticks, expected, "{formats:?}: every 10th tick");
        let events = record.events.unwrap();
        let modes: Vec<String> = (0..events.rows.len())
            .filter(|&row| events.text(row, 2) == "mode")
            .map(|row| events.text(row, 3))
            .collect();
        assert_eq!(modes, ["halt -> autonomous"], "events of ticks between");
    }
}

#[test]
fn a_full_disk_is_a_warning_and_the_robot_runs_on() {
    let full = |name: &str| {
        let file = File::options().write(true).open("/dev/full").unwrap();
        (
            std::path::PathBuf::from(format!("/dev/full ({name})")),
            file,
        )
    };
    let sink = CsvSink::new(full("ticks"), full("events"));
    // The header fits the buffer; the disk says it is full at the first flush.
    let sink = sink.unwrap();
    let (tap, recorder) =
        start_with_sinks(vec![Box::new(sink)], 1, Delivery::WaitForRoom, None).unwrap();
    let mut sim = Lockstep::new(&Settings::shipped(), Mode::Autonomous);
    sim.record_into(tap);
    sim.run_for(4.0);
    assert_eq!(
        sim.supervisor.mode(),
        Mode::Autonomous,
        "the robot drives on"
    );
    assert!(sim.supervisor.status().measured.distance_m > 0.5);
    sim.stop_recording();
    let outcome = recorder.finish();
    assert_eq!(
        outcome.ticks_recorded, 400,
        "the queue was emptied all along"
    );
    assert_eq!(outcome.problems.len(), 1, "one warning: {outcome:?}");
    let problem = &outcome.problems[0];
    assert!(problem.contains("/dev/full (ticks)"), "{problem}");
    assert!(
        problem.contains("recording stopped, the robot runs on"),
        "{problem}"
    );
}

#[test]
fn a_folder_under_a_file_cannot_be_made_and_says_which() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.txt");
    std::fs::write(&plain, "not a folder").unwrap();
    let mut run_settings = Settings::shipped();
    run_settings.record.folder = plain.join("records");
    let settings = run_settings.record.clone();
    let err = start(&run_settings, None, Delivery::NeverWait)
        .err()
        .unwrap();
    assert_eq!(
        err,
        RecordError::CreateFolder {
            folder: settings.folder.clone(),
            error: io::ErrorKind::NotADirectory
        }
    );
    let why = err.to_string();
    assert!(
        why.starts_with(&format!(
            "cannot record this run in {}:",
            settings.folder.display()
        )),
        "{why}"
    );
    let (mut tap, recorder) = start_for_run(&run_settings, truth_of_a_robot());
    // The tap records nothing, and takes ticks as if nothing were wrong.
    tap.offer(
        &Status::default(),
        &SteerCommand::default(),
        &LinkStatus::default(),
        None,
        &Given::default(),
    );
    let outcome = recorder.finish();
    assert!(outcome.files.is_empty());
    assert!(outcome.problems[0].ends_with("the robot runs on without a record"));
}

fn truth_of_a_robot() -> mechweed_hw::sim::TruthHandle {
    let (camera, _robot_end) = mechweed_hw::sim::byte_pipe(64);
    let robot = mechweed_hw::sim::SimRobot::new(&Settings::shipped().sim, camera);
    mechweed_hw::sim::SimHw::new(robot).truth_handle()
}

#[test]
fn a_record_that_cannot_be_read_back_is_an_error_naming_the_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.csv");
    assert_eq!(
        read::read(&missing, &["t_s"]).unwrap_err(),
        RecordError::Read {
            file: missing,
            problem: ReadProblem::CannotRead(io::ErrorKind::NotFound)
        }
    );
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "t_s,tick\n0.01,1\n0.02,\"2\n").unwrap();
    let err = read::read(&bad, &["tick"]).unwrap_err();
    let RecordError::Read { file, problem } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(
        (file, problem),
        (&bad, &ReadProblem::UnclosedQuote { line: 3 })
    );
    std::fs::write(&bad, "t_s,tick\n0.01,1\n0.02,two\n").unwrap();
    let record = read::read(&bad, &["tick"]).unwrap();
    assert_eq!(
        record.ticks.number(1, 0).unwrap_err(),
        ReadProblem::NotANumber {
            place: Place::Line(3),
            column: "tick".into(),
            text: "two".into()
        }
    );
}
