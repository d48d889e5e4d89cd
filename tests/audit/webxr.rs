//! The WebXR generic hands (data/rigs/webxr-generic-hand, MIT): real rigs whose
//! 25 joints are siblings, read by name, judged, and fixed.

use super::hand::read_glb;
use super::{
    assert_second_fix_changes_nothing, audit_json, finger_of, fingers, joint_of, worst_vertex_move,
};
use crate::common::*;
use serde_json::Value;

/// Copies a vendored hand into the work directory; `None` (with the reason
/// printed) when the repository lacks it.
fn hand(wd: &Workdir, side: &str) -> Option<Vec<u8>> {
    let bytes = vendored(&format!("data/rigs/webxr-generic-hand/{side}.glb"))?;
    wd.write(&format!("{side}.glb"), &bytes);
    Some(bytes)
}

#[test]
fn both_hands_have_every_finger_found_and_judged_by_name() {
    let wd = Workdir::with_paper_data();
    for side in ["left", "right"] {
        let Some(_) = hand(&wd, side) else { return };
        let file = format!("{side}.glb");
        let doc = audit_json(&wd, &file);
        assert_eq!(fingers(&doc).len(), 5, "{side}");
        for f in fingers(&doc) {
            let name = f["finger"].as_str().unwrap();
            let prefix = match name {
                "thumb" => "thumb".to_string(),
                "little" => "pinky-finger".to_string(),
                n => format!("{n}-finger"),
            };
            // Siblings under Armature: read from the names alone.
            assert_eq!(f["hierarchy"], false, "{side} {name}");
            assert_eq!(f["side"], Value::Null);
            assert_eq!(f["audit"]["basis"], "relative", "{side} {name}");
            let joints = f["joints"].as_array().unwrap();
            assert_eq!(joints.len(), if name == "thumb" { 3 } else { 4 });
            assert_eq!(joints[0]["name"], format!("{prefix}-phalanx-proximal"));
            assert_eq!(joints.last().unwrap()["name"], format!("{prefix}-tip"));
            // The metacarpal and the wrist are recognised too.
            assert_eq!(f["metacarpal"]["name"], format!("{prefix}-metacarpal"));
            assert_eq!(f["wrist"]["name"], "wrist");
            // Every bending joint carries skin weight; the tips carry none.
            for j in joints {
                assert_eq!(j["weighted"], j["joint"] != "tip", "{side} {name} {j}");
            }
            // Every joint and value is judged, the MCP and the tip included.
            let kinds: Vec<&str> = f["audit"]["joints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|j| j["joint"].as_str().unwrap())
                .collect();
            let want: &[&str] = if name == "thumb" {
                &["MCP", "IP", "tip"]
            } else {
                &["MCP", "PIP", "DIP", "tip"]
            };
            assert_eq!(kinds, want);
            for j in f["audit"]["joints"].as_array().unwrap() {
                assert!(j["standing"].is_string(), "{j}");
            }
            // The tip joints are the centres of the fingertips' spheres: the
            // mesh reaches 9-13 mm past them (measured independently in Python
            // from the file: 9.6-12.6 mm on the right hand).
            let beyond = num(&f["skin_tip"]["beyond_node"]);
            assert!((0.009..0.013).contains(&beyond), "{side} {name}: {beyond}");
            // The inner joints sit within 3 mm of where the skin bends.
            for b in f["bends"].as_array().unwrap() {
                if b["joint"] != "MCP" {
                    assert!(num(&b["offset"]).abs() < 0.003, "{side} {name} {b}");
                    assert_eq!(b["flagged"], false);
                }
            }
        }
        let notes = doc["rig"]["notes"].to_string();
        assert!(notes.contains("not parent and child"), "{notes}");
        // Once the tip is the skin's end less its soft tissue, every finger
        // but the thumb fits the X-rays as it is. The thumb lies just
        // outside its joint region (T^2 9.0 of at most 7.7): its IP goes 2.7
        // mm to where the X-rays put it given the MCP and the tip, its
        // weights carried with it, and nothing is held.
        for f in fingers(&doc) {
            let e = &f["audit"]["explanation"];
            assert_eq!(e["consistent"], true, "{side} {f}");
            for j in f["audit"]["joints"].as_array().unwrap() {
                assert!(j.get("held").is_none(), "{side} {} {j}", f["finger"]);
            }
            if f["finger"] != "thumb" {
                assert_eq!(e["moved"], serde_json::json!([]), "{side} {e}");
                continue;
            }
            assert_eq!(e["moved"], serde_json::json!(["IP"]), "{side} {e}");
            let ip = joint_of(f, "IP");
            assert!((num(&ip["shift"]) - 0.0027).abs() < 0.0001, "{side} {ip}");
        }
        let middle = &finger_of(&doc, "middle")["audit"]["explanation"];
        assert_eq!(middle["moved"], serde_json::json!([]), "{side}");
        // The text fits 100 columns.
        let text = wd.run(&["audit", "--explain", &file]).ok().stdout.clone();
        for line in text.lines() {
            assert!(
                line.chars().count() <= 100,
                "{} columns: {line}",
                line.len()
            );
        }
    }
}

#[test]
fn a_fix_moves_sibling_joints_alone_and_keeps_the_mesh() {
    let wd = Workdir::with_paper_data();
    let Some(input) = hand(&wd, "right") else {
        return;
    };
    // Tips taken at the nodes: every finger is then off, and the X-rays put
    // its PIP and DIP (the thumb's IP) 4-9 mm nearer the root. With the
    // weights carried, the fix moves all nine (not the MCPs: without
    // --fix-mcp atlas it holds every MCP), and every finger is inside after.
    wd.run(&[
        "audit",
        "--explain",
        "right.glb",
        "--tip",
        "skin",
        "--fix",
        "fixed.glb",
    ])
    .ok()
    .stderr_has("wrote fixed.glb: 9 joints moved; re-audited, 0 of 5 fingers outside");
    // With the weights as painted (--keep-weights) every inner joint sits
    // within 1.3 mm of its skin bend, so the fix holds them and moves none.
    wd.run(&[
        "audit",
        "--explain",
        "right.glb",
        "--tip",
        "skin",
        "--keep-weights",
        "--fix",
        "kept.glb",
    ])
    .ok()
    .stderr_has("nothing to fix: no joint moves, so kept.glb was not written");
    let text = wd
        .run(&[
            "audit",
            "--explain",
            "right.glb",
            "--tip",
            "skin",
            "--keep-weights",
        ])
        .ok()
        .stdout
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        text.contains("The DIP is held: it sits where its skin bends"),
        "{text}"
    );
    let fixed = wd.read("fixed.glb");
    let worst = worst_vertex_move(&input, &fixed);
    assert!(worst < 1e-5, "a vertex moved by {worst} m");
    // A moved joint moved alone: its siblings (the tips, the metacarpals) stayed.
    let (before, _) = read_glb(&input);
    let (after, _) = read_glb(&fixed);
    let pos = |doc: &Value, name: &str| super::node_position(doc, name);
    for name in ["index-finger-tip", "index-finger-metacarpal", "wrist"] {
        let (a, b) = (pos(&before, name), pos(&after, name));
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-7), "{name} moved");
    }
    let (a, b) = (
        pos(&before, "index-finger-phalanx-distal"),
        pos(&after, "index-finger-phalanx-distal"),
    );
    // The DIP moved alone, towards the root.
    assert!((0..3).any(|k| (a[k] - b[k]).abs() > 1e-3));
    // The skin now bends within 1 mm of each moved joint (the weights went
    // with it), by the audit's own reading of the written file.
    let doc = wd
        .run(&["audit", "fixed.glb", "--tip", "skin", "--format", "json"])
        .ok()
        .json();
    for f in fingers(&doc) {
        for b in f["bends"].as_array().unwrap() {
            if b["joint"] != "MCP" {
                assert!(num(&b["offset"]).abs() < 0.001, "{} {b}", f["finger"]);
            }
        }
    }
    assert_second_fix_changes_nothing(&wd, &["--tip", "skin"]);
}

