//! A recorded lockstep run reads back the same from its CSV and its MCAP, with the
//! values the supervisor had, and a fault in mid-run is in the record with its cause.

use crate::common;

use std::path::{Path, PathBuf};

use common::{autonomous, settings_with};
use mechweed_core::record::read::{Cell, Table, read};
use mechweed_core::record::{self, Delivery, RecordOutcome, column_names};
use mechweed_core::threads::lockstep::Lockstep;

/// What the test saw of each supervisor tick, to compare with the record.
struct Seen {
    t_s: f64,
    mode: &'static str,
    speed_mps: f64,
    amp_steer_v: f64,
    law_tool_offset_m: f64,
    cross_track_m: f64,
}

/// Run `seconds` of the default row with `events`, recorded into `folder`.
fn recorded(folder: &Path, events: &str, seconds: f64) -> (Lockstep, Vec<Seen>, RecordOutcome) {
    let mut settings = settings_with(events, &[]);
    settings.record.folder = folder.to_path_buf();
    let (tap, recorder) = record::start(&settings, None, Delivery::WaitForRoom).unwrap();
    let mut sim = autonomous(&settings);
    sim.record_into(tap);
    let mut seen = Vec::new();
    let end_s = seconds - 1e-9;
    while sim.now_s() < end_s {
        sim.tick();
        let st = sim.supervisor.status();
        seen.push(Seen {
            t_s: st.t_s,
            mode: st.mode.name(),
            speed_mps: st.measured.speed_mps,
            amp_steer_v: st.outputs.amp_steer_v,
            law_tool_offset_m: sim.steer_command.law.tool_offset_m,
            cross_track_m: sim.robot.truth().tool_cross_track_m,
        });
    }
    sim.stop_recording();
    let outcome = recorder.finish();
    (sim, seen, outcome)
}

/// The record's tick CSV (not its .events.csv) or its MCAP file.
fn file_ending(outcome: &RecordOutcome, ending: &str) -> PathBuf {
    let name = outcome
        .files
        .iter()
        .find(|f| f.ends_with(ending) && !f.ends_with(".events.csv"));
    PathBuf::from(name.unwrap_or_else(|| panic!("no {ending} in {:?}", outcome.files)))
}

fn num(table: &Table, row: usize, name: &str) -> f64 {
    let col = table.column(name).unwrap();
    table.number(row, col).unwrap().unwrap_or(f64::NAN)
}

#[test]
fn a_lockstep_record_reads_back_the_same_from_csv_and_mcap() {
    let dir = tempfile::tempdir().unwrap();
    let (_, seen, outcome) = recorded(dir.path(), "", 8.0);
    assert_eq!(outcome.ticks_recorded, 800, "{outcome:?}");
    assert_eq!(outcome.ticks_dropped, 0);
    assert!(outcome.problems.is_empty(), "{outcome:?}");
    assert_eq!(outcome.files.len(), 3, "{outcome:?}");

    let names: Vec<&str> = column_names().collect();
    let csv = read(&file_ending(&outcome, ".csv"), &names).unwrap_or_else(|e| panic!("{e}"));
    let mcap = read(&file_ending(&outcome, ".mcap"), &names).unwrap();
    assert!(csv.notes.is_empty() && mcap.notes.is_empty());
    assert_eq!(csv.ticks.rows.len(), seen.len());
    assert_eq!(mcap.ticks.rows.len(), seen.len());
    // Every column of every tick, the same in both formats.
    for (row, (a, b)) in csv.ticks.rows.iter().zip(&mcap.ticks.rows).enumerate() {
        assert_eq!(a, b, "tick {row} differs between CSV and MCAP");
    }
    // And the values are the ones the supervisor, the steering law and the plant had.
    let t = &csv.ticks;
    let mode = t.column("mode").unwrap();
    for (row, s) in seen.iter().enumerate() {
        assert_eq!(num(t, row, "t_s"), s.t_s);
        assert_eq!(t.rows[row][mode], Cell::Text(s.mode.to_string()));
        assert_eq!(num(t, row, "speed_mps"), s.speed_mps);
        assert_eq!(num(t, row, "amp_steer_v"), s.amp_steer_v);
        assert_eq!(num(t, row, "law_tool_offset_m"), s.law_tool_offset_m);
        assert_eq!(num(t, row, "sim_tool_cross_track_m"), s.cross_track_m);
    }
    let last = seen.len() - 1;
    assert_eq!(seen[last].mode, "autonomous");
    assert!(num(t, last, "speed_mps") > 0.3, "it drove");
    assert!(
        num(t, last, "cam_age_s") < 0.5,
        "a fresh camera estimate was in use"
    );
    let events = csv.events.unwrap();
    assert_eq!(
        events.rows,
        mcap.events.unwrap().rows,
        "events alike in both"
    );
    assert!(
        events
            .rows
            .iter()
            .any(|r| r[3] == Cell::Text("halt -> autonomous".into()))
    );
}

