//! A disk that fills during a run: the recorder stops, closes what it wrote, says so
//! once, and the run goes on.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use super::SpaceWatch;
use crate::config::Settings;
use crate::record::{Delivery, new_sinks, read, start_watched};
use crate::state::modes::Mode;
use crate::threads::lockstep::Lockstep;

/// The fake disk's free bytes.
static FREE: AtomicU64 = AtomicU64::new(u64::MAX);

fn fake_free(_: &std::path::Path) -> Option<u64> {
    Some(FREE.load(Ordering::Relaxed))
}

#[test]
fn a_disk_nearly_full_stops_the_record_with_its_files_closed_and_the_run_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let mut settings = Settings::shipped();
    settings.record.folder = dir.path().to_path_buf();
    let sinks = new_sinks(&settings.record, "2026-12-02T10-00-00", 0, 1, None).unwrap();
    let watch = SpaceWatch::with(dir.path(), fake_free, 1_000_000, Duration::from_millis(20));
    let (tap, recorder) =
        start_watched(sinks, 1, Delivery::WaitForRoom, None, Some(watch)).unwrap();
    let files = recorder.files().to_vec();
    let mut sim = Lockstep::new(&settings, Mode::Autonomous);
    sim.record_into(tap);
    sim.run_for(1.0);
    std::thread::sleep(Duration::from_millis(300));
    FREE.store(900_000, Ordering::Relaxed);
    std::thread::sleep(Duration::from_millis(300));
    sim.run_for(1.0);
    sim.stop_recording();
    let outcome = recorder.finish();

    let said: Vec<&String> = outcome
        .problems
        .iter()
        .filter(|p| p.contains("nearly full"))
        .collect();
    assert_eq!(said.len(), 1, "said once: {:?}", outcome.problems);
    assert!(said[0].contains("the robot runs on"), "{said:?}");
    // The first second is in the files, the second is not; the MCAP file was closed
    // properly (its index written), as at the end of a run.
    let csv = std::fs::read_to_string(&files[0]).unwrap();
    let rows = csv.lines().count() - 1;
    assert!((100..200).contains(&rows), "{rows} rows");
    let mcap = read::read(std::path::Path::new(&files[2]), &["t_s"]).unwrap();
    assert_eq!(mcap.ticks.rows.len(), rows);
    assert!(mcap.notes.is_empty(), "closed: {:?}", mcap.notes);
    // The supervisor went on: every tick was taken off the queue.
    assert_eq!(outcome.ticks_recorded + outcome.ticks_dropped, 200);
}
