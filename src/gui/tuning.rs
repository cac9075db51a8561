//! Tuning: every regulator gain and steering-law parameter, applied with one button
//! (only in Halt, so nothing jumps while moving), saved to robot.ini changing only those
//! values, or reverted from the file.
//!
//! Values are checked by the same code that reads robot.ini (ranges included): "Apply"
//! reads the settings file in use (the shipped one without a file) with the panel's
//! values as `--set` overrides, so every cross-check sees this robot's own settings;
//! "Save" reads the rewritten file before it replaces the old one.

use std::path::PathBuf;

use eframe::egui::{self, RichText};

use super::ini_edit::{NewValue, set_values, write_atomic};
use super::requests::Requests;
use super::view::View;
use crate::config::{DEFAULT_INI, Settings};
use crate::state::modes::{Gains, Mode, Refusal, Request};

/// One tunable value: where it lives in robot.ini, how it is shown, and how to read
/// it from the settings.
pub(crate) struct Tunable {
    pub section: &'static str,
    pub key: &'static str,
    pub what: &'static str,
    pub get: fn(&Settings) -> f64,
}

macro_rules! tunable {
    ($section:literal, $key:literal, $what:literal, |$s:ident| $get:expr) => {
        Tunable {
            section: $section,
            key: $key,
            what: $what,
            get: |$s: &Settings| $get,
        }
    };
}

/// Every regulator gain and steering-law parameter (the steer thread's rate and the
/// end-switch angle are not: they are fixed for a run).
pub(crate) const TUNABLES: &[Tunable] = &[
    tunable!("pid.left", "kp", "V per m/s", |s| s.pid_left.kp),
    tunable!("pid.left", "ki", "V per m", |s| s.pid_left.ki),
    tunable!("pid.left", "kff", "V per m/s of reference", |s| s
        .pid_left
        .kff),
    tunable!("pid.left", "out_max_v", "V", |s| s.pid_left.out_max_v),
    tunable!("pid.right", "kp", "V per m/s", |s| s.pid_right.kp),
    tunable!("pid.right", "ki", "V per m", |s| s.pid_right.ki),
    tunable!("pid.right", "kff", "V per m/s of reference", |s| s
        .pid_right
        .kff),
    tunable!("pid.right", "out_max_v", "V", |s| s.pid_right.out_max_v),
    tunable!("pid.steer", "kp", "V per rad", |s| s.pid_steer.kp),
    tunable!("pid.steer", "kd", "V per rad/s", |s| s.pid_steer.kd),
    tunable!("pid.steer", "d_filter_s", "s", |s| s.pid_steer.d_filter_s),
    tunable!("pid.steer", "out_max_v", "V", |s| s.pid_steer.out_max_v),
    tunable!("steer", "speed_mps", "autonomous speed, m/s", |s| s
        .steer
        .speed_mps),
    tunable!("steer", "lookahead_m", "m", |s| s.steer.lookahead_m),
    tunable!("steer", "ki_per_m2", "1/m^2", |s| s.steer.ki_per_m2),
    tunable!("steer", "integral_max_deg", "deg", |s| s
        .steer
        .integral_max_deg),
    tunable!("steer", "curvature_filter_m", "m", |s| s
        .steer
        .curvature_filter_m),
    tunable!("steer", "latency_s", "camera latency, s", |s| s
        .steer
        .latency_s),
];

/// A value as robot.ini gets it: the shortest text that reads back the same number.
pub(crate) fn value_text(v: f64) -> String {
    format!("{v}")
}

pub struct Tuning {
    /// The panel's values, one per `TUNABLES` entry.
    pub values: Vec<f64>,
    /// Where "Save" writes; None when the program runs on its built-in settings.
    pub file: Option<PathBuf>,
    /// The settings file in use, as text: the panel's values are checked in it, with
    /// every cross-check against this robot's own settings (its amplifier ranges, ...).
    base_text: String,
}

impl Tuning {
    pub fn new(settings: &Settings, file: Option<PathBuf>) -> Tuning {
        let base_text = file
            .as_ref()
            .and_then(|path| std::fs::read_to_string(path).ok())
            .unwrap_or_else(|| DEFAULT_INI.to_string());
        Tuning {
            values: TUNABLES.iter().map(|t| (t.get)(settings)).collect(),
            file,
            base_text,
        }
    }

    /// Set one value by section and key (for tests and scripts); false if unknown.
    pub fn set(&mut self, section: &str, key: &str, value: f64) -> bool {
        match TUNABLES
            .iter()
            .position(|t| t.section == section && t.key == key)
        {
            Some(i) => {
                self.values[i] = value;
                true
            }
            None => false,
        }
    }

    fn overrides(&self) -> Vec<String> {
        TUNABLES
            .iter()
            .zip(&self.values)
            .map(|(t, v)| format!("{}.{}={}", t.section, t.key, value_text(*v)))
            .collect()
    }

    /// The panel's values as settings, checked as robot.ini is checked.
    pub fn checked(&self) -> Result<Settings, String> {
        Settings::parse("the tuning panel", &self.base_text, &self.overrides()).map_err(|errors| {
            errors
                .iter()
                .map(|e| e.what.clone())
                .collect::<Vec<_>>()
                .join("; ")
        })
    }

