//! The hardware test panel (mode Test, entered only from Halt with the robot standing):
//! every input live, a switch for each digital output, and for each amplifier a fixed
//! voltage, a slow ramp or a step, limited to a settable maximum, with a stop.
//!
//! The panel computes the amplifier voltages at its own pass rate (30 a second while a
//! ramp or a step is under way, see `changing`) and sends them as `Request::TestOutputs`. Safety does not rest on it: the supervisor
//! takes test outputs only in Test, limits every amplifier to +-10 V, keeps the end-switch
//! guard, starts Test with the safe outputs (the motor contactor as it was: the relay
//! switch is then the power switch, watched by the power checks), and on leaving Test
//! (HALT) or any fault writes the safe outputs in that same tick; e-stops and every fault check keep working.
//! If the GUI stops, its heartbeat fault does the same. When the mode is not Test the
//! panel forgets its switches, so re-entering Test starts from safe outputs.
//!
//! Hold to run: the amplifiers get the panel's volts only while a person holds the
//! panel's Hold to run (the pointer pressed on it, or the H key held) or the joystick's
//! dead-man. The panel tells the supervisor each frame a hold goes on (renewed every
//! HOLD_RENEW_S) and at once when it ends; the supervisor lets a hold that is not
//! renewed lapse by itself, so a GUI that stops with the button down stops the wheels.

use eframe::egui::{self, RichText};
use mechweed_hw::Outputs;

use super::commissioning::Commissioning;
use super::requests::Requests;
use super::status::inputs_grid;
use super::view::View;
use crate::state::modes::{Mode, Request};
use crate::supervisor::rules::why_not;

/// A step waits this long at 0 V before jumping, so the plot shows the jump, s.
const STEP_DELAY_S: f64 = 1.0;

/// A hold is renewed this often, s: well inside the supervisor's lapse time
/// (supervisor::test_mode::PANEL_HOLD_S, 0.25 s).
pub(crate) const HOLD_RENEW_S: f64 = 0.1;

/// The key that holds like the button, while no text field has the keyboard.
const HOLD_KEY: egui::Key = egui::Key::H;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wave {
    Stop,
    Fixed,
    Ramp,
    Step,
}

/// One amplifier's test program.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmpTest {
    pub wave: Wave,
    /// Target voltage (fixed, end of the ramp, height of the step), V.
    pub level_v: f64,
    /// Ramp rate, V/s.
    pub ramp_v_per_s: f64,
    /// When the wave was started, s.
    pub started_s: f64,
}

impl Default for AmpTest {
    fn default() -> Self {
        AmpTest {
            wave: Wave::Stop,
            level_v: 1.0,
            ramp_v_per_s: 0.5,
            started_s: 0.0,
        }
    }
}

impl AmpTest {
    /// The voltage now, limited to +-`max_v`.
    pub fn volts(&self, now_s: f64, max_v: f64) -> f64 {
        let t_s = (now_s - self.started_s).max(0.0);
        let v = match self.wave {
            Wave::Stop => 0.0,
            Wave::Fixed => self.level_v,
            Wave::Ramp => {
                self.level_v.signum() * (self.ramp_v_per_s.abs() * t_s).min(self.level_v.abs())
            }
            Wave::Step if t_s < STEP_DELAY_S => 0.0,
            Wave::Step => self.level_v,
        };
        v.clamp(-max_v.abs(), max_v.abs())
    }
}

pub struct TestPanel {
    pub outputs: Outputs,
    /// Left drive, right drive, steering.
    pub amps: [AmpTest; 3],
    /// No amplifier gets more than this, V.
    pub max_v: f64,
    last_sent: Option<Outputs>,
    /// The last frame drawn saw Hold to run held.
    holding: bool,
    /// When the hold now going on was last sent (None: no hold sent), s.
    hold_sent_s: Option<f64>,
    /// The commissioning steps and their last result (commissioning.rs).
    commissioning: Commissioning,
}

impl Default for TestPanel {
    fn default() -> Self {
        TestPanel {
            outputs: Outputs::SAFE,
            amps: [AmpTest::default(); 3],
            max_v: 3.0,
            last_sent: None,
            holding: false,
            hold_sent_s: None,
            commissioning: Commissioning::default(),
        }
    }
}

