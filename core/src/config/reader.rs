//! Reads typed values out of robot.ini and collects every error, each naming the file,
//! the line, the section and the key, so that `check-config` can list them all at once.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

use ini::{Ini, ParseOption};

use super::lines;

/// Where in the settings a problem is.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A line of the file, counted from 1.
    Line { file: String, line: usize },
    /// A `--set SECTION.KEY=VALUE` of the command line (its text).
    Override(String),
    /// The file as a whole (a missing section, a file that cannot be read).
    File(String),
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::Line { file, line } => write!(f, "{file} line {line}"),
            Place::Override(item) => write!(f, "--set {item}"),
            Place::File(file) => f.write_str(file),
        }
    }
}

/// One thing wrong with the settings, said so that a person can fix it.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigError {
    /// Where: "config/robot.ini line 42" or "--set pid.left.kp=abc".
    pub place: Place,
    /// What: "[pid.steer] kp = 'abc' is not a number".
    pub what: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.place, self.what)
    }
}

/// Where a value came from, to name it in an error.
enum Origin {
    Line(usize),
    Override(String),
    Nowhere,
}

/// Reads one ini text (plus `--set` overrides) into typed values.
pub struct Reader {
    file: String,
    ini: Ini,
    /// (section, key) -> 1-based line in the file, for messages.
    lines: BTreeMap<(String, String), usize>,
    section_lines: BTreeMap<String, usize>,
    /// (section, key) -> the `--set` text that changed it.
    overrides: BTreeMap<(String, String), String>,
    used: BTreeSet<(String, String)>,
    /// Settings that are missing or could not be read: checks across settings skip them.
    failed: BTreeSet<(String, String)>,
    pub errors: Vec<ConfigError>,
}

impl Reader {
    /// Parse `text` (named `file` in messages) and apply `--set SECTION.KEY=VALUE` items.
    pub fn new(file: &str, text: &str, overrides: &[String]) -> Reader {
        Reader::scanned(file, text, overrides, false)
    }

    /// Parse a file whose headings may be a kind and a name, `[machine robot-pc]` (the
    /// cluster's graph file), with the same rules and messages as robot.ini.
    pub fn with_named_sections(file: &str, text: &str) -> Reader {
        Reader::scanned(file, text, &[], true)
    }

    fn scanned(file: &str, text: &str, overrides: &[String], kind_and_name: bool) -> Reader {
        let layout = lines::scan(text, kind_and_name);
        let errors = layout
            .errors
            .iter()
            .map(|(line, what)| ConfigError {
                place: Place::Line {
                    file: file.to_string(),
                    line: *line,
                },
                what: what.clone(),
            })
            .collect();
        // Values as written, to the end of the line: no quotes or backslash escapes that
        // would silently change a folder name or a device path.
        let literal = ParseOption {
            enabled_quote: false,
            enabled_escape: false,
            ..ParseOption::default()
        };
        let mut reader = Reader {
            file: file.to_string(),
            ini: Ini::new(),
            lines: layout.keys,
            section_lines: layout.sections,
            overrides: BTreeMap::new(),
            used: BTreeSet::new(),
            failed: BTreeSet::new(),
            errors,
        };
        // The scan passed only lines rust-ini reads as the scan does, so this should not
        // fail; if it does, say where.
        match Ini::load_from_str_opt(&layout.clean, literal) {
            Ok(ini) => reader.ini = ini,
            Err(e) => reader.push(
                Origin::Line(e.line),
                format!("cannot read this line as ini ({})", e.msg),
            ),
        }
        for item in overrides {
            reader.apply_override(item);
        }
        reader
    }

    fn apply_override(&mut self, item: &str) {
        let parsed = override_parts(item)
            .map(|(section, key, value)| (section.to_string(), key.to_string(), value.to_string()));
        let Some((section, key, value)) = parsed else {
            self.push(
                Origin::Override(item.to_string()),
                "expected SECTION.KEY=VALUE, for example steer.speed_mps=0.3".to_string(),
            );
            return;
        };
        let known = self
            .ini
            .section(Some(section.as_str()))
            .is_some_and(|s| s.contains_key(&key));
        if !known {
            self.push(
                Origin::Override(item.to_string()),
                format!("[{section}] {key} is not a setting in {}", self.file),
            );
            return;
        }
        self.ini
            .with_section(Some(section.as_str()))
            .set(key.as_str(), value);
        self.overrides.insert((section, key), item.to_string());
    }

