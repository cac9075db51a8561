//! `mechweed cluster master GRAPH`: serves the graph on the bus and waits. Each
//! launcher asks it for its machine's plan and reports its processes' states to it;
//! `cluster status` asks it for the whole. At Ctrl-C it stops the cluster in order:
//! the controller first (its safe outputs written as it ends), then every other
//! process, and each launcher ends.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, bounded};
use serde_json::{Value, json};
use zenoh::sample::SampleKind;
use zenoh::{Session, Wait};

use super::graph::Graph;
use super::plan::for_machine;
use super::{Keys, ProcessReport, answer, ask};
use crate::bus::session::{Role, open};

/// How long a launcher has to stop what it was asked to (10 s per process at most, the
/// controller usually within one).
const STOP_WAIT: Duration = Duration::from_secs(40);

/// What the master knows of the cluster.
struct Table {
    reports: BTreeMap<(String, String), ProcessReport>,
    /// Machines whose launcher is there.
    launchers: BTreeSet<String>,
    /// Each machine's launcher by its session, and when it took its plan: a second one
    /// for a machine is refused while the first is linked.
    holders: BTreeMap<String, (String, Instant)>,
}

/// Serve `graph` until `stop` (Ctrl-C), then stop the cluster.
pub fn serve(graph: &Graph, stop: &Arc<AtomicBool>) -> Result<(), String> {
    let keys = Keys::new(&graph.robot);
    crate::bus::session::check_robot(graph.tls.as_ref(), &graph.robot)?;
    let session = open(
        Role::Master {
            listen: graph.master.clone(),
        },
        graph.tls.as_ref(),
    )
    .map_err(|e| e.to_string())?;
    let (query_tx, queries) = bounded(64);
    let mut queryables = Vec::new();
    for key in [keys.plan("*"), keys.status(), keys.states()] {
        let tx = query_tx.clone();
        let queryable = session
            .declare_queryable(key)
            .callback(move |q| {
                let _ = tx.try_send(q);
            })
            .wait()
            .map_err(|e| e.to_string())?;
        queryables.push(queryable);
    }
    let (state_tx, states) = bounded(256);
    let _states = session
        .declare_subscriber(keys.state("*", "*"))
        .callback(move |sample| {
            let key = sample.key_expr().as_str().to_string();
            let _ = state_tx.try_send((key, sample.payload().to_bytes().into_owned()));
        })
        .wait()
        .map_err(|e| e.to_string())?;
    let (launcher_tx, launchers) = bounded(64);
    let _launchers = session
        .liveliness()
        .declare_subscriber(keys.launcher("*"))
        .history(true)
        .callback(move |sample| {
            let machine = sample.key_expr().as_str().rsplit('/').next().unwrap_or("");
            let _ = launcher_tx.try_send((sample.kind() == SampleKind::Put, machine.to_string()));
        })
        .wait()
        .map_err(|e| e.to_string())?;
    // Declared last: a launcher that sees the master finds its plan served.
    let _token = session
        .liveliness()
        .declare_token(keys.master())
        .wait()
        .map_err(|e| e.to_string())?;
    println!(
        "master: serving {} (robot {}) at {}; on each machine start `mechweed cluster launcher --machine NAME --connect {}`",
        graph.file, graph.robot, graph.master, graph.master
    );
    let mut table = Table {
        reports: BTreeMap::new(),
        launchers: BTreeSet::new(),
        holders: BTreeMap::new(),
    };
    while !stop.load(Ordering::Relaxed) {
        table.follow_launchers(graph, &launchers);
        table.take_reports(graph, &keys, &states);
        while let Ok(query) = queries.try_recv() {
            let key = query.key_expr().as_str().to_string();
            let result = match key.rsplit_once("/plan/") {
                Some((_, machine)) => {
                    let asker = crate::bus::inbox::requester(&query);
                    (table.admit(&session, machine, &asker)).and_then(|()| plan(graph, machine))
                }
                None if key == keys.states() => Ok(table.states(graph)),
                None => Ok(table.status(graph)),
            };
            answer(&query, result);
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    drop(queryables);
    stop_cluster(&session, graph, &keys, &table.launchers);
    Ok(())
}

impl Table {
    /// Whether the launcher of session `asker` may have `machine`'s plan: not while
    /// another launcher of that machine, which took it first, is linked.
    fn admit(&mut self, session: &Session, machine: &str, asker: &str) -> Result<(), String> {
        // A launcher that does not name its session (an older one) is taken as before.
        if asker.is_empty() {
            return Ok(());
        }
        if let Some((holder, since)) = self.holders.get(machine)
            && holder != asker
            && session
                .info()
                .peers_zid()
                .wait()
                .any(|z| z.to_string() == *holder)
        {
            let why = format!(
                "a launcher of {machine} runs already (session {holder}, which took the plan {:.0} s ago): one launcher for each machine; stop that one first",
                since.elapsed().as_secs_f64()
            );
            eprintln!("master: a second launcher of {machine} (session {asker}) refused: {why}");
            return Err(why);
        }
        let taken = (asker.to_string(), Instant::now());
        self.holders.insert(machine.to_string(), taken);
        Ok(())
    }

    /// Launchers that came or went, of the graph's machines only (whoever declares a
    /// launcher's token).
    fn follow_launchers(&mut self, graph: &Graph, launchers: &Receiver<(bool, String)>) {
        while let Ok((present, machine)) = launchers.try_recv() {
            // The table holds the graph's machines only, whoever declares a token.
            if graph.machine(&machine).is_none() {
                continue;
            }
            let word = if present { "is there" } else { "went away" };
            println!("master: the launcher of {machine} {word}");
            if present {
                self.launchers.insert(machine);
            } else {
                self.launchers.remove(&machine);
            }
        }
    }

    /// The processes' state reports, each taken only from its own machine's key.
    fn take_reports(&mut self, graph: &Graph, keys: &Keys, states: &Receiver<(String, Vec<u8>)>) {
        while let Ok((key, bytes)) = states.try_recv() {
            match serde_json::from_slice::<ProcessReport>(&bytes) {
                Ok(report) if reports_itself(graph, keys, &key, &report) => self.note(report),
                Ok(report) => eprintln!(
                    "master: a state report on {key} for {} on {} refused: a launcher reports its own machine's processes of the graph, on their own key",
                    report.process, report.machine
                ),
                Err(e) => eprintln!("master: a state report that cannot be read ({e})"),
            }
        }
    }
}

/// Whether `report` came on its own process's key and names a process of the graph on
/// its machine: the access rules let a launcher publish only its own machine's keys,
/// and this keeps a report from speaking for another (and the table to the graph).
fn reports_itself(graph: &Graph, keys: &Keys, key: &str, report: &ProcessReport) -> bool {
    key == keys.state(&report.machine, &report.process)
        && graph
            .process(&report.process)
            .is_some_and(|p| p.machine == report.machine)
}

fn plan(graph: &Graph, machine: &str) -> Result<Value, String> {
    let names: Vec<&str> = graph.machines.iter().map(|m| m.name.as_str()).collect();
    let plan = for_machine(graph, machine).ok_or_else(|| {
        format!(
            "{} has no machine '{machine}' (its machines: {})",
            graph.file,
            names.join(", ")
        )
    })?;
    serde_json::to_value(plan).map_err(|e| e.to_string())
}

impl Table {
    /// A launcher's report; a change of state is said on the console.
    fn note(&mut self, report: ProcessReport) {
        let id = (report.machine.clone(), report.process.clone());
        let changed = self
            .reports
            .get(&id)
            .is_none_or(|old| (&old.state, old.restarts) != (&report.state, report.restarts));
        if changed {
            let exit = report
                .exit
                .as_ref()
                .filter(|_| report.state == "exited" || report.state == "stopped")
                .map(|e| format!(" ({e})"))
                .unwrap_or_default();
            println!(
                "master: {} on {}: {}{exit}",
                report.process, report.machine, report.state
            );
        }
        self.reports.insert(id, report);
    }

    /// Each process's machine, name and state, for the launchers: a launcher may hold
    /// any machine's identity's key, so it sees no command line (nor its tokens).
    fn states(&self, graph: &Graph) -> Value {
        let processes: Vec<Value> = (graph.processes.iter())
            .map(|p| {
                let id = (p.machine.clone(), p.name.clone());
                let state = self
                    .reports
                    .get(&id)
                    .map_or("not reported", |r| r.state.as_str());
                json!({"machine": p.machine, "process": p.name, "state": state})
            })
            .collect();
        json!({ "processes": processes })
    }

    /// The whole cluster, for `cluster status`.
    fn status(&self, graph: &Graph) -> Value {
        let machines: Vec<Value> = graph
            .machines
            .iter()
            .map(|m| json!({"name": m.name, "endpoint": m.endpoint, "launcher": self.launchers.contains(&m.name)}))
            .collect();
        let processes: Vec<Value> = graph
            .processes
            .iter()
            .map(|p| {
                let id = (p.machine.clone(), p.name.clone());
                match self.reports.get(&id) {
                    Some(report) => json!(report),
                    None => json!({"machine": p.machine, "process": p.name, "state": "not reported",
                                   "exit": null, "restarts": 0, "pid": null, "command": p.program.name()}),
                }
            })
            .collect();
        let flows: Vec<Value> = graph
            .flows
            .iter()
            .map(|f| {
                let to: Vec<String> = f.to.iter().map(ToString::to_string).collect();
                json!({"name": f.name, "from": f.from.to_string(), "to": to, "key": f.key})
            })
            .collect();
        json!({
            "graph": graph.file,
            "robot": graph.robot,
            "master": graph.master,
            "controller": graph.controller().map(|c| c.name.clone()),
            "controller_endpoint": graph.controller_endpoint(),
            "machines": machines,
            "processes": processes,
            "flows": flows,
        })
    }
}

/// Stop the controller first, then every other process, and end the launchers.
fn stop_cluster(session: &Session, graph: &Graph, keys: &Keys, present: &BTreeSet<String>) {
    println!("master: stopping the cluster, the controller first");
    let say = |machine: &str, result: Result<Value, String>| match result {
        Ok(answer) => {
            for stopped in answer["stopped"].as_array().into_iter().flatten() {
                println!(
                    "master: {} on {machine} stopped ({})",
                    stopped["process"].as_str().unwrap_or("?"),
                    stopped["exit"].as_str().unwrap_or("?")
                );
            }
        }
        Err(why) => println!("master: the launcher of {machine} did not stop: {why}"),
    };
    let controller = graph.controller();
    if let Some(c) = controller
        && present.contains(&c.machine)
    {
        let asked = json!({"stop": c.name});
        say(
            &c.machine,
            ask(session, &keys.stop(&c.machine), Some(asked), STOP_WAIT),
        );
    }
    // The controller's machine last: the others' programs were its clients.
    let mut machines: Vec<&str> = graph.machines.iter().map(|m| m.name.as_str()).collect();
    machines.sort_by_key(|m| controller.is_some_and(|c| c.machine == *m));
    for machine in machines {
        if !present.contains(machine) {
            println!("master: no launcher on {machine}: nothing to stop there");
            continue;
        }
        let asked = json!({"stop": "*", "exit": true});
        say(
            machine,
            ask(session, &keys.stop(machine), Some(asked), STOP_WAIT),
        );
    }
    println!("master: the cluster is stopped");
}
