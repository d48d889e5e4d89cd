//! The default audit, read in a minute (issue 41): on every shared rig, at most
//! 40 lines per hand at 100 columns, and the opening, the tables, the summary,
//! the JSON and the fix say the same.

use crate::common::{Workdir, shared_rig_files, skip};
use serde_json::Value;

/// The atlas and the soft tissue beside the paper's data, as `audit` finds them.
fn workdir() -> Option<Workdir> {
    super::ray::with_atlas()
}

/// "8.3" from "move 8.3 mm towards the tip" (the first move in `cell`).
fn move_mm(cell: &str) -> Option<String> {
    let rest = &cell[cell.find("move ")? + 5..];
    Some(rest.split_whitespace().next()?.to_string())
}

/// The joints the JSON's fix moves, as (finger index, joint, shift in mm to 0.1).
fn fixed_joints(doc: &Value) -> Vec<(usize, String, String)> {
    let mut out = Vec::new();
    for (i, f) in doc["rig"]["fingers"].as_array().unwrap().iter().enumerate() {
        for j in f["audit"]["joints"].as_array().unwrap() {
            if j["fix"] == true {
                assert_eq!(j["explains"], true, "{j}");
                let mm = j["shift"].as_f64().unwrap() * 1000.0;
                out.push((
                    i,
                    j["joint"].as_str().unwrap().to_string(),
                    format!("{mm:.1}"),
                ));
            }
        }
    }
    out
}

/// The moves the text's tables give, as (finger index, joint, mm): each finger's
/// table opens with a line at the margin, its rows two columns in.
fn table_moves(text: &str) -> Vec<(usize, String, String)> {
    let mut finger: Option<usize> = None;
    let mut out = Vec::new();
    let tables = text
        .lines()
        .skip_while(|l| !l.contains("  rig  "))
        .take_while(|l| !l.starts_with("Summary:"));
    for line in tables {
        if line.contains("  rig  ") && !line.starts_with(' ') {
            finger = Some(finger.map_or(0, |k| k + 1));
            continue;
        }
        let (Some(k), Some(row)) = (finger, line.strip_prefix("  ")) else {
            continue;
        };
        let first = row.split_whitespace().next().unwrap_or("");
        if row.starts_with(' ') || !["MCP", "PIP", "DIP", "IP", "tip"].contains(&first) {
            continue;
        }
        if let Some(mm) = move_mm(row) {
            let joint = row.split_whitespace().next().unwrap().to_string();
            out.push((k, joint, mm));
        }
    }
    out
}

/// The count before `what` in the summary ("4 MCPs lie outside": 4).
fn summary_count(text: &str, what: &[&str]) -> usize {
    let summary: String = text
        .lines()
        .skip_while(|l| !l.starts_with("Summary:"))
        .collect::<Vec<_>>()
        .join(" ");
    let summary = summary.split_whitespace().collect::<Vec<_>>().join(" ");
    for w in what {
        if let Some(at) = summary.find(w) {
            let before = summary[..at].trim_end();
            let n = before.rsplit(' ').next().unwrap();
            return n.parse().unwrap_or_else(|_| panic!("{summary}"));
        }
    }
    0
}

#[test]
fn the_default_audit_is_short_and_every_part_agrees() {
    let Some(wd) = workdir() else {
        return;
    };
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    if rigs.is_empty() {
        skip("../shared/rigs holds no rig");
        return;
    }
    for (n, rig) in rigs.iter().enumerate() {
        let rig = rig.display().to_string();
        let text = wd.run(&["audit", &rig]).ok().stdout.clone();
        let doc = wd.run(&["audit", &rig, "--format", "json"]).ok().json();
        let fingers = doc["rig"]["fingers"].as_array().unwrap();
        let hands = fingers.len().div_ceil(5).max(1);
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines.len() <= 40 * hands,
            "{rig}: {} lines for {hands} hand(s)\n{text}",
            lines.len()
        );
        for l in &lines {
            assert!(l.chars().count() <= 100, "{rig}: wider than 100: {l}");
        }
        assert!(!text.contains('?'), "{rig}: a question in\n{text}");
        let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
        for clause in flat.split([';', '(', ',']) {
            if clause.contains("move") || clause.contains("held") {
                assert!(!clause.contains(" 0.0 mm"), "{rig}: '{clause}'\n{text}");
            }
        }
        // The opening names every MCP the summary counts outside from its base.
        let opening = lines
            .iter()
            .take_while(|l| !l.starts_with("Against"))
            .cloned()
            .collect::<Vec<_>>()
            .join(" ");
        let opening = opening.split_whitespace().collect::<Vec<_>>().join(" ");
        let named = opening.matches("the MCP from its CMC: OUT").count()
            + opening.matches("the MCP from the wrist: OUT").count();
        let counted = summary_count(&text, &["MCPs lie outside", "MCP lies outside"]);
        assert_eq!(named, counted, "{rig}: opening against summary\n{text}");
        // The tables' verdicts count the fingers the summary and the JSON count.
        let outside = lines
            .iter()
            .filter(|l| !l.starts_with(' ') && l.contains("  rig  ") && l.contains(": OUT"))
            .count();
        let summary_outside = summary_count(&text, &[" of "]);
        assert_eq!(outside, summary_outside, "{rig}: tables against summary");
        assert_eq!(
            doc["fingers_outside"].as_u64(),
            Some(outside as u64),
            "{rig}: tables against JSON"
        );
        // Each move a row gives is a move of the JSON's fix, and each of those a row's.
        let mut rows = table_moves(&text);
        let mut fixed = fixed_joints(&doc);
        rows.sort();
        fixed.sort();
        assert_eq!(rows, fixed, "{rig}: table moves against JSON fix\n{text}");
        // The fix makes those moves and no other: a node per move, or no file.
        if rig.ends_with(".fbx") {
            continue;
        }
        let out = format!("fixed-{n}.glb");
        let fix = wd
            .run(&["audit", &rig, "--fix", &out, "--format", "json"])
            .ok()
            .json();
        let moved = fix["fix"]["moved"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|m| m["shift"].as_f64().unwrap() > 0.0)
            .count();
        assert_eq!(moved, fixed.len(), "{rig}: the fix against the JSON");
        let written = fix["fix"]["written"] == true;
        assert_eq!(written, moved > 0, "{rig}");
        assert_eq!(wd.path().join(&out).is_file(), written, "{rig}");
    }
}

#[test]
fn a_fix_that_moves_nothing_writes_no_file() {
    let Some(wd) = workdir() else {
        return;
    };
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    let Some(rig) = rigs
        .iter()
        .find(|p| p.ends_with("webxr-generic-hand/right.glb"))
    else {
        skip("../shared/rigs has no webxr-generic-hand/right.glb");
        return;
    };
    let rig = rig.display().to_string();
    let run = wd.run(&[
        "audit",
        &rig,
        "--hold",
        "ip,pip,dip,tip",
        "--fix",
        "same.glb",
    ]);
    let run = run.ok();
    assert!(run.stderr.contains("was not written"), "{}", run.stderr);
    assert!(!wd.path().join("same.glb").exists());
}
