//! The shape of every line of robot.ini, checked before rust-ini reads the file.
//!
//! rust-ini is forgiving where a robot must not be: it keeps only the first of two
//! `[faults]` sections, joins a stray word to the next line's key, reports errors one
//! line too far down in its own words, and takes a Windows byte-order mark for part of
//! a section name. So each line is first sorted into blank, comment, `[section]` or
//! `key = value`, anything else is an error naming its line, and rust-ini then reads a
//! clean copy of the file in which every line stands where it stood (so line numbers
//! agree) but holds only what this scan understood.

use std::collections::BTreeMap;

use super::reader::{ConfigError, Place};

/// What the scan found: the clean text for rust-ini, where each section and key
/// stands, and the lines that are wrong.
pub(super) struct Layout {
    /// One line per line of the file: `[name]`, `key=value`, or empty.
    pub clean: String,
    /// (section, key) -> 1-based line of its first appearance.
    pub keys: BTreeMap<(String, String), usize>,
    /// section -> 1-based line of its first heading.
    pub sections: BTreeMap<String, usize>,
    /// (1-based line, what is wrong with it).
    pub errors: Vec<(usize, String)>,
}

/// The UTF-8 byte-order mark Windows Notepad writes at the start of a file.
const BOM: char = '\u{feff}';

/// The file's bytes as text, or (line, why) where they stop being UTF-8.
pub(super) fn decode(bytes: &[u8]) -> Result<String, (usize, String)> {
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok(text.to_string()),
        Err(e) => {
            let good = &bytes[..e.valid_up_to()];
            let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
            Err((
                line,
                "is not UTF-8 text: save the file as UTF-8 (plain text)".to_string(),
            ))
        }
    }
}

/// The text of an ini file (`what` names it in the message), or why it cannot be read:
/// a file that is not UTF-8 is named by the line where it stops being so.
pub fn read_text(path: &std::path::Path, what: &str) -> Result<String, Vec<ConfigError>> {
    let label = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        vec![ConfigError {
            place: Place::File(label.clone()),
            what: format!("cannot read {what}: {e}"),
        }]
    })?;
    decode(&bytes).map_err(|(line, what)| {
        vec![ConfigError {
            place: Place::Line { file: label, line },
            what,
        }]
    })
}

/// Letters, digits, `_`, `.` and `-`: every section and key name robot.ini uses, and
/// nothing rust-ini would read differently (it also splits a key at ':').
fn is_name(text: &str) -> bool {
    !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'))
}

/// A line as the error shows it, cut short if it is long.
fn quoted(line: &str) -> String {
    const MAX: usize = 60;
    match line.char_indices().nth(MAX) {
        Some((cut, _)) => format!("`{}...`", &line[..cut]),
        None => format!("`{line}`"),
    }
}

/// Which section the lines below a heading belong to.
enum Under {
    /// Above the first heading.
    NoSection,
    Section(String),
    /// A second heading of a section: its keys are checked against the first one's
    /// but not read (the file is refused anyway).
    Again(String),
    /// A heading that is wrong: its keys are not read (its error says enough).
    Broken,
}

/// Sort every line of `text` (a byte-order mark and CR-LF line ends allowed).
/// `kind_and_name`: a heading may also be two names, `[machine robot-pc]` (the cluster's
/// graph file); robot.ini's headings are one name.
pub(super) fn scan(text: &str, kind_and_name: bool) -> Layout {
    let text = text.strip_prefix(BOM).unwrap_or(text);
    let mut layout = Layout {
        clean: String::with_capacity(text.len()),
        keys: BTreeMap::new(),
        sections: BTreeMap::new(),
        errors: Vec::new(),
    };
    let mut under = Under::NoSection;
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let line = raw.trim();
        let clean = if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
            None
        } else if let Some(heading) = line.strip_prefix('[') {
            under = layout.heading(n, line, heading, kind_and_name);
            match &under {
                Under::Section(name) => Some(format!("[{name}]")),
                _ => None,
            }
        } else if let Some((key, value)) = line.split_once('=') {
            let key = key.trim();
            layout
                .key(n, line, &under, key)
                .then(|| format!("{key}={}", value.trim()))
        } else {
            let why = format!("{} is neither [section] nor key = value", quoted(line));
            layout.errors.push((n, why));
            None
        };
        layout.clean.push_str(clean.as_deref().unwrap_or(""));
        layout.clean.push('\n');
    }
    layout
}

