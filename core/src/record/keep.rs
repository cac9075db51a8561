//! The records in a folder, as the recorder names them (files.rs): the newest one for
//! `record summary latest`, and the oldest ones deleted for `[record] keep`.
//!
//! A record is the group of files of one start time: NAME.csv, NAME.events.csv,
//! NAME.mcap and NAME.run.json, where NAME is a UTC stamp (2026-11-23T07-43-12), perhaps with `-2`, `-3`
//! for a second record of the same second. Any other file in the folder is not ours
//! and is never touched.

use std::path::{Path, PathBuf};

/// The endings the recorder gives its files; `.events.csv` before `.csv`.
const ENDINGS: [&str; 4] = [".events.csv", ".csv", ".mcap", ".run.json"];

/// One record: its name without ending, and its files.
#[derive(Debug)]
pub(crate) struct RecordGroup {
    pub name: String,
    pub files: Vec<PathBuf>,
}

/// The records in `folder`, oldest first. A folder that cannot be read has none.
pub(crate) fn records_in(folder: &Path) -> Vec<RecordGroup> {
    let mut groups: Vec<RecordGroup> = Vec::new();
    let Ok(entries) = std::fs::read_dir(folder) else {
        return groups;
    };
    for entry in entries.flatten() {
        let Ok(file_name) = entry.file_name().into_string() else {
            continue;
        };
        let Some(name) = record_name(&file_name) else {
            continue;
        };
        if !entry.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        match groups.iter_mut().find(|g| g.name == name) {
            Some(group) => group.files.push(entry.path()),
            None => groups.push(RecordGroup {
                name: name.to_string(),
                files: vec![entry.path()],
            }),
        }
    }
    groups.sort_by_key(|g| order(&g.name));
    groups
}

/// The record's name if `file_name` is one the recorder makes, else None.
fn record_name(file_name: &str) -> Option<&str> {
    let name = ENDINGS.iter().find_map(|e| file_name.strip_suffix(e))?;
    order(name).map(|_| name)
}

/// Sort key of a record name: (stamp, n), so that `…12-10` comes after `…12-2`.
/// None if the name is not a stamp, perhaps with `-N`.
fn order(name: &str) -> Option<(String, u32)> {
    let (stamp, rest) = name.split_at_checked(19)?;
    let pattern = "0000-00-00T00-00-00";
    let shaped = stamp.bytes().zip(pattern.bytes()).all(|(c, p)| {
        if p == b'0' {
            c.is_ascii_digit()
        } else {
            c == p
        }
    });
    if !shaped {
        return None;
    }
    let n = match rest {
        "" => 1,
        _ => rest.strip_prefix('-')?.parse().ok().filter(|n| *n >= 2)?,
    };
    Some((stamp.to_string(), n))
}

/// The record name of a file's path, if the recorder names it so.
pub(crate) fn record_of(path: &Path) -> Option<String> {
    let file_name = path.file_name()?.to_str()?;
    record_name(file_name).map(str::to_string)
}

/// The newest record's file to summarise: its .csv, else its .mcap.
pub fn latest(folder: &Path) -> Result<PathBuf, String> {
    let newest = records_in(folder).into_iter().rev().find_map(|g| {
        let pick = |ending: &str| g.files.iter().find(|f| ending_is(f, ending)).cloned();
        pick(".csv").or_else(|| pick(".mcap"))
    });
    newest.ok_or_else(|| {
        format!(
            "no record in {} ([record] folder): records are named by their start time, \
             for example 2026-11-23T07-43-12.csv",
            folder.display()
        )
    })
}

/// True if `file`'s ending is `ending`, not a longer one (NAME.events.csv is not
/// NAME's .csv).
fn ending_is(file: &Path, ending: &str) -> bool {
    let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
    name.is_some_and(|n| ENDINGS.iter().find(|e| n.ends_with(**e)) == Some(&ending))
}

/// Delete the oldest records beyond the newest `keep`, never the one named `current`
/// (the record this run is writing). Returns one line per record deleted, or per
/// file that could not be.
pub(crate) fn remove_oldest(folder: &Path, keep: usize, current: &str) -> Vec<String> {
    let groups = records_in(folder);
    let excess = groups.len().saturating_sub(keep);
    let mut lines = Vec::new();
    for group in groups.iter().filter(|g| g.name != current).take(excess) {
        remove(
            folder,
            group,
            &format!("keeping the newest {keep}"),
            &mut lines,
        );
    }
    lines
}

/// Delete the oldest records until the rest take at most `keep_gb` GB, never the one
/// named `current`. Returns one line per record deleted, or per file that could not be.
pub(crate) fn remove_beyond_size(folder: &Path, keep_gb: f64, current: &str) -> Vec<String> {
    let groups = records_in(folder);
    let limit_bytes = (keep_gb * 1e9) as u64;
    let mut total: u64 = groups.iter().map(size_bytes).sum();
    let mut lines = Vec::new();
    for group in groups.iter().filter(|g| g.name != current) {
        if total <= limit_bytes {
            break;
        }
        let before = size_bytes(group);
        remove(
            folder,
            group,
            &format!("keeping the newest within {keep_gb} GB"),
            &mut lines,
        );
        // What is gone: all of it, or without the files that were refused.
        total -= before - size_bytes(group).min(before);
    }
    lines
}

/// The bytes a record's files take now (a file gone counts nothing).
fn size_bytes(group: &RecordGroup) -> u64 {
    (group.files.iter())
        .filter_map(|f| std::fs::metadata(f).ok())
        .map(|m| m.len())
        .sum()
}

/// Delete one record's files, with a line saying so (`why`), or one per file refused.
fn remove(folder: &Path, group: &RecordGroup, why: &str, lines: &mut Vec<String>) {
    let mut failed = false;
    for file in &group.files {
        if let Err(e) = std::fs::remove_file(file) {
            failed = true;
            lines.push(format!(
                "could not remove old record file {}: {}",
                file.display(),
                e.kind()
            ));
        }
    }
    if !failed {
        lines.push(format!(
            "removed old record {}: {why}",
            folder.join(&group.name).display()
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_names_the_recorder_makes_are_records() {
        assert_eq!(
            record_name("2026-11-23T07-43-12.csv"),
            Some("2026-11-23T07-43-12")
        );
        assert_eq!(
            record_name("2026-11-23T07-43-12-2.events.csv"),
            Some("2026-11-23T07-43-12-2")
        );
        assert_eq!(record_name("2026-11-23T07-43-12.mcap.bak"), None);
        assert_eq!(record_name("notes.csv"), None);
        assert_eq!(record_name("2026-11-23T07-43-12-1.csv"), None);
        assert_eq!(record_name("2026-11-23 07-43-12.csv"), None);
        assert!(order("2026-11-23T07-43-12-10") > order("2026-11-23T07-43-12-2"));
        assert!(order("2026-11-23T07-43-13") > order("2026-11-23T07-43-12-10"));
    }
}
