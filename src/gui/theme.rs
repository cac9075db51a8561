//! The window's looks for a field: a light, high-contrast theme for daylight and a dark
//! one (`[gui] theme`, F2 switches), text no smaller than 12 px, and the colours that
//! carry meaning (a fault, a warning, a mode) chosen for each ground.

use eframe::egui::{self, Color32, FontId, TextStyle, Visuals};

use crate::config::Theme;
use crate::state::modes::Mode;

/// The smallest text in the window, px: hints and reasons stay readable in sunlight.
pub(crate) const SMALLEST_TEXT_PX: f32 = 12.5;

/// Set `theme`'s colours and the text sizes on `ctx` (not the system's preference: the
/// operator chose in robot.ini or with F2).
pub fn apply(ctx: &egui::Context, theme: Theme) {
    ctx.set_visuals_of(egui::Theme::Light, visuals(Theme::Light));
    ctx.set_visuals_of(egui::Theme::Dark, visuals(Theme::Dark));
    ctx.all_styles_mut(|style| {
        style.text_styles = [
            (TextStyle::Small, FontId::proportional(SMALLEST_TEXT_PX)),
            (TextStyle::Body, FontId::proportional(15.0)),
            (TextStyle::Button, FontId::proportional(15.0)),
            (TextStyle::Monospace, FontId::monospace(14.0)),
            (TextStyle::Heading, FontId::proportional(20.0)),
        ]
        .into();
    });
    ctx.set_theme(match theme {
        Theme::Light => egui::Theme::Light,
        Theme::Dark => egui::Theme::Dark,
    });
}

fn visuals(theme: Theme) -> Visuals {
    match theme {
        Theme::Light => {
            let mut v = Visuals::light();
            // Black on white, and weak text dark grey rather than egui's pale one.
            v.override_text_color = Some(Color32::BLACK);
            v.weak_text_color = Some(Color32::from_gray(60));
            v.panel_fill = Color32::WHITE;
            v.window_fill = Color32::WHITE;
            v.faint_bg_color = Color32::from_gray(235);
            v
        }
        Theme::Dark => {
            let mut v = Visuals::dark();
            v.override_text_color = Some(Color32::from_gray(235));
            v.weak_text_color = Some(Color32::from_gray(185));
            v
        }
    }
}

/// The colour for the ground the window has now: `on_dark` or `on_light`.
fn on_ground(ui: &egui::Ui, on_dark: Color32, on_light: Color32) -> Color32 {
    if ui.visuals().dark_mode {
        on_dark
    } else {
        on_light
    }
}

/// A fault, an e-stop pressed, anything abnormal.
pub fn fault(ui: &egui::Ui) -> Color32 {
    on_ground(
        ui,
        Color32::from_rgb(255, 90, 90),
        Color32::from_rgb(190, 0, 0),
    )
}

/// A warning that is not a fault (a refusal, no real-time priority).
pub fn warning(ui: &egui::Ui) -> Color32 {
    on_ground(
        ui,
        Color32::from_rgb(255, 170, 60),
        Color32::from_rgb(170, 80, 0),
    )
}

/// The link to a robot watched over the bus, while it is fresh.
pub fn link(ui: &egui::Ui) -> Color32 {
    on_ground(
        ui,
        Color32::from_rgb(120, 200, 255),
        Color32::from_rgb(0, 70, 160),
    )
}

/// What is no longer known (a silent robot's mode).
pub fn unknown(ui: &egui::Ui) -> Color32 {
    on_ground(ui, Color32::from_gray(140), Color32::from_gray(110))
}

pub fn mode(ui: &egui::Ui, mode: Mode) -> Color32 {
    let (on_dark, on_light) = match mode {
        Mode::Halt => ((200, 200, 200), (60, 60, 60)),
        Mode::Joystick => ((120, 180, 255), (0, 80, 200)),
        Mode::Autonomous => ((90, 220, 120), (0, 130, 40)),
        Mode::Test => ((240, 200, 80), (150, 100, 0)),
        Mode::Fault => ((255, 90, 90), (190, 0, 0)),
    };
    let rgb = |(r, g, b)| Color32::from_rgb(r, g, b);
    on_ground(ui, rgb(on_dark), rgb(on_light))
}
