//! The operator GUI (egui/eframe): how every user meets mechweed.
//!
//! The GUI thread is a reader of the protected objects and a sender of requests: it
//! copies one `View` out per pass (never holding a lock across a frame) and asks the
//! supervisor for everything (modes, power-up, gains, test outputs) without waiting for
//! the answer, which the next pass shows. It never writes an output.
//!
//! It draws only when something it shows has changed (`pace`): a pacer thread looks at
//! the controller 30 times a second, asks for a frame when one is due, and beats for
//! the GUI while every frame asked for has been drawn (`pacer`); the supervisor faults
//! if the beat stops for `[rt] gui_heartbeat_timeout_s`.
//!
//! One file per idea: `app` (the eframe App and its layout), `view` (the snapshot the
//! panels draw and the source that fills it), `pace` and `pacer` (when to draw),
//! `requests` (requests out, answers back, the feedback line), `script` (`--mode` in the
//! GUI), `header` (mode, HALT, fault), `modes` (mode buttons and why one is disabled),
//! `status` (every input, output, the camera link and loop figures), `plots` and
//! `plot_data` (the last 60 s), `tuning` (gains and the steering law, saved to
//! robot.ini by `ini_edit`), `test_panel` (mode Test, with `commissioning`'s steps), `sim_panel` (the simulated
//! robot's e-stops, joystick and faults). Every panel draws from a `View` and asks
//! through `Requests` only, so it can be tested from a `View`
//! made by hand (tests/gui/gui_panels.rs).

pub mod app;
mod commissioning;
mod display;
pub mod header;
pub mod ini_edit;
pub mod modes;
pub mod pace;
pub mod pacer;
pub mod plot_data;
pub mod plots;
pub mod remote;
mod remote_view;
pub mod requests;
pub mod script;
mod sim_panel;
pub mod status;
pub mod test_panel;
pub mod theme;
pub mod tuning;
pub mod view;
pub mod x11_focus;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use std::time::Instant;

use crate::rt::health::ThreadName;
use crate::run::{RunOptions, RunOutcome, Running, start};
use crate::state::request_channel::SupervisorHandle;

/// The controller's threads now running: the GUI replaces them when the operator resets
/// the simulated robot, and `run_gui` stops the last ones when the window closes.
pub type Controller = Arc<Mutex<Option<Running>>>;

/// Something run on a thread of its own beside the GUI, with the supervisor's handle
/// and the controller's clock (`bench loop --press-space` presses keys in the window).
pub(crate) type Beside = Box<dyn FnOnce(SupervisorHandle, Instant) + Send>;

pub use app::{GuiApp, Tab};
pub use display::{display_missing, window_failed};

/// Run the controller with the GUI on this (the main) thread until the window closes,
/// `duration_s` passes, or `stop` is set; then stop the threads (safe outputs). Gives
/// the run's outcome and the number of frames the window drew.
/// `settings_file` is where "Save to robot.ini" writes (None: built-in settings);
/// `first_tab` is the tab shown at start; `advice` ends a message that there is no
/// window (what to type instead).
pub fn run_gui(
    opts: &RunOptions,
    settings_file: Option<PathBuf>,
    first_tab: Tab,
    stop: Arc<AtomicBool>,
    advice: &str,
    beside: Option<Beside>,
) -> Result<(RunOutcome, u64), String> {
    if let Some(why) = display_missing() {
        return Err(format!("{why}: {advice}"));
    }
    // The controller's own stop flag: a reset stops one controller and starts another,
    // while `stop` (Ctrl-C) closes the window.
    let (handles, running) =
        start(opts, Arc::new(AtomicBool::new(false))).map_err(|e| e.to_string())?;
    running.watch_this_thread_as(ThreadName::Gui);
    if let Some(beside) = beside {
        let (supervisor, clock) = (handles.supervisor.clone(), handles.clock);
        std::thread::Builder::new()
            .name("beside-gui".into())
            .spawn(move || beside(supervisor, clock))
            .map_err(|e| format!("cannot start the thread beside the GUI: {e}"))?;
    }
    // Pinned after the controller's threads have started, before the window: the
    // software renderer's threads and the pacer are started from this thread and
    // inherit its CPU.
    if opts.settings.rt.gui_cpu >= 0
        && let Some(why) = crate::rt::set_this_thread(0, opts.settings.rt.gui_cpu)
    {
        crate::say!("operator GUI: {why} ([rt] gui_cpu); it runs on any CPU");
    }
    let controller: Controller = Arc::new(Mutex::new(Some(running)));
    let mut app = GuiApp::new(
        pacer::Source::Local(handles),
        opts,
        settings_file,
        stop.clone(),
        controller.clone(),
    );
    app.tab = first_tab;
    let (shown, frames) = show_window(app, stop);
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
        Ok(()) => Ok((outcome, frames)),
        // The window library's own message quotes its source files: said in our words.
        Err(_) => Err(format!(
            "{}; the controller was stopped with safe outputs: {advice}",
            window_failed()
        )),
    }
}

