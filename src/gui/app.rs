//! The eframe App: per pass, the supervisor's answers, one `View` of the controller,
//! then the layout; what the panels asked for is sent at the end without waiting.
//! Header on top (mode, HALT, fault), modes on the left, the simulated robot on the
//! right, and the tabs Status, Plots, Tuning, Test panel in the middle.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use eframe::egui;

use super::Controller;
use super::pacer::{SharedGui, Source, shared};
use super::plot_data::PlotSamples;
use super::plots::Plots;
use super::requests::{Feedback, Requests};
use super::script::GuiScript;
use super::sim_panel::SimPanel;
use super::test_panel::TestPanel;
use super::tuning::Tuning;
use super::view::{View, ViewSource};
use super::{header, modes, status, theme};
use crate::config::{Settings, Theme};
use crate::run::{RunOptions, start};
use crate::state::modes::Mode;
use crate::state::operator::needs_confirmation;

/// While an answer of the supervisor is awaited, and while a test ramp or step is under
/// way (it is sent from the pass), the GUI thread passes this often of its own accord,
/// s; the operator script says when it needs a pass.
const ANSWER_LOOK_S: f64 = 0.05;
const TEST_WAVE_S: f64 = 1.0 / 30.0;

/// The tab in the middle (`mechweed run --tab` chooses the first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Tab {
    #[default]
    Status,
    Plots,
    Tuning,
    Test,
}

pub struct GuiApp {
    /// The controller's objects and the plots' samples, shared with the pacer thread
    /// (pacer.rs), which decides when to draw.
    pub shared: SharedGui,
    pub view: View,
    pub tab: Tab,
    /// What the panels asked of the supervisor, its answers, and the feedback line.
    pub requests: Requests,
    pub tuning: Tuning,
    pub plots: Plots,
    pub test: TestPanel,
    pub sim: SimPanel,
    duration_s: Option<f64>,
    /// `--mode` and the operator actions of [sim] events, as the console follows them.
    script: GuiScript,
    /// `--mode` on the real robot, waiting for the operator's confirmation.
    pub confirm_start: Option<Mode>,
    stop: Arc<AtomicBool>,
    controller: Controller,
    /// The window's colours ([gui] theme; F2 switches), and those last set on egui.
    pub theme: Theme,
    theme_set: Option<Theme>,
    /// The window has asked the system for the keyboard (Space = HALT from the start).
    focus_asked: bool,
    /// A window on a screen (not a test's): it takes the keyboard from the X server
    /// itself while it has none, a few times, a second apart.
    pub take_keyboard: bool,
    keyboard_tries: u8,
    keyboard_tried_s: f64,
}

/// How many times, a second apart, a window without the keyboard takes it, and only
/// this long after it opened, s: later a person chose another window, and keeps it.
const KEYBOARD_TRIES: u8 = 3;
const KEYBOARD_AT_START_S: f64 = 6.0;

impl GuiApp {
    pub fn new(
        source: Source,
        opts: &RunOptions,
        settings_file: Option<PathBuf>,
        stop: Arc<AtomicBool>,
        controller: Controller,
    ) -> GuiApp {
        let settings = &opts.settings;
        let mut app = GuiApp {
            shared: shared(source, Tab::default()),
            view: View::default(),
            tab: Tab::default(),
            requests: Requests::default(),
            tuning: Tuning::new(settings, settings_file),
            plots: Plots::default(),
            test: TestPanel::default(),
            sim: SimPanel::new(settings),
            duration_s: opts.duration_s,
            script: GuiScript::new(&settings.sim.events, opts.start_mode),
            confirm_start: None,
            stop,
            controller,
            theme: settings.gui.theme,
            theme_set: None,
            focus_asked: false,
            take_keyboard: false,
            keyboard_tries: 0,
            keyboard_tried_s: f64::NEG_INFINITY,
        };
        if needs_confirmation(settings.backend, opts.start_mode) {
            app.ask_to_start(opts.start_mode);
        }
        app
    }

    /// Stand in Halt until the operator confirms that `mode` may power the robot up
    /// (`--mode` on the real robot).
    pub fn ask_to_start(&mut self, mode: Mode) {
        self.script = GuiScript::new(&[], Mode::Halt);
        self.confirm_start = Some(mode);
    }

