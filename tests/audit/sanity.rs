//! Warnings that a rig's bones do not match its mesh: joints far outside the
//! mesh they skin, and a node rest pose that is not the skin's bind pose (told
//! apart from a wrong unit). The rigs are built here (tests/audit/hand.rs);
//! the expected figures come from the built files, computed here.

use super::hand::{
    CM_PER_UNIT, HandSpec, Naming, XRAY_1B, build, glb, read_glb, skinned_rest_vertices, world_of,
};
use crate::common::*;
use glam::DVec3;
use serde_json::Value;

fn warnings(wd: &Workdir, file: &str) -> Vec<String> {
    let doc = wd.run(&["audit", file, "--format", "json"]).ok().json();
    doc["rig"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect()
}

/// A length as the warnings write it: metres with 2 decimals from 0.1 m, else mm with 1.
fn words(x: f64) -> String {
    if x >= 0.1 {
        format!("{x:.2} m")
    } else {
        format!("{:.1} mm", x * 1000.0)
    }
}

#[test]
fn finger_joints_far_outside_their_mesh_are_named_with_the_distance_and_the_mesh_size() {
    let wd = Workdir::with_paper_data();
    // A Rigify-like hand with metacarpals, its palm 30 times too long (palm
    // bones about 2 m), skinned to the mesh of the same hand with a normal palm:
    // the mesh stays where a hand is, the finger joints sit metres away. The
    // inverse bind matrices are the long hand's own, so the rest pose is the
    // bind pose and the mesh does not follow the bones.
    let spec = HandSpec {
        metacarpals: true,
        ..HandSpec::new(Naming::Rigify)
    };
    let normal = build(&spec);
    let long = build(&HandSpec {
        palm: 30.0,
        ..spec.clone()
    });
    let (doc_n, bin_n) = read_glb(&normal);
    let (mut doc, mut bin) = read_glb(&long);
    // Same nodes and vertex count, so the same layout: accessor 0 (POSITION) in view 0.
    assert_eq!(doc["bufferViews"][0], doc_n["bufferViews"][0]);
    let off = doc["bufferViews"][0]["byteOffset"].as_u64().unwrap() as usize;
    let len = doc["bufferViews"][0]["byteLength"].as_u64().unwrap() as usize;
    bin[off..off + len].copy_from_slice(&bin_n[off..off + len]);
    doc["accessors"][0]["min"] = doc_n["accessors"][0]["min"].clone();
    doc["accessors"][0]["max"] = doc_n["accessors"][0]["max"].clone();
    let bytes = glb(&doc, bin);
    wd.write("normal.glb", &normal);
    wd.write("long.glb", &bytes);
    assert!(
        warnings(&wd, "normal.glb")
            .iter()
            .all(|w| !w.contains("outside the mesh")),
        "the normal hand's joints are inside its mesh"
    );
    let w = warnings(&wd, "long.glb");
    let w = w
        .iter()
        .find(|w| w.contains("finger joints lie far outside the mesh they skin"))
        .unwrap_or_else(|| panic!("no warning in {w:?}"));
    // The expected figures, from the file: the skinned rest vertices (glTF
    // skinning written in the tests) and the nodes' world positions.
    let verts = skinned_rest_vertices(&bytes);
    let (lo, hi) = verts.iter().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), v| (lo.min(*v), hi.max(*v)),
    );
    let size = hi - lo;
    assert!(
        w.contains(&format!(
            "which spans {} x {} x {}",
            words(size.x),
            words(size.y),
            words(size.z)
        )),
        "{w}"
    );
    let nodes = doc["nodes"].as_array().unwrap();
    let world = world_of(nodes);
    let node = |name: &str| nodes.iter().position(|n| n["name"] == name).unwrap();
    // The middle finger: its farthest joint from any vertex, by hand.
    let chain = [
        "DEF-f_middle.01.R",
        "DEF-f_middle.02.R",
        "DEF-f_middle.03.R",
        "DEF-f_middle.03.R_end",
    ];
    let nearest = |n: usize| {
        let p = world[n].w_axis.truncate();
        verts
            .iter()
            .map(|v| v.distance(p))
            .fold(f64::INFINITY, f64::min)
    };
    let (far, d) = chain
        .iter()
        .map(|&c| (c, nearest(node(c))))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    // Several metres: the palm is 30 x 9.3 cm long (tests/audit/hand.rs).
    assert!(d > 2.0, "{far} is {d} m from the mesh");
    let joint = if far.ends_with("_end") { "tip" } else { "MCP" };
    assert!(
        w.contains(&format!(
            "right middle's {joint} {far} (node {}) lies {} from the nearest vertex",
            node(far),
            words(d)
        )),
        "{far} at {d}: {w}"
    );
    // What to check.
    assert!(w.contains("a palm or hand bone far too long"), "{w}");
}

