//! The graph file: which machines take part in a run, which programs each one runs
//! with which parameters, and which flows go from which program to which. It is read
//! with robot.ini's rules (every error names its line and key, all errors at once), and
//! checked whole before anything starts.
//!
//! ```ini
//! [cluster]
//! robot = mechweed
//! master = tcp/192.168.1.20:7450
//! master_lost = run_on
//! [machine robot-pc]
//! endpoint = tcp/192.168.1.10:7510
//! [process controller]
//! machine = robot-pc
//! program = run
//! args = --headless --mode autonomous
//! set.steer.speed_mps = 0.5
//! [flow rows]
//! from = camera.rows
//! to = controller.rows
//! ```

use std::collections::BTreeSet;

use crate::config::{ConfigError, Reader, TlsFiles, listen_refusal, parse_endpoints, parse_prefix};

use super::flow::flow;
use super::program::Program;

/// What each launcher does when the master goes away (a dropped Wi-Fi link).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum MasterLost {
    /// Its processes run on: the robot's safety never depends on the master.
    RunOn,
    /// It stops its processes, the controller first.
    Stop,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Machine {
    pub name: String,
    /// Where the programs of other machines reach this one's (the controller's bus).
    pub endpoint: String,
    /// Where this machine's controller listens (default: `endpoint`; e.g. tcp/0.0.0.0:7510).
    pub listen: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The launcher starts it.
    Auto,
    /// A person starts it (e.g. in a debugger); the launcher prints the command.
    Manual,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Process {
    pub name: String,
    pub machine: String,
    pub program: Program,
    /// Its arguments, split at spaces (double quotes keep spaces inside one).
    pub args: Vec<String>,
    /// Settings overrides (`set.SECTION.KEY = VALUE`), given as `--set SECTION.KEY=VALUE`.
    pub settings: Vec<String>,
    pub start: Start,
    /// Started again when it exits, after `restart_delay_s`.
    pub restart: bool,
    pub restart_delay_s: f64,
    /// Processes that must be running before this one starts (the controller in
    /// autonomous after the camera, whose rows it needs at once).
    pub after: Vec<String>,
}

/// One end of a flow: a process and one of its ports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct End {
    pub process: String,
    pub port: String,
}

impl std::fmt::Display for End {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}", self.process, self.port)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Flow {
    pub name: String,
    pub from: End,
    pub to: Vec<End>,
    /// The bus key it travels on.
    pub key: String,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Graph {
    /// The file, as messages name it.
    pub file: String,
    /// The robot's name on the bus: the first part of every key.
    pub robot: String,
    /// Where the master listens for the launchers.
    pub master: String,
    pub master_lost: MasterLost,
    /// The master's identity ([cluster] tls_ca, tls_cert, tls_key): the cluster is
    /// secured, every endpoint tls/, every program with its own identity.
    pub tls: Option<TlsFiles>,
    /// Plain tcp/ beyond loopback allowed ([cluster] trusted_network = yes).
    pub trusted_network: bool,
    pub machines: Vec<Machine>,
    pub processes: Vec<Process>,
    pub flows: Vec<Flow>,
}

impl Graph {
    /// Read and check a graph file.
    pub fn load(path: &std::path::Path) -> Result<Graph, Vec<ConfigError>> {
        let text = crate::config::read_text(path, "the graph file")?;
        Graph::parse(&path.display().to_string(), &text)
    }

