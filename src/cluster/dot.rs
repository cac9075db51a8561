//! `mechweed cluster dot GRAPH`: the graph as a Graphviz picture (DOT), one box per
//! machine with its processes, an arrow per flow, and the master's control links
//! dashed (they carry no data).

use std::fmt::Write as _;

use super::graph::{Graph, Start};

/// A name as a DOT string.
fn quoted(text: &str) -> String {
    let escaped = text
        .replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n");
    format!("\"{escaped}\"")
}

pub(crate) fn dot(graph: &Graph) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "digraph {} {{", quoted(&graph.robot));
    out.push_str("  rankdir=LR;\n  node [shape=box, style=rounded, fontname=\"Helvetica\"];\n");
    out.push_str("  edge [fontname=\"Helvetica\", fontsize=10];\n");
    let _ = writeln!(
        out,
        "  master [label={}, shape=ellipse, style=dashed];",
        quoted(&format!(
            "master\n{}\n(control only: no data)",
            graph.master
        ))
    );
    for (i, machine) in graph.machines.iter().enumerate() {
        let _ = writeln!(out, "  subgraph cluster_{i} {{");
        let _ = writeln!(
            out,
            "    label={};",
            quoted(&format!("{}  {}", machine.name, machine.endpoint))
        );
        let launcher = format!("launcher {}", machine.name);
        let _ = writeln!(
            out,
            "    {} [label=\"launcher\", shape=plaintext];",
            quoted(&launcher)
        );
        for p in graph.processes.iter().filter(|p| p.machine == machine.name) {
            let how = match (p.start, p.restart) {
                (Start::Manual, _) => "\n(started by hand)",
                (Start::Auto, true) => "\n(restarted if it exits)",
                (Start::Auto, false) => "",
            };
            let after = if p.after.is_empty() {
                String::new()
            } else {
                format!("\n(starts after {})", p.after.join(", "))
            };
            let label = format!("{}\n{}{how}{after}", p.name, p.program.name());
            let _ = writeln!(out, "    {} [label={}];", quoted(&p.name), quoted(&label));
        }
        out.push_str("  }\n");
        let _ = writeln!(
            out,
            "  master -> {} [style=dashed, arrowhead=none, color=gray];",
            quoted(&launcher)
        );
    }
    // One arrow per pair of processes, naming every flow between them.
    let mut arrows: Vec<((&str, &str), Vec<String>)> = Vec::new();
    for flow in &graph.flows {
        for to in &flow.to {
            let label = if flow.from.port == to.port {
                flow.from.port.clone()
            } else {
                format!("{} -> {}", flow.from.port, to.port)
            };
            let pair = (flow.from.process.as_str(), to.process.as_str());
            match arrows.iter_mut().find(|(p, _)| *p == pair) {
                Some((_, labels)) => labels.push(label),
                None => arrows.push((pair, vec![label])),
            }
        }
    }
    for ((from, to), labels) in arrows {
        let _ = writeln!(
            out,
            "  {} -> {} [label={}];",
            quoted(from),
            quoted(to),
            quoted(&labels.join(", "))
        );
    }
    out.push_str("}\n");
    out
}
