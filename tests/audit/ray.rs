//! The MCP judged along its ray from the wrist (a hand bone, no metacarpals),
//! `--strict` counting it, and `--fix-mcp atlas` moving it.

use super::hand::{HandSpec, Naming, build};
use super::{audit_json, finger_of, fingers, worst_vertex_move};
use crate::common::*;
use serde_json::Value;

/// A workdir with the paper's data and the atlas (its measurements and its
/// landmarks, which give the wrist-to-MCP distance over the finger's length) at its default path; `None`
/// (skipped, with the reason printed) when the atlas is not readable.
pub(super) fn with_atlas() -> Option<Workdir> {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // The atlas's tips are at the bone and the rigs' at the skin: the measured soft
    // tissue (data/literature/) bridges them.
    for file in [
        "data/atlas/measurements.csv",
        "data/atlas/landmarks.csv",
        "data/literature/buryanov-kotiuk-2010.csv",
        "data/literature/buryanov-kotiuk-2010.cohort.csv",
    ] {
        let path = manifest_dir().join(file);
        let Ok(bytes) = std::fs::read(&path) else {
            skip(format!("{} is not readable", path.display()));
            return None;
        };
        wd.write(file, &bytes);
    }
    Some(wd)
}

/// Without the soft tissue table that bridges the atlas's bone tips and a rig's
/// skin tips, no MCP is judged from its base, and a note says why.
#[test]
fn without_the_soft_tissue_table_a_note_says_why_no_mcp_is_judged_from_its_base() {
    let Some(wd) = with_atlas() else { return };
    std::fs::remove_dir_all(wd.path().join("data/literature")).unwrap();
    wd.write("hand.glb", build(&HandSpec::new(Naming::Mixamo)));
    let doc = audit_json(&wd, "hand.glb");
    assert!(
        fingers(&doc)
            .iter()
            .all(|f| f["metacarpal_check"].is_null())
    );
    wd.run(&["audit", "--explain", "hand.glb"])
        .ok()
        .stdout_has("4 MCPs are not judged from the wrist: the rig's tips are read as skin tips")
        .stdout_has("no MCP is judged from its CMC or the wrist")
        .stdout_has("--tip-soft-tissue MM");
}

