//! The eframe App: one snapshot of every protected object per pass, then the layout.
//! Header on top (mode, HALT, fault), modes on the left, the simulated robot on the
//! right, and the tabs Status, Plots, Tuning, Test panel in the middle.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use eframe::egui;
use mechweed_hw::sim::Truth;

use super::Controller;
use super::plots::Plots;
use super::sim_panel::SimPanel;
use super::test_panel::TestPanel;
use super::tuning::Tuning;
use super::{header, modes, status};
use crate::camlink::LinkStatus;
use crate::config::Settings;
use crate::modes::{Mode, Request};
use crate::operator::{OperatorScript, needs_confirmation};
use crate::rt::LoopSummary;
use crate::run::{Handles, RunOptions, start};
use crate::state::Reader;
use crate::status::Status;
use crate::steer::SteerCommand;

/// Repaint period while the robot may move (about 30 Hz) and while it stands, s.
const FRAME_MOVING: Duration = Duration::from_millis(33);
const FRAME_STANDING: Duration = Duration::from_millis(100);

/// Copies of the protected objects, taken once per pass: every panel draws the same
/// instant, and no lock is held while drawing.
#[derive(Debug, Clone, Copy, Default)]
pub struct View {
    /// Seconds since the controller started.
    pub now_s: f64,
    pub status: Status,
    pub link: LinkStatus,
    pub steer: SteerCommand,
    /// Supervisor and steer loop figures.
    pub loops: [LoopSummary; 2],
    /// The simulated robot's true state.
    pub truth: Truth,
}

/// The supervisor's last answer to something the operator did, shown in the header.
#[derive(Debug, Clone, PartialEq)]
pub struct Feedback {
    pub text: String,
    pub refused: bool,
    pub at_s: f64,
}

/// Send `request` and say what came of it (a refusal in the supervisor's own words).
pub fn ask(handles: &Handles, request: Request, done: &str, feedback: &mut Option<Feedback>) {
    let at_s = handles.clock.elapsed().as_secs_f64();
    *feedback = Some(match handles.supervisor.request(request) {
        Ok(()) => Feedback {
            text: done.to_string(),
            refused: false,
            at_s,
        },
        Err(why) => Feedback {
            text: format!("refused: {why}"),
            refused: true,
            at_s,
        },
    });
}

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
    pub handles: Handles,
    pub view: View,
    pub tab: Tab,
    pub feedback: Option<Feedback>,
    pub tuning: Tuning,
    pub plots: Plots,
    pub test: TestPanel,
    pub sim: SimPanel,
    duration_s: Option<f64>,
    /// `--mode` and the operator actions of [sim] events, as the console follows them.
    script: OperatorScript,
    /// `--mode` on the real robot, waiting for the operator's confirmation.
    pub confirm_start: Option<Mode>,
    stop: Arc<AtomicBool>,
    controller: Controller,
}

impl GuiApp {
    pub fn new(
        handles: Handles,
        opts: &RunOptions,
        settings_file: Option<PathBuf>,
        stop: Arc<AtomicBool>,
        controller: Controller,
    ) -> GuiApp {
        let settings = &opts.settings;
        let mut app = GuiApp {
            handles,
            view: View::default(),
            tab: Tab::default(),
            feedback: None,
            tuning: Tuning::new(settings, settings_file),
            plots: Plots::default(),
            test: TestPanel::default(),
            sim: SimPanel::new(settings),
            duration_s: opts.duration_s,
            script: OperatorScript::new(&settings.sim.events, opts.start_mode),
            confirm_start: None,
            stop,
            controller,
        };
        if needs_confirmation(settings.backend, opts.start_mode) {
            app.ask_to_start(opts.start_mode);
        }
        app
    }

