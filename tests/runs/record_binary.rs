//! Run records made by the real program, and `mechweed record summary` on them.

use crate::common;

use common::{mechweed, text};

use std::path::{Path, PathBuf};
use std::process::Output;

fn summary(file: &Path) -> Output {
    mechweed()
        .args(["record", "summary", "--from-m", "0"])
        .arg(file)
        .output()
        .unwrap()
}

/// The number printed after `label` in `out`, e.g. "mean 0.31 cm" -> 0.31.
fn figure(out: &str, label: &str) -> f64 {
    let at = out
        .find(label)
        .unwrap_or_else(|| panic!("no '{label}' in\n{out}"))
        + label.len();
    let number: String = out[at..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
        .collect();
    number
        .parse()
        .unwrap_or_else(|_| panic!("'{label}' {number}"))
}

/// Mean, RMS and max of the tool's cross-track error (cm) by true distance, worked
/// out here from the CSV on its own, without the program's reader.
fn cross_track_from_csv(csv: &str) -> (f64, f64, f64) {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (e, d, done) = (
        col("sim_tool_cross_track_m"),
        col("sim_distance_m"),
        col("sim_row_done"),
    );
    let (mut sum, mut sum_sq, mut max, mut total) = (0.0, 0.0, 0.0f64, 0.0);
    let mut last_d: Option<f64> = None;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let error_m: f64 = cells[e].parse().unwrap();
        let d_m: f64 = cells[d].parse().unwrap();
        let w = last_d.map_or(0.0, |last| d_m - last);
        last_d = Some(d_m);
        if w > 0.0 && cells[done] == "0" {
            sum += error_m * w;
            sum_sq += error_m * error_m * w;
            max = max.max(error_m.abs());
            total += w;
        }
    }
    (
        sum / total * 100.0,
        (sum_sq / total).sqrt() * 100.0,
        max * 100.0,
    )
}

#[test]
fn record_summary_of_a_real_run_prints_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("records");
    let report_path = dir.path().join("report.json");
    let out = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "3",
        ])
        .arg("--set")
        .arg(format!("record.folder={}", folder.display()))
        .args(["--set", "sim.events=2.5 estop_front", "--report"])
        .arg(&report_path)
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    // The e-stop ends the run in Fault: exit status 3.
    assert_eq!(
        out.status.code(),
        Some(3),
        "{stdout}\n{}",
        text(&out.stderr)
    );
    assert!(
        stdout.contains(&format!("recording into {}", folder.display())),
        "{stdout}"
    );
    assert!(stdout.contains(" dropped)"), "{stdout}");

    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 4, "{names:?}");
    let stem = names[0].strip_suffix(".csv").unwrap();
    assert_eq!(stem.len(), "2026-11-23T07-43-12".len(), "{names:?}");
    assert_eq!(names[1], format!("{stem}.events.csv"));
    assert_eq!(names[2], format!("{stem}.mcap"));
    assert_eq!(
        names[3],
        format!("{stem}.run.json"),
        "the settings, for a replay"
    );

    let from_csv = summary(&files[0]);
    let from_mcap = summary(&files[2]);
    let (csv_out, mcap_out) = (text(&from_csv.stdout), text(&from_mcap.stdout));
    assert!(from_csv.status.success(), "{}", text(&from_csv.stderr));
    assert!(from_mcap.status.success(), "{}", text(&from_mcap.stderr));
    // Both formats tell the same story (all but the first line, which names the file).
    let body = |s: &str| s.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(body(&csv_out), body(&mcap_out));

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    // The record runs from the first tick to the run's end at 3 s; when the first tick
    // comes depends on how busy the machine is at the start, so it is not checked here.
    let (first_s, last_s) = (figure(&csv_out, "t = "), figure(&csv_out, " .. "));
    let duration_s = figure(&csv_out, "duration");
    assert!((2.95..=3.05).contains(&last_s), "{csv_out}");
    assert!((duration_s - (last_s - first_s)).abs() < 0.015, "{csv_out}");
    let distance_m = figure(&csv_out, "distance:");
    let reported_m = report["distance_m"].as_f64().unwrap();
    assert!(
        (distance_m - reported_m).abs() < 0.02,
        "{csv_out}\n{report:#}"
    );
    assert!(distance_m > 0.3, "{csv_out}");
    let fault_s = figure(&csv_out, "fault at");
    assert!((fault_s - 2.5).abs() < 0.1, "{csv_out}");
    assert!(
        csv_out.contains("s: front emergency stop pressed (or its wire is broken)"),
        "{csv_out}"
    );
    assert_eq!(
        figure(&csv_out, "recorded,"),
        0.0,
        "no dropped ticks: {csv_out}"
    );
    assert_eq!(
        report["record"]["ticks_recorded"].as_u64().unwrap() as f64,
        figure(&csv_out, "ticks:")
    );

    let (mean_cm, rms_cm, max_cm) =
        cross_track_from_csv(&std::fs::read_to_string(&files[0]).unwrap());
    for (label, expected) in [("mean", mean_cm), ("RMS", rms_cm), ("max", max_cm)] {
        let printed = figure(&csv_out, label);
        assert!(
            (printed - expected).abs() < 0.006,
            "{label}: {printed} vs {expected}\n{csv_out}"
        );
    }
    let p95 = figure(&csv_out, "p95");
    assert!(p95 <= max_cm + 0.006 && p95 > 0.0, "{csv_out}");
}

#[test]
fn an_unwritable_record_folder_is_a_warning_and_the_run_completes() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.txt");
    std::fs::write(&plain, "a file, not a folder").unwrap();
    let folder = plain.join("records");
    let out = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "1.5",
        ])
        .arg("--set")
        .arg(format!("record.folder={}", folder.display()))
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr.contains(&format!("cannot record this run in {}", folder.display())),
        "{stderr}"
    );
    assert!(stdout.contains("final mode: autonomous"), "{stdout}");
    assert!(stdout.contains("record: none"), "{stdout}");
}

#[test]
fn record_summary_of_a_broken_file_names_it_and_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let header = "t_s,tick,mode,distance_m,sim_tool_cross_track_m,sim_distance_m,sim_row_done";
    let cases: [(&str, &[u8], &str); 5] = [
        (
            "notes.csv",
            b"hello\nworld\n",
            "not a mechweed record: the first line has no column t_s",
        ),
        (
            "noise.csv",
            &[0xff, 0xfe, 0x00, 0x81],
            "neither a CSV record (not text) nor an MCAP file",
        ),
        (
            "cut.mcap",
            b"\x89MCAP0\r\n\x01\x02",
            "not a readable MCAP file",
        ),
        ("empty.csv", b"", "the file is empty"),
        ("bad.csv", b"", "line 3: distance_m = 'abc' is not a number"),
    ];
    for (name, bytes, expected) in cases {
        let path = dir.path().join(name);
        if name == "bad.csv" {
            let rows = format!("{header}\n0.01,1,halt,0,,,\n0.02,2,halt,abc,,,\n");
            std::fs::write(&path, rows).unwrap();
        } else {
            std::fs::write(&path, bytes).unwrap();
        }
        let out = summary(&path);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {}", text(&out.stdout));
        assert!(stderr.contains(&path.display().to_string()), "{stderr}");
        assert!(stderr.contains(expected), "{name}: {stderr}");
    }
    let missing = dir.path().join("missing.mcap");
    let stderr = text(&summary(&missing).stderr);
    assert!(stderr.contains("missing.mcap: cannot read it"), "{stderr}");
}