fn point(v: &Value) -> [f64; 3] {
    [num(&v[0]), num(&v[1]), num(&v[2])]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The Mixamo fixture has `mixamorig:RightHand` and no metacarpals: each
/// finger but the thumb is judged from the wrist, the hand bone's origin, on
/// y = w/J (w the wrist-to-MCP distance, J the compared length); the MCP
/// belongs at S y / (1 + y) from the wrist, S = w + J, y the atlas's mean w/J,
/// and the range and prediction interval of y map the same way.
#[test]
fn a_hand_bone_without_metacarpals_judges_the_mcp_from_the_wrist() {
    let Some(wd) = with_atlas() else { return };
    // MCPs 7 % further from the wrist than the builder's default palm.
    let spec = HandSpec {
        palm: 1.07,
        ..HandSpec::new(Naming::Mixamo)
    };
    wd.write("hand.glb", build(&spec));
    let doc = audit_json(&wd, "hand.glb");
    for f in fingers(&doc) {
        let name = f["finger"].as_str().unwrap();
        let m = &f["metacarpal_check"];
        if name == "thumb" {
            assert!(m.is_null(), "the thumb is not judged from the wrist: {m}");
            continue;
        }
        assert_eq!(m["base"], "wrist", "{name}");
        assert_eq!(m["node"], "mixamorig:RightHand", "{name}");
        assert!(m["base_definition"].as_str().unwrap().contains("capitate"));
        let w = dist(
            point(&f["wrist"]["position"]),
            point(&f["joints"][0]["position"]),
        );
        assert_close(num(&m["to_mcp"]), w, 1e-9, name);
        assert!(
            m["mc"].is_null() && m["values"] == serde_json::json!([]),
            "{m}"
        );
        // J runs to the atlas's tips, at the bone: the rig's skin tip less the finger's
        // measured soft tissue, as a share of the finger.
        let j = num(&m["length"]);
        let share = 1.0 - j / num(&f["audit"]["length"]);
        assert_close(share, super::soft_tissue_share(name), 1e-9, name);
        let y = &m["wrist_over_length"];
        assert_close(num(&y["measured"]), w / j, 1e-9, name);
        assert_eq!(y["n"], 910, "{name}");
        let mean = num(&y["mean"]);
        // The atlas's mean w/J (0.96 ring to 1.19 little; see judge's unit test).
        assert!((0.9..1.25).contains(&mean), "{name}: {mean}");
        let at = |y: f64| (w + j) * y / (1.0 + y);
        assert_close(num(&m["expected"]), at(mean), 1e-9, name);
        for key in ["range", "pi"] {
            for end in 0..2 {
                assert_close(num(&m[key][end]), at(num(&y[key][end])), 1e-9, name);
            }
        }
        // The 95 % t prediction interval of y: mean -/+ t sd sqrt(1 + 1/n),
        // t_{0.975, 909} = 1.9625772 (scipy.stats.t.ppf).
        let half = 1.9625772 * num(&y["sd"]) * (1.0 + 1.0 / 910.0f64).sqrt();
        assert_close(num(&y["pi"][0]), mean - half, 1e-6, name);
        assert_close(num(&y["pi"][1]), mean + half, 1e-6, name);
        // The fixture's palm is a plausible adult's: inside the interval.
        assert!(
            ["in_range", "in_prediction"].contains(&m["standing"].as_str().unwrap()),
            "{name}: {m}"
        );
    }
    let run = wd.run(&["audit", "--explain", "hand.glb"]);
    let words = run
        .ok()
        .stdout
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    run.stdout_has("| MCP from wrist (mm)");
    for needle in [
        "Wrist (mixamorig:RightHand; no metacarpal): wrist to MCP ",
        "0 MCPs lie outside the atlas's 95% prediction interval",
    ] {
        assert!(words.contains(needle), "{needle}\n{words}");
    }
    // The index MCP 1 cm towards the tip: too distal from the wrist too.
    wd.write("web.glb", build(&spec.moved("index", 0, 1.0)));
    let doc = audit_json(&wd, "web.glb");
    assert_eq!(
        finger_of(&doc, "index")["metacarpal_check"]["standing"],
        "above"
    );
    // Without the atlas's landmarks beside its measurements the ratios are
    // unknown: no MCP is judged from the wrist, and a note says why.
    std::fs::remove_file(wd.path().join("data/atlas/landmarks.csv")).unwrap();
    let doc = audit_json(&wd, "hand.glb");
    assert!(
        fingers(&doc)
            .iter()
            .all(|f| f["metacarpal_check"].is_null())
    );
    let out = wd
        .run(&["audit", "--explain", "hand.glb"])
        .ok()
        .stdout
        .clone();
    let words = out.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        words.contains("4 MCPs are not judged from the wrist")
            && words.contains("landmarks.csv beside data/atlas/measurements.csv"),
        "{words}"
    );
    // A landmark file with a bad line is an error naming its line and column.
    let mut bad = std::fs::read_to_string(manifest_dir().join("data/atlas/landmarks.csv")).unwrap();
    bad = bad.replacen(",297,", ",x,", 1);
    wd.write("data/atlas/landmarks.csv", bad.as_bytes());
    wd.run(&["audit", "--explain", "hand.glb"])
        .data_error()
        .stderr_has("data/atlas/landmarks.csv:1:2: x0: image '3142', landmark 0");
}

/// A palm 40 % longer, the fingers as they are: every finger fits the
/// paper's proportions, but its MCP is too far from the wrist. `--strict`
/// counts that, and only with the atlas.
#[test]
fn strict_counts_an_mcp_outside_from_its_base() {
    let Some(wd) = with_atlas() else { return };
    let long = HandSpec {
        palm: 1.4,
        ..HandSpec::new(Naming::Mixamo)
    };
    wd.write("long.glb", build(&long));
    let doc = audit_json(&wd, "long.glb");
    assert!(
        fingers(&doc)
            .iter()
            .all(|f| f["audit"]["explanation"]["moved"] == serde_json::json!([]))
    );
    let outside = fingers(&doc)
        .iter()
        .filter(|f| f["metacarpal_check"]["standing"] == "above")
        .count();
    assert_eq!(outside, 4, "{doc}");
    wd.run(&["audit", "--explain", "long.glb"]).ok();
    let words = |run: &Run| run.stdout.split_whitespace().collect::<Vec<_>>().join(" ");
    let strict = wd.run(&["audit", "--explain", "long.glb", "--strict"]);
    strict.expect_code(1);
    assert!(
        words(&strict).contains("4 MCPs lie outside"),
        "{}",
        strict.stdout
    );
    // Without the atlas nothing is outside.
    std::fs::remove_file(wd.path().join("data/atlas/measurements.csv")).unwrap();
    wd.run(&["audit", "--explain", "long.glb", "--strict"]).ok();
    wd.write("hand.glb", build(&HandSpec::new(Naming::Mixamo)));
    wd.run(&[
        "audit",
        "--explain",
        "hand.glb",
        "--fix",
        "x.glb",
        "--fix-mcp",
        "atlas",
    ])
    .expect_code(2)
    .stderr_has("--fix-mcp atlas needs the metacarpals' dataset");
}

