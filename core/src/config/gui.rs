//! The [gui] section: how the operator's window looks, and how long a view over the bus
//! may go without the robot's status before it stops claiming to know the robot's mode.

use super::reader::Reader;

/// The window's colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Theme {
    /// Dark text on a light ground, strong colours: readable in sunlight.
    #[default]
    Light,
    /// Light text on a dark ground: a workshop or dusk.
    Dark,
}

impl Theme {
    pub fn other(self) -> Theme {
        match self {
            Theme::Light => Theme::Dark,
            Theme::Dark => Theme::Light,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Theme::Light => "light",
            Theme::Dark => "dark",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuiSettings {
    pub theme: Theme,
    /// `mechweed watch`: with no status from the robot for this long, its mode is shown
    /// as unknown, s (what the window shows goes grey after a second already).
    pub remote_stale_s: f64,
}

pub(super) fn load(r: &mut Reader) -> GuiSettings {
    let s = "gui";
    GuiSettings {
        theme: [Theme::Light, Theme::Dark][r.choice(s, "theme", &["light", "dark"])],
        remote_stale_s: r.f64(s, "remote_stale_s", 1.0, 60.0),
    }
}
