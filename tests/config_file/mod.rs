//! Helpers for the check-config tests: broken copies of the shipped robot.ini in a
//! temporary folder, and `mechweed check-config` run on them.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

pub const SHIPPED: &str = include_str!("../../config/robot.ini");

/// A settings file in a temporary folder.
pub struct File {
    _dir: tempfile::TempDir,
    pub path: PathBuf,
}

impl File {
    pub fn new(text: impl AsRef<[u8]>) -> File {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("robot.ini");
        std::fs::write(&path, text).unwrap();
        File { _dir: dir, path }
    }

    /// "FILE line N: WHAT", as check-config prints an error.
    pub fn error(&self, line: usize, what: &str) -> String {
        format!("{} line {line}: {what}", self.path.display())
    }
}

/// check-config's exit code and its error lines.
pub fn check(path: &Path) -> (Option<i32>, Vec<String>) {
    let out = Command::new(env!("CARGO_BIN_EXE_mechweed"))
        .arg("check-config")
        .arg(path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.success() {
        assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "ok");
    }
    (
        out.status.code(),
        stderr.lines().map(str::to_string).collect(),
    )
}

/// 1-based line of `[section] key` in `text`.
pub fn line_of(text: &str, section: &str, key: &str) -> usize {
    let mut current = "";
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            current = name;
        } else if current == section && line.split_once('=').is_some_and(|(k, _)| k.trim() == key) {
            return i + 1;
        }
    }
    panic!("[{section}] {key} is not in the text");
}

/// `text` with `[section] key` set to `value`.
pub fn with(text: &str, section: &str, key: &str, value: &str) -> String {
    let n = line_of(text, section, key);
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[n - 1] = format!("{key} = {value}");
    lines.join("\n") + "\n"
}

/// The shipped file with each (section, key, value) set.
pub fn shipped_with(changes: &[(&str, &str, &str)]) -> String {
    changes
        .iter()
        .fold(SHIPPED.to_string(), |text, (s, k, v)| with(&text, s, k, v))
}

/// check-config refuses `text` and prints exactly `expected` (each "line N: WHAT"
/// with N the line of the setting named).
pub fn assert_refused(text: &str, expected: &[(usize, &str)]) {
    let file = File::new(text);
    let (code, errors) = check(&file.path);
    let expected: Vec<String> = expected.iter().map(|(n, w)| file.error(*n, w)).collect();
    assert_eq!(code, Some(1), "{errors:?}");
    assert_eq!(errors, expected);
}