    fn place_of(&self, section: &str, key: &str) -> Origin {
        let id = (section.to_string(), key.to_string());
        if let Some(item) = self.overrides.get(&id) {
            Origin::Override(item.clone())
        } else if let Some(&line) = self.lines.get(&id) {
            Origin::Line(line)
        } else {
            Origin::Nowhere
        }
    }

    fn push(&mut self, origin: Origin, what: String) {
        let place = match origin {
            Origin::Line(line) => Place::Line {
                file: self.file.clone(),
                line,
            },
            Origin::Override(item) => Place::Override(item),
            Origin::Nowhere => Place::File(self.file.clone()),
        };
        self.errors.push(ConfigError { place, what });
    }

    /// Record an error about one setting, which then counts as not read.
    fn fail(&mut self, section: &str, key: &str, what: String) {
        self.failed.insert((section.to_string(), key.to_string()));
        let place = self.place_of(section, key);
        self.push(place, what);
    }

    /// A setting as written (the --set item over the file) and its line in the file;
    /// None if there is no such setting. Records nothing.
    pub fn written(&self, section: &str, key: &str) -> Option<(String, Option<usize>)> {
        let value = self
            .ini
            .section(Some(section))?
            .get(key)?
            .trim()
            .to_string();
        let line = self
            .lines
            .get(&(section.to_string(), key.to_string()))
            .copied();
        Some((value, line))
    }

    /// The sections, in file order.
    pub fn sections(&self) -> Vec<String> {
        self.ini.sections().flatten().map(str::to_string).collect()
    }

    /// The keys of `section`, in file order.
    pub fn keys(&self, section: &str) -> Vec<String> {
        self.ini
            .section(Some(section))
            .map(|props| props.iter().map(|(k, _)| k.to_string()).collect())
            .unwrap_or_default()
    }

    /// The line of a section's heading, for an error about the section as a whole.
    pub fn section_error(&mut self, section: &str, what: String) {
        let origin = match self.section_lines.get(section) {
            Some(&line) => Origin::Line(line),
            None => Origin::Nowhere,
        };
        self.push(origin, what);
    }

    /// Free text, as written, or None (with an error) if it is missing.
    pub fn text(&mut self, section: &str, key: &str) -> Option<String> {
        self.raw(section, key)
    }

    /// Free text if the key is there; None, and no error, if it is not.
    pub fn optional(&mut self, section: &str, key: &str) -> Option<String> {
        let there = self
            .ini
            .section(Some(section))
            .is_some_and(|props| props.contains_key(key));
        if there { self.raw(section, key) } else { None }
    }

    /// The raw text of a setting, or None (with an error recorded) if it is missing.
    fn raw(&mut self, section: &str, key: &str) -> Option<String> {
        self.used.insert((section.to_string(), key.to_string()));
        let Some(props) = self.ini.section(Some(section)) else {
            // Reported once per section by `finish`.
            self.failed.insert((section.to_string(), key.to_string()));
            return None;
        };
        match props.get(key) {
            Some(v) => Some(v.trim().to_string()),
            None => {
                let place = match self.section_lines.get(section) {
                    Some(&line) => Origin::Line(line),
                    None => Origin::Nowhere,
                };
                self.failed.insert((section.to_string(), key.to_string()));
                self.push(place, format!("[{section}] {key} is missing"));
                None
            }
        }
    }

    /// A number within `min..=max` (the unit is part of the key's name).
    pub fn f64(&mut self, section: &str, key: &str, min: f64, max: f64) -> f64 {
        self.number(section, key, min, max, "a number")
    }

    /// A whole number within `min..=max`.
    pub fn u64(&mut self, section: &str, key: &str, min: u64, max: u64) -> u64 {
        self.number(section, key, min, max, "a whole number")
    }

    /// A whole number, perhaps negative, within `min..=max` (1.7 is an error, not 1).
    pub fn i64(&mut self, section: &str, key: &str, min: i64, max: i64) -> i64 {
        self.number(section, key, min, max, "a whole number")
    }

