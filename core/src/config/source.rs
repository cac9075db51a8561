//! Where settings came from, kept beside them: the bus's configuration ports show a
//! setting as robot.ini writes it and check a new value as robot.ini would be.

use super::reader::Reader;

/// Where settings came from: a file's text (its name for messages) and the `--set`
/// items over it. The bus shows and checks a setting as robot.ini says it, from this.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SettingsSource {
    pub label: String,
    pub text: String,
    pub overrides: Vec<String>,
}

impl SettingsSource {
    /// A setting as written, with the comment lines just above it in the file (which
    /// give its meaning and unit); None if there is no such setting.
    pub fn setting(&self, section: &str, key: &str) -> Option<(String, String)> {
        let reader = Reader::new(&self.label, &self.text, &self.overrides);
        let (value, line) = reader.written(section, key)?;
        let lines: Vec<&str> = self.text.lines().collect();
        let mut comment: Vec<&str> = Vec::new();
        if let Some(line) = line {
            // 1-based line of the key: the comment is the run of ; lines before it.
            for text in lines[..line.saturating_sub(1).min(lines.len())]
                .iter()
                .rev()
            {
                match text.trim().strip_prefix(';') {
                    Some(words) => comment.push(words.trim()),
                    None => break,
                }
            }
        }
        comment.reverse();
        Some((value, comment.join(" ")))
    }
}
