//! [hw] and [io] alone: where the cards are and how the robot is wired to them, read
//! whatever the rest of robot.ini says. It is all that writing the safe outputs needs,
//! so that `mechweed safe`, and a `run` or `probe` that refuses the file, can still
//! stop a robot that a killed run left driving.

use std::path::Path;

use mechweed_hw::cards::CardsSettings;
use mechweed_hw::cards::wiring::Wiring;

use super::reader::Reader;
use super::{Backend, ConfigError, io, lines};

/// What the cards' safe outputs need.
#[derive(Debug, Clone)]
pub struct CardsOnly {
    pub backend: Backend,
    pub cards: CardsSettings,
    pub io: Wiring,
}

impl CardsOnly {
    /// [hw] and [io] of the file at `path`.
    pub fn load(path: &Path) -> Result<CardsOnly, Vec<ConfigError>> {
        let text = lines::read_text(path, "the settings file")?;
        CardsOnly::parse(&path.display().to_string(), &text)
    }

    /// [hw] and [io] of `text` (`file` names it in messages). Every other section is
    /// left out before reading, line for line, so that the errors name the file's own
    /// lines and nothing outside the two sections can make them fail.
    pub fn parse(file: &str, text: &str) -> Result<CardsOnly, Vec<ConfigError>> {
        let kept = only_sections(text, &["hw", "io"]);
        let mut r = Reader::new(file, &kept, &[]);
        let only = CardsOnly {
            backend: [Backend::Sim, Backend::Cards][r.choice("hw", "backend", &["sim", "cards"])],
            cards: io::cards(&mut r),
            io: io::wiring(&mut r),
        };
        // Read so that it is a known key here too; the safe outputs do not need it.
        let _ = super::watchdog_relay::load(&mut r);
        let errors = r.finish(&["hw", "io"]);
        if errors.is_empty() {
            Ok(only)
        } else {
            Err(errors)
        }
    }
}

/// `text` with every line outside `sections` blanked (the line count kept).
fn only_sections(text: &str, sections: &[&str]) -> String {
    let mut inside = false;
    let mut kept = String::with_capacity(text.len());
    for line in text.lines() {
        let trimmed = line.trim();
        if let Some(name) = trimmed.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
            inside = sections.contains(&name.trim());
        }
        if inside {
            kept += line;
        }
        kept.push('\n');
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{DEFAULT_INI, Settings};

    #[test]
    fn a_file_broken_outside_hw_and_io_still_gives_the_cards_and_their_wiring() {
        let broken = DEFAULT_INI
            .replace("kp = 16.7", "kp = fast")
            .replace("[steer]", "[steer]\nnonsense = 1");
        assert!(Settings::parse("robot.ini", &broken, &[]).is_err());
        let only = CardsOnly::parse("robot.ini", &broken).unwrap();
        let shipped = Settings::shipped();
        assert_eq!(only.io, shipped.io);
        assert_eq!(only.cards, shipped.cards);
        assert_eq!(only.backend, Backend::Sim);
    }

    #[test]
    fn an_error_in_io_is_named_with_its_line_in_the_file() {
        let broken = DEFAULT_INI.replace(
            "amp_left_v = dda06 ao 0, scale 1",
            "amp_left_v = dda06 ao 9, scale 1",
        );
        let line = broken
            .lines()
            .position(|l| l.starts_with("amp_left_v"))
            .unwrap()
            + 1;
        let errors = CardsOnly::parse("robot.ini", &broken).unwrap_err();
        let text: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(text.len(), 1, "{text:?}");
        assert!(
            text[0].contains(&format!("line {line}")) && text[0].contains("amp_left_v"),
            "{text:?}"
        );
    }
}
