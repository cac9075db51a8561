//! Whether the tool's cross-track error means anything, one rule for every place that
//! shows it: the console, the GUI's plots and truth line, watch, the bus's status, the
//! record's header and its summary, the run report and the benchmarks.
//!
//! Cross-track is the simulated field's truth: how far the tool is from the rows the
//! simulated camera sees. When the rows come from outside this program (a camera
//! computer on a port, camsim, a vision program on the bus) while the robot is the
//! simulated one, the robot steers along rows that are not the field's, and the
//! field's cross-track says nothing about the steering: it is then "not meaningful",
//! never a number. On the real robot there is no truth at all, and a robot program or
//! record that does not say is vouched for by no figure either.

use serde::{Deserialize, Serialize};

use crate::config::{Backend, CameraPort, Settings};

/// What a cross-track figure of a run is worth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CrossTrackMeaning {
    /// The simulated robot steered by its own simulated camera: the figures are true.
    #[default]
    Meaningful,
    /// The simulated robot steered by rows from outside ([camera] port is not sim).
    OutsideCamera,
    /// The real robot: nobody knows where the row truly is.
    RealRobot,
    /// Not said (a robot program or a record from before this rule): no figure is
    /// vouched for.
    Unknown,
}

/// What is shown instead of a number, everywhere.
pub(crate) const NOT_MEANINGFUL_OUTSIDE: &str = "not meaningful (outside camera)";
const NOT_KNOWN_REAL: &str = "not known on the real robot";
const NOT_SAID: &str = "not known (the robot did not say whether it means anything)";

const ALL: [CrossTrackMeaning; 4] = [
    CrossTrackMeaning::Meaningful,
    CrossTrackMeaning::OutsideCamera,
    CrossTrackMeaning::RealRobot,
    CrossTrackMeaning::Unknown,
];

impl CrossTrackMeaning {
    /// The rule: the simulated robot with its own camera, or not.
    pub fn of(settings: &Settings) -> CrossTrackMeaning {
        CrossTrackMeaning::of_robot(settings.backend, &settings.camera_port)
    }

    /// The same, from a robot's `[hw] backend` and `[camera] port` alone (what the
    /// off-board recorder asks of a robot over the bus).
    pub fn of_robot(backend: Backend, camera_port: &CameraPort) -> CrossTrackMeaning {
        if backend != Backend::Sim {
            CrossTrackMeaning::RealRobot
        } else if camera_port.is_outside_of(backend) {
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
            CrossTrackMeaning::RealRobot => Some(NOT_KNOWN_REAL),
            CrossTrackMeaning::Unknown => Some(NOT_SAID),
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

    /// Read back from the bus's word; a missing or unknown word vouches for nothing.
    pub fn from_word(word: Option<&str>) -> CrossTrackMeaning {
        ALL.into_iter()
            .find(|m| Some(m.word()) == word)
            .unwrap_or(CrossTrackMeaning::Unknown)
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
        assert_eq!(
            CrossTrackMeaning::from_word(Some("???")),
            CrossTrackMeaning::Unknown
        );
        // A robot program from before the rule says nothing: no figure is vouched for.
        assert_eq!(
            CrossTrackMeaning::from_word(None),
            CrossTrackMeaning::Unknown
        );
        for m in ALL {
            assert_eq!(CrossTrackMeaning::from_word(Some(m.word())), m);
        }
        let shipped = Settings::shipped();
        assert_eq!(CrossTrackMeaning::of(&shipped), m);
        let mut cards = shipped;
        cards.backend = Backend::Cards;
        assert_eq!(
            CrossTrackMeaning::of(&cards).cm(0.0),
            "not known on the real robot"
        );
    }
}
