//! The simulated robot (only with the simulated plant): press and release each e-stop,
//! inject every fault of the sim events, and an on-screen joystick (drag pad plus
//! dead-man button) standing in for the analog one. All of it goes to the plant through
//! `SimControl`, as a person at the robot would act: never to the controller directly.

use eframe::egui::{self, RichText, Sense};
use mechweed_hw::sim::{EventAction, RowShape, SimControl};
use mechweed_hw::{EncoderId, Side};

use super::requests::Requests;
use super::view::View;
use crate::bench::rows::row_name;
use crate::config::Settings;
use crate::state::modes::Mode;

/// Battery reading of the "battery low" fault, V (below [faults] battery_min_v).
const LOW_BATTERY_V: f64 = 19.0;
/// How long "camera link silent" lasts, s.
const SILENT_S: f64 = 2.0;
/// Size of the joystick's drag pad, points.
const PAD: f32 = 170.0;

pub struct SimPanel {
    /// Stick position, -1..1: x to the right, y forward.
    pub stick: [f64; 2],
    pub dead_man: bool,
    full_scale_v: f64,
    battery_v: f64,
    last_sent: Option<(f64, f64, bool)>,
    /// The settings of the run, and the row and speed the next reset will use.
    settings: Settings,
    pub row: RowShape,
    pub speed_mps: f64,
    /// Asked for by "Reset": the settings to restart the controller with.
    pub restart: Option<Settings>,
}

impl SimPanel {
    pub fn new(settings: &Settings) -> SimPanel {
        SimPanel {
            stick: [0.0; 2],
            dead_man: false,
            full_scale_v: settings.joystick.full_scale_v,
            battery_v: settings.sim.battery_v,
            last_sent: None,
            settings: settings.clone(),
            row: settings.sim.row,
            speed_mps: settings.steer.speed_mps,
            restart: None,
        }
    }

    /// The joystick's volts as wired (steer + = right, speed + = forward) and dead-man.
    pub fn joystick(&self) -> (f64, f64, bool) {
        let v = self.full_scale_v;
        (self.stick[0] * v, self.stick[1] * v, self.dead_man)
    }

