//! The operator GUI (egui/eframe): how every user meets mechweed.
//!
//! The GUI thread is a reader of the protected objects and a sender of requests: it
//! copies one `View` out per pass (never holding a lock across a frame) and asks the
//! supervisor for everything (modes, power-up, gains, test outputs) without waiting for
//! the answer, which the next pass shows. It never writes an output. It beats once per
//! pass (`App::logic`, which eframe also runs while the window is minimised), and the
//! supervisor faults if it stops for `[rt] gui_heartbeat_timeout_s`.
//!
//! One file per idea: `app` (the eframe App and its layout), `view` (the snapshot the
//! panels draw and the source that fills it), `requests` (requests out, answers back,
//! the feedback line), `script` (`--mode` in the GUI), `header` (mode, HALT, fault),
//! `modes` (mode buttons and why one is disabled), `status` (every input, output, the
//! camera link and loop figures), `plots` (the last 60 s), `tuning` (gains and the
//! steering law, saved to robot.ini by `ini_edit`), `test_panel` (mode Test),
//! `sim_panel` (the simulated robot's e-stops, joystick and faults). Every panel draws
//! from a `View` and asks through `Requests` only, so it can be tested from a `View`
//! made by hand (tests/gui_panels.rs).

pub mod app;
mod display;
pub mod header;
pub mod ini_edit;
pub mod modes;
pub mod plots;
pub mod requests;
pub mod script;
mod sim_panel;
pub mod status;
pub mod test_panel;
pub mod tuning;
pub mod view;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use crate::health::ThreadName;
use crate::run::{RunOptions, RunOutcome, Running, start};

/// The controller's threads now running: the GUI replaces them when the operator resets
/// the simulated robot, and `run_gui` stops the last ones when the window closes.
pub type Controller = Arc<Mutex<Option<Running>>>;

pub use app::{GuiApp, Tab};
pub use display::{display_missing, window_failed};

/// Run the controller with the GUI on this (the main) thread until the window closes,
/// `duration_s` passes, or `stop` is set; then stop the threads (safe outputs).
/// `settings_file` is where "Save to robot.ini" writes (None: built-in settings);
/// `first_tab` is the tab shown at start; `advice` ends a message that there is no
/// window (what to type instead).
pub fn run_gui(
    opts: &RunOptions,
    settings_file: Option<PathBuf>,
    first_tab: Tab,
    stop: Arc<AtomicBool>,
    advice: &str,
) -> Result<RunOutcome, String> {
    if let Some(why) = display_missing() {
        return Err(format!("{why}: {advice}"));
    }
    // The controller's own stop flag: a reset stops one controller and starts another,
    // while `stop` (Ctrl-C) closes the window.
    let (handles, running) =
        start(opts, Arc::new(AtomicBool::new(false))).map_err(|e| e.to_string())?;
    running.watch_this_thread_as(ThreadName::Gui);
    let controller: Controller = Arc::new(Mutex::new(Some(running)));
    let mut app = GuiApp::new(handles, opts, settings_file, stop, controller.clone());
    app.tab = first_tab;
    let native = eframe::NativeOptions {
        viewport: eframe::egui::ViewportBuilder::default()
            .with_title("mechweed")
            .with_inner_size([1280.0, 860.0]),
        ..Default::default()
    };
    let shown = eframe::run_native("mechweed", native, Box::new(|_cc| Ok(Box::new(app))));
    // Whatever happened to the window, stop the controller: the supervisor writes the
    // safe outputs as it ends.
    let running = controller
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .take();
    let outcome = running
        .ok_or("the controller could not be restarted after a reset: see the messages above")?
        .finish();
    match shown {
        Ok(()) => Ok(outcome),
        // The window library's own message quotes its source files: said in our words.
        Err(_) => Err(format!(
            "{}; the controller was stopped with safe outputs: {advice}",
            window_failed()
        )),
    }
}