    /// Read and check a graph from text (`file` names it in messages).
    pub fn parse(file: &str, text: &str) -> Result<Graph, Vec<ConfigError>> {
        let mut r = Reader::with_named_sections(file, text);
        let sections = r.sections();
        let named = |kind: &str| -> Vec<String> {
            let prefix = format!("{kind} ");
            sections
                .iter()
                .filter_map(|s| s.strip_prefix(&prefix).map(str::to_string))
                .collect()
        };
        let (machine_names, process_names, flow_names) =
            (named("machine"), named("process"), named("flow"));
        let s = "cluster";
        let robot = r.parsed(s, "robot", parse_prefix).unwrap_or_default();
        let master = r.parsed(s, "master", one_endpoint).unwrap_or_default();
        let master_lost =
            [MasterLost::RunOn, MasterLost::Stop][r.choice(s, "master_lost", &["run_on", "stop"])];
        let tls = crate::config::tls_files(&mut r, s, false);
        let trusted_network = crate::config::optional_yes(&mut r, s, "trusted_network");
        let machines: Vec<Machine> = machine_names.iter().map(|n| machine(&mut r, n)).collect();
        check_endpoints(&mut r, &master, &machines, tls.is_some(), trusted_network);
        let processes: Vec<Process> = process_names
            .iter()
            .map(|n| process(&mut r, n, &machine_names, &process_names))
            .collect();
        let flows: Vec<Flow> = flow_names
            .iter()
            .filter_map(|n| flow(&mut r, n, &processes, &robot))
            .collect();
        check_whole(&mut r, &processes);
        let mut known: Vec<&str> = vec!["cluster"];
        known.extend(sections.iter().map(String::as_str).filter(|s| {
            ["machine ", "process ", "flow "]
                .iter()
                .any(|kind| s.starts_with(kind))
        }));
        let errors = r.finish(&known);
        if !errors.is_empty() {
            return Err(errors);
        }
        Ok(Graph {
            file: file.to_string(),
            robot,
            master,
            master_lost,
            tls,
            trusted_network,
            machines,
            processes,
            flows,
        })
    }

    pub fn machine(&self, name: &str) -> Option<&Machine> {
        self.machines.iter().find(|m| m.name == name)
    }

    pub fn process(&self, name: &str) -> Option<&Process> {
        self.processes.iter().find(|p| p.name == name)
    }

    /// The robot program (`program = run`), if the graph has one.
    pub fn controller(&self) -> Option<&Process> {
        self.processes.iter().find(|p| p.program == Program::Run)
    }

    /// Where the controller's flows are reached: its machine's endpoint.
    pub(crate) fn controller_endpoint(&self) -> Option<&str> {
        let controller = self.controller()?;
        Some(&self.machine(&controller.machine)?.endpoint)
    }
}

/// One endpoint `tcp/HOST:PORT`.
fn one_endpoint(text: &str) -> Result<String, String> {
    match parse_endpoints(text)?.as_slice() {
        [one] => Ok(one.clone()),
        _ => Err(format!("'{text}' must be one endpoint tcp/HOST:PORT")),
    }
}

fn machine(r: &mut Reader, name: &str) -> Machine {
    let s = format!("machine {name}");
    let endpoint = r.parsed(&s, "endpoint", one_endpoint).unwrap_or_default();
    let listen = r.keys(&s).contains(&"listen".to_string());
    let listen = if listen {
        r.parsed(&s, "listen", one_endpoint).unwrap_or_default()
    } else {
        endpoint.clone()
    };
    Machine {
        name: name.to_string(),
        endpoint,
        listen,
    }
}

/// A word of `choices`, or `default` when the key is not there.
fn choice_or(r: &mut Reader, s: &str, key: &str, choices: &[&str], default: usize) -> usize {
    if r.keys(s).iter().any(|k| k == key) {
        r.choice(s, key, choices)
    } else {
        default
    }
}