impl TestPanel {
    /// A ramp or a step is under way, or a hold that must be renewed: the GUI must keep
    /// passing.
    pub(crate) fn changing(&self, now_s: f64) -> bool {
        self.hold_sent_s.is_some()
            || self.last_sent.is_some()
                && self
                    .amps
                    .iter()
                    .any(|a| a.volts(now_s, self.max_v) != a.volts(f64::INFINITY, self.max_v))
    }

    /// The outputs the panel asks for now.
    pub(crate) fn wanted(&self, now_s: f64) -> Outputs {
        let [l, r, s] = self.amps.map(|a| a.volts(now_s, self.max_v));
        Outputs {
            amp_left_v: l,
            amp_right_v: r,
            amp_steer_v: s,
            ..self.outputs
        }
    }

    /// Every pass: in Test, send the outputs when they change; otherwise forget them.
    /// (A refusal comes back as "test outputs refused: ..." in the feedback line.)
    pub fn keep_sending(&mut self, view: &View, requests: &mut Requests) {
        if view.status.mode != Mode::Test {
            if self.last_sent.is_some() || self.outputs != Outputs::SAFE {
                let max_v = self.max_v;
                *self = TestPanel {
                    max_v,
                    ..TestPanel::default()
                };
            }
            return;
        }
        if self.last_sent.is_none() {
            // Test keeps the contactor as it was: the relay switch starts where the
            // supervisor has it, so entering Test after Power up leaves power on.
            self.outputs.main_power_on = view.status.outputs.main_power_on;
        }
        self.keep_holding(view.now_s, requests);
        let wanted = self.wanted(view.now_s);
        if self.last_sent == Some(wanted) {
            return;
        }
        self.last_sent = Some(wanted);
        requests.ask_quietly(Request::TestOutputs(wanted));
    }

    /// The hold as the last frame saw it: renewed while held, ended when let go. A pass
    /// with no frame drawn (the tab not shown, the window minimised) is no hold.
    fn keep_holding(&mut self, now_s: f64, requests: &mut Requests) {
        let held = std::mem::take(&mut self.holding);
        match (held, self.hold_sent_s) {
            (true, Some(sent_s)) if now_s - sent_s < HOLD_RENEW_S => {}
            (true, _) => {
                requests.ask_quietly(Request::TestHold(true));
                self.hold_sent_s = Some(now_s);
            }
            (false, Some(_)) => {
                requests.ask_quietly(Request::TestHold(false));
                self.hold_sent_s = None;
            }
            (false, None) => {}
        }
    }

    pub fn show(&mut self, ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
        let in_test = view.status.mode == Mode::Test;
        ui.horizontal(|ui| {
            let reason = if in_test {
                None
            } else {
                why_not(Mode::Test, &view.status)
            };
            if ui
                .add_enabled(
                    !in_test && reason.is_none(),
                    egui::Button::new("Enter Test"),
                )
                .clicked()
            {
                requests.ask(Request::Mode(Mode::Test), "mode test");
            }
            if ui
                .add_enabled(in_test, egui::Button::new("Leave Test"))
                .clicked()
            {
                requests.ask(Request::Mode(Mode::Halt), "left test: safe outputs");
            }
            if let Some(why) = reason {
                ui.label(RichText::new(why).weak());
            }
        });
        if in_test {
            ui.label(
                RichText::new(
                    "The robot must be on its stand with the drive wheels off the ground.",
                )
                .strong()
                .color(super::theme::warning(ui)),
            );
        }
        ui.add_enabled_ui(in_test, |ui| {
            self.hold_button(ui, view);
            ui.heading("Digital outputs");
            ui.horizontal(|ui| {
                let o = &mut self.outputs;
                ui.checkbox(&mut o.main_power_on, "Main power relay");
                ui.checkbox(&mut o.brake_release_left, "Release brake left");
                ui.checkbox(&mut o.brake_release_right, "Release brake right");
                ui.checkbox(&mut o.tool_on, "Tool");
            });
            ui.heading("Amplifiers");
            ui.horizontal(|ui| {
                ui.label("Limit +-");
                ui.add(
                    egui::DragValue::new(&mut self.max_v)
                        .range(0.0..=10.0)
                        .speed(0.05)
                        .suffix(" V"),
                );
                if ui.button("Stop all").clicked() {
                    for a in &mut self.amps {
                        a.wave = Wave::Stop;
                    }
                }
            });
            self.amplifiers_grid(ui, view.now_s);
            ui.separator();
            self.commissioning.show(ui, view, requests);
        });
        ui.separator();
        ui.heading("Inputs");
        inputs_grid(ui, view);
    }

