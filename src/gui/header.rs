//! Always visible: the mode, the HALT button (also the Space key), a pressed e-stop,
//! the active fault in a field technician's words, how long ago it happened, what to
//! check and whether it came back after a power-up, and the supervisor's last answer
//! to the operator.

use eframe::egui::{self, Color32, RichText};

use super::requests::Requests;
use super::theme;
use super::view::{RemoteLink, View};
use crate::state::fault_advice::CameBack;
use crate::state::modes::{Mode, Request};

/// If the supervisor has not published for this long, it has stopped, s.
pub(crate) const SUPERVISOR_SILENT_S: f64 = 1.0;

/// HALT: asked in every mode. In Fault the outputs are already safe, so the
/// supervisor's refusal is said as that.
pub fn halt(view: &View, requests: &mut Requests) {
    if view.status.mode == Mode::Fault {
        requests.say(
            "halt: the robot is in fault, its outputs are already safe",
            false,
            view.now_s,
        );
        return;
    }
    requests.ask(Request::Mode(Mode::Halt), "halted");
}

pub fn show(ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
    ui.add_space(4.0);
    ui.horizontal(|ui| {
        let halt_button = egui::Button::new(
            RichText::new("HALT")
                .size(34.0)
                .strong()
                .color(Color32::WHITE),
        )
        .fill(Color32::from_rgb(200, 30, 30))
        .min_size(egui::vec2(170.0, 64.0));
        if ui
            .add(halt_button)
            .on_hover_text("Stop driving and stand, in every mode (also the Space key)")
            .clicked()
        {
            halt(view, requests);
        }
        ui.add_space(12.0);
        ui.vertical(|ui| {
            mode_line(ui, view);
            if let Some(warning) = &view.not_realtime {
                ui.label(RichText::new(warning).strong().color(theme::warning(ui)));
            }
            // Always one line, so that the layout stays when the keyboard comes and goes.
            if ui.input(|i| i.focused) {
                ui.label(RichText::new("Space = HALT: this window has the keyboard").weak());
            } else {
                ui.label(
                    RichText::new(
                        "the keyboard is another window's: Space = HALT only after a click in this window",
                    )
                    .strong()
                    .color(theme::warning(ui)),
                );
            }
            if let Some(link) = &view.remote {
                remote(ui, link);
            }
            // In a scope of its own: a stale fault line greys only itself.
            ui.scope(|ui| fault_line(ui, view));
            if view.remote.is_none() && view.status.tick > 0 && view.now_s - view.status.t_s > SUPERVISOR_SILENT_S {
                ui.label(
                    RichText::new("the controller has stopped: close this window and see the log")
                        .strong()
                        .color(theme::fault(ui)),
                );
            }
            // Always one line, empty or not: the layout does not move at the first answer.
            match requests.feedback() {
                Some(f) => {
                    let colour = if f.refused {
                        theme::warning(ui)
                    } else {
                        ui.visuals().text_color()
                    };
                    ui.label(RichText::new(format!("{:.1} s  {}", f.at_s, f.text)).color(colour));
                }
                None => {
                    ui.label(RichText::new("requests and answers show here").weak());
                }
            }
        });
    });
    ui.add_space(4.0);
}

/// The mode in big letters, then speed, wheel angle, power and time. Over the bus:
/// nothing until the first status, grey once it is stale, and "unknown" after
/// [gui] remote_stale_s.
fn mode_line(ui: &mut egui::Ui, view: &View) {
    let st = &view.status;
    let remote = view.remote.as_ref();
    ui.horizontal(|ui| {
        ui.label(RichText::new("Mode").size(16.0));
        let (word, colour) = match remote {
            Some(link) if link.no_data() => ("NO DATA YET".to_string(), theme::unknown(ui)),
            Some(link) if link.mode_unknown() => ("UNKNOWN".to_string(), theme::unknown(ui)),
            Some(link) if link.stale() => (st.mode.name().to_uppercase(), theme::unknown(ui)),
            _ => (st.mode.name().to_uppercase(), theme::mode(ui, st.mode)),
        };
        ui.label(RichText::new(word).size(30.0).strong().color(colour));
        ui.add_space(16.0);
        if remote.is_none_or(|link| !link.no_data()) {
            let values = format!(
                "{:.2} m/s   wheel {:+.1} deg   power {}   t = {:.1} s",
                st.measured.speed_mps,
                st.measured.wheel_angle_rad.to_degrees(),
                power_text(st.power),
                view.now_s
            );
            let stale = remote.is_some_and(RemoteLink::stale);
            ui.add_enabled(!stale, egui::Label::new(values));
        }
    });
}