/// Open the window for `app` and run it until it closes; the pacer thread looks for it.
/// Gives how the window ended and the number of frames drawn.
fn show_window(app: GuiApp, stop: Arc<AtomicBool>) -> (Result<(), eframe::Error>, u64) {
    let native = eframe::NativeOptions {
        viewport: eframe::egui::ViewportBuilder::default()
            .with_title(x11_focus::TITLE)
            .with_inner_size([1280.0, 720.0]),
        // Dithering costs a software renderer a tenth of each frame, for gradients the
        // panels do not have.
        dithering: false,
        ..Default::default()
    };
    let mut app = app;
    // A real window: it takes the keyboard where nothing gives it one (app.rs).
    app.take_keyboard = true;
    let shared = app.shared.clone();
    let quit_pacer = Arc::new(AtomicBool::new(false));
    let mut pacer = None;
    let shown = eframe::run_native(
        "mechweed",
        native,
        Box::new(|cc| {
            let ctx = cc.egui_ctx.clone();
            let spawned = pacer::spawn(ctx, app.shared.clone(), stop, quit_pacer.clone());
            pacer = Some(spawned.map_err(|e| format!("cannot start the GUI's pacer thread: {e}"))?);
            Ok(Box::new(app))
        }),
    );
    quit_pacer.store(true, std::sync::atomic::Ordering::Relaxed);
    if let Some(pacer) = pacer {
        let _ = pacer.join();
    }
    let frames = shared.lock().frames;
    (shown, frames)
}

/// `mechweed watch`: the operator GUI on another computer, fed by `remote`, until the
/// window closes, `duration_s` passes or `stop` is set. Gives the frames drawn.
/// `settings` are this computer's (the Tuning tab's file); `advice` ends a message that
/// there is no window.
pub(crate) fn run_watch(
    remote: remote::RemoteView,
    settings: crate::config::Settings,
    duration_s: Option<f64>,
    first_tab: Tab,
    stop: Arc<AtomicBool>,
    advice: &str,
) -> Result<u64, String> {
    if let Some(why) = display_missing() {
        return Err(format!("{why}: {advice}"));
    }
    // The robot's clock is not this window's: the time limit is kept here.
    let opts = RunOptions::in_halt(settings);
    if let Some(seconds) = duration_s {
        let stop = stop.clone();
        std::thread::Builder::new()
            .name("watch-duration".into())
            .spawn(move || {
                std::thread::sleep(std::time::Duration::from_secs_f64(seconds));
                stop.store(true, std::sync::atomic::Ordering::Relaxed);
            })
            .map_err(|e| format!("cannot start a thread: {e}"))?;
    }
    let controller: Controller = Arc::new(Mutex::new(None));
    let mut app = GuiApp::new(
        pacer::Source::Remote(Box::new(remote)),
        &opts,
        None,
        stop.clone(),
        controller,
    );
    app.tab = first_tab;
    match show_window(app, stop) {
        (Ok(()), frames) => Ok(frames),
        (Err(_), _) => Err(format!("{}: {advice}", window_failed())),
    }
}
