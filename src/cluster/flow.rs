//! A graph's `[flow NAME]` sections: which process's output feeds which inputs, each end
//! a port its program has, the two ends carrying the same kind of message, and the bus
//! key the flow travels on.

use std::collections::BTreeSet;

use super::graph::{End, Flow, Process, listed};
use super::program::{Direction, Program};
use crate::config::Reader;

/// `PROCESS.PORT`, a process of the graph and a port its program has in `direction`.
fn end(text: &str, processes: &[Process], direction: Direction) -> Result<End, String> {
    let Some((process, port)) = text.trim().split_once('.') else {
        return Err(format!(
            "'{text}' is not PROCESS.PORT, for example camera.rows"
        ));
    };
    let Some(found) = processes.iter().find(|p| p.name == process) else {
        let names: Vec<String> = processes.iter().map(|p| p.name.clone()).collect();
        return Err(format!(
            "'{process}' is not a process of this graph (its processes: {})",
            listed(&names)
        ));
    };
    found.program.check_port(port, direction)?;
    Ok(End {
        process: process.to_string(),
        port: port.to_string(),
    })
}

pub(super) fn flow(r: &mut Reader, name: &str, processes: &[Process], robot: &str) -> Option<Flow> {
    let s = format!("flow {name}");
    let from = r.parsed(&s, "from", |t| end(t, processes, Direction::Out));
    let to = r.parsed(&s, "to", |text| {
        let ends: Vec<End> = text
            .split(',')
            .map(|t| end(t, processes, Direction::In))
            .collect::<Result<_, _>>()?;
        let mut seen = BTreeSet::new();
        match ends.iter().find(|e| !seen.insert(e.to_string())) {
            Some(again) => Err(format!("{again} is named twice")),
            None => Ok(ends),
        }
    });
    let (from, to) = (from?, to?);
    let program = |end: &End| {
        processes
            .iter()
            .find(|p| p.name == end.process)
            .map(|p| &p.program)
    };
    for receiver in &to {
        if let (Some(a), Some(b)) = (program(&from), program(receiver))
            && let Err(why) = Program::check_link(a, &from.port, b, &receiver.port)
        {
            r.error_at(&s, "to", format!("{from} -> {receiver}: {why}"));
            return None;
        }
    }
    let key = Program::key(robot, &from.process, &from.port);
    Some(Flow {
        name: name.to_string(),
        from,
        to,
        key,
    })
}
