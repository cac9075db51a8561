//! `mechweed record summary latest` and `[record] keep`, through the real program, in
//! a record folder of its own (--set record.folder=DIR).

use crate::common;

use common::{mechweed, text};

use std::path::Path;
use std::process::Output;

fn folder_setting(folder: &Path) -> String {
    format!("record.folder={}", folder.display())
}

/// A one-second headless run recording into `folder`, keeping `keep` records.
fn run(folder: &Path, keep: &str) -> Output {
    mechweed()
        .args(["run", "--headless", "--duration", "1", "--set"])
        .arg(folder_setting(folder))
        .arg("--set")
        .arg(format!("record.keep={keep}"))
        .output()
        .unwrap()
}

fn latest(folder: &Path) -> Output {
    mechweed()
        .args(["record", "summary", "latest", "--from-m", "0", "--set"])
        .arg(folder_setting(folder))
        .output()
        .unwrap()
}

fn touch(folder: &Path, name: &str) {
    std::fs::write(folder.join(name), "not a record\n").unwrap();
}

/// The file names in `folder`, sorted.
fn names(folder: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

/// Files the recorder would never make: they must outlive every `keep`.
const FOREIGN: [&str; 5] = [
    "notes.txt",
    "field-A.csv",
    "2000-01-01T00-00-00.csv.bak",
    "2000-01-01T00-00-00-1.csv",
    "zz-2000-01-01T00-00-00.mcap",
];

#[test]
fn latest_summarises_the_newest_of_several_records() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("records");
    let out = run(&folder, "all");
    assert!(out.status.success(), "{}", text(&out.stderr));
    // One real record; copies of it under older and newer names around it. `-10` is
    // newer than `-2` of the same second, though it sorts before it as text.
    let real = names(&folder);
    let real_csv = real
        .iter()
        .find(|n| n.ends_with(".csv") && !n.ends_with(".events.csv"))
        .unwrap()
        .clone();
    let real_events = real_csv.replace(".csv", ".events.csv");
    for name in ["2000-01-01T00-00-00", "2099-01-01T00-00-00-2"] {
        let copy = |from: &str, ending: &str| {
            std::fs::copy(folder.join(from), folder.join(format!("{name}{ending}"))).unwrap();
        };
        copy(&real_csv, ".csv");
        copy(&real_events, ".events.csv");
    }
    std::fs::copy(
        folder.join(real_csv.replace(".csv", ".mcap")),
        folder.join("2099-01-01T00-00-00-10.mcap"),
    )
    .unwrap();
    for name in FOREIGN {
        touch(&folder, name);
    }

    let out = latest(&folder);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    let newest = folder.join("2099-01-01T00-00-00-10.mcap");
    let (first, rest) = stdout.split_once('\n').unwrap();
    assert_eq!(first, format!("the newest record: {}", newest.display()));

    // The same summary as naming the file.
    let named = mechweed()
        .args(["record", "summary", "--from-m", "0"])
        .arg(&newest)
        .output()
        .unwrap();
    assert!(named.status.success(), "{}", text(&named.stderr));
    assert_eq!(rest, text(&named.stdout));
    assert!(rest.contains("duration"), "{rest}");
}

#[test]
fn latest_without_a_record_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    for name in FOREIGN {
        touch(dir.path(), name);
    }
    let missing = dir.path().join("no-such-folder");
    for folder in [dir.path(), missing.as_path()] {
        let out = latest(folder);
        assert!(!out.status.success());
        let stderr = text(&out.stderr);
        assert!(
            stderr.contains(&format!("no record in {}", folder.display())),
            "{stderr}"
        );
        assert!(text(&out.stdout).is_empty(), "{}", text(&out.stdout));
    }
}

/// Four old records (one only an .mcap), oldest first.
const OLD: [(&str, &[&str]); 4] = [
    (
        "2000-01-01T00-00-00",
        &[".csv", ".events.csv", ".mcap", ".run.json"],
    ),
    ("2000-01-01T00-00-00-2", &[".mcap"]),
    ("2000-01-01T00-00-00-10", &[".csv", ".events.csv"]),
    ("2000-01-02T00-00-00", &[".csv", ".events.csv", ".mcap"]),
];