/// The active fault, or "no fault"; over the bus, the robot's own words, not known
/// before its first status or once its mode is unknown, and greyed while stale.
fn fault_line(ui: &mut egui::Ui, view: &View) {
    if let Some(link) = view.remote.as_ref().filter(|link| link.mode_unknown()) {
        let words = if link.no_data() {
            "fault: no data yet"
        } else {
            "fault: not known (the robot is silent)"
        };
        ui.label(RichText::new(words).size(18.0).color(theme::unknown(ui)));
        return;
    }
    if view.remote.as_ref().is_some_and(RemoteLink::stale) {
        ui.disable();
    }
    // Whatever fault is latched: a pressed e-stop is what a person at the robot must
    // know first, and a latched fault of another cause would hide it.
    if let Some(pressed) = estop_words(view) {
        ui.label(
            RichText::new(pressed)
                .size(18.0)
                .strong()
                .color(theme::fault(ui)),
        );
    }
    let remote = view.remote.as_ref();
    let (text, check, came_back_after_s) = match (view.status.fault, remote) {
        // Over the bus the fault comes in words.
        (
            None,
            Some(RemoteLink {
                fault: Some(fault),
                fault_check,
                fault_came_back_after_s,
                ..
            }),
        ) => (
            format!("FAULT: {fault}"),
            fault_check.as_deref(),
            *fault_came_back_after_s,
        ),
        (Some(fault), _) => (
            format!(
                "FAULT: {}  ({:.1} s ago)",
                fault.cause,
                (view.now_s - fault.t_s).max(0.0)
            ),
            Some(fault.cause.what_to_check()),
            fault.came_back_after_s,
        ),
        (None, _) => {
            ui.label(RichText::new("no fault").size(18.0));
            return;
        }
    };
    ui.label(
        RichText::new(text)
            .size(18.0)
            .strong()
            .color(theme::fault(ui)),
    );
    if let Some(after_s) = came_back_after_s {
        let words = CameBack { after_s }.to_string();
        ui.label(
            RichText::new(words)
                .size(16.0)
                .strong()
                .color(theme::fault(ui)),
        );
    }
    if let Some(check) = check {
        ui.label(RichText::new(format!("what to check: {check}")).size(16.0));
    }
}

/// "E-STOP FRONT PRESSED" (or back, or both) while one is, once the inputs are known:
/// here from the first tick, over the bus from the first tick flow.
fn estop_words(view: &View) -> Option<&'static str> {
    let known = match &view.remote {
        Some(link) => link.inputs_seen,
        None => view.status.tick > 0,
    };
    let i = &view.status.inputs;
    match (known, i.estop_front_released, i.estop_back_released) {
        (false, _, _) | (true, true, true) => None,
        (true, false, true) => Some("E-STOP FRONT PRESSED"),
        (true, true, false) => Some("E-STOP BACK PRESSED"),
        (true, false, false) => Some("E-STOP FRONT AND BACK PRESSED"),
    }
}

/// Which robot this window watches over the bus, and how old its newest status is.
pub(crate) fn remote_line(link: &RemoteLink) -> String {
    let what = match link.operator {
        Some(true) => "HALT, power up and modes",
        Some(false) => "HALT only",
        None => "HALT; the rest not known yet (asking the robot)",
    };
    match link.age_s {
        None => format!(
            "no data yet: waiting for {}'s status at {} ({:.0} s)",
            link.robot, link.endpoint, link.waited_s
        ),
        Some(age_s) if link.mode_unknown() => format!(
            "watching {} at {}: no status for {age_s:.0} s: its mode is not known",
            link.robot, link.endpoint
        ),
        Some(age_s) if link.stale() => format!(
            "watching {} at {}: no status for {age_s:.1} s",
            link.robot, link.endpoint
        ),
        Some(age_s) => format!(
            "watching {} at {}: status {:.0} ms old; requests: {what}",
            link.robot,
            link.endpoint,
            age_s * 1000.0
        ),
    }
}

/// The link to a robot watched over the bus: red once its status is older than a
/// second, since everything else in the window is then older too.
fn remote(ui: &mut egui::Ui, link: &RemoteLink) {
    let colour = if link.stale() {
        theme::fault(ui)
    } else {
        theme::link(ui)
    };
    ui.label(
        RichText::new(remote_line(link))
            .size(16.0)
            .strong()
            .color(colour),
    );
}

pub(crate) fn power_text(power: crate::state::status::PowerState) -> &'static str {
    match power {
        crate::state::status::PowerState::Off => "off",
        crate::state::status::PowerState::Closing { .. } => "closing",
        crate::state::status::PowerState::On => "on",
    }
}
