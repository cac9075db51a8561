//! Shared helpers for the lockstep tests (the program's own tests take them too).
#![allow(dead_code)]

use mechweed_core::config::{DEFAULT_INI, Settings};
use mechweed_core::rt::health::ThreadHealth;
use mechweed_core::state::modes::Mode;
use mechweed_core::steer::SteerCommand;
use mechweed_core::threads::lockstep::Lockstep;
use mechweed_hw::sim::parse_events;
use mechweed_hw::{Inputs, Outputs};

/// The shipped settings with `[sim] events` set and other overrides.
pub fn settings_with(events: &str, overrides: &[&str]) -> Settings {
    let mut set: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    set.push(format!("sim.events={events}"));
    // The shipped file, as built in (this file is compiled by the program's tests too).
    let mut s =
        Settings::parse("config/robot.ini", DEFAULT_INI, &set).unwrap_or_else(|e| panic!("{e:?}"));
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

/// One supervisor tick at `now_s`, the test standing in for the steer thread: `command`
/// as if made now, a camera link that is alive, the robot's inputs as `alter` leaves them.
pub fn tick_by_hand(
    sim: &mut Lockstep,
    now_s: f64,
    command: &SteerCommand,
    alter: impl FnOnce(&mut Inputs),
) -> Outputs {
    sim.robot.advance_to(now_s);
    let mut inputs = sim.robot.inputs();
    alter(&mut inputs);
    let mut link = *sim.link.status();
    link.beat_s = now_s;
    let command = SteerCommand {
        t_s: now_s,
        ..*command
    };
    let outputs = sim
        .supervisor
        .tick(now_s, &inputs, &command, &link, &ThreadHealth::default());
    sim.robot.set_outputs(&outputs);
    outputs
}
