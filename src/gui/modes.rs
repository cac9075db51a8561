//! Mode buttons, enabled only where the supervisor's state machine allows, each with the
//! reason when it is not: the GUI asks the supervisor's own rules (`supervisor::rules::why_not`,
//! `power_up_refusal`), so the two cannot disagree.

use eframe::egui::{self, RichText};

use super::requests::Requests;
use super::theme;
use super::view::View;
use crate::state::modes::{Mode, Request};
use crate::supervisor::rules::{power_up_refusal, why_not};

/// A wide button that may be disabled, with the reason in small text under it.
fn button_with_reason(ui: &mut egui::Ui, label: RichText, why_not: Option<String>) -> bool {
    let clicked = ui
        .add_enabled(
            why_not.is_none(),
            egui::Button::new(label).min_size(egui::vec2(ui.available_width(), 34.0)),
        )
        .clicked();
    if let Some(why) = why_not {
        ui.label(RichText::new(why).small().weak());
    }
    ui.add_space(4.0);
    clicked
}

/// Over the bus, only HALT unless the robot takes more from it; nothing before the
/// robot has been heard from.
fn read_only(view: &View) -> Option<String> {
    let link = view.remote.as_ref()?;
    if link.no_data() {
        return Some(format!(
            "waiting for the robot's first status (no data yet from {})",
            link.endpoint
        ));
    }
    if link.mode_unknown() {
        return Some("the robot has been silent too long: its mode is not known".into());
    }
    match link.operator {
        Some(true) => None,
        Some(false) => Some(
            "watching only: the robot takes only HALT from the bus ([bus] accept_requests = halt)"
                .into(),
        ),
        None => Some("asking the robot whether it takes requests from the bus".into()),
    }
}

pub fn show(ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
    let st = &view.status;
    ui.heading("Modes");
    ui.add_space(4.0);
    let power_up = button_with_reason(
        ui,
        RichText::new("Power up").size(18.0),
        read_only(view).or_else(|| power_up_refusal(st).map(|r| r.to_string())),
    );
    if power_up {
        requests.ask(Request::PowerUp, "powering up");
    }
    ui.separator();
    for (mode, label) in [
        (Mode::Joystick, "Joystick"),
        (Mode::Autonomous, "Autonomous"),
        (Mode::Test, "Test"),
    ] {
        // The mode we are in needs no button press: say so rather than grey it silently.
        let reason = match read_only(view) {
            Some(why) => Some(why),
            None if st.mode == mode => Some(format!("now in {mode}")),
            None => why_not(mode, st),
        };
        let text = RichText::new(label).size(18.0).color(theme::mode(ui, mode));
        if button_with_reason(ui, text, reason) {
            requests.ask(Request::Mode(mode), &format!("mode {mode}"));
        }
    }
    ui.separator();
    ui.label(
        RichText::new(
            "HALT (top, or Space) stops in every mode. After a fault: release the cause, \
             then Power up.",
        )
        .small(),
    );
}
