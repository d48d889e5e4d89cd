//! What `--fix` keeps: where the skin bends relative to each moved joint,
//! every keyframe of an animation, channels it does not understand, and its
//! own output (a second fix changes nothing).

use super::hand::{HandSpec, Naming, build, posed, read_glb, skinned_vertices, world_of};
use super::{assert_second_fix_changes_nothing, finger_of, worst_vertex_move};
use crate::common::*;
use glam::DVec3;
use serde_json::Value;

/// The fix's JSON report: the names of the nodes it moved.
fn moved_nodes(wd: &Workdir, input: &str, out: &str, extra: &[&str]) -> Vec<String> {
    let mut args = vec!["audit", input, "--fix", out, "--format", "json"];
    args.extend_from_slice(extra);
    let doc = wd.run(&args).ok().json();
    doc["fix"]["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap().to_string())
        .collect()
}

/// Where the skin bends at the joint node `joint` of the Mixamo chain
/// `chain` (root first, tip last): the signed distance (m, + towards the
/// tip) from the joint to where the share of weight on the joint's and later
/// nodes passes 1/2 among the vertices near the finger. Its own method: each
/// vertex's distance along the finger is its projection on the nearest
/// segment of the joints' polyline (extended one segment before the root);
/// the vertices are grouped by that distance to 1 um (a ring of the tube's
/// vertices shares one distance, up to the f32 positions' rounding), and the
/// crossing is interpolated linearly between the first consecutive groups
/// whose mean shares straddle 1/2. (Grouping to 0.1 mm moved each ring by up
/// to 0.05 mm, so a reading could err by that much: the 0.016 mm that a fixed
/// ring DIP once seemed to gain was that rounding, not the remap.)
fn bend(bytes: &[u8], chain: &[&str], hand: &str, joint: usize) -> f64 {
    let (doc, bin) = read_glb(bytes);
    let nodes = doc["nodes"].as_array().unwrap();
    let world = world_of(nodes);
    let index = |name: &str| nodes.iter().position(|n| n["name"] == name).unwrap();
    let pts: Vec<DVec3> = chain
        .iter()
        .map(|n| world[index(n)].w_axis.truncate())
        .collect();
    let skin: Vec<usize> = doc["skins"][0]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_u64().unwrap() as usize)
        .collect();
    let slot = |name: &str| skin.iter().position(|&j| j == index(name));
    let distal: Vec<usize> = chain[joint..].iter().filter_map(|n| slot(n)).collect();
    let proximal: Vec<usize> = chain[..joint]
        .iter()
        .chain(std::iter::once(&hand))
        .filter_map(|n| slot(n))
        .collect();
    let acc = |k: &str| {
        let a = &doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"][k]
            .as_u64()
            .unwrap() as usize];
        let v = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        (
            v["byteOffset"].as_u64().unwrap_or(0) as usize,
            a["count"].as_u64().unwrap() as usize,
        )
    };
    let f = |o: usize| f32::from_le_bytes(bin[o..o + 4].try_into().unwrap()) as f64;
    let (p, n) = acc("POSITION");
    let (j, _) = acc("JOINTS_0");
    let (w, _) = acc("WEIGHTS_0");
    let mut axis = vec![pts[0] - (pts[1] - pts[0])];
    axis.extend_from_slice(&pts);
    let at_joint: f64 = (0..=joint).map(|k| axis[k].distance(axis[k + 1])).sum();
    let mut groups: std::collections::BTreeMap<i64, (f64, f64)> = Default::default();
    for v in 0..n {
        let pos = DVec3::new(f(p + 12 * v), f(p + 12 * v + 4), f(p + 12 * v + 8));
        let (mut d, mut q) = (0.0, 0.0);
        for k in 0..4 {
            let s = u16::from_le_bytes(
                bin[j + 8 * v + 2 * k..j + 8 * v + 2 * k + 2]
                    .try_into()
                    .unwrap(),
            ) as usize;
            let x = f(w + 16 * v + 4 * k);
            if distal.contains(&s) {
                d += x;
            } else if proximal.contains(&s) {
                q += x;
            }
        }
        if d + q < 0.5 {
            continue;
        }
        // Nearest segment; distance along the polyline.
        let (mut best, mut along, mut start) = (f64::INFINITY, 0.0, 0.0);
        for s in axis.windows(2) {
            let dir = s[1] - s[0];
            let t = ((pos - s[0]).dot(dir) / dir.length_squared()).clamp(0.0, 1.0);
            let dist = (s[0] + t * dir).distance(pos);
            if dist < best {
                best = dist;
                along = start + t * dir.length();
            }
            start += dir.length();
        }
        if best > 0.01 || (along - at_joint).abs() > 0.01 {
            continue;
        }
        let key = ((along - at_joint) * 1e6).round() as i64;
        let g = groups.entry(key).or_default();
        g.0 += d / (d + q);
        g.1 += 1.0;
    }
    let means: Vec<(f64, f64)> = groups
        .into_iter()
        .map(|(k, (s, c))| (k as f64 * 1e-6, s / c))
        .collect();
    let i = means
        .windows(2)
        .position(|m| m[0].1 < 0.5 && m[1].1 >= 0.5)
        .expect("a crossing");
    let (a, b) = (means[i], means[i + 1]);
    a.0 + (0.5 - a.1) / (b.1 - a.1) * (b.0 - a.0)
}

