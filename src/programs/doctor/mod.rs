//! `mechweed doctor`: whether this PC can run the robot. Each check says ok, warning or
//! fail, with the fix in words; `--json` for scripts; exit 0 only if nothing fails.
//!
//! The checks read the PC through a `Machine` (the root of its /sys, /proc and /dev), so
//! that the tests give them a fake tree. The checks themselves are in four files: the
//! kernel and its limits (machine.rs), the devices robot.ini names (devices.rs), the
//! files and ports (files.rs), and the loop's own timing (latency.rs).

mod devices;
mod files;
mod latency;
mod machine;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::config::{Backend, Settings, WatchdogRelay};
use crate::programs::{HERE_INI, find_settings, system_ini};

pub use machine::Machine;

#[derive(clap::Args)]
pub struct DoctorArgs {
    /// Settings file [default: as `run` finds it: config/robot.ini, then
    /// /etc/mechweed/robot.ini, then the built-in copy]
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Print the checks as JSON (one object: `checks`, `fails`, `warnings`).
    #[arg(long)]
    pub json: bool,
    /// Seconds of the latency test: the supervisor's loop at its rate and priority
    /// (0 leaves it out).
    #[arg(long, value_name = "SECONDS", default_value_t = 3.0)]
    pub latency_s: f64,
}

/// How a check came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    Ok,
    Warning,
    Fail,
}

/// One line of the doctor's answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Check {
    /// Short and stable, for scripts: "rt_priority", "card_das08", ...
    pub check: String,
    pub level: Level,
    /// What was found.
    pub says: String,
    /// What to do about it ("" when ok).
    pub fix: String,
}

impl Check {
    pub fn ok(check: &str, says: impl Into<String>) -> Check {
        Check::new(check, Level::Ok, says, "")
    }

    pub fn new(
        check: &str,
        level: Level,
        says: impl Into<String>,
        fix: impl Into<String>,
    ) -> Check {
        Check {
            check: check.to_string(),
            level,
            says: says.into(),
            fix: fix.into(),
        }
    }

    /// A refusal that stops the real robot but only slows the simulated one.
    pub fn needed_on_cards(
        check: &str,
        backend: Backend,
        says: impl Into<String>,
        fix: impl Into<String>,
    ) -> Check {
        let level = match backend {
            Backend::Cards => Level::Fail,
            Backend::Sim => Level::Warning,
        };
        Check::new(check, level, says, fix)
    }
}

pub fn doctor(args: DoctorArgs) -> ExitCode {
    let (found, said) = find_settings(args.config.as_deref(), Path::new(HERE_INI), &system_ini());
    if !args.json {
        eprintln!("{said}");
    }
    let machine = Machine::real();
    let checks = examine(&machine, found.as_deref(), args.latency_s, !args.json);
    let fails = checks.iter().filter(|c| c.level == Level::Fail).count();
    let warnings = checks.iter().filter(|c| c.level == Level::Warning).count();
    if args.json {
        let answer = serde_json::json!({"checks": checks, "fails": fails, "warnings": warnings});
        println!("{answer:#}");
    } else {
        crate::say!(
            "{}: {fails} failed, {warnings} warnings, {} ok",
            if fails == 0 {
                "this PC can run the robot"
            } else {
                "this PC cannot run the robot yet"
            },
            checks.len() - fails - warnings
        );
    }
    if fails == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Every check, in the order a technician mends them: the settings first (the others
/// read them), then the kernel, the devices, the files, and the loop's timing last.
/// With `say`, each line is printed as it comes (the latency test takes seconds).
pub fn examine(machine: &Machine, file: Option<&Path>, latency_s: f64, say: bool) -> Vec<Check> {
    let mut checks = Vec::new();
    let mut add = |check: Check| {
        if say {
            print_line(&check);
        }
        checks.push(check);
    };
    let settings = match settings_check(file) {
        Ok((check, settings)) => {
            add(check);
            settings
        }
        Err(check) => {
            add(check);
            add(Check::new(
                "rest",
                Level::Warning,
                "the other checks need the settings and were left out",
                "mend the settings, then run mechweed doctor again",
            ));
            return checks;
        }
    };
    if settings.watchdog_relay == WatchdogRelay::NoneAccepted {
        add(Check::new(
            "watchdog_relay",
            Level::Warning,
            "[io] watchdog_relay = none_accepted: nothing opens the motor contactor when the program is killed or hangs but the e-stop buttons",
            "fit the charge-pump relay in the e-stop chain and set watchdog_relay = fitted",
        ));
    }
    for check in machine::checks(machine, &settings) {
        add(check);
    }
    for check in devices::checks(machine, &settings) {
        add(check);
    }
    for check in files::checks(machine, &settings) {
        add(check);
    }
    if latency_s > 0.0 {
        add(latency::check(&settings, latency_s));
    }
    checks
}

/// check-config of the file in use (the built-in copy if none).
fn settings_check(file: Option<&Path>) -> Result<(Check, Settings), Check> {
    let (name, read) = match file {
        Some(path) => (path.display().to_string(), Settings::load(path, &[])),
        None => (
            "the built-in settings".to_string(),
            Settings::parse("built-in robot.ini", crate::config::DEFAULT_INI, &[]),
        ),
    };
    match read {
        Ok(settings) => {
            let robot = match settings.backend {
                Backend::Cards => "the real robot ([hw] backend = cards)",
                Backend::Sim => "the simulated robot ([hw] backend = sim)",
            };
            Ok((
                Check::ok("settings", format!("{name}: ok, for {robot}")),
                settings,
            ))
        }
        Err(errors) => {
            let first: Vec<String> = errors.iter().take(3).map(|e| e.to_string()).collect();
            Err(Check::new(
                "settings",
                Level::Fail,
                format!("{name}: {} errors: {}", errors.len(), first.join("; ")),
                format!(
                    "mechweed check-config {name} lists them all (mechweed config upgrade {name} adds settings an older file lacks)"
                ),
            ))
        }
    }
}

fn print_line(check: &Check) {
    let level = match check.level {
        Level::Ok => "ok     ",
        Level::Warning => "warning",
        Level::Fail => "FAIL   ",
    };
    crate::say!("{level}  {:<14} {}", check.check, check.says);
    if !check.fix.is_empty() {
        crate::say!("         {:<14} fix: {}", "", check.fix);
    }
}

#[cfg(test)]
mod tests;
