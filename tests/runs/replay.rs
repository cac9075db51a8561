//! `mechweed replay`: a record of a lockstep run and of a real-thread run give every
//! output again; a changed fault limit reports the fault that would have tripped, at
//! its tick; a truncated or edited record is reported or refused, never a panic.

use crate::common;

use std::path::{Path, PathBuf};

use common::{mechweed, settings_with, test_run_settings, text};
use mechweed::record::{self, Delivery};
use mechweed::replay::{ReplayOptions, replay};
use mechweed::state::modes::Mode;
use mechweed::threads::lockstep::Lockstep;

fn options(record: &Path, set: &[&str]) -> ReplayOptions {
    ReplayOptions {
        record: record.to_path_buf(),
        set: set.iter().map(|s| s.to_string()).collect(),
        from_s: 0.0,
        to_s: f64::INFINITY,
    }
}

fn the(files: &[String], ending: &str) -> PathBuf {
    let file = files
        .iter()
        .find(|f| f.ends_with(ending) && !f.ends_with(".events.csv"));
    PathBuf::from(file.unwrap_or_else(|| panic!("no {ending} in {files:?}")))
}

#[test]
fn a_lockstep_run_with_an_estop_and_a_power_up_replays_to_the_same_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let folder = format!("record.folder={}", dir.path().display());
    let events = "3 estop_front, 4 estop_release, 5 power_up, 6 mode autonomous";
    let settings = settings_with(events, &[&folder]);
    let (tap, recorder) = record::start(&settings, None, Delivery::WaitForRoom).unwrap();
    let mut sim = Lockstep::new(&settings, Mode::Autonomous);
    sim.record_into(tap);
    sim.run_for(8.0);
    sim.stop_recording();
    let files = recorder.finish().files;
    for ending in [".csv", ".mcap"] {
        let outcome = replay(&options(&the(&files, ending), &[])).unwrap();
        assert_eq!(outcome.ticks, 800, "{ending}");
        assert_eq!(outcome.first_difference, None, "{ending}");
        // Power up and autonomous at the start, power up and autonomous again after
        // the e-stop: each given at its tick, each answered as in the run.
        assert!(outcome.requests >= 4, "{}", outcome.requests);
        let words: Vec<&str> = outcome
            .faults_replayed
            .iter()
            .map(|f| f.words.as_str())
            .collect();
        assert_eq!(
            words,
            ["front emergency stop pressed (or its wire is broken)"]
        );
        assert_eq!(
            outcome.faults_replayed[0].tick,
            outcome.faults_recorded[0].tick
        );
        // The steering law, made again from the recorded estimates at the recorded
        // times, within its stated tolerance.
        let steer = &outcome.steer;
        assert!(steer.commands > 60, "{steer:?}");
        assert_eq!(steer.beyond, 0, "{steer:?}");
    }
    // --from and --to: a second of the run compared (both ends included: 2.00 s to
    // 3.00 s is 101 ticks), the run still replayed whole.
    let csv = the(&files, ".csv");
    let window = ReplayOptions {
        from_s: 2.0,
        to_s: 3.0,
        ..options(&csv, &[])
    };
    let outcome = replay(&window).unwrap();
    assert_eq!((outcome.ticks, outcome.compared), (800, 101));
    assert_eq!(outcome.first_difference, None);
    damaged_copies_never_panic(&csv);
}

/// Records damaged at random (a cell changed, a line dropped or repeated, the file cut
/// anywhere): each is replayed or refused with a reason, and nothing panics.
fn damaged_copies_never_panic(csv: &Path) {
    use rand::{Rng, SeedableRng};
    let text = std::fs::read_to_string(csv).unwrap();
    let stem = csv.file_stem().unwrap().to_string_lossy().to_string();
    let dir = csv.parent().unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let garbage = [
        "",
        "x",
        "-1",
        "1e999",
        "NaN",
        "2.5",
        "\"",
        "left",
        "99999999999999999999",
    ];
    for n in 0..60 {
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let at = rng.random_range(0..lines.len());
        match n % 4 {
            0 => {
                let mut cells: Vec<String> = lines[at].split(',').map(String::from).collect();
                let k = rng.random_range(0..cells.len());
                cells[k] = garbage[rng.random_range(0..garbage.len())].to_string();
                lines[at] = cells.join(",");
            }
            1 => {
                lines.remove(at);
            }
            2 => lines.insert(at, lines[at].clone()),
            _ => {}
        }
        let mut damaged = lines.join("\n") + "\n";
        if n % 4 == 3 {
            damaged.truncate(rng.random_range(0..damaged.len()));
        }
        let name = format!("damaged-{n}");
        std::fs::write(dir.join(format!("{name}.csv")), damaged).unwrap();
        for ending in [".events.csv", ".run.json"] {
            std::fs::copy(
                dir.join(format!("{stem}{ending}")),
                dir.join(format!("{name}{ending}")),
            )
            .unwrap();
        }
        let outcome = replay(&options(&dir.join(format!("{name}.csv")), &[]));
        if let Err(why) = &outcome {
            assert!(why.contains(&name), "the reason names the file: {why}");
        }
    }
}

