//! `mechweed cluster status`: the cluster as the master knows it (machines, their
//! launchers, processes and their states), each flow's rate, counted where the flows
//! are: at the controller's endpoint, not at the master; and what each receiver says it
//! gets, as the controller's status names them.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use zenoh::Wait;

use super::{Keys, ask};
use crate::bus::session::{Role, open};

/// The master's view of the cluster, with `rates` (messages per second of each flow
/// over `seconds`) added.
pub(crate) fn fetch(
    master: &str,
    robot: &str,
    seconds: f64,
    tls: Option<&crate::config::TlsFiles>,
) -> Result<Value, String> {
    let session = open(
        Role::Tool {
            connect: vec![master.to_string()],
            wait: false,
        },
        tls,
    )
    .map_err(|_| {
        format!(
            "no cluster master answers at {master} (is `mechweed cluster master GRAPH` running there, with this [cluster] master?)"
        )
    })?;
    let keys = Keys::new(robot);
    let mut status =
        ask(&session, &keys.status(), None, Duration::from_secs(3)).map_err(|why| {
            format!("the cluster master of robot '{robot}' at {master} does not answer: {why}")
        })?;
    (status["rates"], status["receivers"]) = match status["controller_endpoint"].as_str() {
        Some(endpoint) => match rates(endpoint, &status, seconds, tls) {
            Ok((rates, receivers)) => (json!(rates), receivers),
            Err(why) => (json!({ "error": why }), Value::Null),
        },
        None => (
            json!({ "error": "the graph has no controller" }),
            Value::Null,
        ),
    };
    Ok(status)
}

/// Each flow's rate over `seconds`, counted at the controller's `endpoint`: a flow out
/// of the controller by its messages; the rows into it by the frames its camera link
/// took (from its status); any other flow does not pass the controller and is not
/// counted (its reason instead of a number). With the receivers the controller's newest
/// status names.
fn rates(
    endpoint: &str,
    status: &Value,
    seconds: f64,
    tls: Option<&crate::config::TlsFiles>,
) -> Result<(BTreeMap<String, Value>, Value), String> {
    let session = open(
        Role::Tool {
            connect: vec![endpoint.to_string()],
            wait: false,
        },
        tls,
    )
    .map_err(|e| format!("the controller's endpoint cannot be reached: {e}"))?;
    let controller = status["controller"].as_str().unwrap_or_default();
    let robot = status["robot"].as_str().unwrap_or_default();
    let (tx, rx) = crossbeam_channel::bounded::<(String, Vec<u8>)>(4096);
    let (mut subscribers, mut rates, rows_flow) = counted_flows(status, controller);
    // The controller's status, for the frames its camera link took.
    subscribers.push((String::new(), format!("{robot}/status")));
    let mut held = Vec::new();
    for (name, key) in subscribers {
        let tx = tx.clone();
        let subscriber = session
            .declare_subscriber(key)
            .callback(move |sample| {
                let _ = tx.try_send((name.clone(), sample.payload().to_bytes().into_owned()));
            })
            .wait()
            .map_err(|e| e.to_string())?;
        held.push(subscriber);
    }
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    let (mut first, mut last) = (None, None);
    let mut receivers = Value::Null;
    while let Ok((name, bytes)) = rx.recv_deadline(end) {
        if let Some(Value::Number(n)) = rates.get_mut(&name) {
            *n = serde_json::Number::from_f64(n.as_f64().unwrap_or(0.0) + 1.0).unwrap_or(0.into());
        }
        if name.is_empty() {
            let status: Value = serde_json::from_slice(&bytes).unwrap_or_default();
            receivers = status["bus"]["receivers"].clone();
            let frames = status["camera"]["counters"]["frames_ok"].as_f64();
            if let (Some(t_s), Some(frames)) = (status["t_s"].as_f64(), frames) {
                first.get_or_insert((t_s, frames));
                last = Some((t_s, frames));
            }
        }
    }
    for rate in rates.values_mut() {
        if let Some(n) = rate.as_f64() {
            *rate = json!(n / seconds.max(1e-3));
        }
    }
    if let Some(name) = rows_flow {
        let rate = match (first, last) {
            (Some((t0, f0)), Some((t1, f1))) if t1 > t0 => json!((f1 - f0) / (t1 - t0)),
            _ => json!("not counted: no status from the controller"),
        };
        rates.insert(name, rate);
    }
    Ok((rates, receivers))
}

/// Which of the graph's flows can be counted at the controller's endpoint: the
/// subscriptions (flow name, key) for the flows out of the controller, each flow's rate
/// so far (0, or why it is not counted), and the flow of rows into it (counted from
/// the controller's status instead).
#[allow(clippy::type_complexity)]
fn counted_flows(
    status: &Value,
    controller: &str,
) -> (
    Vec<(String, String)>,
    BTreeMap<String, Value>,
    Option<String>,
) {
    let mut subscribers = Vec::new();
    let mut rates = BTreeMap::new();
    let flows: Vec<&Value> = status["flows"].as_array().into_iter().flatten().collect();
    let mut rows_flow = None;
    for flow in &flows {
        let name = flow["name"].as_str().unwrap_or_default().to_string();
        let from = flow["from"].as_str().unwrap_or_default();
        let into_rows = flow["to"]
            .as_array()
            .into_iter()
            .flatten()
            .any(|t| t.as_str() == Some(&format!("{controller}.rows")));
        if from.split('.').next() == Some(controller) {
            let key = flow["key"].as_str().unwrap_or_default().to_string();
            subscribers.push((name.clone(), key));
            rates.insert(name, json!(0.0));
        } else if into_rows {
            rows_flow = Some(name);
        } else if from.ends_with(".requests") {
            let why = "not counted: requests are questions, each answered on its own";
            rates.insert(name, json!(why));
        } else {
            rates.insert(
                name,
                json!("not counted: it does not pass through the controller's endpoint"),
            );
        }
    }
    (subscribers, rates, rows_flow)
}

