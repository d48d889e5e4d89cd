//! The README's two commands share one build: the test-only crates turn on no
//! feature of a crate the main build compiles (crates/workspace-hack/Cargo.toml).
//! A crate built with other features is a second build of it and of every crate
//! above it, which before the workspace-hack was about 140 crates.

use crate::common::manifest_dir;
use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// Each package of `cargo tree -e <edges>` with the feature sets it is built with.
fn feature_sets(edges: &str) -> Result<BTreeMap<String, BTreeSet<String>>, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let out = Command::new(cargo)
        .current_dir(manifest_dir())
        .args([
            "tree", "--frozen", "--prefix", "none", "-f", "{p}|{f}", "-e", edges,
        ])
        .output()
        .map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).trim().to_string());
    }
    let mut sets: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let line = line.trim_end_matches(" (*)");
        if let Some((package, features)) = line.split_once('|') {
            sets.entry(package.to_string())
                .or_default()
                .insert(features.to_string());
        }
    }
    Ok(sets)
}

/// Every (crate, features) of the main build (`cargo run`, no dev-dependencies) is
/// one the test build (`cargo test`) also has, so the test build reuses it.
#[test]
fn one_build_serves_both_readme_commands() {
    let (main, test) = match (feature_sets("no-dev"), feature_sets("normal,build,dev")) {
        (Ok(main), Ok(test)) => (main, test),
        (Err(e), _) | (_, Err(e)) => {
            println!("skipped: `cargo tree --frozen` could not run here: {e}");
            return;
        }
    };
    assert!(
        main.len() > 100 && test.len() > main.len(),
        "{} and {} crates",
        main.len(),
        test.len()
    );
    let mut differ = Vec::new();
    for (package, sets) in &main {
        let in_test = test.get(package).cloned().unwrap_or_default();
        for set in sets.difference(&in_test) {
            differ.push(format!(
                "{package}: [{set}] in the main build, [{}] in the test build",
                in_test.iter().cloned().collect::<Vec<_>>().join("] [")
            ));
        }
    }
    assert!(
        differ.is_empty(),
        "these crates would be built twice; add the test build's features to \
         crates/workspace-hack/Cargo.toml:\n{}",
        differ.join("\n")
    );
}