/// A real-thread run of the program: autonomous, the battery sagging to 22 V at 3 s.
fn real_run(dir: &Path) -> PathBuf {
    let out = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "6",
        ])
        .args(["--set", "sim.events=3 battery 22"])
        .args(test_run_settings(dir))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let csv = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            let name = p.to_string_lossy();
            name.ends_with(".csv") && !name.ends_with(".events.csv")
        });
    csv.expect("the run left a record")
}

fn replay_command(args: &[&str]) -> (bool, String) {
    let out = mechweed().arg("replay").args(args).output().unwrap();
    let said = format!("{}{}", text(&out.stdout), text(&out.stderr));
    (out.status.success(), said)
}

#[test]
fn a_real_run_replays_exactly_a_changed_limit_shows_its_fault_and_edits_are_caught() {
    let dir = tempfile::tempdir().unwrap();
    let csv = real_run(dir.path());
    let csv_text = std::fs::read_to_string(&csv).unwrap();
    let name = csv.to_string_lossy().to_string();
    let mcap = name.replace(".csv", ".mcap");

    // The code in hand is the code that drove: every output again, from either file.
    for file in [&name, &mcap] {
        let (ok, said) = replay_command(&[file]);
        assert!(
            ok && said.contains("ticks, outputs identical to the record: the mode, the amplifiers"),
            "{said}"
        );
        assert!(
            said.contains("steer commands: ") && said.contains(" made again by the steering law"),
            "{said}"
        );
        // Steer commands beyond the tolerance are said apart, with why, never as a
        // difference of the outputs.
        assert!(
            !said.contains(" differ from it by at most")
                || said.contains("such differences are expected"),
            "{said}"
        );
    }
    // The steering law made again from the recorded estimates: within the tolerance,
    // but for the steer commands the record could not keep (the replay says why). On a
    // busy machine (the whole test suite at once) that was more than 1 in 20; a law that is
    // not the one that drove differs in nearly every command.
    let same = dir.path().join("same.json");
    let (ok, said) = replay_command(&[&name, "--json", &same.to_string_lossy()]);
    assert!(ok, "{said}");
    let same: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&same).unwrap()).unwrap();
    let commands = same["steer"]["commands"].as_u64().unwrap();
    let beyond = same["steer"]["beyond_tolerance"].as_u64().unwrap();
    // A missed command moves the law's integral and filters for a while: in one full
    // run of the suite 71 of 108 commands were beyond the tolerance, none by more than
    // 0.23 deg. Replayed with [steer] ki_per_m2 1.0 instead of 0.8, 65 of 102 were
    // beyond, up to 0.57 deg; with lookahead_m 0.7 instead of 0.8, 87, up to 1.6 deg.
    let worst_deg = same["steer"]["max_angle_diff_deg"].as_f64().unwrap();
    assert!(
        commands > 40 && (beyond * 4 <= commands || worst_deg < 0.4),
        "{said}"
    );

    // With the battery limit at 23 V the sag to 22 V at 3 s trips "battery low" after
    // [faults] battery_low_s (1 s): at the tick 1 s after the first tick below 23 V.
    let json = dir.path().join("whatif.json");
    let json_arg = json.to_string_lossy().to_string();
    let (ok, said) = replay_command(&[
        &name,
        "--set",
        "faults.battery_min_v=23",
        "--json",
        &json_arg,
    ]);
    assert!(ok, "{said}");
    let lines: Vec<&str> = csv_text.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (t_col, battery_col) = (col("t_s"), col("battery_v"));
    let low_s: f64 = (lines[1..].iter())
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[battery_col].parse::<f64>().unwrap() < 23.0)
        .map(|f| f[t_col].parse().unwrap())
        .expect("the battery sagged");
    let outcome: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let fault = &outcome["faults_replayed"][0];
    assert!(
        fault["fault"].as_str().unwrap().starts_with("battery low"),
        "{said}"
    );
    let t_fault = fault["t_s"].as_f64().unwrap();
    assert!(
        (t_fault - (low_s + 1.0)).abs() <= 0.015,
        "fault at {t_fault} s, low from {low_s} s\n{said}"
    );
    assert_eq!(
        outcome["faults_recorded"].as_array().unwrap().len(),
        0,
        "{said}"
    );
    assert!(
        said.contains("the run: no fault") && said.contains("the what-if: fault at"),
        "{said}"
    );
    assert!(
        outcome["first_difference"]["tick"].as_u64().is_some(),
        "{said}"
    );
    let whatif = name.replace(".csv", "-whatif.csv");
    let (ok, said) = replay_command(&[&whatif]);
    assert!(
        ok && said.contains("outputs identical"),
        "the what-if's own record replays: {said}"
    );

    edits_are_caught(dir.path(), &csv, &csv_text);
}