impl Layout {
    /// A `[name]` line (`heading` is what follows the `[`): a plain name, seen for the
    /// first time.
    fn heading(&mut self, n: usize, line: &str, heading: &str, kind_and_name: bool) -> Under {
        let written = heading.strip_suffix(']').unwrap_or_default().trim();
        // `[machine   robot-pc]` is `[machine robot-pc]`.
        let two = written
            .split_once(char::is_whitespace)
            .map(|(kind, name)| (kind, name.trim()))
            .filter(|&(kind, name)| kind_and_name && is_name(kind) && is_name(name));
        let joined = two.map(|(kind, name)| format!("{kind} {name}"));
        let name = joined.as_deref().unwrap_or(written);
        let (under, why) = if !heading.ends_with(']') {
            let why = format!(
                "{} starts a [section] heading but does not end with ]",
                quoted(line)
            );
            (Under::Broken, why)
        } else if name.is_empty() {
            (
                Under::Broken,
                format!("{} has no section name", quoted(line)),
            )
        } else if two.is_none() && !is_name(name) {
            let why = format!(
                "{}: '{name}' is not a section name (letters, digits, _ . -)",
                quoted(line)
            );
            (Under::Broken, why)
        } else if let Some(first) = self.sections.get(name) {
            let why = format!(
                "[{name}] appears again (first at line {first}): put its keys in one section"
            );
            (Under::Again(name.to_string()), why)
        } else {
            self.sections.insert(name.to_string(), n);
            return Under::Section(name.to_string());
        };
        self.errors.push((n, why));
        under
    }

    /// A `key = value` line: a plain name, in a section, set once there. True if it
    /// is to be read.
    fn key(&mut self, n: usize, line: &str, under: &Under, key: &str) -> bool {
        let why = if key.is_empty() {
            format!("{} has no setting name before '='", quoted(line))
        } else if !is_name(key) {
            let shown = quoted(line);
            format!("{shown}: '{key}' is not a setting name (letters, digits, _ . -)")
        } else {
            match under {
                Under::Broken => return false,
                Under::NoSection => format!(
                    "{} stands before any [section]: move it into its section",
                    quoted(line)
                ),
                Under::Section(section) | Under::Again(section) => {
                    let id = (section.clone(), key.to_string());
                    match self.keys.get(&id) {
                        Some(first) => format!(
                            "[{section}] {key} is set more than once (first at line {first}): keep one"
                        ),
                        None if matches!(under, Under::Again(_)) => return false,
                        None => {
                            self.keys.insert(id, n);
                            return true;
                        }
                    }
                }
            }
        };
        self.errors.push((n, why));
        false
    }
}

/// A time in seconds as the command line takes it, 0 to a day.
pub fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if (0.0..=86_400.0).contains(&s) => Ok(s),
        _ => Err(format!("'{text}' is not a time in s (0 to 86400)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn errors(text: &str) -> Vec<(usize, String)> {
        scan(text, false).errors
    }

    #[test]
    fn the_clean_copy_keeps_every_line_in_its_place() {
        let layout = scan(
            "\u{feff}; head\r\n[a]\r\n  k =  v w \r\n\r\n[ b ]\nx=\n",
            false,
        );
        assert_eq!(layout.clean, "\n[a]\nk=v w\n\n[b]\nx=\n");
        assert!(layout.errors.is_empty(), "{:?}", layout.errors);
        assert_eq!(layout.sections["b"], 5);
        assert_eq!(layout.keys[&("a".to_string(), "k".to_string())], 3);
    }

    #[test]
    fn each_wrong_line_is_named_by_its_own_number() {
        let text =
            "[a]\nk = 1\nnot ini\n[a]\nk = 2\nj = 2\n[]\nk:1\n[b c]\n= 3\nk = 3\n[c\nk = 4\n";
        let found: Vec<usize> = errors(text).iter().map(|(n, _)| *n).collect();
        // Line 6 (a new key under the repeated [a]), line 11 and line 13 (under broken
        // headings) are covered by their heading's error.
        assert_eq!(found, vec![3, 4, 5, 7, 8, 9, 10, 12]);
        assert_eq!(
            scan(text, false).clean,
            format!("[a]\nk=1{}", "\n".repeat(12))
        );
        assert_eq!(
            errors("[a]\nk = 1\n[a]\n")[0].1,
            "[a] appears again (first at line 1): put its keys in one section"
        );
        assert_eq!(
            errors("k = 1\n")[0].1,
            "`k = 1` stands before any [section]: move it into its section"
        );
    }

    #[test]
    fn a_graph_heading_is_a_kind_and_a_name() {
        let layout = scan("[machine  robot-pc]\nendpoint = x\n[process a b c]\n", true);
        assert_eq!(layout.sections["machine robot-pc"], 1);
        assert_eq!(layout.errors.len(), 1, "{:?}", layout.errors);
        assert!(
            layout.errors[0]
                .1
                .contains("'process a b c' is not a section name")
        );
        // robot.ini's headings stay one name.
        assert_eq!(scan("[machine robot-pc]\n", false).errors.len(), 1);
    }

    #[test]
    fn a_long_line_is_cut_short_in_the_message() {
        let long = "x".repeat(200);
        let (_, why) = &errors(&format!("[a]\n{long}\n"))[0];
        assert!(why.len() < 120, "{why}");
    }

    #[test]
    fn bytes_that_are_not_utf8_are_named_by_line() {
        assert_eq!(decode(b"[a]\nk = \xe9\n").unwrap_err().0, 2);
        assert_eq!(decode("[a]\n".as_bytes()).unwrap(), "[a]\n");
    }
}
