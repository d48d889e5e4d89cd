//! The dependency direction of ARCHITECTURE.md, enforced: each room of `src/`
//! may name only the rooms listed for it (its `crate::` paths outside test
//! code), and the rooms that must not know about files, plots or templates
//! use none of those crates.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each room and the rooms it may depend on (ARCHITECTURE.md, "Who may use whom").
const ALLOWED: &[(&str, &[&str])] = &[
    ("stats", &[]),
    ("atomic", &[]),
    ("format", &["stats"]),
    ("dataset", &["stats", "format", "atomic"]),
    ("error", &["dataset"]),
    ("analysis", &["dataset", "stats", "format"]),
    (
        "synth",
        &["analysis", "dataset", "stats", "format", "atomic"],
    ),
    (
        "rig",
        &["analysis", "dataset", "stats", "format", "atomic", "error"],
    ),
    (
        "track",
        &["analysis", "dataset", "stats", "format", "atomic", "error"],
    ),
    (
        "report",
        &[
            "rig", "analysis", "dataset", "stats", "format", "atomic", "error",
        ],
    ),
    (
        "cmd",
        &[
            "report", "track", "rig", "analysis", "dataset", "stats", "format", "atomic", "error",
            "synth",
        ],
    ),
    ("cli", &["cmd", "error"]),
];

/// Crates a room must not use: the statistics know nothing of files, plots,
/// templates or glTF; the rig knows nothing of plots or templates.
const FORBIDDEN: &[(&str, &[&str])] = &[
    (
        "stats",
        &["std::fs", "plotters", "tera", "gltf", "serde_json"],
    ),
    ("analysis", &["std::fs", "plotters", "tera", "gltf"]),
    ("dataset", &["plotters", "tera", "gltf"]),
    ("rig", &["plotters", "tera"]),
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The `.rs` files of a room (a directory or a single file under src/).
fn files(room: &str) -> Vec<PathBuf> {
    let dir = src().join(room);
    if dir.is_dir() {
        let mut out = Vec::new();
        let mut stack = vec![dir];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).expect("read src dir") {
                let p = e.expect("dir entry").path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    out.push(p);
                }
            }
        }
        out.sort();
        out
    } else {
        vec![src().join(format!("{room}.rs"))]
    }
}

/// The code of a file without comments and without its test modules (everything
/// from the first `#[cfg(test)]` on, which by convention ends each file), and
/// without files that are test modules themselves (`tests.rs`, `*_tests.rs`).
fn code(path: &Path) -> String {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    if name.ends_with("tests.rs") {
        return String::new();
    }
    let text = std::fs::read_to_string(path).expect("read source");
    let body = text.split("#[cfg(test)]").next().unwrap_or_default();
    body.lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The rooms named by `crate::room` paths (and `use crate::{a, b}` groups).
fn rooms_used(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let word = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for part in group[..end].split(',') {
                let w = word(part.trim());
                if !w.is_empty() {
                    out.insert(w);
                }
            }
        } else {
            out.insert(word(rest));
        }
    }
    out
}

#[test]
fn every_room_depends_only_on_the_rooms_below_it() {
    let rooms: BTreeSet<&str> = ALLOWED.iter().map(|(r, _)| *r).collect();
    let mut wrong: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (room, allowed) in ALLOWED {
        for file in files(room) {
            for used in rooms_used(&code(&file)) {
                let known = rooms.contains(used.as_str());
                if known && used != *room && !allowed.contains(&used.as_str()) {
                    wrong
                        .entry(file.display().to_string())
                        .or_default()
                        .push(format!("uses {used}"));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "dependencies against ARCHITECTURE.md: {wrong:#?}"
    );
}

#[test]
fn every_room_of_src_is_in_the_map() {
    let rooms: BTreeSet<&str> = ALLOWED.iter().map(|(r, _)| *r).collect();
    let mut missing = Vec::new();
    for e in std::fs::read_dir(src()).expect("read src") {
        let p = e.expect("dir entry").path();
        let name = p
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        if ["lib", "main"].contains(&name.as_str()) {
            continue;
        }
        if !rooms.contains(name.as_str()) {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "rooms of src/ missing from ARCHITECTURE.md and tests/architecture.rs: {missing:?}"
    );
}

#[test]
fn the_statistics_know_nothing_of_files_plots_or_templates() {
    let mut wrong = Vec::new();
    for (room, crates) in FORBIDDEN {
        for file in files(room) {
            let code = code(&file);
            for c in *crates {
                if code.contains(&format!("{c}::")) || code.contains(&format!("use {c}")) {
                    wrong.push(format!("{} uses {c}", file.display()));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

#[test]
fn the_scanner_sees_a_forbidden_edge() {
    // The test above would pass vacuously if the scanner found nothing.
    let used = rooms_used("use crate::{report, dataset::Row};\nlet x = crate::rig::Rig::load(p);");
    assert_eq!(
        used.into_iter().collect::<Vec<_>>(),
        vec!["dataset", "report", "rig"]
    );
    assert!(code(&src().join("analysis/mod.rs")).contains("crate::dataset"));
}