    /// Hold to run, and whether something holds now.
    fn hold_button(&mut self, ui: &mut egui::Ui, view: &View) {
        ui.horizontal(|ui| {
            let button = ui.add(egui::Button::new(RichText::new("Hold to run").strong()));
            let key = ui.input(|i| i.key_down(HOLD_KEY)) && !ui.ctx().text_edit_focused();
            self.holding = button.is_pointer_button_down_on() || key;
            let deadman = view.status.inputs.joystick_enable;
            ui.label(if self.holding || deadman {
                "held: the amplifiers get the panel's volts"
            } else {
                "not held: every amplifier 0 V (hold this button, the H key, or the dead-man)"
            });
        });
    }

    /// One row per amplifier: its level, its ramp, its wave, and the volts it gives now.
    fn amplifiers_grid(&mut self, ui: &mut egui::Ui, now_s: f64) {
        egui::Grid::new("amps").striped(true).show(ui, |ui| {
            for (k, name) in ["left drive", "right drive", "steering"]
                .into_iter()
                .enumerate()
            {
                let a = &mut self.amps[k];
                ui.label(name);
                ui.add(
                    egui::DragValue::new(&mut a.level_v)
                        .range(-10.0..=10.0)
                        .speed(0.05)
                        .suffix(" V"),
                );
                ui.add(
                    egui::DragValue::new(&mut a.ramp_v_per_s)
                        .range(0.01..=5.0)
                        .speed(0.01)
                        .suffix(" V/s"),
                );
                for (wave, label) in [
                    (Wave::Fixed, "Fixed"),
                    (Wave::Ramp, "Ramp"),
                    (Wave::Step, "Step"),
                ] {
                    if ui.selectable_label(a.wave == wave, label).clicked() {
                        a.wave = wave;
                        a.started_s = now_s;
                    }
                }
                if ui.button("Stop").clicked() {
                    a.wave = Wave::Stop;
                }
                ui.monospace(format!("{:+.2} V", a.volts(now_s, self.max_v)));
                ui.end_row();
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waves_are_limited_to_the_maximum() {
        let mut a = AmpTest {
            wave: Wave::Fixed,
            level_v: 8.0,
            ramp_v_per_s: 1.0,
            started_s: 10.0,
        };
        assert_eq!(a.volts(11.0, 3.0), 3.0);
        a.wave = Wave::Ramp;
        assert!((a.volts(12.0, 5.0) - 2.0).abs() < 1e-12);
        assert_eq!(a.volts(30.0, 5.0), 5.0);
        a.level_v = -2.0;
        assert_eq!(a.volts(30.0, 5.0), -2.0);
        a.wave = Wave::Step;
        assert_eq!(a.volts(10.5, 5.0), 0.0);
        assert_eq!(a.volts(11.5, 5.0), -2.0);
        a.wave = Wave::Stop;
        assert_eq!(a.volts(11.5, 5.0), 0.0);
    }

    #[test]
    fn a_ramp_or_step_under_way_keeps_the_gui_passing_and_a_fixed_level_does_not() {
        let mut panel = TestPanel::default();
        panel.amps[0] = AmpTest {
            wave: Wave::Ramp,
            level_v: 2.0,
            ramp_v_per_s: 1.0,
            started_s: 10.0,
        };
        assert!(!panel.changing(11.0), "not in Test: nothing is sent");
        panel.last_sent = Some(Outputs::SAFE);
        assert!(panel.changing(11.0));
        assert!(!panel.changing(12.5), "the ramp has reached its level");
        panel.amps[0].wave = Wave::Step;
        assert!(panel.changing(10.5));
        assert!(!panel.changing(11.5));
        panel.amps[0].wave = Wave::Fixed;
        assert!(!panel.changing(10.0));
    }
}
