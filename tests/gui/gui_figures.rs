//! One run, one figure everywhere: the Liu-Layland load the GUI shows is the run
//! summary's, and the summary's tool cross-track and distance are `record summary`'s of
//! the run's own record, at the precision each shows.

use std::path::PathBuf;

use egui_kittest::kittest::{NodeT, Queryable};
use mechweed::config::Settings;
use mechweed::console::report::closing_summary;
use mechweed::state::modes::Mode;

use crate::common::{mechweed, text};
use crate::gui_harness::gui_from;

/// The one line of `said` that starts with `start`.
fn line<'a>(said: &'a str, start: &str) -> &'a str {
    let mut found = said.lines().map(str::trim).filter(|l| l.starts_with(start));
    let one = found
        .next()
        .unwrap_or_else(|| panic!("no '{start}' in\n{said}"));
    assert!(found.next().is_none(), "two '{start}' in\n{said}");
    one
}

/// The word after `label` in `line`, as printed: "max 1.18 cm" -> "1.18".
fn figure<'a>(line: &'a str, label: &str) -> &'a str {
    let at = line
        .find(label)
        .unwrap_or_else(|| panic!("no '{label}' in '{line}'"));
    let rest = line[at + label.len()..].trim_start();
    rest.split([' ', ',']).next().unwrap_or_default()
}

#[test]
fn the_gui_the_run_summary_and_record_summary_give_one_load_and_one_cross_track() {
    let _one = crate::one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    let mut settings = Settings::shipped();
    settings.record.enabled = true;
    settings.record.folder = dir.path().to_path_buf();
    // Figures from 0.5 m on, so that a few metres of driving give them.
    settings.sim.cross_track_from_m = 0.5;
    let mut gui = gui_from(settings, None, |_| {});
    gui.power_up();
    gui.click("Autonomous");
    gui.wait_until("autonomous", |app| app.view.status.mode == Mode::Autonomous);
    gui.wait_until("the robot drives 2.5 m", |app| {
        app.view.truth.distance_m > 2.5
    });

    // The window closes before the controller stops: here it draws once more after the
    // threads have ended, showing the figures they published last, those of their last
    // tick.
    let outcome = gui.stop_controller();
    gui.look();
    gui.harness.step();
    gui.harness.step();
    let shown = gui
        .harness
        .query_all_by_label_contains("Liu-Layland:")
        // A label keeps its text as its value (AccessKit).
        .filter_map(|node| node.accesskit_node().value())
        .next()
        .expect("the Status tab shows the Liu-Layland check");
    let summary = closing_summary(&outcome);
    let summarised = line(&summary, "Liu-Layland:");
    assert_eq!(
        figure(&shown, "load"),
        figure(summarised, "load"),
        "GUI: {shown}\nsummary: {summarised}"
    );
    assert_eq!(shown, summarised);
    let load: f64 = figure(summarised, "load").parse().unwrap();
    assert!(load > 0.0, "a load was measured: {summarised}");

    assert_eq!(outcome.record.ticks_dropped, 0, "a whole record: {summary}");
    let file = |ending: &str| {
        let found = (outcome.record.files.iter())
            .find(|f| f.ends_with(ending) && !f.ends_with(".events.csv"));
        PathBuf::from(found.unwrap_or_else(|| panic!("no {ending} in {summary}")))
    };
    let reported = line(&summary, "tool cross-track (");
    let final_line = line(&summary, "final mode:");
    for record in [file(".csv"), file(".mcap")] {
        let out = mechweed()
            .args(["record", "summary", "--from-m", "0.5"])
            .arg(&record)
            .output()
            .unwrap();
        let said = text(&out.stdout);
        assert!(out.status.success(), "{said}{}", text(&out.stderr));
        let recorded = line(&said, "tool cross-track (");
        for label in ["max", "RMS", "mean", "p95", "over"] {
            assert_eq!(
                figure(reported, label),
                figure(recorded, label),
                "{label}: run summary {reported}\nrecord summary {recorded}"
            );
        }
        assert_eq!(reported, recorded);
        let over_m: f64 = figure(recorded, "over").parse().unwrap();
        assert!(over_m > 1.0, "figures over more than a metre: {recorded}");
        assert_eq!(
            figure(final_line, "distance"),
            figure(line(&said, "distance:"), "distance:"),
            "run summary: {final_line}\nrecord summary: {said}"
        );
    }
}
