//! The layers point one way (docs/architecture.md): this test reads the source and
//! fails where a module reaches up. Two rules:
//! - only the operator interfaces and the programs that start a run may use `run`;
//! - no two top-level modules import each other, directly or round a circle
//!   (the GUI's panels may use each other: gui/ counts as one module).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The modules that sit above run.rs: they start a run or operate one.
const ABOVE_RUN: &[&str] = &["main", "console", "gui", "bench_loop", "report", "lib"];

/// Top-level module -> the top-level modules its files name as `crate::NAME`.
fn imports() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let name = path.file_name().unwrap().to_str().unwrap();
            // Unit tests may drive a module from above (tests.rs, *_tests.rs, and the
            // `#[cfg(test)]` part of a file): they are not the product's layers.
            if !name.ends_with(".rs") || name == "tests.rs" || name.ends_with("_tests.rs") {
                continue;
            }
            let relative = path.strip_prefix(&src).unwrap();
            let first = relative.components().next().unwrap().as_os_str();
            let module = first.to_str().unwrap().trim_end_matches(".rs").to_string();
            let whole = std::fs::read_to_string(&path).unwrap();
            let text = whole.split("#[cfg(test)]").next().unwrap();
            let uses = graph.entry(module.clone()).or_default();
            for (i, _) in text.match_indices("crate::") {
                let rest = &text[i + "crate::".len()..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() && name != module {
                    uses.insert(name);
                }
            }
        }
    }
    graph
}

#[test]
fn nothing_below_run_imports_from_it() {
    let offenders: Vec<String> = imports()
        .into_iter()
        .filter(|(module, uses)| uses.contains("run") && !ABOVE_RUN.contains(&module.as_str()))
        .map(|(module, _)| module)
        .collect();
    assert!(
        offenders.is_empty(),
        "these modules below run.rs import from it: {offenders:?}"
    );
}

#[test]
fn no_module_imports_round_a_circle() {
    let graph = imports();
    // Depth-first search; a module met again while still on the path closes a circle.
    fn visit(
        module: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
        circles: &mut Vec<String>,
    ) {
        if let Some(start) = path.iter().position(|m| m == module) {
            let mut circle = path[start..].to_vec();
            circle.push(module.to_string());
            circles.push(circle.join(" -> "));
            return;
        }
        if !done.insert(module.to_string()) {
            return;
        }
        path.push(module.to_string());
        for next in graph.get(module).into_iter().flatten() {
            if next != "lib" && next != "main" {
                visit(next, graph, path, done, circles);
            }
        }
        path.pop();
    }
    let mut circles = Vec::new();
    let mut done = BTreeSet::new();
    for module in graph.keys() {
        visit(module, &graph, &mut Vec::new(), &mut done, &mut circles);
    }
    assert!(circles.is_empty(), "import circles: {circles:#?}");
}
