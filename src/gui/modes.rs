//! Mode buttons, enabled only where the supervisor's state machine allows, each with the
//! reason when it is not: the GUI asks the supervisor's own rules (`supervisor::rules::why_not`,
//! `power_up_refusal`), so the two cannot disagree.

use eframe::egui::{self, RichText};

use super::header::mode_colour;
use super::requests::Requests;
use super::view::View;
use crate::modes::{Mode, Request};
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

/// Over the bus, only HALT unless the robot takes more from it.
fn read_only(view: &View) -> Option<String> {
    let link = view.remote.as_ref()?;
    if link.operator {
        None
    } else {
        Some(
            "watching only: the robot takes only HALT from the bus ([bus] accept_requests = halt)"
                .into(),
        )
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
        let reason = if st.mode == mode {
            Some(format!("now in {mode}"))
        } else {
            read_only(view).or_else(|| why_not(mode, st))
        };
        let text = RichText::new(label).size(18.0).color(mode_colour(mode));
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
