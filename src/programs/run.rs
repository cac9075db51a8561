//! `mechweed run` (and `mechweed` alone): the controller on real threads and real time,
//! with the operator GUI or on the console.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::ValueEnum;

use crate::bench::rows::row_name;
use crate::config::{Backend, Settings};
use crate::console::report::Report;
use crate::console::run as run_on_console;
use crate::gui::Tab;
use crate::programs::{load_settings, parse_metres, print_errors, settings_file};
use crate::run::RunOptions;
use crate::state::modes::Mode;

const RUN_ADVICE: &str = "run with --headless for the console, or start it in a desktop session";

#[derive(clap::Args, Default)]
pub struct RunArgs {
    /// Settings file [default: config/robot.ini, or the built-in copy if there is none]
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Run without the operator GUI: the console prints the status instead.
    #[arg(long)]
    pub headless: bool,
    /// The operator GUI's tab at start.
    #[arg(
        long,
        value_enum,
        default_value = "status",
        conflicts_with = "headless"
    )]
    pub tab: Tab,
    /// Mode to bring the robot into at start (powering up first).
    #[arg(long, value_enum, default_value = "halt")]
    pub mode: StartMode,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Seed of the simulation (overrides [sim] seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override one setting, e.g. --set steer.speed_mps=0.3 (repeatable).
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// Write the run report as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Tool cross-track figures from this distance on, m [default: 5, while the robot
    /// settles onto the row; 0 for short runs]
    #[arg(long, value_name = "METRES", value_parser = parse_metres)]
    pub from_m: Option<f64>,
    /// List every scripted event of [sim] events, with its argument and an example.
    #[arg(long)]
    pub list_events: bool,
}

#[derive(Clone, Copy, ValueEnum, Default)]
pub enum StartMode {
    #[default]
    Halt,
    Joystick,
    Autonomous,
}

pub fn run(args: RunArgs) -> ExitCode {
    if args.list_events {
        print!("{}", crate::state::operator::events_help());
        return ExitCode::SUCCESS;
    }
    let Some(settings) = settings_for_the_run(&args) else {
        return ExitCode::FAILURE;
    };
    // Set by Ctrl-C or SIGTERM, told apart from the end of --duration, so that the run
    // says who ended it.
    let stop = crate::console::ctrl_c();
    let start_mode = start_mode(&args, &settings);
    let options = RunOptions {
        settings,
        start_mode,
        duration_s: args.duration,
        status_every_s: 5.0,
        inject: None,
    };
    let outcome = if args.headless {
        run_on_console(&options, stop).map_err(|e| e.to_string())
    } else {
        let settings_file = settings_file(args.config.as_deref());
        crate::gui::run_gui(&options, settings_file, args.tab, stop, RUN_ADVICE, None)
            .map(|(outcome, _frames)| outcome)
    };
    let outcome = match outcome {
        Ok(outcome) => outcome,
        Err(why) => {
            eprintln!("cannot start: {why}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(who) = crate::console::stop_request() {
        // The threads have ended: the supervisor wrote the safe outputs as it stopped.
        crate::say!(
            "run stopped by {who}; the outputs are safe: amplifiers 0 V, motor power off, brakes on, tool off"
        );
    }
    report(&Report::from_run(&outcome), args.report)
}

/// The run's settings, with the command line's; None (said why) if they are wrong, or
/// if the run could not end as asked (a report it cannot write, a GUI with no display).
fn settings_for_the_run(args: &RunArgs) -> Option<Settings> {
    let mut overrides = args.set.clone();
    if let Some(seed) = args.seed {
        overrides.push(format!("sim.seed={seed}"));
    }
    let mut settings = load_settings(args.config.as_deref(), &overrides)
        .map_err(|errors| {
            print_errors(&errors);
            crate::programs::safe::after_refusal(args.config.as_deref(), true);
        })
        .ok()?;
    if let Some(from_m) = args.from_m {
        settings.sim.cross_track_from_m = from_m;
    }
    // Found out now, not after a run whose figures would then be lost.
    if let Some(path) = &args.report
        && let Err(e) = check_writable(path)
    {
        eprintln!(
            "cannot write the report to {}: {e} (nothing started)",
            path.display()
        );
        return None;
    }
    if !args.headless
        && let Some(why) = crate::gui::display_missing()
    {
        eprintln!("{why}: {RUN_ADVICE} (nothing started)");
        return None;
    }
    Some(settings)
}

/// The mode the run starts in, said with what it runs on. Nothing powers the real robot
/// up without a person: the console asks here, the GUI in a window of its own.
fn start_mode(args: &RunArgs, settings: &Settings) -> Mode {
    let start_mode = match args.mode {
        StartMode::Halt => Mode::Halt,
        StartMode::Joystick => Mode::Joystick,
        StartMode::Autonomous => Mode::Autonomous,
    };
    match settings.backend {
        Backend::Sim => crate::say!(
            "mechweed on the simulated robot: {} row, {} m/s, seed {}; start mode {start_mode}",
            row_name(settings.sim.row),
            settings.steer.speed_mps,
            settings.sim.seed
        ),
        Backend::Cards => crate::say!("mechweed on the I/O cards; start mode {start_mode}"),
    }
    if settings.backend == Backend::Cards
        && settings.watchdog_relay == crate::config::WatchdogRelay::NoneAccepted
    {
        crate::say!("{}", crate::config::NO_RELAY);
    }
    if !crate::state::cross_track::CrossTrackMeaning::of(settings).meaningful() {
        crate::say!(
            "camera: {}; {}",
            settings.camera_port.describe(),
            crate::console::report::OUTSIDE_CAMERA
        );
    }
    let operator = crate::state::operator::needs_confirmation(settings.backend, start_mode);
    if args.headless
        && operator
        && !crate::state::operator::confirm_on_console(
            start_mode,
            &mut std::io::stdin().lock(),
            &mut std::io::stdout(),
        )
    {
        return Mode::Halt;
    }
    start_mode
}

/// The run's report on the console, and as JSON where --report says.
fn report(report: &Report, path: Option<PathBuf>) -> ExitCode {
    crate::say!("{}", report.human().trim_end());
    if let Some(path) = path {
        let json = serde_json::to_string_pretty(report).expect("the report is plain data");
        if let Err(e) = std::fs::write(&path, json) {
            eprintln!("cannot write the report to {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    // A run that ended in Fault is not a success, whoever stopped it after.
    ExitCode::from(report.exit_code)
}

/// Can `path` be written? Opens it as the report will be written, without changing an
/// existing file and without leaving a new one behind.
fn check_writable(path: &Path) -> std::io::Result<()> {
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)?;
    if !existed {
        std::fs::remove_file(path)?;
    }
    Ok(())
}
