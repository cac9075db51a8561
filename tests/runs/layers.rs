//! The layers point one way: this test reads docs/architecture.md's table of folders
//! and the source, and fails where the two disagree.
//! - Every folder and file at the top of each crate's `src/` has a row in the table,
//!   and every row names one that exists.
//! - A folder imports only from folders of a lower layer (its own files aside). Two
//!   folders of one layer import nothing from each other, so no circle can close.
//! - The core builds without the bus or the GUI: neither Zenoh nor egui is among the
//!   packages it depends on, directly or not (Cargo.lock).
//!
//! Unit tests (tests.rs, *_tests.rs, and the `#[cfg(test)]` part of a file) may drive
//! a folder from above: they are not the product's layers.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The three crates' sources, from the bottom up, and how the others name each.
const CRATES: [(&str, &str); 3] = [
    ("hw/src/", "mechweed_hw"),
    ("core/src/", "mechweed_core"),
    ("src/", "mechweed"),
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The table's rows: `| LAYER | `PATH` | what it is |` -> PATH, LAYER.
fn table() -> BTreeMap<String, u32> {
    let text = std::fs::read_to_string(root().join("docs/architecture.md")).unwrap();
    let mut layers = BTreeMap::new();
    for line in text.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 4 {
            continue;
        }
        let (Ok(layer), Some(path)) = (
            cells[1].parse::<u32>(),
            cells[2].strip_prefix('`').and_then(|c| c.strip_suffix('`')),
        ) else {
            continue;
        };
        layers.insert(path.to_string(), layer);
    }
    assert!(
        layers.len() > 20,
        "docs/architecture.md's table of layers has {} rows",
        layers.len()
    );
    layers
}

/// The entries at the top of a crate's src/, as the table names them ("core/src/steer/").
fn entries(src: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for entry in std::fs::read_dir(root().join(src)).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if path.is_dir() {
            found.insert(format!("{src}{name}/"));
        } else if name.ends_with(".rs") && !is_test(&name) && name != "lib.rs" && name != "main.rs"
        {
            found.insert(format!("{src}{name}"));
        }
    }
    found
}

fn is_test(file_name: &str) -> bool {
    file_name == "tests.rs" || file_name.ends_with("_tests.rs")
}

/// The table's entry for module `name` of the crate whose source is `src`, if any:
/// the app's names of the core's modules are the core's.
fn entry_of(src: &str, name: &str, table: &BTreeMap<String, u32>) -> Option<String> {
    let candidates = [format!("{src}{name}/"), format!("{src}{name}.rs")];
    let own = candidates.into_iter().find(|c| table.contains_key(c));
    own.or_else(|| {
        (src == "src/")
            .then(|| entry_of("core/src/", name, table))
            .flatten()
    })
}

/// The modules a text names after `prefix` (`crate::steer::law`, `crate::{steer, gnss}`).
fn named_after(text: &str, prefix: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut names = BTreeSet::new();
    for (i, _) in text.match_indices(prefix) {
        let before = text[..i].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &text[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // The group's items at its own depth: `a::b`, `c::{d, e}`, `f`.
            let mut depth = 0;
            let mut item = String::new();
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        names.insert(ident(&item));
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                item.push(c);
            }
            names.insert(ident(&item));
        } else {
            names.insert(ident(rest));
        }
    }
    names.retain(|n| n.starts_with(|c: char| c.is_ascii_lowercase()));
    names
}

/// Every import from one table entry to another: (from, to).
fn imports(table: &BTreeMap<String, u32>) -> BTreeSet<(String, String)> {
    let mut found = BTreeSet::new();
    for (src, _) in CRATES {
        let mut stack = vec![root().join(src)];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                    continue;
                }
                let name = path.file_name().unwrap().to_str().unwrap();
                if !name.ends_with(".rs") || is_test(name) {
                    continue;
                }
                let Some(from) = owner(src, &path) else {
                    continue;
                };
                let whole = std::fs::read_to_string(&path).unwrap();
                let text = whole.split("#[cfg(test)]").next().unwrap();
                let mut targets = BTreeSet::new();
                for module in named_after(text, "crate::") {
                    targets.extend(entry_of(src, &module, table));
                }
                for (other, crate_name) in CRATES {
                    for module in named_after(text, &format!("{crate_name}::")) {
                        targets.extend(entry_of(other, &module, table));
                    }
                }
                for to in targets.into_iter().filter(|to| *to != from) {
                    found.insert((from.clone(), to));
                }
            }
        }
    }
    found
}

