//! The test panel's commissioning steps (the supervisor runs them:
//! core/src/supervisor/commission.rs): a short voltage step on one amplifier, which
//! moves it only while Hold to run is held, and says which way its encoder and the
//! potentiometer moved; and the voltmeter step, a known voltage on AO0..AO2 with the
//! contactor open, which says what a meter must read there. The last result stays on
//! the panel until the next.

use eframe::egui::{self, RichText};
use mechweed_hw::EncoderId;

use super::requests::Requests;
use super::view::View;
use crate::state::commission::TestStep;
use crate::state::modes::Request;
use crate::state::status::Notice;

/// The panel's part: the last step's words.
#[derive(Debug, Default)]
pub struct Commissioning {
    last_said: Option<String>,
}

impl Commissioning {
    pub fn show(&mut self, ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
        if let Some(notice @ (Notice::StepDone { .. } | Notice::Voltmeter { .. })) =
            view.status.notice
        {
            self.last_said = Some(notice.to_string());
        }
        ui.heading("Commissioning");
        ui.label(
            "After probe --watch, in this order: the voltmeter step (relay off), then each \
             amplifier's step (relay on, hold Hold to run while it runs). docs/robot-pc.md, \
             \"Commissioning\".",
        );
        ui.horizontal(|ui| {
            let steps = [
                ("Step left drive", TestStep::Actuator(EncoderId::Left)),
                ("Step right drive", TestStep::Actuator(EncoderId::Right)),
                ("Step steering", TestStep::Actuator(EncoderId::Steer)),
                ("Voltmeter step", TestStep::Voltmeter),
                ("Stop step", TestStep::Stop),
            ];
            for (label, step) in steps {
                if ui.button(label).clicked() {
                    requests.ask(Request::TestStep(step), &format!("{label}: started"));
                }
            }
        });
        if let Some(said) = &self.last_said {
            ui.label(RichText::new(said).strong());
        }
    }
}
