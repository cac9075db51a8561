//! `mechweed cluster launcher --machine NAME`: asks the master for this machine's
//! processes, starts them, reports each one's state (a flow, and a liveliness token
//! per state), restarts those the graph says to restart, and stops them when the
//! master says stop, when the master goes away and the graph says stop, or at Ctrl-C:
//! the controller first, so that the robot is in safe outputs before anything else
//! ends.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, bounded};
use serde_json::{Value, json};
use zenoh::liveliness::LivelinessToken;
use zenoh::query::Query;
use zenoh::sample::SampleKind;
use zenoh::{Session, Wait};

use super::admit::Admission;
use super::child::Child;
use super::plan::Plan;
use super::{Keys, answer, ask};
use crate::bus::session::{Role, open};
use crate::config::TlsFiles;
use crate::console::systemd;

/// How long a process has to end after SIGTERM before it is killed.
const STOP_PATIENCE: Duration = Duration::from_secs(10);
/// States are published when they change and this often besides, so that a master
/// started (or restarted) later learns them.
const REPORT_EVERY: Duration = Duration::from_secs(1);
const LOOK_EVERY: Duration = Duration::from_millis(50);

/// Run the launcher of `machine` until the master says stop, or Ctrl-C (`stop`); as
/// the identity `tls` names on a secured cluster (it must be `machine`'s launcher), and
/// running only what `admission` lets run.
pub fn run(
    machine: &str,
    master: &str,
    robot: &str,
    tls: Option<&TlsFiles>,
    admission: &Admission,
    stop: &Arc<AtomicBool>,
) -> Result<(), String> {
    let keys = Keys::new(robot);
    crate::bus::session::check_robot(tls, robot)?;
    let session = open(
        Role::Tool {
            connect: vec![master.to_string()],
            wait: true,
        },
        tls,
    )
    .map_err(|e| e.to_string())?;
    let _token = session
        .liveliness()
        .declare_token(keys.launcher(machine))
        .wait()
        .map_err(|e| e.to_string())?;
    // Under systemd: up once its session is open; the watchdog is fed from its loops.
    systemd::notify(&format!(
        "READY=1\nSTATUS=waiting for the master's plan at {master}"
    ));
    let Some(plan) = fetch_plan(&session, &keys, machine, master, tls.is_some(), stop)? else {
        return Ok(());
    };
    // Everything that can fail before the first process starts: an error after it would
    // leave that process behind.
    let (query_tx, queries) = bounded::<Query>(16);
    let _stop_queryable = session
        .declare_queryable(keys.stop(machine))
        .callback(move |q| {
            let _ = query_tx.try_send(q);
        })
        .wait()
        .map_err(|e| e.to_string())?;
    let (masters, _watching) = watch_master(&session, &keys)?;
    let mechweed =
        std::env::current_exe().map_err(|e| format!("cannot find this program's own path: {e}"))?;
    let children = start_children(&plan, machine, admission, &mechweed);
    let mut launcher = Launcher {
        machine: machine.to_string(),
        keys,
        session,
        children,
        tokens: BTreeMap::new(),
    };
    launcher.report_all();
    systemd::notify(&format!(
        "STATUS=running the plan: {} processes",
        launcher.children.len()
    ));
    let why = launcher.watch(&queries, &masters, &plan, stop);
    println!("launcher {machine}: {why}: stopping its processes, the controller first");
    systemd::notify(&format!("STOPPING=1\nSTATUS=stopping: {why}"));
    launcher.stop_all();
    Ok(())
}

