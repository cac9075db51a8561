//! Always visible: the mode, the HALT button (also the Space key), the active fault in
//! a field technician's words and how long ago it happened, and the supervisor's last
//! answer to the operator.

use eframe::egui::{self, Color32, RichText};

use super::requests::Requests;
use super::view::{RemoteLink, View};
use crate::modes::{Mode, Request};

/// If the supervisor has not published for this long, it has stopped, s.
pub const SUPERVISOR_SILENT_S: f64 = 1.0;

pub fn mode_colour(mode: Mode) -> Color32 {
    match mode {
        Mode::Halt => Color32::from_rgb(200, 200, 200),
        Mode::Joystick => Color32::from_rgb(120, 180, 255),
        Mode::Autonomous => Color32::from_rgb(90, 220, 120),
        Mode::Test => Color32::from_rgb(240, 200, 80),
        Mode::Fault => Color32::from_rgb(255, 90, 90),
    }
}

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
    let st = &view.status;
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
            ui.horizontal(|ui| {
                ui.label(RichText::new("Mode").size(16.0));
                ui.label(
                    RichText::new(st.mode.name().to_uppercase())
                        .size(30.0)
                        .strong()
                        .color(mode_colour(st.mode)),
                );
                ui.add_space(16.0);
                ui.label(format!(
                    "{:.2} m/s   wheel {:+.1} deg   power {}   t = {:.1} s",
                    st.measured.speed_mps,
                    st.measured.wheel_angle_rad.to_degrees(),
                    power_text(st.power),
                    view.now_s
                ));
            });
            if let Some(warning) = &view.not_realtime {
                ui.label(
                    RichText::new(warning)
                        .strong()
                        .color(Color32::from_rgb(255, 150, 40)),
                );
            }
            if let Some(link) = &view.remote {
                remote(ui, link);
            }
            let remote_fault = view.remote.as_ref().and_then(|link| link.fault.as_ref());
            match st.fault {
                // Over the bus the fault comes in words.
                None if remote_fault.is_some() => {
                    let fault = remote_fault.cloned().unwrap_or_default();
                    ui.label(
                        RichText::new(format!("FAULT: {fault}"))
                            .size(18.0)
                            .strong()
                            .color(Color32::from_rgb(255, 90, 90)),
                    );
                }
                Some(fault) => {
                    ui.label(
                        RichText::new(format!(
                            "FAULT: {}  ({:.1} s ago)",
                            fault.cause,
                            (view.now_s - fault.t_s).max(0.0)
                        ))
                        .size(18.0)
                        .strong()
                        .color(Color32::from_rgb(255, 90, 90)),
                    );
                }
                None => {
                    ui.label(RichText::new("no fault").size(18.0));
                }
            }
            if view.remote.is_none() && st.tick > 0 && view.now_s - st.t_s > SUPERVISOR_SILENT_S {
                ui.label(
                    RichText::new("the controller has stopped: close this window and see the log")
                        .strong()
                        .color(Color32::RED),
                );
            }
            if let Some(f) = requests.feedback() {
                let colour = if f.refused {
                    Color32::from_rgb(255, 170, 60)
                } else {
                    ui.visuals().text_color()
                };
                ui.label(RichText::new(format!("{:.1} s  {}", f.at_s, f.text)).color(colour));
            }
        });
    });
    ui.add_space(4.0);
}

/// Which robot this window watches over the bus, and how old its newest status is.
pub fn remote_line(link: &RemoteLink) -> String {
    let what = if link.operator {
        "HALT, power up and modes"
    } else {
        "HALT only"
    };
    match link.age_s {
        None => format!("waiting for {}'s status at {}", link.robot, link.endpoint),
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
        Color32::RED
    } else {
        Color32::from_rgb(120, 200, 255)
    };
    ui.label(
        RichText::new(remote_line(link))
            .size(16.0)
            .strong()
            .color(colour),
    );
}

pub fn power_text(power: crate::status::PowerState) -> &'static str {
    match power {
        crate::status::PowerState::Off => "off",
        crate::status::PowerState::Closing { .. } => "closing",
        crate::status::PowerState::On => "on",
    }
}
