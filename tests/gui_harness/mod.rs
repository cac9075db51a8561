//! The operator GUI in an egui_kittest harness over the real controller (the real
//! threads on the simulated robot, in this process), with helpers that click by label
//! and wait for conditions with a generous time-out.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use mechweed::config::Settings;
use mechweed::gui::pace::Pace;
use mechweed::gui::pacer::{Source, look_once};
use mechweed::gui::{Controller, GuiApp};
use mechweed::run::{Handles, RunOptions, RunOutcome, Running, start};
use mechweed::state::fault_cause::FaultCause;
use mechweed::state::status::PowerState;

pub struct Gui {
    pub harness: Harness<'static, GuiApp>,
    controller: Controller,
    /// The pacer's decision, looked at before each step as the pacer thread would: it
    /// beats for the GUI, so the supervisor watches the GUI's heartbeat in these tests.
    pub pace: Pace,
    clock: Instant,
}

pub fn gui_with(settings_file: Option<PathBuf>) -> Gui {
    gui_customised(settings_file, |_| {})
}

/// The GUI over a controller whose handles `adjust` may change first.
pub fn gui_customised(settings_file: Option<PathBuf>, adjust: impl FnOnce(&mut Handles)) -> Gui {
    gui_from(Settings::shipped(), settings_file, adjust)
}

/// The GUI over a controller with these settings (the bus off, late ticks tolerated).
pub fn gui_from(
    mut settings: Settings,
    settings_file: Option<PathBuf>,
    adjust: impl FnOnce(&mut Handles),
) -> Gui {
    // Tests run side by side; the bus has tests of its own, on ports of their own.
    settings.bus.enabled = false;
    // Software rendering is slow: a late tick now and then is not these tests' subject.
    settings.rt.max_late_periods = 100.0;
    // Two tests draw side by side with the processor, at normal priority: the steer and
    // camera-link threads may wait longer than the robot's 0.5 s for a turn (in one CI
    // run the steer thread's first beat came 0.58 s after the start). The longest time
    // a robot.ini may set; the GUI's own heartbeat, these tests' subject, is kept.
    settings.rt.heartbeat_timeout_s = 1.0;
    let opts = RunOptions::in_halt(settings);
    let stop = Arc::new(AtomicBool::new(false));
    let (mut handles, running) = start(&opts, stop.clone()).expect("the controller starts");
    adjust(&mut handles);
    let controller: Controller = Arc::new(Mutex::new(Some(running)));
    let app = GuiApp::new(
        Source::Local(handles),
        &opts,
        settings_file,
        stop,
        controller.clone(),
    );
    let harness = Harness::builder()
        .with_size(eframe::egui::vec2(1280.0, 1000.0))
        .build_ui_state(
            |ui, app: &mut GuiApp| {
                app.pass(ui.ctx());
                app.show(ui);
            },
            app,
        );
    Gui {
        harness,
        controller,
        pace: Pace::default(),
        clock: Instant::now(),
    }
}

impl Gui {
    /// One look of the pacer (it may ask for a frame, and beats if none is owed).
    pub fn look(&mut self) {
        let shared = self.harness.state().shared.clone();
        let t_s = self.clock.elapsed().as_secs_f64();
        look_once(&self.harness.ctx, &shared, &mut self.pace, t_s);
    }

    /// Run GUI passes until `condition` holds (panics after 30 s, naming `what`).
    pub fn wait_until(&mut self, what: &str, condition: impl Fn(&GuiApp) -> bool) {
        let end = Instant::now() + Duration::from_secs(30);
        loop {
            self.look();
            self.harness.step();
            if condition(self.harness.state()) {
                return;
            }
            let v = &self.harness.state().view;
            assert!(
                Instant::now() < end,
                "timed out waiting for {what}; mode {}, fault {:?}, feedback {:?}",
                v.status.mode,
                v.status.fault,
                self.harness.state().feedback()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    pub fn click(&mut self, label: &str) {
        self.harness.get_by_label(label).click();
        self.harness.step();
        self.look();
        self.harness.step();
    }

    pub fn enabled(&self, label: &str) -> bool {
        !self
            .harness
            .get_by_label(label)
            .accesskit_node()
            .is_disabled()
    }

    pub fn shows(&self, text: &str) -> bool {
        self.harness
            .query_all_by_label_contains(text)
            .next()
            .is_some()
    }

    pub fn power_up(&mut self) {
        self.wait_until("Power up enabled", |app| {
            app.view.status.measured.calibrated && app.view.status.tick > 0
        });
        self.click("Power up");
        self.wait_until("power on", |app| app.view.status.power == PowerState::On);
    }

    pub fn finish(mut self) -> RunOutcome {
        self.stop_controller()
    }

    /// Stop the controller's threads and collect the run's outcome, keeping the window:
    /// it goes on drawing what the stopped controller published last.
    pub fn stop_controller(&mut self) -> RunOutcome {
        let running: Running = self.controller.lock().unwrap().take().expect("running");
        let outcome = running.finish();
        for f in &outcome.faults {
            assert!(
                !matches!(f.cause, FaultCause::ThreadStopped { .. }),
                "a heartbeat fault: {}",
                f.cause
            );
        }
        outcome
    }
}