/// `--fix-mcp atlas` moves each MCP outside from its wrist to the atlas's
/// mean when that brings it to its skin bend, keeps the mesh, and a second
/// fix changes nothing.
#[test]
fn fix_mcp_atlas_places_the_mcp_from_its_base_and_keeps_the_mesh() {
    let Some(wd) = with_atlas() else { return };
    // The skin bending at each MCP, the atlas's MCP would leave its bend and
    // is held (the bend guard). So the hand is built twice: once to read
    // where the atlas puts each MCP (`expected - to_mcp`, + towards the tip),
    // and again with each MCP's skin bending there, so each must move.
    let long = |smooth: Vec<(&'static str, usize, f64)>| HandSpec {
        palm: 1.4,
        smooth: Some(smooth),
        ..HandSpec::new(Naming::Mixamo)
    };
    wd.write("probe.glb", build(&long(Vec::new())));
    let probe = audit_json(&wd, "probe.glb");
    let bends: Vec<(&'static str, usize, f64)> = ["index", "middle", "ring", "little"]
        .into_iter()
        .map(|name| {
            let m = &finger_of(&probe, name)["metacarpal_check"];
            (name, 0, (num(&m["expected"]) - num(&m["to_mcp"])) * 1e3)
        })
        .collect();
    assert!(bends.iter().all(|b| b.2 < -1.0), "{bends:?}");
    let input = build(&long(bends));
    wd.write("long.glb", &input);
    let before = audit_json(&wd, "long.glb");
    let run = wd.run(&[
        "audit",
        "--explain",
        "long.glb",
        "--fix",
        "fixed.glb",
        "--fix-mcp",
        "atlas",
    ]);
    run.ok();
    // Read as words, across the wrap.
    let words = run.stderr.split_whitespace().collect::<Vec<_>>().join(" ");
    // Every MCP placed inside; with the weights carried, the middle, ring
    // and little fingers' PIPs and DIPs then move to where the X-rays put
    // them given the placed MCPs (the index, on the region's shape pooled
    // with the atlas's, lies inside at 0.76 of its bound with its MCP alone
    // placed, and keeps its own; the thumb has no metacarpal check here and
    // fits as built). The line says so finger by finger.
    assert!(
        words.contains("10 joints moved; re-audited, 0 of 5 fingers outside the 95% joint region, 0 of 4 MCPs outside"),
        "{}",
        run.stderr
    );
    assert!(
        words.contains("each moved finger after the fix: right index T^2 19.3 of 25.5 (0.76), right middle T^2 0.0 of 25.5 (0.00)"),
        "{}",
        run.stderr
    );
    // Each MCP now within 1 mm of where its skin bends (12-18 mm before).
    for name in ["index", "middle", "ring", "little"] {
        let each = format!("right {name} MCP ");
        let after = words
            .split(&each)
            .nth(1)
            .and_then(|w| w.split("-> ").nth(1))
            .and_then(|w| w.split(' ').next())
            .and_then(|w| w.parse::<f64>().ok());
        assert!(after.is_some_and(|d| d < 1.0), "{name}: {}", run.stderr);
    }
    // The summary is wrapped to the 100 columns of a pipe, like the table.
    assert!(
        run.stderr.lines().all(|l| l.chars().count() <= 100),
        "{}",
        run.stderr
    );
    let fixed = wd.read("fixed.glb");
    assert!(worst_vertex_move(&input, &fixed) < 1e-5);
    let after = audit_json(&wd, "fixed.glb");
    for f in fingers(&after) {
        let name = f["finger"].as_str().unwrap();
        if name == "thumb" {
            continue;
        }
        let m = &f["metacarpal_check"];
        assert_eq!(m["standing"], "in_range", "{name}: {m}");
        // At the atlas's mean, where the input's check put it.
        let old = &finger_of(&before, name)["metacarpal_check"];
        let mcp = point(&f["joints"][0]["position"]);
        assert!(dist(mcp, point(&old["suggested"])) < 1e-6, "{name}");
        // (Not exactly at the new mean: PIP and DIP then moved on the bent
        // chain, which changes J and so the expected position, < 1 mm here.)
    }
    // Without --fix-mcp the fix leaves these MCPs alone (the fingers fit).
    wd.run(&["audit", "--explain", "long.glb", "--fix", "plain.glb"])
        .ok()
        .stderr_has("nothing to fix: no joint moves, so plain.glb was not written");
    wd.run(&[
        "audit",
        "--explain",
        "fixed.glb",
        "--fix",
        "again.glb",
        "--fix-mcp",
        "atlas",
    ])
    .ok()
    .stderr_has("nothing to fix: no joint moves, so again.glb was not written");
    assert!(
        !wd.path().join("again.glb").exists(),
        "a second fix wrote a file"
    );
}