/// The table entry a file belongs to ("core/src/steer/" for core/src/steer/law.rs);
/// None for the crate's root (lib.rs, main.rs).
fn owner(src: &str, file: &Path) -> Option<String> {
    let relative = file.strip_prefix(root().join(src)).unwrap();
    let mut parts = relative.components();
    let first = parts.next()?.as_os_str().to_str()?.to_string();
    if parts.next().is_some() {
        Some(format!("{src}{first}/"))
    } else if first == "lib.rs" || first == "main.rs" {
        None
    } else {
        Some(format!("{src}{first}"))
    }
}

#[test]
fn the_table_of_layers_names_every_folder_and_nothing_else() {
    let table = table();
    let mut missing = Vec::new();
    let mut listed = BTreeSet::new();
    for (src, _) in CRATES {
        for entry in entries(src) {
            if !table.contains_key(&entry) {
                missing.push(entry.clone());
            }
            listed.insert(entry);
        }
    }
    let gone: Vec<&String> = table.keys().filter(|k| !listed.contains(*k)).collect();
    assert!(
        missing.is_empty() && gone.is_empty(),
        "docs/architecture.md's table of layers does not match the folders: \
         not in the table {missing:?}; in the table but not in the source {gone:?}"
    );
}

#[test]
fn every_folder_imports_only_from_the_layers_below_it() {
    let table = table();
    let upward: Vec<String> = imports(&table)
        .into_iter()
        .filter(|(from, to)| table[to] >= table[from])
        .map(|(from, to)| {
            format!(
                "{from} (layer {}) imports {to} (layer {})",
                table[&from], table[&to]
            )
        })
        .collect();
    assert!(
        upward.is_empty(),
        "imports that do not go down a layer (docs/architecture.md):\n{}",
        upward.join("\n")
    );
}

/// The packages a package depends on, directly or not, from Cargo.lock.
fn depends_on(package: &str) -> BTreeSet<String> {
    let lock = std::fs::read_to_string(root().join("Cargo.lock")).unwrap();
    let mut deps: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for block in lock.split("[[package]]").skip(1) {
        let name = block
            .lines()
            .find_map(|l| l.strip_prefix("name = "))
            .unwrap()
            .trim_matches('"')
            .to_string();
        let list: Vec<String> = block
            .split("dependencies = [")
            .nth(1)
            .map(|rest| {
                let list = rest.split(']').next().unwrap();
                let first_word =
                    |item: &str| item.split_whitespace().next().unwrap_or("").to_string();
                list.split(',')
                    .map(|item| first_word(item.trim().trim_matches('"')))
                    .filter(|item| !item.is_empty())
                    .collect()
            })
            .unwrap_or_default();
        deps.entry(name).or_default().extend(list);
    }
    let mut seen = BTreeSet::new();
    let mut stack = vec![package.to_string()];
    while let Some(next) = stack.pop() {
        for dep in deps.get(&next).into_iter().flatten() {
            if seen.insert(dep.clone()) {
                stack.push(dep.clone());
            }
        }
    }
    seen
}

#[test]
fn the_core_builds_without_the_bus_or_the_gui() {
    let core = depends_on("mechweed-core");
    assert!(
        core.contains("mechweed-hw") && core.contains("nalgebra"),
        "{core:?}"
    );
    let heavy: Vec<&String> = core
        .iter()
        .filter(|p| ["zenoh", "egui", "eframe", "winit", "mechweed"].contains(&p.as_str()))
        .collect();
    assert!(heavy.is_empty(), "mechweed-core depends on {heavy:?}");
    let hw = depends_on("mechweed-hw");
    assert!(
        !hw.iter().any(|p| p.starts_with("mechweed")),
        "mechweed-hw depends on {hw:?}"
    );
}

#[test]
fn the_import_reader_sees_every_module_a_use_names() {
    let text = "use crate::steer::law;\nuse crate::{state::modes::Mode, gnss, rt::{self, Periodic}};\n\
                let x = mechweed_core::config::DEFAULT_INI; crate::Hw; notcrate::faults;";
    let names = named_after(text, "crate::");
    let expected: BTreeSet<String> = ["steer", "state", "gnss", "rt"].map(String::from).into();
    assert_eq!(names, expected);
    assert_eq!(
        named_after(text, "mechweed_core::"),
        ["config".to_string()].into()
    );
}