fn old_records(folder: &Path) {
    std::fs::create_dir_all(folder).unwrap();
    for (name, endings) in OLD {
        for ending in endings {
            touch(folder, &format!("{name}{ending}"));
        }
    }
    for name in FOREIGN {
        touch(folder, name);
    }
}

#[test]
fn keep_removes_exactly_the_oldest_records_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("records");
    old_records(&folder);
    let before = names(&folder);

    // 4 old records and the new one; keep 3: the two oldest go.
    let out = run(&folder, "3");
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    let removed: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains("removed old record"))
        .collect();
    let said = |name: &str| {
        format!(
            "removed old record {}: keeping the newest 3",
            folder.join(name).display()
        )
    };
    assert_eq!(
        removed,
        [said("2000-01-01T00-00-00"), said("2000-01-01T00-00-00-2")]
    );

    let after = names(&folder);
    let gone: Vec<&String> = before.iter().filter(|n| !after.contains(n)).collect();
    assert_eq!(
        gone,
        [
            "2000-01-01T00-00-00-2.mcap",
            "2000-01-01T00-00-00.csv",
            "2000-01-01T00-00-00.events.csv",
            "2000-01-01T00-00-00.mcap",
            "2000-01-01T00-00-00.run.json",
        ]
    );
    for name in FOREIGN {
        assert!(after.iter().any(|n| n == name), "{name} was removed");
    }
    // The new record is there, all four files.
    let new: Vec<&String> = after.iter().filter(|n| !before.contains(n)).collect();
    assert_eq!(new.len(), 4, "{new:?}");
}

#[test]
fn keep_all_or_zero_removes_nothing() {
    for keep in ["all", "0"] {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("records");
        old_records(&folder);
        let before = names(&folder);
        let out = run(&folder, keep);
        let stdout = text(&out.stdout);
        assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
        assert!(!stdout.contains("removed old record"), "{stdout}");
        let after = names(&folder);
        assert!(before.iter().all(|n| after.contains(n)), "keep = {keep}");
        assert_eq!(after.len(), before.len() + 4, "keep = {keep}");
    }
}

#[test]
fn keep_that_is_not_a_number_is_an_error_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("records");
    old_records(&folder);
    let before = names(&folder);
    let out = run(&folder, "lots");
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(stderr.contains("[record] keep"), "{stderr}");
    assert!(
        stderr.contains("'lots' is not a number of records"),
        "{stderr}"
    );
    assert_eq!(names(&folder), before);
}

#[test]
fn keep_gb_removes_the_oldest_records_until_the_rest_fit() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("records");
    std::fs::create_dir_all(&folder).unwrap();
    // Sparse files: their size counts, the disk holds none of it.
    let sized = |name: &str, mb: u64| {
        let file = std::fs::File::create(folder.join(name)).unwrap();
        file.set_len(mb * 1_000_000).unwrap();
    };
    sized("2000-01-01T00-00-00.csv", 600);
    sized("2000-01-02T00-00-00.mcap", 600);
    sized("2000-01-03T00-00-00.csv", 300);
    touch(&folder, "notes.txt");
    let out = mechweed()
        .args(["run", "--headless", "--duration", "1", "--set"])
        .arg(folder_setting(&folder))
        .args(["--set", "record.keep=all", "--set", "record.keep_gb=1"])
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", text(&out.stderr));
    let removed: Vec<&str> = (stdout.lines())
        .filter(|l| l.contains("removed old record"))
        .collect();
    let said = format!(
        "removed old record {}: keeping the newest within 1 GB",
        folder.join("2000-01-01T00-00-00").display()
    );
    assert_eq!(removed, [said], "{stdout}");
    let after = names(&folder);
    assert!(!after.contains(&"2000-01-01T00-00-00.csv".to_string()));
    for kept in [
        "2000-01-02T00-00-00.mcap",
        "2000-01-03T00-00-00.csv",
        "notes.txt",
    ] {
        assert!(
            after.contains(&kept.to_string()),
            "{kept} was removed: {after:?}"
        );
    }
}
