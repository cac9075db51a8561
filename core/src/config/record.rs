//! The [record] section: where and how each run leaves its record (core/src/record/).

use std::path::PathBuf;

use super::reader::Reader;

/// Which files a record is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RecordFormats {
    Both,
    Csv,
    Mcap,
}

impl RecordFormats {
    pub fn csv(self) -> bool {
        matches!(self, RecordFormats::Both | RecordFormats::Csv)
    }

    pub fn mcap(self) -> bool {
        matches!(self, RecordFormats::Both | RecordFormats::Mcap)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct RecordSettings {
    pub enabled: bool,
    /// Folder of the records, relative to the working directory.
    pub folder: PathBuf,
    /// Record every Nth supervisor tick (1 = all).
    pub every_n_ticks: u64,
    pub formats: RecordFormats,
    /// How many records the folder keeps, the newest (None: all of them).
    pub keep_records: Option<usize>,
    /// How much the folder's records may take, GB, the newest kept (None: no limit).
    pub keep_gb: Option<f64>,
}

const FORMATS: [(&str, RecordFormats); 3] = [
    ("both", RecordFormats::Both),
    ("csv", RecordFormats::Csv),
    ("mcap", RecordFormats::Mcap),
];

pub(super) fn load(r: &mut Reader) -> RecordSettings {
    let s = "record";
    let names: Vec<&str> = FORMATS.iter().map(|(name, _)| *name).collect();
    RecordSettings {
        enabled: r.choice(s, "enabled", &["yes", "no"]) == 0,
        folder: r
            .parsed(s, "folder", |text| {
                if text.is_empty() {
                    Err("is empty: name a folder, for example records".to_string())
                } else {
                    Ok(PathBuf::from(text))
                }
            })
            .unwrap_or_default(),
        every_n_ticks: r.u64(s, "every_n_ticks", 1, 10_000),
        formats: FORMATS[r.choice(s, "formats", &names)].1,
        keep_records: r.parsed(s, "keep", parse_keep).flatten(),
        keep_gb: r.parsed(s, "keep_gb", parse_keep_gb).flatten(),
    }
}

/// `keep_gb = 20` (GB) or `0` (no limit in space).
fn parse_keep_gb(text: &str) -> Result<Option<f64>, String> {
    match text.parse::<f64>() {
        Ok(0.0) => Ok(None),
        Ok(gb) if gb.is_finite() && gb > 0.0 => Ok(Some(gb)),
        _ => Err(format!(
            "'{text}' is not a size in GB (for example 20, or 0 for no limit in space)"
        )),
    }
}

/// `keep = 50` (records) or `0` / `all` (keep everything).
fn parse_keep(text: &str) -> Result<Option<usize>, String> {
    if text.eq_ignore_ascii_case("all") {
        return Ok(None);
    }
    match text.parse::<usize>() {
        Ok(0) => Ok(None),
        Ok(n) => Ok(Some(n)),
        Err(_) => Err(format!(
            "'{text}' is not a number of records (for example 50, or 0 or all to keep every record)"
        )),
    }
}
