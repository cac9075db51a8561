//! Everything a user or contributor needs is inside the project: no file may point to a
//! document the project does not have (a `*.md` named anywhere must be one of the
//! project's), to a folder outside it (`../`, `shared/`), and no link in the project's
//! Markdown may lead to a file that is not there.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Folders that are not the project's own text: build output, records of runs, git.
const SKIP: &[&str] = &["target", ".git", "records", "corpus", "artifacts"];
/// Files whose text is not ours or not text.
const TEXT: &[&str] = &[
    "rs", "md", "ini", "toml", "sh", "txt", "yml", "yaml", "jsonl",
];

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            if !SKIP.contains(&name.as_str()) {
                files(&path, out);
            }
        } else if name != "Cargo.lock" {
            out.push(path);
        }
    }
}

fn project() -> (PathBuf, Vec<PathBuf>) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut all = Vec::new();
    files(&root, &mut all);
    all.push(root.join(".ci/run"));
    (root, all)
}

/// Words of a text as a reader would pick out file names: letters, digits and `_.-/`.
fn names(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || "_.-/".contains(c)))
        .map(|w| w.trim_end_matches('.'))
}

#[test]
fn no_file_names_a_document_or_folder_outside_the_project() {
    let (root, all) = project();
    let ours: BTreeSet<String> = all
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| p.file_name().unwrap().to_string_lossy().to_string())
        .collect();
    let mut wrong = Vec::new();
    for path in &all {
        let is_text = path.file_name().is_some_and(|n| n == "run")
            || path
                .extension()
                .is_some_and(|e| TEXT.contains(&e.to_str().unwrap()));
        let Ok(text) = std::fs::read_to_string(path) else {
            continue;
        };
        if !is_text || path.ends_with("tests/runs/docs_references.rs") {
            continue;
        }
        let file = path.strip_prefix(&root).unwrap().display().to_string();
        for (n, line) in text.lines().enumerate() {
            for word in names(line) {
                let outside = word.starts_with("shared/") || word.contains("/shared/");
                let document = word.rsplit('/').next().unwrap();
                let unknown = document.ends_with(".md") && !ours.contains(document);
                if outside || unknown || word.starts_with("../shared") {
                    wrong.push(format!("{file}:{}: {word}", n + 1));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "names of files outside the project:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn every_link_in_the_projects_markdown_leads_to_a_file_of_the_project() {
    let (root, all) = project();
    let mut broken = Vec::new();
    for path in all
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
    {
        let text = std::fs::read_to_string(path).unwrap();
        let dir = path.parent().unwrap();
        for (i, _) in text.match_indices("](") {
            let rest = &text[i + 2..];
            let target = &rest[..rest.find(')').unwrap_or(rest.len())];
            let file = target.split('#').next().unwrap();
            if file.is_empty() || file.contains("://") || file.starts_with("mailto:") {
                continue;
            }
            let resolved = dir.join(file);
            let inside = resolved
                .canonicalize()
                .is_ok_and(|p| p.starts_with(root.canonicalize().unwrap()));
            if !inside {
                let name = path.strip_prefix(&root).unwrap().display();
                broken.push(format!("{name}: ]({target})"));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "links to files that are not in the project:\n{}",
        broken.join("\n")
    );
}