/// The plan's processes as this launcher's children, the controller first (the other
/// programs connect to it): each admitted one started unless it waits for others or is
/// started by hand (said with its command line), each refused one said with why.
fn start_children(
    plan: &Plan,
    machine: &str,
    admission: &Admission,
    mechweed: &Path,
) -> Vec<Child> {
    let mut children: Vec<Child> = plan
        .processes
        .iter()
        .map(|launch| match admission.admit(launch.clone()) {
            Ok(admitted) => Child::new(admitted, mechweed),
            Err(why) => {
                eprintln!("launcher {machine}: {why}");
                Child::refused(launch.clone(), mechweed, why)
            }
        })
        .collect();
    children.sort_by_key(|c| !c.launch.controller);
    println!(
        "launcher {machine}: {} process(es) from {}",
        children.len(),
        plan.graph
    );
    for child in &mut children {
        match child.state {
            "manual" => println!(
                "launcher {machine}: {} is started by hand: {}",
                child.launch.name,
                child.launch.command_line()
            ),
            "waiting" => println!(
                "launcher {machine}: {} starts once {} run(s)",
                child.launch.name,
                child.launch.after.join(", ")
            ),
            "refused" => {}
            _ => start(child, machine),
        }
    }
    children
}

fn start(child: &mut Child, machine: &str) {
    if let Err(why) = child.start() {
        eprintln!("launcher {machine}: {why}");
        child.state = "exited";
        child.exit = Some(why);
    }
}

/// Ask the master for this machine's plan until it answers; None: Ctrl-C came first.
fn fetch_plan(
    session: &Session,
    keys: &Keys,
    machine: &str,
    master: &str,
    secured: bool,
    stop: &AtomicBool,
) -> Result<Option<Plan>, String> {
    let mut said = false;
    while !stop.load(Ordering::Relaxed) {
        systemd::notify("WATCHDOG=1");
        match ask(session, &keys.plan(machine), None, Duration::from_secs(2)) {
            Ok(json) => {
                return serde_json::from_value(json)
                    .map(Some)
                    .map_err(|e| format!("the master's plan cannot be read: {e}"));
            }
            // The master answered, and said no (a machine it does not know).
            Err(why) if !why.starts_with("no answer") => return Err(why),
            Err(_) if !said => {
                println!(
                    "launcher {machine}: waiting for the master at {master}{}",
                    if secured {
                        " (a plan is taken only from the master's identity of this cluster's authority: a program there without it gets no hearing)"
                    } else {
                        ""
                    }
                );
                said = true;
            }
            Err(_) => std::thread::sleep(Duration::from_millis(500)),
        }
    }
    Ok(None)
}

/// The master's token coming (true) and going (false).
type Watch = (Receiver<bool>, zenoh::pubsub::Subscriber<()>);

fn watch_master(session: &Session, keys: &Keys) -> Result<Watch, String> {
    let (tx, rx) = bounded(16);
    let subscriber = session
        .liveliness()
        .declare_subscriber(keys.master())
        .history(true)
        .callback(move |sample| {
            let _ = tx.try_send(sample.kind() == SampleKind::Put);
        })
        .wait()
        .map_err(|e| e.to_string())?;
    Ok((rx, subscriber))
}

struct Launcher {
    machine: String,
    keys: Keys,
    session: Session,
    children: Vec<Child>,
    /// Each process's token, for the state it is in.
    tokens: BTreeMap<String, (String, LivelinessToken)>,
}

impl Launcher {
    /// Watch the processes until a reason to stop them all, which it returns.
    fn watch(
        &mut self,
        queries: &Receiver<Query>,
        masters: &Receiver<bool>,
        plan: &Plan,
        stop: &AtomicBool,
    ) -> String {
        let mut reported = Instant::now();
        loop {
            if stop.load(Ordering::Relaxed) {
                return crate::console::stop_request()
                    .unwrap_or("a stop request")
                    .to_string();
            }
            for i in 0..self.children.len() {
                if self.children[i].poll() {
                    self.report(i);
                }
            }
            while let Ok(query) = queries.try_recv() {
                if self.serve(&query) {
                    return "the master stopped the cluster".to_string();
                }
            }
            while let Ok(present) = masters.try_recv() {
                match (present, plan.stop_when_master_lost) {
                    (true, _) => println!("launcher {}: the master is there", self.machine),
                    (false, true) => {
                        return "the master went away ([cluster] master_lost = stop)".to_string();
                    }
                    (false, false) => println!(
                        "launcher {}: the master went away; the processes run on ([cluster] master_lost = run_on)",
                        self.machine
                    ),
                }
            }
            if reported.elapsed() >= REPORT_EVERY {
                systemd::notify("WATCHDOG=1");
                self.start_those_due();
                self.report_all();
                reported = Instant::now();
            }
            std::thread::sleep(LOOK_EVERY);
        }
    }

