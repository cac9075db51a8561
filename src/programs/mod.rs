//! The programs of `mechweed`, one file (or folder) each, with its options (clap)
//! beside its code: `run`, `check-config`, `bench ...`, `camsim`, `teach`, `gnsssim`,
//! `probe`, `record ...`, `replay`, `bus ...`, `cluster ...`, `watch`, `ros2` and
//! `keys ...`.
//! Here: the command line as a whole, and the few steps every program shares (its
//! settings, its errors, its last line). src/main.rs only picks the program.

pub mod bench;
pub mod bus;
pub mod camsim;
pub mod check_config;
pub mod cluster;
pub mod config;
pub mod doctor;
pub mod gnsssim;
pub mod keys;
pub mod man_pages;
pub mod probe;
pub mod probe_watch;
pub mod record;
pub mod replay;
pub mod ros2;
pub mod run;
pub mod safe;
pub mod teach;
pub mod watch;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::config::{ConfigError, DEFAULT_INI, Settings};

#[derive(Parser)]
#[command(
    name = "mechweed",
    version,
    about = "Control program for the weeding robot. Runs on the simulated robot unless config/robot.ini [hw] says otherwise.",
    after_help = "Without a command, mechweed runs as `mechweed run` and takes its options (e.g. `mechweed --headless`): the operator GUI on the simulated robot.",
    // `mechweed --headless` is `mechweed run --headless`; the run's options mean nothing
    // before another command.
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The options of `run`, for `mechweed` without a command.
    #[command(flatten)]
    pub run: run::RunArgs,
}

#[derive(Subcommand)]
pub enum Command {
    /// Run the controller on real threads and real time.
    Run(run::RunArgs),
    /// Check a settings file: prints "ok", or every error found (exit 1).
    CheckConfig(check_config::CheckConfigArgs),
    /// Benchmarks on the simulated robot.
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// A stand-alone simulated camera computer, for bench tests of a link.
    Camsim(camsim::CamsimArgs),
    /// Teach a row for the row map: drive it in joystick mode with the weeding tool on the
    /// row (or give a record of such a drive); the tool's path goes into the map file.
    Teach(teach::TeachArgs),
    /// A stand-alone simulated RTK GNSS receiver (NMEA on a serial device or TCP), for
    /// bench tests of the GNSS link.
    Gnsssim(gnsssim::GnssSimArgs),
    /// List the gamepads; find the I/O cards and read every input once (writes nothing
    /// but safe outputs).
    Probe(probe::ProbeArgs),
    /// Open the I/O cards and write the safe outputs only, from robot.ini's [hw] and
    /// [io] alone (after a killed run; the service runs it when the controller stops).
    Safe(safe::SafeArgs),
    /// Run records (CSV or MCAP) left by `mechweed run`, and the off-board recorder
    /// (`record --bus`).
    Record(record::RecordArgs),
    /// Feed a record's inputs through the supervisor again: the same outputs, or with
    /// --set a what-if on the same inputs.
    Replay(replay::ReplayArgs),
    /// The robot's data flows on the bus, from this or another computer.
    Bus(bus::BusArgs),
    /// The virtual cluster: one graph file starts the programs of several machines.
    #[command(subcommand)]
    Cluster(cluster::ClusterCommand),
    /// The operator GUI on another computer, fed by the robot's flows on the bus.
    Watch(watch::WatchArgs),
    /// The robot's flows as ROS 2 topics, for rviz2, ros2 topic echo, PlotJuggler and
    /// Foxglove on the ROS machines (rmw_zenoh's format; read-only).
    Ros2(ros2::Ros2Args),
    /// The cluster's certificates: who may do what on the bus and the cluster.
    #[command(subcommand)]
    Keys(keys::KeysCommand),
    /// Whether this PC can run the robot: each check ok, warning or fail, with the fix
    /// (exit 1 if any fails).
    Doctor(doctor::DoctorArgs),
    /// Settings files of older releases brought up to this one.
    #[command(subcommand)]
    Config(config::ConfigCommand),
    /// The bus process of a run: started by `mechweed run` itself, its link on stdin.
    #[command(hide = true)]
    BusGateway,
    /// Write the man pages into DIR (for the package).
    #[command(hide = true)]
    ManPages { dir: std::path::PathBuf },
}