#[test]
fn a_fault_in_mid_run_is_in_the_record_with_its_cause() {
    let dir = tempfile::tempdir().unwrap();
    let (sim, _, outcome) = recorded(dir.path(), "3 estop_front", 5.0);
    let fault = sim.supervisor.faults()[0];
    for file in [
        file_ending(&outcome, ".csv"),
        file_ending(&outcome, ".mcap"),
    ] {
        let record = read(&file, &["t_s", "mode", "amp_left_v"]).unwrap();
        let events = record.events.unwrap();
        let faults: Vec<&Vec<Cell>> = events
            .rows
            .iter()
            .filter(|r| r[2] == Cell::Text("fault".into()))
            .collect();
        assert_eq!(faults.len(), 1, "{file:?}: {events:?}");
        assert_eq!(faults[0][0], Cell::Num(fault.t_s));
        assert_eq!(faults[0][1], Cell::Num(fault.tick_seen as f64));
        let Cell::Text(cause) = &faults[0][3] else {
            panic!()
        };
        assert!(cause.contains("front emergency stop pressed"), "{cause}");
        // From the fault's tick on, the record shows fault mode and safe outputs.
        let t = &record.ticks;
        for row in (0..t.rows.len()).filter(|&r| num(t, r, "t_s") >= fault.t_s) {
            assert_eq!(t.rows[row][1], Cell::Text("fault".into()));
            assert_eq!(num(t, row, "amp_left_v"), 0.0);
        }
        let summary = record::summary::summarise(&file, 0.0).unwrap().text();
        assert!(
            summary.contains(&format!(
                "fault at {:.2} s: front emergency stop pressed",
                fault.t_s
            )),
            "{summary}"
        );
    }
}

#[test]
fn the_record_summary_agrees_with_the_run_report() {
    // 24 s at 0.5 m/s: about 11 m, so the report's figures (from 5 m) have 6 m to go on.
    let dir = tempfile::tempdir().unwrap();
    let (sim, _, outcome) = recorded(dir.path(), "", 24.0);
    let report = sim.robot.cross_track().summary();
    assert!(report.distance_m > 4.0, "{report:?}");
    let summary = record::summary::summarise(&file_ending(&outcome, ".mcap"), 5.0).unwrap();
    let c = summary.cross_track.unwrap();
    // The report samples each cm of travel, the record each 10 ms tick (0.5 cm).
    assert!(
        (c.distance_m - report.distance_m).abs() < 0.05,
        "{c:?} {report:?}"
    );
    for (record_cm, report_cm) in [
        (c.mean_cm, report.mean_cm),
        (c.sd_cm, report.sd_cm),
        (c.rms_cm, report.rms_cm),
        (c.p95_cm, report.p95_cm),
        (c.max_cm, report.max_cm),
    ] {
        assert!(
            (record_cm - report_cm).abs() < 0.03 + 0.05 * report_cm.abs(),
            "record {c:?}\nreport {report:?}"
        );
    }
    assert!((summary.last_t_s - 24.0).abs() < 0.02);
    assert_eq!(summary.ticks_dropped, 0);
}

#[test]
fn every_column_is_named_in_the_readme_and_the_spec() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let records = std::fs::read_to_string(format!("{root}/docs/records.md")).unwrap();
    let spec = std::fs::read_to_string(format!("{root}/docs/function_spec.md")).unwrap();
    let records_words: Vec<&str> = records.split_whitespace().collect();
    for name in column_names() {
        assert!(
            records_words.contains(&name),
            "docs/records.md does not list {name}"
        );
        assert!(
            spec.contains(&format!("| `{name}` |")),
            "function_spec.md: no row for {name}"
        );
    }
}