    /// Send the gains and the steering-law parameters to the supervisor (Halt only).
    pub fn apply(&self, requests: &mut Requests, now_s: f64) {
        let s = match self.checked() {
            Ok(s) => s,
            Err(why) => {
                requests.say(format!("not applied: {why}"), true, now_s);
                return;
            }
        };
        // One request: the supervisor takes both or neither.
        requests.ask(
            Request::Tuning(Gains::from_settings(&s), s.steer),
            "gains and steering law applied",
        );
    }

    /// Rewrite only the values that differ from the file's, atomically.
    pub fn save(&self) -> Result<String, String> {
        let path = self
            .file
            .as_ref()
            .ok_or("the program runs on its built-in settings: there is no robot.ini to save to")?;
        self.checked()?;
        let shown = path.display();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {shown}: {e}; your values are still here"))?;
        let in_file = Settings::parse(&shown.to_string(), &text, &[])
            .map_err(|errors| format!("{shown} has errors, fix them first: {}", errors[0]))?;
        let changed: Vec<NewValue> = TUNABLES
            .iter()
            .zip(&self.values)
            .filter(|(t, v)| (t.get)(&in_file) != **v)
            .map(|(t, v)| NewValue {
                section: t.section.to_string(),
                key: t.key.to_string(),
                value: value_text(*v),
            })
            .collect();
        if changed.is_empty() {
            return Ok(format!("{shown} already holds these values"));
        }
        let new_text = set_values(&text, &changed)?;
        Settings::parse(&shown.to_string(), &new_text, &[])
            .map_err(|errors| format!("not saved: {}", errors[0]))?;
        write_atomic(path, &new_text).map_err(|e| format!("{e}; your values are still here"))?;
        Ok(format!("saved {} value(s) to {shown}", changed.len()))
    }

    /// Read the values back from the file.
    pub(crate) fn revert(&mut self) -> Result<String, String> {
        let path = self
            .file
            .as_ref()
            .ok_or("there is no robot.ini to revert to")?;
        let s =
            Settings::load(path, &[]).map_err(|errors| format!("cannot revert: {}", errors[0]))?;
        self.values = TUNABLES.iter().map(|t| (t.get)(&s)).collect();
        if let Ok(text) = std::fs::read_to_string(path) {
            self.base_text = text;
        }
        Ok(format!("values read from {}", path.display()))
    }

    pub fn show(&mut self, ui: &mut egui::Ui, view: &View, requests: &mut Requests) {
        egui::Grid::new("tuning").striped(true).show(ui, |ui| {
            let mut section = "";
            for (t, v) in TUNABLES.iter().zip(self.values.iter_mut()) {
                let label = if t.section == section {
                    String::new()
                } else {
                    format!("[{}]", t.section)
                };
                section = t.section;
                ui.label(RichText::new(label).strong());
                ui.label(t.key);
                // Drag by about 1 % of the value per point.
                let speed = (v.abs() * 0.01).max(0.001);
                ui.add(egui::DragValue::new(v).speed(speed))
                    .on_hover_text(format!("{}.{}", t.section, t.key));
                ui.label(RichText::new(t.what).weak());
                ui.end_row();
            }
        });
        ui.add_space(6.0);
        let halted = view.status.mode == Mode::Halt;
        ui.horizontal(|ui| {
            let apply = ui.add_enabled(halted, egui::Button::new("Apply"));
            if apply.clicked() {
                self.apply(requests, view.now_s);
            }
            let mut say = |result: Result<String, String>| match result {
                Ok(text) => requests.say(text, false, view.now_s),
                Err(text) => requests.say(text, true, view.now_s),
            };
            if ui.button("Save to robot.ini").clicked() {
                say(self.save());
            }
            if ui.button("Revert").clicked() {
                say(self.revert());
            }
        });
        if !halted {
            ui.label(
                RichText::new(Refusal::OnlyInHalt.to_string())
                    .small()
                    .weak(),
            );
        }
        match &self.file {
            Some(path) => ui.label(format!("settings file: {}", path.display())),
            None => ui.label("built-in settings: no file to save to"),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_checked_against_the_robots_own_settings_file() {
        // This robot's left drive output is switched to +-5 V and its regulator limited
        // to match: 10 V passes against the shipped file, not against this one.
        let text = DEFAULT_INI
            .replacen(
                "dda06_ranges_v = +-10, +-10, +-10, +-5, +-5, +-5",
                "dda06_ranges_v = +-5, +-10, +-10, +-5, +-5, +-5",
                1,
            )
            // The first out_max_v is [pid.left]'s.
            .replacen("out_max_v = 10\n", "out_max_v = 5\n", 1);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("robot.ini");
        std::fs::write(&path, &text).unwrap();
        let settings = Settings::load(&path, &[]).expect("a valid file");
        let mut tuning = Tuning::new(&settings, Some(path));
        assert!(tuning.checked().is_ok());
        assert!(tuning.set("pid.left", "out_max_v", 10.0));
        let why = tuning.checked().unwrap_err();
        assert!(why.contains("dda06_ranges_v"), "{why}");
    }
}