fn mixamo_chain(finger: &str) -> Vec<String> {
    let (f, first) = match finger {
        "thumb" => ("Thumb", 2),
        "little" => ("Pinky", 1),
        f => (
            match f {
                "index" => "Index",
                "middle" => "Middle",
                _ => "Ring",
            },
            1,
        ),
    };
    (first..=4)
        .map(|k| format!("mixamorig:RightHand{f}{k}"))
        .collect()
}

#[test]
fn moved_joints_keep_their_bends_close() {
    let wd = Workdir::with_paper_data();
    // Index PIP 5 mm distal and ring DIP 6 mm proximal of where the hand was
    // built, middle MCP at the web; the skin still bends where the joints
    // were built (5 mm proximal of the index PIP, 6 mm distal of the ring
    // DIP), so the fix moves those two towards their bends (as far as the
    // joint region's edge, not all the way); the middle MCP
    // (its skin 2 mm distal of it) is held, as every MCP is without
    // --fix-mcp atlas.
    let mut spec = HandSpec::new(Naming::Mixamo)
        .moved("index", 1, 0.5)
        .moved("ring", 2, -0.6)
        .moved("middle", 0, 1.5);
    spec.smooth = Some(vec![
        ("index", 1, -5.0),
        ("ring", 2, 6.0),
        ("middle", 0, 2.0),
        ("index", 2, -1.0),
    ]);
    let input = build(&spec);
    wd.write("smooth.glb", &input);
    let doc = wd
        .run(&[
            "audit",
            "smooth.glb",
            "--fix",
            "fixed.glb",
            "--format",
            "json",
        ])
        .ok()
        .json();
    let moved: Vec<&str> = doc["fix"]["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap())
        .collect();
    assert_eq!(
        moved,
        ["mixamorig:RightHandIndex2", "mixamorig:RightHandRing3"]
    );
    // The middle MCP, 15 mm off, is held and says why (10 mm off, the finger
    // lies inside the joint region of 5 X-rays: T^2 24.7 of at most 25.5).
    let middle = doc["rig"]["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["finger"] == "middle")
        .unwrap();
    let mcp = middle["audit"]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["joint"] == "MCP")
        .unwrap();
    super::assert_knuckle_held(mcp);
    let fixed = wd.read("fixed.glb");
    assert!(worst_vertex_move(&input, &fixed) < 1e-5);
    let mut index_after = 0.0;
    for (finger, joint, set) in [("index", 1, -0.005), ("ring", 2, 0.006)] {
        let chain = mixamo_chain(finger);
        let chain: Vec<&str> = chain.iter().map(String::as_str).collect();
        let before = bend(&input, &chain, "mixamorig:RightHand", joint);
        let after = bend(&fixed, &chain, "mixamorig:RightHand", joint);
        eprintln!(
            "{finger} joint {joint}: bend {:.3} mm from it before, {:.3} mm after the fix",
            before * 1e3,
            after * 1e3
        );
        // The test's own reading of the weights finds the bend the builder set.
        assert!((before - set).abs() < 2e-4, "{finger}: {before}");
        // The weights stay as painted, so the move brings the joint towards
        // its bend: at least 1 mm closer (the moves are 2-4 mm, towards it).
        assert!(
            after.abs() <= before.abs() - 0.001,
            "{finger}: {before} -> {after}"
        );
        if finger == "index" {
            index_after = after;
        }
    }
    // The audit of the fixed copy agrees with the test's own reading of where
    // the index PIP's skin now bends (5 mm from it before, 1.5 mm after).
    let doc = wd
        .run(&["audit", "fixed.glb", "--format", "json"])
        .ok()
        .json();
    let index = finger_of(&doc, "index");
    let pip = index["bends"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["joint"] == "PIP")
        .unwrap();
    assert!(
        (num(&pip["offset"]).abs() - index_after.abs()).abs() < 3e-4,
        "{pip} against {index_after}"
    );
}

/// The skinned mesh at each keyframe of animation 0 agrees between two files.
fn keyframes_agree(a: &[u8], b: &[u8], keys: usize) -> f64 {
    (0..keys)
        .map(|k| {
            let (va, vb) = (skinned_vertices(a, Some(k)), skinned_vertices(b, Some(k)));
            va.iter()
                .zip(&vb)
                .map(|(x, y)| x.distance(*y))
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn constant_translation_keys_follow_the_moved_joints() {
    let wd = Workdir::with_paper_data();
    // Every finger joint keyed at rest, as Mixamo and Blender export: a
    // constant translation key equal to its rest translation, and its rest
    // rotation. Skin with smooth weights (which the fix moves too).
    let mut spec = HandSpec::new(Naming::Mixamo)
        .moved("index", 1, 1.0)
        .moved("middle", 0, 1.0);
    spec.animate = true;
    // The index PIP's skin bends where the joint was built, 10 mm proximal
    // of it, so the fix moves it (a joint at its bend would be held, as the
    // middle MCP is: no MCP moves without --fix-mcp atlas).
    spec.smooth = Some(vec![("index", 1, -10.0)]);
    let input = build(&spec);
    wd.write("anim.glb", &input);
    wd.run(&["audit", "--explain", "anim.glb", "--fix", "fixed.glb"])
        .ok()
        .stderr_has("constant translation channels of moved joints now key the new rest");
    let fixed = wd.read("fixed.glb");
    // At every keyframe the skin is where the original's is.
    let worst = keyframes_agree(&input, &fixed, 2);
    eprintln!("worst vertex difference over the keyframes: {worst:e} m");
    assert!(worst < 1e-5, "{worst}");
    // The moved joints' keys did change (the check is not vacuous): they now
    // equal the new rest translation.
    let (doc, bin) = read_glb(&fixed);
    let node = |name: &str| super::node_at(&doc, name);
    let pip = node("mixamorig:RightHandIndex2");
    let rest: Vec<f64> = doc["nodes"][pip]["translation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let (before, _) = read_glb(&input);
    assert!((rest[1] - before["nodes"][pip]["translation"][1].as_f64().unwrap()).abs() > 0.5);
    let keyed = posed(doc.clone(), &bin, Some(1));
    for c in 0..3 {
        let x = keyed["nodes"][pip]["translation"][c].as_f64().unwrap();
        assert!((x - rest[c]).abs() < 1e-6, "{x} vs {}", rest[c]);
    }
    assert_second_fix_changes_nothing(&wd, &[]);
}

#[test]
fn varying_translation_keys_move_the_joints_as_before() {
    let wd = Workdir::with_paper_data();
    // The index PIP's second key moves it 3 mm: off the rest pose, so the
    // skin (whose weights the fix moves) may differ; the skeleton may not.
    let mut spec = HandSpec::new(Naming::Mixamo).moved("index", 1, 1.0);
    spec.animate = true;
    spec.varying = vec![("index", 1), ("index", 2)];
    spec.smooth = Some(Vec::new());
    let input = build(&spec);
    wd.write("anim.glb", &input);
    wd.run(&["audit", "--explain", "anim.glb", "--fix", "fixed.glb"])
        .ok()
        .stderr_has(
            "the translation keys of 'mixamorig:RightHandIndex2', 'mixamorig:RightHandIndex3' vary",
        );
    let fixed = wd.read("fixed.glb");
    let (a, abin) = read_glb(&input);
    let (b, bbin) = read_glb(&fixed);
    for key in 0..2 {
        let wa = world_of(
            posed(a.clone(), &abin, Some(key))["nodes"]
                .as_array()
                .unwrap(),
        );
        let wb = world_of(
            posed(b.clone(), &bbin, Some(key))["nodes"]
                .as_array()
                .unwrap(),
        );
        // Every node but the moved PIP is where it was at this keyframe; the
        // PIP is where its move put it, plus the key's own 3 mm.
        let names: Vec<&str> = a["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n["name"].as_str().unwrap_or(""))
            .collect();
        for (i, name) in names.iter().enumerate() {
            let d = wa[i].w_axis.truncate().distance(wb[i].w_axis.truncate());
            if *name == "mixamorig:RightHandIndex2" {
                assert!(d > 0.005, "key {key}: the PIP moved only {d}");
            } else {
                assert!(d < 1e-6, "key {key}: {name} moved {d}");
            }
        }
    }
    // At the rest keyframe the skin is unchanged.
    assert!(keyframes_agree(&input, &fixed, 1) < 1e-5);
}

/// Edits the JSON of a GLB.
fn edit(bytes: &[u8], f: impl FnOnce(&mut Value)) -> Vec<u8> {
    let (mut json, bin) = read_glb(bytes);
    f(&mut json);
    super::hand::glb(&json, bin)
}

#[test]
fn channels_with_unknown_paths_are_reported_and_left_alone() {
    let wd = Workdir::with_paper_data();
    // A PIP 5 mm off, so that the fix moves it and writes its copy.
    let mut spec = HandSpec::new(Naming::Mixamo).moved("index", 1, 5.0);
    spec.smooth = Some(Vec::new());
    spec.animate = true;
    let input = edit(&build(&spec), |j| {
        let chs = j["animations"][0]["channels"].as_array_mut().unwrap();
        chs[1]["target"]["path"] = serde_json::json!("rottaion");
        chs.push(
            serde_json::json!({"sampler": 0, "target": {"path": "pointer",
            "extensions": {"KHR_animation_pointer": {"pointer": "/nodes/5/translation"}}}}),
        );
        j["extensionsUsed"] = serde_json::json!(["KHR_animation_pointer"]);
    });
    wd.write("odd.glb", &input);
    wd.run(&["audit", "--explain", "odd.glb", "--fix", "fixed.glb"])
        .ok()
        .stderr_has("channel 1 (path 'rottaion')")
        .stderr_has("(KHR_animation_pointer)")
        .stderr_has("left alone");
    let (a, _) = read_glb(&input);
    let (b, _) = read_glb(&wd.read("fixed.glb"));
    assert_eq!(
        a["animations"][0]["channels"],
        b["animations"][0]["channels"]
    );
    // The fixed copy reads back, its mesh unchanged.
    assert!(worst_vertex_move(&input, &wd.read("fixed.glb")) < 1e-5);
}

#[test]
fn only_outside_moves_only_joints_outside_their_interval() {
    let wd = Workdir::with_paper_data();
    let input = super::index_dip_inside_yet_explaining();
    wd.write("index.glb", &input);
    let doc = wd
        .run(&["audit", "index.glb", "--format", "json"])
        .ok()
        .json();
    let index = finger_of(&doc, "index");
    assert_eq!(
        index["audit"]["explanation"]["moved"],
        serde_json::json!(["DIP"])
    );
    assert_eq!(index["audit"]["region"]["inside"], false);
    assert_eq!(super::joint_of(index, "DIP")["standing"], "in_prediction");
    assert_eq!(doc["fingers_outside"], 1);
    assert_eq!(
        moved_nodes(&wd, "index.glb", "all.glb", &[]),
        ["mixamorig:RightHandIndex3"]
    );
    assert!(moved_nodes(&wd, "index.glb", "outside.glb", &["--only-outside"]).is_empty());
    wd.run(&[
        "audit",
        "--explain",
        "index.glb",
        "--fix",
        "outside.glb",
        "--only-outside",
        "--force",
    ])
    .ok()
    .stderr_has("nothing to fix: no joint moves, so outside.glb was not written");
}