    /// Parse a value and check its range; NaN and infinities fail the range check.
    fn number<T>(&mut self, section: &str, key: &str, min: T, max: T, kind: &str) -> T
    where
        T: std::str::FromStr + PartialOrd + fmt::Display + Copy,
    {
        let Some(text) = self.raw(section, key) else {
            return min;
        };
        let what = match text.parse::<T>() {
            Ok(v) if (min..=max).contains(&v) => return v,
            Ok(_) => format!("[{section}] {key} = {text} is out of range ({min} to {max})"),
            Err(_) => format!("[{section}] {key} = '{text}' is not {kind}"),
        };
        self.fail(section, key, what);
        min
    }

    /// One of a fixed list of words; returns its index in `choices`.
    pub fn choice(&mut self, section: &str, key: &str, choices: &[&str]) -> usize {
        let Some(text) = self.raw(section, key) else {
            return 0;
        };
        match choices.iter().position(|c| c.eq_ignore_ascii_case(&text)) {
            Some(i) => i,
            None => {
                let what = format!(
                    "[{section}] {key} = '{text}' is not one of: {}",
                    choices.join(", ")
                );
                self.fail(section, key, what);
                0
            }
        }
    }

    /// Free text, parsed by `parse`; its error message is shown after the key.
    pub fn parsed<T>(
        &mut self,
        section: &str,
        key: &str,
        parse: impl FnOnce(&str) -> Result<T, String>,
    ) -> Option<T> {
        let text = self.raw(section, key)?;
        match parse(&text) {
            Ok(v) => Some(v),
            Err(why) => {
                self.fail(section, key, format!("[{section}] {key}: {why}"));
                None
            }
        }
    }

    /// Record an error about a key that a check across several settings found.
    pub fn error_at(&mut self, section: &str, key: &str, what: String) {
        self.fail(section, key, format!("[{section}] {key}: {what}"));
    }

    /// True if every one of `keys` (section, key) was read without an error: a check
    /// across settings means something only then.
    pub(crate) fn all_read(&self, keys: &[(&str, &str)]) -> bool {
        keys.iter()
            .all(|&(s, k)| !self.failed.contains(&(s.to_string(), k.to_string())))
    }

    /// Record an error that a check across `keys` found; `what` names them and their
    /// values. It is placed where a `--set` changed one of them, else at the first.
    pub(crate) fn cross_error(&mut self, keys: &[(&str, &str)], what: String) {
        let overridden = keys
            .iter()
            .find_map(|&(s, k)| self.overrides.get(&(s.to_string(), k.to_string())).cloned());
        let place = match (overridden, keys.first()) {
            (Some(item), _) => Origin::Override(item),
            (None, Some(&(s, k))) => self.place_of(s, k),
            (None, None) => Origin::Nowhere,
        };
        self.push(place, what);
    }

    /// Report missing sections, unknown sections and unknown keys; return every error.
    pub fn finish(self, sections: &[&str]) -> Vec<ConfigError> {
        self.finish_with(sections, &[])
    }

    /// As `finish`, with `optional` sections that may be missing.
    pub fn finish_with(mut self, sections: &[&str], optional: &[&str]) -> Vec<ConfigError> {
        for &name in sections {
            if self.ini.section(Some(name)).is_none() {
                self.push(Origin::Nowhere, format!("missing section [{name}]"));
            }
        }
        let mut unknown = Vec::new();
        for (name, props) in self.ini.iter() {
            let name = name.unwrap_or("");
            if !sections.contains(&name) && !optional.contains(&name) {
                if name.is_empty() && props.is_empty() {
                    continue;
                }
                let line = self.section_lines.get(name).copied();
                unknown.push((line, format!("unknown section [{name}]")));
                continue;
            }
            for (key, _) in props.iter() {
                if !self.used.contains(&(name.to_string(), key.to_string())) {
                    let line = self
                        .lines
                        .get(&(name.to_string(), key.to_string()))
                        .copied();
                    unknown.push((line, format!("[{name}] {key} is not a known setting")));
                }
            }
        }
        for (line, what) in unknown {
            let origin = line.map_or(Origin::Nowhere, Origin::Line);
            self.push(origin, what);
        }
        self.errors
    }
}

/// A `--set SECTION.KEY=VALUE` item's (section, key, value), or None if it is not one.
/// The section is everything before the last dot: `pid.steer.kp` is [pid.steer] kp.
pub fn override_parts(item: &str) -> Option<(&str, &str, &str)> {
    let (path, value) = item.split_once('=')?;
    let (section, key) = path.trim().rsplit_once('.')?;
    Some((section, key, value.trim()))
}