/// Copies of the record, each damaged one way.
fn edits_are_caught(dir: &Path, csv: &Path, csv_text: &str) {
    let stem = csv.file_stem().unwrap().to_string_lossy().to_string();
    let copy = |name: &str, ticks: &str| {
        let to = dir.join(format!("{name}.csv"));
        std::fs::write(&to, ticks).unwrap();
        for ending in [".events.csv", ".run.json"] {
            let from = dir.join(format!("{stem}{ending}"));
            std::fs::copy(from, dir.join(format!("{name}{ending}"))).unwrap();
        }
        to.to_string_lossy().to_string()
    };
    let lines: Vec<&str> = csv_text.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let amp = header.iter().position(|h| *h == "amp_left_v").unwrap();

    // Cut in the middle of a line: the ticks it has replay, and it says where it ends.
    let cut = &csv_text[..csv_text.len() / 2];
    let (ok, said) = replay_command(&[&copy("cut", cut)]);
    assert!(
        ok && said.contains("is incomplete") && said.contains("outputs identical"),
        "{said}"
    );

    // A tick taken out: refused, naming the gap.
    let mut gap: Vec<&str> = lines.clone();
    gap.remove(100);
    let (ok, said) = replay_command(&[&copy("gap", &(gap.join("\n") + "\n"))]);
    assert!(!ok && said.contains("tick 101 follows tick 99"), "{said}");

    // An output changed by hand: the replay names the tick and both values.
    let mut edited: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let mut fields: Vec<String> = edited[300].split(',').map(String::from).collect();
    let was = fields[amp].clone();
    fields[amp] = "9.5".into();
    edited[300] = fields.join(",");
    let (ok, said) = replay_command(&[&copy("edited", &(edited.join("\n") + "\n"))]);
    assert!(!ok, "{said}");
    assert!(
        said.contains("first difference at tick 300")
            && said.contains("amp_left_v: recorded 9.5, replayed"),
        "{said}"
    );
    assert!(
        said.contains(&format!("replayed {}", was.trim())) || was.is_empty(),
        "{said}"
    );

    // A cell that is not a number: refused with its line and column.
    fields[amp] = "lots".into();
    edited[300] = fields.join(",");
    let (ok, said) = replay_command(&[&copy("garbled", &(edited.join("\n") + "\n"))]);
    assert!(
        !ok && said.contains("line 301") && said.contains("amp_left_v = 'lots'"),
        "{said}"
    );

    // Without the settings beside it: refused, saying what is missing.
    let lone = copy("lone", csv_text);
    std::fs::remove_file(dir.join("lone.run.json")).unwrap();
    let (ok, said) = replay_command(&[&lone]);
    assert!(!ok && said.contains("lone.run.json beside it"), "{said}");

    // A request in the events that is not one: refused with its line.
    let bad_events = dir.join("badreq.events.csv");
    let ticks = copy("badreq", csv_text);
    let events = std::fs::read_to_string(&bad_events)
        .unwrap()
        .replace("power_up =>", "jump =>");
    std::fs::write(&bad_events, events).unwrap();
    let (ok, said) = replay_command(&[&ticks]);
    assert!(
        !ok && said.contains("'jump' is not a request") && said.contains("line 2"),
        "{said}"
    );
}

#[test]
fn a_record_that_is_not_there_is_said_to_be_missing() {
    // It used to blame the missing NAME.run.json beside it instead.
    let (ok, said) = replay_command(&["records/nope.csv"]);
    assert!(!ok, "{said}");
    assert!(said.contains("records/nope.csv: no such file"), "{said}");
    assert!(!said.contains("run.json"), "{said}");
}