    /// Every pass: pass the on-screen joystick to the plant when it changes.
    pub(crate) fn keep_joystick(&mut self, sim: &SimControl) {
        let now = self.joystick();
        if self.last_sent != Some(now) {
            sim.set_joystick(now.0, now.1, now.2);
            self.last_sent = Some(now);
        }
    }

    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        view: &View,
        sim: &SimControl,
        requests: &mut Requests,
    ) {
        let mut act = |action: EventAction, ui: &mut egui::Ui, label: &str| {
            if ui.button(label).clicked() {
                let queued = sim.apply(action);
                let text = if queued {
                    format!("simulated robot: {label}")
                } else {
                    "simulated robot busy: try again".to_string()
                };
                requests.say(text, !queued, view.now_s);
            }
        };
        ui.heading("Simulated robot");
        let i = &view.status.inputs;
        ui.label(RichText::new("Emergency stops").strong());
        ui.horizontal_wrapped(|ui| {
            act(EventAction::EstopFront, ui, "Press e-stop front");
            act(EventAction::EstopBack, ui, "Press e-stop back");
        });
        act(EventAction::EstopRelease, ui, "Release e-stops");
        let pressed = !(i.estop_front_released && i.estop_back_released);
        ui.label(if pressed {
            "an e-stop is pressed"
        } else {
            "both released"
        });
        ui.separator();

        ui.label(RichText::new("Joystick").strong());
        if view.gamepad.is_some() {
            // The supervisor reads the gamepad in place of the wired joystick.
            ui.label("the gamepad drives ([joystick] source = gamepad): see Inputs");
        } else {
            self.pad(ui);
            ui.checkbox(&mut self.dead_man, "Dead-man button held");
            let (s, v, _) = self.joystick();
            ui.label(format!("steer {s:+.2} V, speed {v:+.2} V"));
        }
        ui.separator();

        ui.label(RichText::new("Faults").strong());
        ui.horizontal_wrapped(|ui| {
            for (action, label) in fault_buttons(self.battery_v) {
                act(action, ui, label);
            }
        });
        ui.label(
            RichText::new(
                "A stuck encoder and a broken potentiometer wire last for the rest of the run.",
            )
            .small()
            .weak(),
        );
        ui.separator();

        self.row_and_reset(ui, view);
    }

    /// The row to reset the robot to and its speed, the reset (standing only), and the
    /// simulated truth.
    fn row_and_reset(&mut self, ui: &mut egui::Ui, view: &View) {
        ui.label(RichText::new("Row and reset").strong());
        ui.horizontal_wrapped(|ui| {
            for row in [RowShape::Straight, RowShape::SCurve, RowShape::Arc] {
                ui.selectable_value(&mut self.row, row, row_name(row));
            }
        });
        ui.horizontal(|ui| {
            ui.label("autonomous speed");
            let max = self.settings.supervisor.max_speed_mps;
            ui.add(
                egui::DragValue::new(&mut self.speed_mps)
                    .range(0.05..=max)
                    .speed(0.01)
                    .suffix(" m/s"),
            );
        });
        let standing = matches!(view.status.mode, Mode::Halt | Mode::Fault);
        if ui
            .add_enabled(standing, egui::Button::new("Reset robot to row start"))
            .clicked()
        {
            let mut settings = self.settings.clone();
            settings.sim.row = self.row;
            settings.steer.speed_mps = self.speed_mps;
            self.restart = Some(settings);
        }
        ui.label(
            RichText::new(if standing {
                "restarts the controller in halt, e-stops released"
            } else {
                "halt first: a reset restarts the controller"
            })
            .small()
            .weak(),
        );
        ui.separator();
        let t = &view.truth;
        ui.label(format!(
            "truth: x {:.2} m, y {:+.3} m, tool off row {}{}",
            t.x_m,
            t.y_m,
            view.cross_track.cm(t.tool_cross_track_m),
            if t.row_done { ", row done" } else { "" }
        ));
    }

    /// The drag pad: drag to deflect, let go and it springs back to the centre.
    fn pad(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(egui::vec2(PAD, PAD), Sense::drag());
        if let Some(pos) = response
            .interact_pointer_pos()
            .filter(|_| response.dragged())
        {
            let x = (pos.x - rect.center().x) / (PAD / 2.0);
            let y = (rect.center().y - pos.y) / (PAD / 2.0);
            self.stick = [x.clamp(-1.0, 1.0) as f64, y.clamp(-1.0, 1.0) as f64];
        } else {
            self.stick = [0.0; 2];
        }
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 6.0, ui.visuals().extreme_bg_color);
        let lines = ui.visuals().weak_text_color();
        painter.line_segment([rect.center_top(), rect.center_bottom()], (1.0, lines));
        painter.line_segment([rect.left_center(), rect.right_center()], (1.0, lines));
        let knob = rect.center()
            + egui::vec2(self.stick[0] as f32, -self.stick[1] as f32) * (PAD / 2.0 - 12.0);
        // Held: the autonomous colour of the theme; released: the weak text's grey.
        let colour = if self.dead_man {
            super::theme::mode(ui, Mode::Autonomous)
        } else {
            ui.visuals().weak_text_color()
        };
        painter.circle_filled(knob, 12.0, colour);
    }
}

/// The faults the panel can cause, each with its button's label; "Battery normal"
/// gives the battery back its `normal_battery_v`.
fn fault_buttons(normal_battery_v: f64) -> [(EventAction, &'static str); 12] {
    [
        (EventAction::PowerLoss, "Power loss"),
        (EventAction::PowerRestore, "Power back"),
        (EventAction::Battery(LOW_BATTERY_V), "Battery low"),
        (EventAction::Battery(normal_battery_v), "Battery normal"),
        (
            EventAction::EncoderStuck(EncoderId::Left),
            "Left encoder stuck",
        ),
        (
            EventAction::EncoderStuck(EncoderId::Right),
            "Right encoder stuck",
        ),
        (
            EventAction::EncoderStuck(EncoderId::Steer),
            "Steering encoder stuck",
        ),
        (EventAction::LinkSilent(SILENT_S), "Camera silent 2 s"),
        (EventAction::CameraReboot, "Camera reboot"),
        (
            EventAction::EndSwitch(Side::Left),
            "Kick to left end switch",
        ),
        (
            EventAction::EndSwitch(Side::Right),
            "Kick to right end switch",
        ),
        (EventAction::PotBroken, "Potentiometer wire broken"),
    ]
}
