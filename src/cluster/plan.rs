//! What a launcher runs: each process of its machine as a command line, with the
//! bus wired as the graph's flows say. The controller listens at its machine's
//! endpoint; every other mechweed program connects there. The master sends this plan;
//! the launcher adds nothing but its own path to the mechweed program.

use serde::{Deserialize, Serialize};

use super::graph::{Graph, MasterLost, Process, Start};
use super::program::Program;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Launch {
    pub name: String,
    /// `mechweed` (this program, as the launcher finds itself) or an executable.
    pub program: String,
    /// After the program: for mechweed, the command first (`run`, `camsim`, ...).
    pub args: Vec<String>,
    /// Environment variables for an executable: where the robot's flows are.
    pub env: Vec<(String, String)>,
    /// Started by the launcher; false: a person starts it (the launcher says how).
    pub auto: bool,
    pub restart: bool,
    pub restart_delay_s: f64,
    /// Started only once these processes run (on any machine).
    pub after: Vec<String>,
    /// The robot program: stopped first, its safe outputs before anything else ends.
    pub controller: bool,
}

impl Launch {
    /// The command line as a person would type it.
    pub(crate) fn command_line(&self) -> String {
        std::iter::once(self.program.as_str())
            .chain(self.args.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Plan {
    pub machine: String,
    /// The graph file it comes from, for messages.
    pub graph: String,
    /// Stop the processes when the master goes away (else they run on).
    pub stop_when_master_lost: bool,
    pub processes: Vec<Launch>,
}

/// The plan of `machine`, or None if the graph has no such machine.
pub(crate) fn for_machine(graph: &Graph, machine: &str) -> Option<Plan> {
    graph.machine(machine)?;
    Some(Plan {
        machine: machine.to_string(),
        graph: graph.file.clone(),
        stop_when_master_lost: graph.master_lost == MasterLost::Stop,
        processes: graph
            .processes
            .iter()
            .filter(|p| p.machine == machine)
            .map(|p| launch(graph, p))
            .collect(),
    })
}

/// One process's command line.
pub(crate) fn launch(graph: &Graph, process: &Process) -> Launch {
    let robot = graph.robot.clone();
    let controller_at = graph.controller_endpoint().map(str::to_string);
    let set = |args: &mut Vec<String>, item: String| args.extend(["--set".to_string(), item]);
    let mut args = Vec::new();
    let mut env = Vec::new();
    match &process.program {
        Program::Run => {
            let listen = graph
                .machine(&process.machine)
                .map_or(String::new(), |m| m.listen.clone());
            args.push("run".to_string());
            args.extend(process.args.iter().cloned());
            for item in [
                "bus.enabled=yes".to_string(),
                // A controller whose flows cannot start would run alone, unseen.
                "bus.required=yes".to_string(),
                format!("bus.robot={robot}"),
                format!("bus.listen={listen}"),
            ] {
                set(&mut args, item);
            }
            let rows_in = graph.flows.iter().any(|f| {
                f.to.iter()
                    .any(|e| e.process == process.name && e.port == "rows")
            });
            if rows_in {
                set(&mut args, "camera.port=bus".to_string());
            }
        }
        Program::Camsim | Program::Watch | Program::Record => {
            args.push(process.program.name().to_string());
            if process.program == Program::Camsim || process.program == Program::Record {
                args.push("--bus".to_string());
            }
            if let Some(at) = &controller_at {
                args.extend(["--connect".to_string(), at.clone()]);
            }
            args.extend(["--robot".to_string(), robot.clone()]);
            args.extend(process.args.iter().cloned());
        }
        Program::Ros2 => {
            args.push("ros2".to_string());
            if let Some(at) = &controller_at {
                args.extend(["--robot-connect".to_string(), at.clone()]);
            }
            args.extend(["--robot".to_string(), robot.clone()]);
            args.extend(process.args.iter().cloned());
        }
        Program::Executable(_) => {
            args.extend(process.args.iter().cloned());
            env.push(("MECHWEED_ROBOT".to_string(), robot.clone()));
            if let Some(at) = &controller_at {
                env.push(("MECHWEED_CONNECT".to_string(), at.clone()));
            }
        }
    }
    // The graph's settings last: they win over the wiring's.
    for item in &process.settings {
        set(&mut args, item.clone());
    }
    Launch {
        name: process.name.clone(),
        program: match &process.program {
            Program::Executable(path) => path.clone(),
            _ => "mechweed".to_string(),
        },
        args,
        env,
        auto: process.start == Start::Auto,
        restart: process.restart,
        restart_delay_s: process.restart_delay_s,
        after: process.after.clone(),
        controller: process.program == Program::Run,
    }
}
