//! Writes a row map file (laid out as `format` describes) so that it always reads back:
//! the map is checked by the reader's rules first, on the numbers as written, and the
//! file is replaced in one step, so a power cut leaves the old map or the new one.

use std::collections::HashMap;
use std::fs::{self, File};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::gnss::rowmap::format::{
    DECIMALS, HEADER, MapFileError, MapFileErrors, Place, name_problem, physical_lines,
    row_problems,
};
use crate::gnss::rowmap::map::RowMap;

/// The comment on top of every row map. No commas: a spreadsheet that opens the file
/// keeps the line in one cell and writes it back as it was.
pub(crate) const FILE_COMMENT: &str = "mechweed row map - one line per point: the row's name then \
     its WGS-84 latitude and longitude in degrees - a row's points on consecutive lines in \
     driving order";

/// Why a row map was not written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("{file}: cannot {action}: {source}")]
    Io {
        file: String,
        action: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// The map breaks a rule of the file: written, it would not read back.
    #[error("{0}")]
    Invalid(MapFileErrors),
}

/// Writes `map` to `path` through a temporary file in the same folder and a rename.
/// `extra_comment` (e.g. "taught on 2026-11-25 by mechweed teach") goes below the
/// file's own comment, each of its lines as a comment line.
pub fn write_map(path: &Path, map: &RowMap, extra_comment: Option<&str>) -> Result<(), WriteError> {
    let file = path.display().to_string();
    let text = map_text(&file, map, extra_comment).map_err(WriteError::Invalid)?;
    let io_error = |action: &'static str| {
        let file = file.clone();
        move |source: std::io::Error| WriteError::Io {
            file,
            action,
            source,
        }
    };
    let Some(name) = path.file_name() else {
        return Err(io_error("write a row map to a folder")(
            std::io::ErrorKind::InvalidInput.into(),
        ));
    };
    let folder = path
        .parent()
        .filter(|folder| !folder.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    // The process id keeps two programs writing the same map from sharing a file.
    let temp: PathBuf = folder.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let written = File::create(&temp)
        .map_err(io_error("create a temporary file beside it"))
        .and_then(|mut out| {
            out.write_all(text.as_bytes())
                .and_then(|()| out.sync_all())
                .map_err(io_error("write a temporary file beside it"))
        })
        .and_then(|()| fs::rename(&temp, path).map_err(io_error("replace it")));
    if let Err(error) = written {
        // Best effort: the error that matters is the one returned.
        let _ = fs::remove_file(&temp);
        return Err(error);
    }
    // The rename reaches the disk with the folder. Some filesystems (FAT on a USB
    // stick) refuse to sync a folder; the map is in place all the same.
    let _ = File::open(folder).and_then(|dir| dir.sync_all());
    Ok(())
}

/// The text of the row map file for `map` (named `file` in errors), or every reason
/// it cannot be written.
pub fn map_text(
    file: &str,
    map: &RowMap,
    extra_comment: Option<&str>,
) -> Result<String, MapFileErrors> {
    let mut errors = Vec::new();
    let file_error = |what: String| MapFileError {
        place: Place::File(file.to_string()),
        what,
    };
    if map.rows.is_empty() {
        errors.push(file_error("the map has no rows to write".to_string()));
    }
    let mut text = format!("# {FILE_COMMENT}\n");
    for line in extra_comment.map(physical_lines).unwrap_or_default() {
        text.push_str(&format!("# {line}\n"));
    }
    text.push_str(HEADER);
    text.push('\n');
    let mut row_of_name: HashMap<&str, usize> = HashMap::new();
    for (index, row) in map.rows.iter().enumerate() {
        if let Some(what) = name_problem(&row.name) {
            errors.push(file_error(format!("row {} of the map: {what}", index + 1)));
        }
        let first = *row_of_name.entry(&row.name).or_insert(index);
        if first != index {
            errors.push(file_error(format!(
                "row {} of the map: the name '{}' is already row {}'s: every row needs \
                 its own name",
                index + 1,
                row.name,
                first + 1
            )));
        }
        let mut written_deg = Vec::with_capacity(row.points_deg.len());
        for &(lat_deg, lon_deg) in &row.points_deg {
            let lat_text = format!("{lat_deg:.DECIMALS$}");
            let lon_text = format!("{lon_deg:.DECIMALS$}");
            text.push_str(&format!("{},{lat_text},{lon_text}\n", row.name));
            // Checked as written: rounding can bring two points under the limit.
            let reread = |written: &str, value: f64| written.parse().unwrap_or(value);
            written_deg.push((reread(&lat_text, lat_deg), reread(&lon_text, lon_deg)));
        }
        for problem in row_problems(&written_deg) {
            let what = problem.describe(&row.name, &|point| format!("point {}", point + 1));
            errors.push(MapFileError {
                place: Place::Point {
                    file: file.to_string(),
                    row: row.name.clone(),
                    point: problem.point() + 1,
                },
                what,
            });
        }
    }
    if errors.is_empty() {
        Ok(text)
    } else {
        Err(MapFileErrors::new(errors))
    }
}

#[cfg(test)]
#[path = "write_tests.rs"]
mod tests;
