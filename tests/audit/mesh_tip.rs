//! The tip from the mesh: a finger without a tip node is judged on relative
//! values, its tip where its skin ends along the DIP's bone (the thumb's IP).

use super::fingers;
use super::hand::{HandSpec, Naming, build};
use crate::common::*;
use glam::DVec3;
use serde_json::Value;
use std::path::PathBuf;

/// The chain's joint positions of a finger of the JSON document.
fn joints(f: &Value) -> Vec<DVec3> {
    f["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let p = &j["position"];
            DVec3::new(num(&p[0]), num(&p[1]), num(&p[2]))
        })
        .collect()
}

/// Asserts that every finger of `doc` is judged on relative values with a tip
/// from the mesh that lies on its last bone's line, past its last joint, and
/// returns each finger's (reach past the last joint, last segment), in metres.
fn assert_tips_from_mesh(doc: &Value, what: &str) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for f in fingers(doc) {
        let name = format!("{what} {}", f["finger"]);
        assert_eq!(f["has_tip"], false, "{name}: the chain has no tip node");
        assert_eq!(f["audit"]["basis"], "relative", "{name}");
        assert_eq!(f["audit"]["has_tip"], true, "{name}");
        let tip = &f["skin_tip"];
        assert_eq!(tip["from_mesh"], true, "{name}: {tip}");
        let p = joints(f);
        let (prev, last) = (p[p.len() - 2], p[p.len() - 1]);
        let t = DVec3::new(
            num(&tip["position"][0]),
            num(&tip["position"][1]),
            num(&tip["position"][2]),
        );
        let dir = (last - prev).normalize();
        let along = (t - last).dot(dir);
        assert!(
            (t - last - along * dir).length() < 1e-6,
            "{name}: the tip is off the last bone's line"
        );
        assert!((along - num(&tip["beyond_node"])).abs() < 1e-9, "{name}");
        out.push((along, prev.distance(last)));
    }
    out
}

#[test]
fn a_tipless_hand_is_judged_with_its_tips_from_the_mesh() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // The Unreal convention has no tip nodes; the tube of skin runs one last
    // segment past each finger's last joint (tests/audit/hand.rs), so the
    // mesh ends that far past it: the independent value.
    let mut spec = HandSpec::new(Naming::Unreal);
    spec.smooth = Some(Vec::new());
    let bytes = build(&spec);
    wd.write("tipless.glb", &bytes);
    let doc = wd
        .run(&["audit", "tipless.glb", "--format", "json"])
        .ok()
        .json();
    let reaches = assert_tips_from_mesh(&doc, "tipless.glb");
    assert_eq!(reaches.len(), 5, "all five fingers, the thumb too");
    for (reach, segment) in reaches {
        // The tube's rings lie 0.5 mm apart.
        assert!(
            (reach - segment).abs() <= 0.0006,
            "reach {reach} against the tube's {segment}"
        );
    }
    let text = wd
        .run(&["audit", "--explain", "tipless.glb"])
        .ok()
        .stdout
        .clone();
    assert!(
        text.contains("judged on relative values (tip from the mesh)"),
        "{text}"
    );
    assert!(text.contains("tip: tip from the mesh"), "{text}");
    assert!(!text.contains("judged on J2/J1 only"), "{text}");

    // --tip skin reads the tip nodes as they are, so a tipless finger keeps
    // J2/J1 (and the thumb is not judged).
    let skin = wd
        .run(&["audit", "tipless.glb", "--tip", "skin", "--format", "json"])
        .ok()
        .json();
    for f in fingers(&skin) {
        assert!(f.get("skin_tip").is_none(), "{f}");
        assert_ne!(f["audit"]["basis"], "relative", "{}", f["finger"]);
    }
}

#[test]
fn a_mesh_without_a_clear_end_is_said_so() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // Two vertices per joint (no tube): too few on the last bone for an end.
    let bytes = build(&HandSpec::new(Naming::Unreal));
    wd.write("sparse.glb", &bytes);
    let doc = wd
        .run(&["audit", "sparse.glb", "--format", "json"])
        .ok()
        .json();
    for f in fingers(&doc) {
        assert!(f.get("skin_tip").is_none(), "{f}");
    }
    let notes: Vec<&str> = doc["rig"]["notes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .filter(|n| n.contains("no tip from the mesh"))
        .collect();
    assert_eq!(notes.len(), 5, "{:?}", doc["rig"]["notes"]);
    assert!(notes.iter().all(|n| n.contains("judged on J2/J1 alone")));
}

#[test]
fn the_mannequiny_is_judged_on_relative_values_with_tips_from_the_mesh() {
    let path: PathBuf = manifest_dir().join("../shared/rigs/gdquest-mannequiny/mannequiny.glb");
    if !path.is_file() {
        skip(format!("{} is absent", path.display()));
        return;
    }
    let wd = Workdir::new();
    wd.copy_paper_data();
    let rig = path.display().to_string();
    let doc = wd.run(&["audit", &rig, "--format", "json"]).ok().json();
    let reaches = assert_tips_from_mesh(&doc, "mannequiny");
    // Thumb, index, middle, ring on each hand (the Mannequiny has no little finger).
    assert_eq!(reaches.len(), 8);
    for (reach, segment) in reaches {
        assert!(
            reach > 0.25 * segment && reach < 1.5 * segment,
            "{reach} {segment}"
        );
    }
}
