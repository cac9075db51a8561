//! The mechweed command line.

mod bus_command;
mod cli;
mod cluster_command;
mod log_style;
mod record_command;
mod replay_command;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;

use mechweed::bench_rows;
use mechweed::config::{Backend, ConfigError, DEFAULT_INI, Settings, SteerSource};
use mechweed::console::run;
use mechweed::modes::Mode;
use mechweed::report::Report;
use mechweed::run::RunOptions;
use mechweed_hw::sim::FieldKind;

use cli::{BenchCommand, Cli, Command, RunArgs, StartMode};

pub(crate) fn print_errors(errors: &[ConfigError]) {
    errors.iter().for_each(|e| eprintln!("{e}"));
}

/// The settings file: the one named, else config/robot.ini here, else the built-in copy.
pub(crate) fn load_settings(
    file: Option<&Path>,
    overrides: &[String],
) -> Result<Settings, Vec<ConfigError>> {
    match settings_file(file) {
        Some(path) => Settings::load(&path, overrides),
        None => {
            eprintln!("no config/robot.ini here: using the built-in settings");
            Settings::parse("built-in robot.ini", DEFAULT_INI, overrides)
        }
    }
}

/// Which file the settings come from (None: the built-in copy).
fn settings_file(file: Option<&Path>) -> Option<PathBuf> {
    let default = Path::new("config/robot.ini");
    match file {
        Some(path) => Some(path.to_path_buf()),
        None if default.exists() => Some(default.to_path_buf()),
        None => None,
    }
}

const RUN_ADVICE: &str = "run with --headless for the console, or start it in a desktop session";

/// `mechweed teach`: drive the row (or take a record of the drive), map the tool's path.
fn teach(args: cli::TeachArgs) -> ExitCode {
    let Ok(settings) = load_settings(args.run.config.as_deref(), &args.run.set)
        .map_err(|errors| print_errors(&errors))
    else {
        return ExitCode::FAILURE;
    };
    if args.field {
        return said(mechweed::teach_command::field_into_map(
            &settings, &args.row, &args.map,
        ));
    }
    if args.record.is_none() {
        mechweed::say!(
            "teaching row {}: drive it in joystick mode with the weeding tool on the row, then end the run (close the window, Ctrl-C, or --duration)",
            args.row
        );
        let run = RunArgs {
            mode: StartMode::Joystick,
            ..args.run
        };
        if run_command(run) != ExitCode::SUCCESS {
            return ExitCode::FAILURE;
        }
    }
    let record = match args.record {
        Some(record) if record.as_os_str() != "latest" => Ok(record),
        _ => mechweed::record::keep::latest(&settings.record.folder), // the run just made
    };
    said(record.and_then(|record| {
        mechweed::say!("teaching row {} from {}", args.row, record.display());
        mechweed::teach_command::teach_into_map(&record, &args.row, &args.map, &settings)
    }))
}

