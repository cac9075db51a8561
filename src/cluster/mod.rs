//! The virtual cluster: one graph file names the machines of a run, the programs each
//! one runs and the flows between them (`graph`, `program`); a master serves the graph
//! (`master`); a launcher on each machine starts, watches and stops what that machine
//! runs (`launcher`, `child`); `status` prints the whole, `dot` draws it.
//!
//! The master is only in the control path: launchers ask it for their plan (`plan`)
//! and report their processes' states to it, and it says stop. The data flows go from
//! program to program: every mechweed program connects to the controller's endpoint,
//! never through the master, so the robot's Wi-Fi link carries only what must leave
//! the robot.
//!
//! Keys, all under `ROBOT/cluster/`: `master` (the master's liveliness token),
//! `plan/MACHINE` and `status` (the master's queries), `launcher/MACHINE` (a
//! launcher's token), `stop/MACHINE` (a launcher's query), `state/MACHINE/PROCESS` (a
//! flow: each process's state as it changes, and every second) and
//! `process/MACHINE/PROCESS/STATE` (a token while the process is in that state).

pub mod admit;
mod child;
pub mod dot;
mod flow;
pub mod graph;
pub mod launcher;
pub mod master;
pub mod plan;
mod plan_check;
pub mod program;
pub mod status;

#[cfg(test)]
mod tests;

use std::time::Duration;

use serde::{Deserialize, Serialize};
use serde_json::Value;
use zenoh::bytes::Encoding;
use zenoh::query::Query;
use zenoh::{Session, Wait};

/// Where the master listens unless the graph says otherwise, and where launchers and
/// `cluster status` look for it by default.
pub const DEFAULT_MASTER: &str = "tcp/127.0.0.1:7450";

/// The cluster's keys for robot `robot`.
#[derive(Debug, Clone)]
pub struct Keys {
    robot: String,
}

impl Keys {
    pub fn new(robot: &str) -> Keys {
        Keys {
            robot: robot.to_string(),
        }
    }

    fn key(&self, rest: &str) -> String {
        format!("{}/cluster/{rest}", self.robot)
    }

    pub fn master(&self) -> String {
        self.key("master")
    }
    pub fn plan(&self, machine: &str) -> String {
        self.key(&format!("plan/{machine}"))
    }
    pub fn status(&self) -> String {
        self.key("status")
    }
    /// Each process's state alone, for the launchers (no command lines).
    pub fn states(&self) -> String {
        self.key("states")
    }
    pub fn launcher(&self, machine: &str) -> String {
        self.key(&format!("launcher/{machine}"))
    }
    pub fn stop(&self, machine: &str) -> String {
        self.key(&format!("stop/{machine}"))
    }
    pub fn state(&self, machine: &str, process: &str) -> String {
        self.key(&format!("state/{machine}/{process}"))
    }
    pub fn process_token(&self, machine: &str, process: &str, state: &str) -> String {
        self.key(&format!("process/{machine}/{process}/{state}"))
    }
}

/// A process as its launcher reports it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProcessReport {
    pub machine: String,
    pub process: String,
    /// manual (waiting for a person), starting, running, restarted (running again
    /// after an exit), exited, stopped (by the launcher or the master).
    pub state: String,
    /// Its exit: the code, or the signal that ended it, in words.
    pub exit: Option<String>,
    pub restarts: u32,
    pub pid: Option<u32>,
    pub command: String,
}

/// Ask `key` with `payload` and wait at most `wait` for the answer, as JSON.
pub fn ask(
    session: &Session,
    key: &str,
    payload: Option<Value>,
    wait: Duration,
) -> Result<Value, String> {
    // Named, so that the master tells two launchers of one machine apart.
    let mut get = (session.get(key).timeout(wait)).attachment(session.zid().to_string());
    if let Some(payload) = payload {
        get = get.payload(payload.to_string());
    }
    let replies = get.wait().map_err(|e| e.to_string())?;
    let reply = replies
        .recv()
        .map_err(|_| format!("no answer on {key} within {:.0} s", wait.as_secs_f64()))?;
    let (body, ok) = match reply.result() {
        Ok(sample) => (sample.payload().to_bytes().into_owned(), true),
        Err(error) => (error.payload().to_bytes().into_owned(), false),
    };
    let text = String::from_utf8_lossy(&body).into_owned();
    let json: Value = serde_json::from_str(&text)
        .map_err(|e| format!("the answer on {key} is not JSON ({e}): {text}"))?;
    if ok {
        Ok(json)
    } else {
        Err(json["error"].as_str().map_or(text, str::to_string))
    }
}

/// Answer `query` with JSON, or with `{"error": WHY}`.
pub fn answer(query: &Query, result: Result<Value, String>) {
    let sent = match result {
        Ok(json) => query
            .reply(query.key_expr().clone(), json.to_string())
            .encoding(Encoding::APPLICATION_JSON)
            .wait(),
        Err(why) => query
            .reply_err(serde_json::json!({ "error": why }).to_string())
            .encoding(Encoding::APPLICATION_JSON)
            .wait(),
    };
    if let Err(e) = sent {
        eprintln!("cluster: an answer could not be sent: {e}");
    }
}