    /// The confirmation window of `--mode` on the real robot.
    fn show_confirmation(&mut self, ctx: &egui::Context) {
        let Some(mode) = self.confirm_start else {
            return;
        };
        egui::Window::new("Confirm the start")
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .show(ctx, |ui| {
                ui.label(format!(
                    "The program was started with --mode {mode}: it will power up the real robot{}.",
                    if mode.drives() { " and drive it" } else { "" }
                ));
                ui.label("Is the area clear and a person at an emergency stop?");
                ui.horizontal(|ui| {
                    if ui.button(format!("Power up and start {mode}")).clicked() {
                        self.script = GuiScript::new(&[], mode);
                        self.confirm_start = None;
                    }
                    if ui.button("Stay in halt").clicked() {
                        self.confirm_start = None;
                    }
                });
            });
    }

    /// Reset the simulated robot to the row start with `settings`: stop the controller
    /// (its supervisor writes the safe outputs as it ends) and start a new one in Halt.
    /// The plots start afresh; the tuning panel keeps its values.
    pub fn restart(&mut self, settings: Settings) {
        let mut slot = self
            .controller
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(running) = slot.take() {
            running.finish();
        }
        let opts = RunOptions::in_halt(settings);
        let at_s = self.view.now_s;
        // What the old controller was asked will not be answered.
        self.requests.forget_open();
        // Started from this (maybe pinned) thread: the real-time threads leave its CPU
        // themselves (`rt::set_this_thread`).
        match start(&opts, Arc::new(AtomicBool::new(false))) {
            Ok((handles, running)) => {
                running.watch_this_thread_as(crate::rt::health::ThreadName::Gui);
                *slot = Some(running);
                {
                    let mut shared = self.shared.lock();
                    shared.source = Source::Local(handles);
                    shared.samples = PlotSamples::default();
                }
                self.script = GuiScript::new(&[], Mode::Halt);
                self.test = TestPanel::default();
                self.duration_s = None;
                self.requests.say(
                    "simulated robot reset to the row start (controller restarted, halt)",
                    false,
                    at_s,
                );
            }
            Err(why) => self.requests.say(
                format!("cannot restart the controller: {why}; close the window"),
                true,
                at_s,
            ),
        }
    }

    /// The feedback line: the supervisor's last answer, or the GUI's last message.
    pub fn feedback(&self) -> Option<&Feedback> {
        self.requests.feedback()
    }

    /// Once per pass, also while the window is minimised: take the answers, then the
    /// view, keep the script and the test outputs going, send what they asked for, and
    /// ask for a pass of its own when one is due (the pacer asks for the rest).
    pub fn pass(&mut self, ctx: &egui::Context) {
        // Answers before the view: a status read after an answer is from the tick that
        // answered or a later one (the script relies on it).
        self.requests.take_answers();
        let sim = {
            let mut shared = self.shared.lock();
            shared.passes += 1;
            let in_words = shared.source.answers_in_words();
            self.requests.take_answers_in_words(in_words);
            self.view = shared.source.view();
            shared.source.sim()
        };
        let now_s = self.view.now_s;
        self.script.pass(&self.view, &mut self.requests);
        self.test.keep_sending(&self.view, &mut self.requests);
        if let Some(sim) = &sim {
            self.sim.keep_joystick(sim);
        }
        self.requests.post(&self.shared.lock().source, now_s);
        if let Some(settings) = self.sim.restart.take() {
            self.restart(settings);
        }
        let ending =
            self.stop.load(Ordering::Relaxed) || self.duration_s.is_some_and(|d| now_s >= d);
        if ending {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        let own_s = [
            self.requests.awaiting().then_some(ANSWER_LOOK_S),
            self.script.next_pass_in_s(now_s),
            self.test.changing(now_s).then_some(TEST_WAVE_S),
            self.duration_s.map(|d| d - now_s),
        ];
        if let Some(after_s) = own_s.into_iter().flatten().reduce(f64::min) {
            ctx.request_repaint_after(Duration::from_secs_f64(after_s.max(0.0)));
        }
    }

    /// Space = HALT from the first frame: ask for the keyboard at start (a window
    /// manager gives it), and on a bare X server with none, where nobody clicks the new
    /// window on a robot computer, take it from the X server, once the window runs (so
    /// that it hears it came) and again a second later while it still has none.
    fn keep_the_keyboard(&mut self, ui: &egui::Ui) {
        if !self.focus_asked {
            self.focus_asked = true;
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Focus);
        }
        let now_s = ui.input(|i| i.time);
        let without = !ui.input(|i| i.focused);
        if self.take_keyboard
            && without
            && now_s < KEYBOARD_AT_START_S
            && self.keyboard_tries < KEYBOARD_TRIES
            && now_s - self.keyboard_tried_s >= 1.0
        {
            self.keyboard_tries += 1;
            self.keyboard_tried_s = now_s;
            let last = self.keyboard_tries == KEYBOARD_TRIES;
            let _ = std::thread::Builder::new()
                .name("gui-keyboard".into())
                .spawn(move || {
                    if let Err(why) = super::x11_focus::take_keyboard()
                        && last
                    {
                        crate::say!(
                            "operator GUI: cannot take the keyboard ({why}): click the window before Space = HALT works"
                        );
                    }
                });
            // The next look comes in a second even if nothing else changes.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_secs(1));
        }
    }