pub(crate) fn print_errors(errors: &[ConfigError]) {
    errors.iter().for_each(|e| eprintln!("{e}"));
    // A file of an older release: one command adds what it lacks (no guess at start);
    // a setting it no longer has is among them.
    let older = |e: &ConfigError| {
        e.what.ends_with(" is missing")
            || e.what.starts_with("missing section")
            || e.what.ends_with(" is not a known setting")
    };
    // Only when nothing else is wrong: a broken heading also leaves a section missing,
    // and an upgrade would not mend it.
    let all_missing = errors.iter().all(older);
    if let Some(file) = (errors.iter())
        .filter(|_| all_missing)
        .find_map(|e| match &e.place {
            crate::config::Place::Line { file, .. } | crate::config::Place::File(file) => {
                Some(file)
            }
            crate::config::Place::Override(_) => None,
        })
    {
        eprintln!(
            "{file} is of an older release: `mechweed config upgrade {file}` adds every missing setting with its comment and the value that keeps the older behaviour (`--check` only lists them)"
        );
    }
}

/// Where the settings are looked for when no --config names a file: in the folder the
/// program is started in, then the robot PC's own (the package installs it), then the
/// built-in copy.
pub const HERE_INI: &str = "config/robot.ini";
pub const SYSTEM_INI: &str = "/etc/mechweed/robot.ini";
/// Another place for the robot PC's file (the tests point it where nothing is, so that
/// a robot PC's own settings never reach them).
pub const SYSTEM_INI_VAR: &str = "MECHWEED_SYSTEM_INI";

pub(crate) fn system_ini() -> PathBuf {
    std::env::var_os(SYSTEM_INI_VAR).map_or(PathBuf::from(SYSTEM_INI), PathBuf::from)
}

/// The settings file as `settings_file` finds it, said on stderr: every start says
/// which settings it runs with.
pub(crate) fn load_settings(
    file: Option<&Path>,
    overrides: &[String],
) -> Result<Settings, Vec<ConfigError>> {
    let (found, said) = find_settings(file, Path::new(HERE_INI), &system_ini());
    eprintln!("{said}");
    match found {
        Some(path) => Settings::load(&path, overrides),
        None => Settings::parse("built-in robot.ini", DEFAULT_INI, overrides),
    }
}

/// Which file the settings come from (None: the built-in copy).
pub fn settings_file(file: Option<&Path>) -> Option<PathBuf> {
    find_settings(file, Path::new(HERE_INI), &system_ini()).0
}

/// The file named, else `here`, else `system`, else none (the built-in copy); with
/// the words that say which.
pub fn find_settings(file: Option<&Path>, here: &Path, system: &Path) -> (Option<PathBuf>, String) {
    match file {
        Some(path) => (
            Some(path.to_path_buf()),
            format!("settings: {} (--config)", path.display()),
        ),
        None if here.exists() => (
            Some(here.to_path_buf()),
            format!("settings: {} (in this folder)", here.display()),
        ),
        None if system.exists() => (
            Some(system.to_path_buf()),
            format!(
                "settings: {} (no {} in this folder)",
                system.display(),
                here.display()
            ),
        ),
        None => (
            None,
            format!(
                "no {} here and no {}: using the built-in settings",
                here.display(),
                system.display()
            ),
        ),
    }
}

/// A command's closing line (none if empty), or why it failed.
pub fn said(result: Result<String, String>) -> ExitCode {
    match result {
        Ok(line) => {
            if !line.is_empty() {
                crate::say!("{line}");
            }
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

/// A command that prints nothing more when it works: its exit code, or why it failed.
pub fn done(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

pub(crate) fn write_json(path: Option<PathBuf>, value: &impl serde::Serialize) -> ExitCode {
    if let Some(path) = path {
        let text = serde_json::to_string_pretty(value).expect("plain data");
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}

pub(crate) fn parse_metres(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(m) if m.is_finite() && m >= 0.0 => Ok(m),
        _ => Err(format!("'{text}' is not a distance in m (0 or more)")),
    }
}

#[cfg(test)]
mod tests {
    use super::find_settings;
    use std::path::Path;

    #[test]
    fn settings_are_found_here_then_on_the_robot_pc_then_built_in_and_said() {
        let dir = tempfile::tempdir().unwrap();
        let (here, system) = (dir.path().join("here.ini"), dir.path().join("etc.ini"));
        let named = Path::new("field.ini");
        let find = |file| find_settings(file, &here, &system);
        // Neither there: the built-in copy, and the start says so.
        let (found, said) = find(None);
        assert_eq!(found, None);
        assert!(said.ends_with("using the built-in settings"), "{said}");
        std::fs::write(&system, "").unwrap();
        let (found, said) = find(None);
        assert_eq!(found.as_deref(), Some(system.as_path()));
        assert!(said.contains("etc.ini (no "), "{said}");
        std::fs::write(&here, "").unwrap();
        let (found, said) = find(None);
        assert_eq!(found.as_deref(), Some(here.as_path()));
        assert!(said.ends_with("here.ini (in this folder)"), "{said}");
        // A file named wins over both.
        let (found, said) = find(Some(named));
        assert_eq!(found.as_deref(), Some(named));
        assert_eq!(said, "settings: field.ini (--config)");
    }
}
