//! Where a record goes: one set of files per run, named by its start time in UTC
//! (2026-11-23T07-43-12.csv), so that a folder of records sorts by time. The time is
//! formatted here from `SystemTime`: a date is all we need, not a time-zone library.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use super::error::RecordError;

/// "2026-11-23T07-43-12": ISO 8601 in UTC, with '-' for ':' (not allowed in file
/// names on Windows, where records are often opened).
pub fn utc_stamp(time: SystemTime) -> String {
    let secs = time
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let (days, of_day) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let (year, month, day) = civil_from_days(days);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}-{:02}-{:02}",
        of_day / 3600,
        of_day % 3600 / 60,
        of_day % 60
    )
}

/// The Gregorian date of a day number counted from 1970-01-01 (H. Hinnant's
/// `civil_from_days`: eras of 400 years, years starting on 1 March).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// The record's files, created new (never overwriting an older record).
pub(crate) struct NewFiles {
    /// (path, file) for each extension asked for, in the same order.
    pub files: Vec<(PathBuf, File)>,
}

/// Make `folder` if needed and create `{stamp}{ext}` for each extension. If a record
/// of that second exists already, `-2`, `-3` … are added to the name.
pub fn create(folder: &Path, stamp: &str, extensions: &[&str]) -> Result<NewFiles, RecordError> {
    std::fs::create_dir_all(folder).map_err(|e| RecordError::CreateFolder {
        folder: folder.to_path_buf(),
        error: e.kind(),
    })?;
    for n in 1..=100 {
        let name = if n == 1 {
            stamp.to_string()
        } else {
            format!("{stamp}-{n}")
        };
        let stem = folder.join(name);
        let paths: Vec<PathBuf> = extensions.iter().map(|e| with_suffix(&stem, e)).collect();
        if paths.iter().any(|p| p.exists()) {
            continue;
        }
        let mut files = Vec::new();
        for path in paths {
            let file = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
                .map_err(|e| RecordError::CreateFile {
                    folder: folder.to_path_buf(),
                    path: path.clone(),
                    error: e.kind(),
                })?;
            files.push((path, file));
        }
        return Ok(NewFiles { files });
    }
    Err(RecordError::NamesTaken {
        folder: folder.to_path_buf(),
        stamp: stamp.to_string(),
    })
}

/// `records/x` + `.events.csv` -> `records/x.events.csv` (the stem has no extension).
pub(crate) fn with_suffix(stem: &Path, suffix: &str) -> PathBuf {
    let mut name = stem.as_os_str().to_os_string();
    name.push(suffix);
    PathBuf::from(name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(secs: u64) -> String {
        utc_stamp(UNIX_EPOCH + Duration::from_secs(secs))
    }

    #[test]
    fn stamps_of_known_dates() {
        assert_eq!(at(0), "1970-01-01T00-00-00");
        assert_eq!(at(951_782_400), "2000-02-29T00-00-00");
        assert_eq!(at(951_868_799), "2000-02-29T23-59-59");
        assert_eq!(at(951_868_800), "2000-03-01T00-00-00");
        assert_eq!(at(1_795_419_792), "2026-11-23T07-43-12");
        assert_eq!(at(4_107_542_400), "2100-03-01T00-00-00");
    }

    #[test]
    fn a_second_record_of_the_same_second_gets_its_own_name() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("new/records");
        let first = create(&folder, "2026-11-23T07-43-12", &[".csv", ".mcap"]).unwrap();
        let second = create(&folder, "2026-11-23T07-43-12", &[".csv"]).unwrap();
        assert_eq!(first.files[0].0, folder.join("2026-11-23T07-43-12.csv"));
        assert_eq!(first.files[1].0, folder.join("2026-11-23T07-43-12.mcap"));
        assert_eq!(second.files[0].0, folder.join("2026-11-23T07-43-12-2.csv"));
    }
}
