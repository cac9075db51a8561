//! What a replay needs besides the ticks and events: the program that made the record
//! and the settings in force at the start, written beside the record as NAME.run.json
//! (plain JSON: the settings file's text as it was read, and the `--set` items).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::config::{ConfigError, Settings};
use crate::state::cross_track::CrossTrackMeaning;

/// The file's ending beside NAME.csv and NAME.mcap.
pub(crate) const HEADER_SUFFIX: &str = ".run.json";

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunHeader {
    /// "mechweed 0.1.0".
    pub program: String,
    /// The settings file's name, its text and the `--set` items over it.
    pub settings_file: String,
    pub settings_text: String,
    pub overrides: Vec<String>,
    /// The settings in force are exactly those the text and the items give (false when
    /// a program changed them after reading, as some tests do): only then can a replay
    /// give the supervisor the same settings.
    pub settings_as_read: bool,
    /// Whether the run's cross-track figures mean anything (not when the simulated
    /// robot steered by rows from outside): every reader of the record says so instead
    /// of a number. Records from before this field was written read as not known.
    #[serde(default = "not_said")]
    pub cross_track: CrossTrackMeaning,
    /// Recorded off-board from the robot's flows (`record --bus`): the settings are not
    /// known, and the record cannot be replayed.
    #[serde(default)]
    pub off_board: bool,
}

fn not_said() -> CrossTrackMeaning {
    CrossTrackMeaning::Unknown
}

/// This program's name and version, as a header names it.
pub fn program() -> String {
    format!("mechweed {}", env!("CARGO_PKG_VERSION"))
}

impl RunHeader {
    pub fn of(settings: &Settings) -> RunHeader {
        let source = &settings.source;
        let read_again = Settings::parse(&source.label, &source.text, &source.overrides);
        RunHeader {
            program: program(),
            settings_file: source.label.clone(),
            settings_text: source.text.clone(),
            overrides: source.overrides.clone(),
            settings_as_read: read_again.is_ok_and(|again| again == *settings),
            cross_track: CrossTrackMeaning::of(settings),
            off_board: false,
        }
    }

    /// The header of an off-board record: no settings, the robot's cross-track meaning.
    pub fn off_board(cross_track: CrossTrackMeaning) -> RunHeader {
        RunHeader {
            program: program(),
            settings_file: String::new(),
            settings_text: String::new(),
            overrides: Vec::new(),
            settings_as_read: false,
            cross_track,
            off_board: true,
        }
    }

    /// The settings of the run, with `more` items over them (a what-if).
    pub fn settings(&self, more: &[String]) -> Result<Settings, Vec<ConfigError>> {
        let items: Vec<String> = self.overrides.iter().chain(more).cloned().collect();
        Settings::parse(&self.settings_file, &self.settings_text, &items)
    }

    pub fn write(&self, file: &mut std::fs::File) -> std::io::Result<()> {
        use std::io::Write;
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        file.write_all(text.as_bytes())?;
        file.write_all(b"\n")
    }

    /// The header beside a record's `file` (NAME.csv or NAME.mcap), if there is one.
    pub fn beside(file: &Path) -> Option<std::path::PathBuf> {
        let name = file.file_name()?.to_string_lossy().to_string();
        let stem = (name
            .strip_suffix(".csv")
            .or_else(|| name.strip_suffix(".mcap")))
        .filter(|_| !name.ends_with(".events.csv"))?;
        Some(file.with_file_name(format!("{stem}{HEADER_SUFFIX}")))
    }

    /// Read a header, or say why it cannot be used.
    pub fn read(path: &Path) -> Result<RunHeader, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text)
            .map_err(|e| format!("{}: not a run header: {e}", path.display()))
    }
}
