//! Whether the tool's cross-track error means anything, one rule for every place that
//! shows it: the console, the GUI's plots and truth line, watch, the bus's status, the
//! record's header and its summary, the run report and the benchmarks.
//!
//! Cross-track is the simulated field's truth: how far the tool is from the rows the
//! simulated camera sees. When the rows come from outside this program (a camera
//! computer on a port, camsim, a vision program on the bus) while the robot is the
//! simulated one, the robot steers along rows that are not the field's, and the
//! field's cross-track says nothing about the steering: it is then "not meaningful",
//! never a number. On the real robot there is no truth at all.

use serde::{Deserialize, Serialize};

use crate::config::Settings;

/// What a cross-track figure of a run is worth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrossTrackMeaning {
    /// The simulated robot steered by its own simulated camera: the figures are true.
    #[default]
    Meaningful,
    /// The simulated robot steered by rows from outside ([camera] port is not sim).
    OutsideCamera,
}

/// What is shown instead of a number, everywhere.
pub const NOT_MEANINGFUL_OUTSIDE: &str = "not meaningful (outside camera)";

impl CrossTrackMeaning {
    /// The rule: the simulated robot with a camera outside this program.
    pub fn of(settings: &Settings) -> CrossTrackMeaning {
        if settings.camera_port.is_outside_of(settings.backend) {
            CrossTrackMeaning::OutsideCamera
        } else {
            CrossTrackMeaning::Meaningful
        }
    }

    pub fn meaningful(self) -> bool {
        self == CrossTrackMeaning::Meaningful
    }

    /// What to show instead of a figure; None: show the figure.
    pub fn instead(self) -> Option<&'static str> {
        match self {
            CrossTrackMeaning::Meaningful => None,
            CrossTrackMeaning::OutsideCamera => Some(NOT_MEANINGFUL_OUTSIDE),
        }
    }

    /// A cross-track error in cm, or the words that replace it.
    pub fn cm(self, error_m: f64) -> String {
        match self.instead() {
            Some(words) => words.to_string(),
            None => format!("{:+.1} cm", error_m * 100.0),
        }
    }

    /// As the status on the bus says it (`"cross_track"`): the words above, or
    /// "meaningful".
    pub fn word(self) -> &'static str {
        self.instead().unwrap_or("meaningful")
    }

    /// Read back from the bus's word; an unknown word is taken as not meaningful, so
    /// that a view never shows a number it cannot vouch for.
    pub fn from_word(word: Option<&str>) -> CrossTrackMeaning {
        match word {
            None | Some("meaningful") => CrossTrackMeaning::Meaningful,
            Some(_) => CrossTrackMeaning::OutsideCamera,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_figure_is_shown_only_where_it_means_something() {
        let m = CrossTrackMeaning::Meaningful;
        assert_eq!(m.cm(-0.414), "-41.4 cm");
        let o = CrossTrackMeaning::OutsideCamera;
        assert_eq!(o.cm(-0.414), "not meaningful (outside camera)");
        assert_eq!(CrossTrackMeaning::from_word(Some(o.word())), o);
        assert_eq!(CrossTrackMeaning::from_word(Some(m.word())), m);
        assert_eq!(CrossTrackMeaning::from_word(Some("???")), o);
    }
}