    /// Start the processes waiting for others once those run (the master knows).
    fn start_those_due(&mut self) {
        if !self.children.iter().any(|c| c.state == "waiting") {
            return;
        }
        let Ok(cluster) = ask(
            &self.session,
            &self.keys.states(),
            None,
            Duration::from_secs(1),
        ) else {
            return;
        };
        let runs = |name: &str| {
            cluster["processes"]
                .as_array()
                .into_iter()
                .flatten()
                .any(|p| {
                    p["process"] == name && (p["state"] == "running" || p["state"] == "restarted")
                })
        };
        for child in &mut self.children {
            if child.state == "waiting" && child.launch.after.iter().all(|a| runs(a)) {
                start(child, &self.machine);
            }
        }
    }

    /// A stop query: `{"stop": NAME or "*", "exit": true}`. True if the launcher is to
    /// end (after answering).
    fn serve(&mut self, query: &Query) -> bool {
        let payload = query.payload().map(|p| p.to_bytes().into_owned());
        let asked: Value = payload
            .and_then(|p| serde_json::from_slice(&p).ok())
            .unwrap_or_default();
        let which = asked["stop"].as_str().unwrap_or("").to_string();
        let exit = asked["exit"].as_bool() == Some(true);
        if which.is_empty() && !exit {
            answer(
                query,
                Err("say {\"stop\": PROCESS or \"*\"} and/or {\"exit\": true}".into()),
            );
            return false;
        }
        let known = which.is_empty()
            || which == "*"
            || self.children.iter().any(|c| c.launch.name == which);
        if !known {
            answer(
                query,
                Err(format!("no process '{which}' on {}", self.machine)),
            );
            return false;
        }
        let mut stopped = Vec::new();
        for i in self.order() {
            let name = self.children[i].launch.name.clone();
            let running = self.children[i].pid().is_some();
            if (which == "*" && running) || which == name {
                let how = self.children[i].stop(STOP_PATIENCE);
                println!("launcher {}: {name} stopped ({how})", self.machine);
                self.report(i);
                stopped.push(json!({"process": name, "exit": how}));
            }
        }
        answer(query, Ok(json!({ "stopped": stopped })));
        exit
    }

    /// The children's indices, the controller first.
    fn order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.children.len()).collect();
        order.sort_by_key(|&i| !self.children[i].launch.controller);
        order
    }

    fn stop_all(&mut self) {
        for i in self.order() {
            if self.children[i].pid().is_some() {
                let how = self.children[i].stop(STOP_PATIENCE);
                let name = &self.children[i].launch.name;
                println!("launcher {}: {name} stopped ({how})", self.machine);
                self.report(i);
            }
        }
    }

    fn report_all(&mut self) {
        for i in 0..self.children.len() {
            self.report(i);
        }
    }

    /// Publish child `i`'s state, and hold the token of that state.
    fn report(&mut self, i: usize) {
        let report = self.children[i].report(&self.machine);
        let key = self.keys.state(&self.machine, &report.process);
        let json = serde_json::to_string(&report).unwrap_or_default();
        if let Err(e) = self.session.put(&key, json).wait() {
            eprintln!("launcher {}: cannot publish {key}: {e}", self.machine);
        }
        let token_key = self
            .keys
            .process_token(&self.machine, &report.process, &report.state);
        let same = self
            .tokens
            .get(&report.process)
            .is_some_and(|(held, _)| *held == token_key);
        if !same {
            // The old state's token goes with the old value.
            self.tokens.remove(&report.process);
            match self.session.liveliness().declare_token(&token_key).wait() {
                Ok(token) => {
                    self.tokens
                        .insert(report.process.clone(), (token_key, token));
                }
                Err(e) => eprintln!("launcher {}: cannot declare a token: {e}", self.machine),
            }
        }
    }
}