    /// Stand in Halt until the operator confirms that `mode` may power the robot up
    /// (`--mode` on the real robot).
    pub fn ask_to_start(&mut self, mode: Mode) {
        self.script = OperatorScript::new(&[], Mode::Halt);
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
                        self.script = OperatorScript::new(&[], mode);
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
        let opts = RunOptions {
            settings,
            start_mode: Mode::Halt,
            duration_s: None,
            status_every_s: 0.0,
            inject: None,
        };
        let at_s = self.view.now_s;
        self.feedback = Some(match start(&opts, Arc::new(AtomicBool::new(false))) {
            Ok((handles, running)) => {
                running.watch_this_thread_as(crate::health::ThreadName::Gui);
                *slot = Some(running);
                self.handles = handles;
                self.script = OperatorScript::new(&[], Mode::Halt);
                self.plots = Plots::default();
                self.test = TestPanel::default();
                self.duration_s = None;
                Feedback {
                    text: "simulated robot reset to the row start (controller restarted, halt)"
                        .to_string(),
                    refused: false,
                    at_s,
                }
            }
            Err(why) => Feedback {
                text: format!("cannot restart the controller: {why}; close the window"),
                refused: true,
                at_s,
            },
        });
    }

    /// Once per pass, also while the window is minimised: beat, take the snapshots,
    /// record a plot sample, keep the test outputs flowing, and ask for the next pass.
    pub fn pass(&mut self, ctx: &egui::Context) {
        let h = &self.handles;
        let now_s = h.clock.elapsed().as_secs_f64();
        h.gui_beat.publish(&now_s);
        let [sup, steer] = [&h.loops[0], &h.loops[1]].map(Reader::snapshot);
        self.view = View {
            now_s,
            status: h.supervisor.status.snapshot(),
            link: h.link.snapshot(),
            steer: h.steer.snapshot(),
            loops: [sup, steer],
            truth: h.truth.truth(),
        };
        if let Some(request) = self.script.due(now_s, &self.view.status) {
            let what = match request {
                Request::Mode(m) => format!("operator script: mode {m}"),
                Request::PowerUp => "operator script: power up".to_string(),
                other => format!("operator script: {other:?}"),
            };
            ask(h, request, &what, &mut self.feedback);
        }
        self.plots.record(&self.view);
        self.test.keep_sending(&self.view, h, &mut self.feedback);
        self.sim.keep_joystick(h);
        if let Some(settings) = self.sim.restart.take() {
            self.restart(settings);
        }
        let ending =
            self.stop.load(Ordering::Relaxed) || self.duration_s.is_some_and(|d| now_s >= d);
        if ending {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        let moving = self.view.status.mode.drives()
            || self.view.status.measured.speed_mps.abs() > 0.01
            || self.view.status.mode == Mode::Test;
        ctx.request_repaint_after(if moving { FRAME_MOVING } else { FRAME_STANDING });
    }

    /// The whole window's contents.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        if ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Space)) {
            header::halt(&self.handles, &self.view, &mut self.feedback);
        }
        self.show_confirmation(&ui.ctx().clone());
        egui::Panel::top("header").show(ui, |ui| {
            header::show(ui, &self.view, &self.handles, &mut self.feedback);
        });
        egui::Panel::left("modes")
            .resizable(false)
            .exact_size(250.0)
            .show(ui, |ui| {
                modes::show(ui, &self.view, &self.handles, &mut self.feedback);
            });
        if self.handles.sim.is_some() {
            egui::Panel::right("sim")
                .resizable(false)
                .exact_size(270.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        self.sim
                            .show(ui, &self.view, &self.handles, &mut self.feedback);
                    });
                });
        }
        egui::CentralPanel::default().show(ui, |ui| {
            ui.horizontal(|ui| {
                for (tab, name) in [
                    (Tab::Status, "Status"),
                    (Tab::Plots, "Plots"),
                    (Tab::Tuning, "Tuning"),
                    (Tab::Test, "Test panel"),
                ] {
                    ui.selectable_value(&mut self.tab, tab, egui::RichText::new(name).heading());
                }
            });
            ui.separator();
            egui::ScrollArea::vertical().show(ui, |ui| match self.tab {
                Tab::Status => status::show(ui, &self.view, &self.handles),
                Tab::Plots => self.plots.show(ui, self.handles.sim.is_some()),
                Tab::Tuning => self
                    .tuning
                    .show(ui, &self.view, &self.handles, &mut self.feedback),
                Tab::Test => self
                    .test
                    .show(ui, &self.view, &self.handles, &mut self.feedback),
            });
        });
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