/// The status as text for a person.
pub fn text(status: &Value) -> String {
    let s = |v: &Value| v.as_str().unwrap_or("?").to_string();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "cluster of robot {} from {} (master at {})",
        s(&status["robot"]),
        s(&status["graph"]),
        s(&status["master"])
    );
    out.push_str("machines:\n");
    for m in status["machines"].as_array().into_iter().flatten() {
        let launcher = if m["launcher"].as_bool() == Some(true) {
            "launcher there"
        } else {
            "NO LAUNCHER"
        };
        let _ = writeln!(
            out,
            "  {:<10} {:<24} {launcher}",
            s(&m["name"]),
            s(&m["endpoint"])
        );
    }
    out.push_str("processes:\n");
    for p in status["processes"].as_array().into_iter().flatten() {
        let pid = p["pid"]
            .as_u64()
            .map_or(String::new(), |pid| format!("pid {pid}"));
        let exit = p["exit"]
            .as_str()
            .map_or(String::new(), |e| format!(", last exit: {e}"));
        let _ = writeln!(
            out,
            "  {:<14} {:<10} {:<11} {:<10} restarts {}{exit}",
            s(&p["process"]),
            s(&p["machine"]),
            s(&p["state"]),
            pid,
            p["restarts"].as_u64().unwrap_or(0)
        );
    }
    out.push_str("flows:\n");
    let rates = &status["rates"];
    for f in status["flows"].as_array().into_iter().flatten() {
        let to: Vec<String> = f["to"].as_array().into_iter().flatten().map(&s).collect();
        let rate = &rates[s(&f["name"])];
        let rate = match (rate.as_f64(), rate.as_str()) {
            (Some(r), _) => format!("{r:.1} per s"),
            (None, Some(why)) => why.to_string(),
            (None, None) => "?".to_string(),
        };
        let _ = writeln!(
            out,
            "  {:<10} {:<22} {rate}\n             {} -> {}",
            s(&f["name"]),
            s(&f["key"]),
            s(&f["from"]),
            to.join(", ")
        );
    }
    if let Some(why) = rates["error"].as_str() {
        let _ = writeln!(out, "  (rates not counted: {why})");
    }
    receivers_text(&status["receivers"], &mut out);
    out
}

/// What each receiver says it gets: "watch-4242 (watch): status 0.1 s old, 5120
/// messages, 0 dropped there, 0 under the wrong key, session opened again 0 times".
fn receivers_text(receivers: &Value, out: &mut String) {
    let Some(receivers) = receivers.as_array() else {
        out.push_str("receivers: not known (no status from the controller)\n");
        return;
    };
    out.push_str("receivers (as each says, about once a second):\n");
    if receivers.is_empty() {
        out.push_str("  none\n");
    }
    for r in receivers {
        let report = &r["report"];
        let n = |key: &str| report[key].as_u64().unwrap_or(0);
        let age = report["status_age_s"]
            .as_f64()
            .map_or("no status yet".to_string(), |s| {
                format!("newest status {s:.1} s old")
            });
        let _ = writeln!(
            out,
            "  {} ({}): {age}, {} messages, {} dropped there, {} under the wrong key, session opened again {} times (said {:.1} s ago)",
            r["name"].as_str().unwrap_or("?"),
            report["program"].as_str().unwrap_or("?"),
            n("received"),
            n("dropped_here"),
            n("wrong_key"),
            n("reopened"),
            r["reported_s_ago"].as_f64().unwrap_or(0.0)
        );
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_process_s_restarts_and_its_last_exit_are_two_things() {
        let status = serde_json::json!({
            "processes": [{"process": "camsim", "machine": "camera", "state": "running",
                           "pid": 42, "restarts": 1, "exit": "killed by SIGKILL"}],
        });
        let said = super::text(&status);
        assert!(
            said.contains("restarts 1, last exit: killed by SIGKILL"),
            "{said}"
        );
    }

    #[test]
    fn each_receiver_is_shown_with_what_it_says_it_gets() {
        let status = serde_json::json!({
            "receivers": [{"name": "watch-77", "reported_s_ago": 0.4, "report": {
                "program": "watch", "status_age_s": 0.1, "received": 5120,
                "dropped_here": 2, "wrong_key": 3, "reopened": 1}}],
        });
        let said = super::text(&status);
        assert!(
            said.contains("watch-77 (watch): newest status 0.1 s old, 5120 messages, 2 dropped there, 3 under the wrong key, session opened again 1 times (said 0.4 s ago)"),
            "{said}"
        );
        let unknown = super::text(&serde_json::json!({}));
        assert!(unknown.contains("receivers: not known"), "{unknown}");
    }
}