fn process(r: &mut Reader, name: &str, machines: &[String], processes: &[String]) -> Process {
    let s = format!("process {name}");
    let on_machine = |text: &str| {
        if machines.iter().any(|m| m == text) {
            Ok(text.to_string())
        } else {
            Err(format!(
                "'{text}' is not a machine of this graph (its machines: {})",
                listed(machines)
            ))
        }
    };
    let machine = r.parsed(&s, "machine", on_machine).unwrap_or_default();
    let program = r.parsed(&s, "program", Program::parse);
    let args = if r.keys(&s).iter().any(|k| k == "args") {
        r.parsed(&s, "args", split_args).unwrap_or_default()
    } else {
        Vec::new()
    };
    let mut settings = Vec::new();
    for key in r.keys(&s) {
        let Some(setting) = key.strip_prefix("set.") else {
            continue;
        };
        let takes_settings = program.as_ref().is_none_or(Program::takes_settings);
        let value = r.text(&s, &key).unwrap_or_default();
        if !setting.contains('.') {
            let what = format!("{key} must name SECTION.KEY, for example set.steer.speed_mps");
            r.error_at(&s, &key, what);
        } else if !takes_settings {
            let what = "only the mechweed programs run, record and ros2 take settings".to_string();
            r.error_at(&s, &key, what);
        } else {
            settings.push(format!("{setting}={value}"));
        }
    }
    let start = [Start::Auto, Start::Manual][choice_or(r, &s, "start", &["auto", "manual"], 0)];
    let restart = choice_or(r, &s, "restart", &["no", "yes"], 0) == 1;
    let restart_delay_s = if r.keys(&s).iter().any(|k| k == "restart_delay_s") {
        r.f64(&s, "restart_delay_s", 0.0, 3600.0)
    } else {
        1.0
    };
    let others = |text: &str| -> Result<Vec<String>, String> {
        let names: Vec<String> = text.split(',').map(|n| n.trim().to_string()).collect();
        match names.iter().find(|n| *n == name || !processes.contains(n)) {
            Some(n) if n == name => Err("a process cannot wait for itself".to_string()),
            Some(n) => Err(format!(
                "'{n}' is not a process of this graph (its processes: {})",
                listed(processes)
            )),
            None => Ok(names),
        }
    };
    let after = if r.keys(&s).iter().any(|k| k == "after") {
        r.parsed(&s, "after", others).unwrap_or_default()
    } else {
        Vec::new()
    };
    Process {
        name: name.to_string(),
        after,
        machine,
        program: program.unwrap_or(Program::Run),
        args,
        settings,
        start,
        restart,
        restart_delay_s,
    }
}

/// Arguments split at spaces; double quotes keep spaces inside one (`-c "echo hi"`).
fn split_args(text: &str) -> Result<Vec<String>, String> {
    let mut args = Vec::new();
    let mut current: Option<String> = None;
    let mut quoted = false;
    for c in text.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                current.get_or_insert_with(String::new);
            }
            c if c.is_whitespace() && !quoted => args.extend(current.take()),
            c => current.get_or_insert_with(String::new).push(c),
        }
    }
    if quoted {
        return Err("a \" is not closed".to_string());
    }
    args.extend(current);
    Ok(args)
}

pub(super) fn listed(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// A graph that would open the robot's bus or the master beyond this computer without
/// TLS is refused, each endpoint named, unless [cluster] trusted_network = yes; with TLS,
/// every endpoint is tls/.
fn check_endpoints(
    r: &mut Reader,
    master: &str,
    machines: &[Machine],
    tls: bool,
    trusted_network: bool,
) {
    let mut places = vec![("cluster".to_string(), "master", master.to_string())];
    for m in machines {
        let section = format!("machine {}", m.name);
        places.push((section.clone(), "endpoint", m.endpoint.clone()));
        places.push((section, "listen", m.listen.clone()));
    }
    for (section, key, endpoint) in places {
        if endpoint.is_empty() {
            continue; // its own error already
        }
        let setting = format!("[{section}] {key}");
        if let Some(why) = listen_refusal(&[endpoint], tls, trusted_network, &setting) {
            let why = why
                .replace(
                    "tls_ca, tls_cert and tls_key",
                    "[cluster] tls_ca, tls_cert and tls_key",
                )
                .replace("set trusted_network", "set [cluster] trusted_network");
            r.error_at(&section, key, why);
        }
    }
}

/// Checks across processes: one robot program per graph (one robot name), and no
/// process waiting, through others, for itself.
fn check_whole(r: &mut Reader, processes: &[Process]) {
    for p in processes {
        let mut seen = BTreeSet::new();
        let mut next: Vec<&str> = p.after.iter().map(String::as_str).collect();
        while let Some(name) = next.pop() {
            if name == p.name {
                let what = "waits for itself through the processes it waits for".to_string();
                r.error_at(&format!("process {}", p.name), "after", what);
                break;
            }
            if seen.insert(name)
                && let Some(other) = processes.iter().find(|o| o.name == name)
            {
                next.extend(other.after.iter().map(String::as_str));
            }
        }
    }
    let controllers: Vec<&Process> = processes
        .iter()
        .filter(|p| p.program == Program::Run)
        .collect();
    if let [_, second, ..] = controllers.as_slice() {
        let what = format!(
            "a second robot program (the first is [process {}]): a graph runs one robot",
            controllers[0].name
        );
        r.error_at(&format!("process {}", second.name), "program", what);
    }
}