/// The Mixamo hand of tests/audit/hand.rs with the Armature's JSON node edited by `f`
/// after the build (its inverse bind matrices left as built).
fn edited(spec: &HandSpec, f: impl FnOnce(&mut Value)) -> Vec<u8> {
    let (mut doc, bin) = read_glb(&build(spec));
    assert_eq!(doc["nodes"][0]["name"], "Armature");
    f(&mut doc["nodes"][0]);
    glb(&doc, bin)
}

#[test]
fn a_rest_pose_that_is_not_the_bind_pose_is_named_instead_of_a_wrong_unit() {
    let wd = Workdir::with_paper_data();
    let spec = HandSpec::new(Naming::Mixamo);
    // The Armature's scale 0.1 in the nodes, the skin bound at 0.01 (the
    // inverse bind matrices as built): every finger 10 times its bind length.
    wd.write(
        "rest.glb",
        edited(&spec, |a| a["scale"] = serde_json::json!([0.1, 0.1, 0.1])),
    );
    let w = warnings(&wd, "rest.glb");
    assert!(
        w.iter().all(|w| !w.contains("likely in")),
        "no unit warning: {w:?}"
    );
    let rest = w
        .iter()
        .find(|w| w.contains("the nodes' rest pose is not the skin's bind pose"))
        .unwrap_or_else(|| panic!("no rest pose warning in {w:?}"));
    // X-ray 1b's index J1, 342.47 image units x 0.0125 cm = 42.8 mm bound;
    // 428.1 mm at rest. The nodes are the 1st and 2nd index joints; their indices
    // are read from the file.
    let bound = XRAY_1B[1].1[0] * CM_PER_UNIT * 10.0;
    assert_eq!(format!("{bound:.1}"), "42.8");
    let (doc, _) = read_glb(&wd.read("rest.glb"));
    let at = |name: &str| super::node_at(&doc, name);
    let expected = format!(
        "right index's MCP-PIP segment, mixamorig:RightHandIndex1 (node {}) to \
         mixamorig:RightHandIndex2 (node {}), is 0.43 m long in the nodes' rest pose and 42.8 mm \
         in the bind pose (10x)",
        at("mixamorig:RightHandIndex1"),
        at("mixamorig:RightHandIndex2")
    );
    assert!(rest.contains(&expected), "{rest}\nwanted: {expected}");
    // A rest pose that only turns the whole hand keeps every length: no warning.
    wd.write(
        "turned.glb",
        edited(&spec, |a| {
            a["rotation"] = serde_json::json!([0.0, 0.6, 0.0, 0.8])
        }),
    );
    let w = warnings(&wd, "turned.glb");
    assert!(w.is_empty(), "{w:?}");
    // A file truly in centimetres (nodes and bind pose alike, no Armature
    // scale): the unit warning, and no rest pose warning.
    wd.write(
        "cm.glb",
        build(&HandSpec {
            armature_scale: 1.0,
            ..spec.clone()
        }),
    );
    let w = warnings(&wd, "cm.glb");
    assert!(
        w.iter().any(|w| w.contains("likely in centimetres")),
        "{w:?}"
    );
    assert!(w.iter().all(|w| !w.contains("bind pose")), "{w:?}");
}