/// The WebXR hands have `*-metacarpal` joints: with the atlas at its default
/// path every finger's MCP is also judged from its CMC, mc the distance
/// between the two nodes and mc/J over the finger's length as judged.
#[test]
fn every_webxr_finger_gets_a_metacarpal_judgement_from_the_atlas() {
    let wd = Workdir::with_paper_data();
    let Some(_) = hand(&wd, "right") else { return };
    let no_atlas = wd
        .run(&["audit", "--explain", "right.glb"])
        .ok()
        .stdout
        .clone();
    assert!(!no_atlas.contains("Metacarpal ("), "{no_atlas}");
    let doc = audit_json(&wd, "right.glb");
    assert!(
        fingers(&doc)
            .iter()
            .all(|f| f.get("metacarpal_check").is_none())
    );
    assert!(
        no_atlas.contains("--metacarpals DATASET"),
        "a note says why: {no_atlas}"
    );
    let Some(bytes) = vendored("data/atlas/measurements.csv") else {
        return;
    };
    wd.write("data/atlas/measurements.csv", &bytes);
    // The atlas's tips are at the bone, the hand's at the skin: the measured soft tissue bridges them.
    for file in [
        "data/literature/buryanov-kotiuk-2010.csv",
        "data/literature/buryanov-kotiuk-2010.cohort.csv",
    ] {
        wd.write(file, std::fs::read(manifest_dir().join(file)).unwrap());
    }
    let doc = audit_json(&wd, "right.glb");
    for f in fingers(&doc) {
        let m = &f["metacarpal_check"];
        let name = f["finger"].as_str().unwrap();
        assert_eq!(m["node"], f["metacarpal"]["name"], "{name}");
        let node = m["node"].as_str().unwrap_or_else(|| panic!("{name}: {f}"));
        assert!(node.ends_with("-metacarpal"), "{name}: {node}");
        let p = |v: &Value| -> Vec<f64> { (0..3).map(|k| num(&v[k])).collect() };
        let (cmc, mcp) = (
            p(&f["metacarpal"]["position"]),
            p(&f["joints"][0]["position"]),
        );
        let mc = (0..3)
            .map(|k| (cmc[k] - mcp[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert_close(num(&m["mc"]), mc, 1e-9, name);
        // J runs to the atlas's (bone) tips: the hand's skin tip less the finger's measured
        // soft tissue, as a share of the finger.
        let share = 1.0 - num(&m["length"]) / num(&f["audit"]["length"]);
        assert_close(share, super::soft_tissue_share(name), 1e-9, name);
        let ratio = &m["values"][0];
        assert_eq!(ratio["quantity"], "ratio_mc_j", "{name}");
        assert_close(num(&ratio["measured"]), mc / num(&m["length"]), 1e-9, name);
        assert!(m["standing"].is_string(), "{name}: {m}");
    }
    wd.run(&["audit", "--explain", "right.glb"])
        .ok()
        .stdout_has("Metacarpal (index-finger-metacarpal): mc ")
        .stdout_has("children's left hands");
    // A named dataset that is missing is an error, not a silent skip.
    wd.run(&[
        "audit",
        "--explain",
        "right.glb",
        "--metacarpals",
        "nowhere.csv",
    ])
    .data_error();
}
