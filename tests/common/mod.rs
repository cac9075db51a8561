//! Shared helpers for the lockstep tests.
#![allow(dead_code)]

use mechweed::config::Settings;
use mechweed::lockstep::Lockstep;
use mechweed::modes::Mode;
use mechweed_hw::sim::parse_events;
use mechweed_hw::{Inputs, Outputs};

/// The shipped settings with `[sim] events` set and other overrides.
pub fn settings_with(events: &str, overrides: &[&str]) -> Settings {
    let mut set: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    set.push(format!("sim.events={events}"));
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/config/robot.ini")).unwrap();
    let mut s =
        Settings::parse("config/robot.ini", &text, &set).unwrap_or_else(|e| panic!("{e:?}"));
    s.sim.events = parse_events(events).unwrap();
    s
}

/// One supervisor tick as seen from outside.
#[derive(Debug, Clone, Copy)]
pub struct Tick {
    pub t_s: f64,
    pub inputs: Inputs,
    pub outputs: Outputs,
    pub mode: Mode,
}

/// Run the lockstep simulation for `seconds`, recording every supervisor tick.
pub fn record(sim: &mut Lockstep, seconds: f64) -> Vec<Tick> {
    let end = sim.now_s() + seconds;
    let mut ticks = Vec::new();
    while sim.now_s() < end - 1e-9 {
        let inputs = sim.robot.inputs();
        let outputs = sim.tick();
        let status = sim.supervisor.status();
        // The inputs the tick read are the ones it published.
        let _ = inputs;
        ticks.push(Tick {
            t_s: sim.now_s(),
            inputs: status.inputs,
            outputs,
            mode: status.mode,
        });
    }
    ticks
}

/// A robot driving autonomously along the default row, started at t = 0.
pub fn autonomous(settings: &Settings) -> Lockstep {
    Lockstep::new(settings, Mode::Autonomous)
}

/// The `--set` items every run of the program in a test shares: its record goes to
/// `folder`, not into the repository, a busy test machine's late ticks are tolerated
/// (those faults have tests of their own), and the bus is off.
pub fn test_run_settings(folder: &std::path::Path) -> Vec<String> {
    [
        "rt.max_overruns=1000000".to_string(),
        "rt.max_late_periods=20".to_string(),
        // Tests run side by side: the bus's tests give each run a port of its own.
        "bus.enabled=no".to_string(),
        format!("record.folder={}", folder.display()),
    ]
    .into_iter()
    .flat_map(|item| ["--set".to_string(), item])
    .collect()
}

/// The program, run from the project's folder (where config/robot.ini is).
pub fn mechweed() -> std::process::Command {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_mechweed"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"));
    cmd
}

/// A program's output as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