    /// The whole window's contents. What the panels asked for leaves at the end of the
    /// frame, without waiting; the answers show from the next pass on.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        self.follow_keys_and_theme(ui);
        self.show_confirmation(&ui.ctx().clone());
        let sim = self.shared.lock().source.sim();
        let (view, requests) = (&self.view, &mut self.requests);
        egui::Panel::top("header").show(ui, |ui| header::show(ui, view, requests));
        egui::Panel::left("modes")
            .resizable(false)
            .exact_size(250.0)
            .show(ui, |ui| {
                // A 720-line screen does not hold every reason under every button.
                egui::ScrollArea::vertical()
                    .id_salt("modes-scroll")
                    .show(ui, |ui| modes::show(ui, view, requests));
            });
        if let Some(sim) = &sim {
            egui::Panel::right("sim")
                .resizable(false)
                .exact_size(270.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical()
                        .show(ui, |ui| self.sim.show(ui, view, sim, requests));
                });
        }
        egui::CentralPanel::default().show(ui, |ui| self.show_central(ui));
        let mut shared = self.shared.lock();
        shared.frames += 1;
        shared.tab = self.tab;
        self.requests.post(&shared.source, self.view.now_s);
    }

    /// Space is HALT, F2 the other theme; the keyboard kept for this window at start.
    fn follow_keys_and_theme(&mut self, ui: &mut egui::Ui) {
        if ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Space)) {
            header::halt(&self.view, &mut self.requests);
        }
        self.keep_the_keyboard(ui);
        if ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::F2)) {
            self.theme = self.theme.other();
        }
        if self.theme_set != Some(self.theme) {
            theme::apply(ui.ctx(), self.theme);
            self.theme_set = Some(self.theme);
            // This frame was laid out in the old looks: the next, in the new, at once.
            // (Applied from eframe's creator instead, before the first frame, Space did
            // nothing on a bare X server in tests/gui/gui_field.rs; why is not known.)
            ui.ctx().request_repaint();
        }
    }

    /// The tabs, and the tab shown (or, watching a robot that has sent nothing yet,
    /// only that line).
    fn show_central(&mut self, ui: &mut egui::Ui) {
        let (view, requests) = (&self.view, &mut self.requests);
        ui.horizontal(|ui| {
            for (tab, name) in [
                (Tab::Status, "Status"),
                (Tab::Plots, "Plots"),
                (Tab::Tuning, "Tuning"),
                (Tab::Test, "Test panel"),
            ] {
                ui.selectable_value(&mut self.tab, tab, egui::RichText::new(name).heading());
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                let other = self.theme.other().name();
                if ui.button(format!("{other} theme (F2)")).clicked() {
                    self.theme = self.theme.other();
                }
            });
        });
        ui.separator();
        if view.remote.is_some() && matches!(self.tab, Tab::Tuning | Tab::Test) {
            ui.label(
                "Watching over the bus: this tab shows this computer's robot.ini, and what it \
                 sends is refused here. Gains: `mechweed bus get|set`; the test panel: on the \
                 robot's own window.",
            );
        }
        if let Some(link) = view.remote.as_ref().filter(|link| link.no_data()) {
            // Nothing received: no value to show, not even a default one.
            ui.add_space(20.0);
            ui.label(
                egui::RichText::new(header::remote_line(link))
                    .size(18.0)
                    .strong(),
            );
            ui.label(
                "Every value shows when the robot's first status arrives. Is the robot \
                 program running there, with [bus] enabled = yes?",
            );
        } else {
            egui::ScrollArea::vertical().show(ui, |ui| {
                // The robot fell silent: its values are old, and greyed to say so.
                if view.remote.as_ref().is_some_and(|link| link.stale()) {
                    ui.disable();
                }
                match self.tab {
                    Tab::Status => status::show(ui, view, requests),
                    Tab::Plots => self.plots.show(ui, view, &self.shared),
                    Tab::Tuning => self.tuning.show(ui, view, requests),
                    Tab::Test => self.test.show(ui, view, requests),
                }
            });
        }
    }
}

impl eframe::App for GuiApp {
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        self.pass(ctx);
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }
}