/// A command's closing line (none if empty), or why it failed.
fn said(result: Result<String, String>) -> ExitCode {
    match result {
        Ok(line) => {
            if !line.is_empty() {
                mechweed::say!("{line}");
            }
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

fn run_command(args: RunArgs) -> ExitCode {
    if args.list_events {
        print!("{}", mechweed::operator::events_help());
        return ExitCode::SUCCESS;
    }
    let mut overrides = args.set.clone();
    if let Some(seed) = args.seed {
        overrides.push(format!("sim.seed={seed}"));
    }
    let mut settings = match load_settings(args.config.as_deref(), &overrides) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
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
        return ExitCode::FAILURE;
    }
    if !args.headless
        && let Some(why) = mechweed::gui::display_missing()
    {
        eprintln!("{why}: {RUN_ADVICE} (nothing started)");
        return ExitCode::FAILURE;
    }
    // Set by Ctrl-C or SIGTERM, told apart from the end of --duration, so that the run
    // says who ended it.
    let stop = mechweed::console::ctrl_c();
    let start_mode = match args.mode {
        StartMode::Halt => Mode::Halt,
        StartMode::Joystick => Mode::Joystick,
        StartMode::Autonomous => Mode::Autonomous,
    };
    match settings.backend {
        Backend::Sim => mechweed::say!(
            "mechweed on the simulated robot: {} row, {} m/s, seed {}; start mode {start_mode}",
            bench_rows::row_name(settings.sim.row),
            settings.steer.speed_mps,
            settings.sim.seed
        ),
        Backend::Cards => mechweed::say!("mechweed on the I/O cards; start mode {start_mode}"),
    }
    if !mechweed::cross_track::CrossTrackMeaning::of(&settings).meaningful() {
        mechweed::say!(
            "camera: {}; {}",
            settings.camera_port.describe(),
            mechweed::report::OUTSIDE_CAMERA
        );
    }
    // Nothing powers the real robot up without a person: the console asks here, the GUI
    // in a window of its own.
    let start_mode = if args.headless
        && mechweed::operator::needs_confirmation(settings.backend, start_mode)
        && !mechweed::operator::confirm_on_console(
            start_mode,
            &mut std::io::stdin().lock(),
            &mut std::io::stdout(),
        ) {
        Mode::Halt
    } else {
        start_mode
    };
    let options = RunOptions {
        settings,
        start_mode,
        duration_s: args.duration,
        status_every_s: 5.0,
        inject: None,
    };
    let outcome = if args.headless {
        run(&options, stop).map_err(|e| e.to_string())
    } else {
        let settings_file = settings_file(args.config.as_deref());
        mechweed::gui::run_gui(&options, settings_file, args.tab, stop, RUN_ADVICE, None)
            .map(|(outcome, _frames)| outcome)
    };
    let outcome = match outcome {
        Ok(outcome) => outcome,
        Err(why) => {
            eprintln!("cannot start: {why}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(who) = mechweed::console::stop_request() {
        // The threads have ended: the supervisor wrote the safe outputs as it stopped.
        mechweed::say!(
            "run stopped by {who}; the outputs are safe: amplifiers 0 V, motor power off, brakes on, tool off"
        );
    }
    let report = Report::from_run(&outcome);
    mechweed::say!("{}", report.human().trim_end());
    if let Some(path) = args.report {
        let json = serde_json::to_string_pretty(&report).expect("the report is plain data");
        if let Err(e) = std::fs::write(&path, json) {
            eprintln!("cannot write the report to {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
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

fn check_config(file: Option<PathBuf>) -> ExitCode {
    let path = file.unwrap_or_else(|| PathBuf::from("config/robot.ini"));
    match Settings::load(&path, &[]) {
        Ok(_) => {
            mechweed::say!("ok");
            ExitCode::SUCCESS
        }
        Err(errors) => {
            print_errors(&errors);
            ExitCode::FAILURE
        }
    }
}

fn write_json(path: Option<PathBuf>, value: &impl serde::Serialize) -> ExitCode {
    if let Some(path) = path {
        let text = serde_json::to_string_pretty(value).expect("plain data");
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

fn bench(command: BenchCommand) -> ExitCode {
    let (config, set, seed, (field, sources), json) = match command {
        BenchCommand::Rows {
            config,
            set,
            seed,
            field,
            sources,
            json,
        } => (config, set, seed, (field, sources), json),
        BenchCommand::Loop {
            rate,
            seconds,
            gui,
            tab,
            press_space,
            set,
            json,
        } => {
            let gui = gui.then(|| tab.unwrap_or_default());
            return bench_loop(rate, seconds, (gui, press_space), &set, json);
        }
    };
    let settings = match load_settings(config.as_deref(), &set) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let field = match field {
        cli::BenchField::Clean => FieldKind::Clean,
        cli::BenchField::Realistic => FieldKind::Realistic,
    };
    let unused = bench_rows::unused_overrides(&set, field);
    unused.iter().for_each(|message| eprintln!("{message}"));
    if !unused.is_empty() {
        return ExitCode::FAILURE;
    }
    let file = settings_file(config.as_deref()) // said: the figures depend on it
        .map_or("the built-in robot.ini".into(), |p| p.display().to_string());
    mechweed::say!("settings: {file} ([sim] is the benchmark's own)");
    let sources: Vec<SteerSource> = (sources.iter())
        .map(|source| match source {
            cli::BenchSource::Camera => SteerSource::Camera,
            cli::BenchSource::Gnss => SteerSource::Gnss,
            cli::BenchSource::Fused => SteerSource::Fused,
        })
        .collect();
    let runs = bench_rows::run_all(&settings, field, &sources, seed);
    print!("{}", bench_rows::table(&runs));
    write_json(json, &runs)
}

fn bench_loop(
    rate: f64,
    seconds: f64,
    (gui, press_space_s): (Option<mechweed::gui::Tab>, Option<f64>),
    set: &[String],
    json: Option<PathBuf>,
) -> ExitCode {
    let settings = match load_settings(None, set) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    if !(1.0..=10_000.0).contains(&rate) || !(0.001..=86_400.0).contains(&seconds) {
        eprintln!("--rate must be 1 to 10000 Hz and --seconds 0.001 to 86400");
        return ExitCode::FAILURE;
    }
    if press_space_s.is_some_and(|s| !(0.2..=60.0).contains(&s)) {
        eprintln!("--press-space must be 0.2 to 60 s");
        return ExitCode::FAILURE;
    }
    // It powers up and drives in autonomous with no one asked: never the real robot.
    if settings.backend != Backend::Sim {
        eprintln!(
            "bench loop drives the simulated robot and starts in autonomous without asking: it does not run on the real robot ([hw] backend = cards in {}); add --set hw.backend=sim",
            settings.source.label
        );
        return ExitCode::FAILURE;
    }
    match mechweed::bench_loop::bench_loop(&settings, rate, seconds, gui, press_space_s) {
        Ok(figures) => {
            print!("{}", figures.text());
            write_json(json, &figures)
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

fn probe(raw: bool, config: Option<PathBuf>) -> ExitCode {
    let settings = match load_settings(config.as_deref(), &[]) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let input_dir = std::path::Path::new(mechweed::gamepad::device::INPUT_DIR);
    print!("{}", mechweed::probe::gamepads(&settings, input_dir));
    match mechweed::probe::probe(&settings, raw) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    log_style::init();
    let cli = Cli::parse();
    match cli.command {
        None => run_command(cli.run),
        Some(Command::Run(args)) => run_command(args),
        Some(Command::CheckConfig { file }) => check_config(file),
        Some(Command::Bench(b)) => bench(b),
        Some(Command::Teach(args)) => teach(args),
        Some(Command::Gnsssim(args)) => said(mechweed::gnsssim::run(args).map(|()| String::new())),
        Some(Command::Camsim(args)) => {
            said(mechweed::camsim_main::run(args).map(|()| String::new()))
        }
        Some(Command::Probe { raw, config }) => probe(raw, config),
        Some(Command::Record(args)) => record_command::record(args),
        Some(Command::Replay(args)) => replay_command::replay(args),
        Some(Command::Bus(args)) => bus_command::bus(args),
        Some(Command::Cluster(command)) => cluster_command::cluster(command),
        Some(Command::Watch(args)) => cluster_command::watch(args),
        Some(Command::Keys(command)) => said(mechweed::keys::command::run(command)),
    }
}
