//! The audit's opening (one line per finger: its verdict and its move),
//! `--brief`, and `--hold`, the joints the artist pins.

use super::hand::{HandSpec, Naming, build, read_glb};
use super::{assert_held, finger_of, fingers, index_dip_inside_yet_explaining, joint_of};
use crate::common::*;
use serde_json::Value;
use std::path::PathBuf;

/// The opening of an audit's text: its lines before the first blank one,
/// each finger's wrapped continuation joined back onto it with one space.
fn opening(text: &str) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for line in text
        .lines()
        .take_while(|l| !l.trim().is_empty() && !l.starts_with("Against"))
    {
        match lines.last_mut() {
            Some(last) if line.starts_with(' ') => {
                last.push(' ');
                last.push_str(line.trim_start());
            }
            _ => lines.push(line.to_string()),
        }
    }
    lines
}

/// "A", "A and B", "A, B and C".
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// A finger's label as the text gives it: "right index", or "index" without a side.
fn label(finger: &Value) -> String {
    match finger["side"].as_str() {
        Some(side) => format!("{side} {}", finger["finger"].as_str().unwrap()),
        None => finger["finger"].as_str().unwrap().to_string(),
    }
}

/// The opening line a finger of the JSON document should have, built from the
/// JSON alone (the independent source): a joint with `held` is held, with the
/// move it gives up (`held.shift`, mm to 0.1) and the reason's words the issue
/// asks for; a joint that `moves` by a `shift` above 0 and is not held moves,
/// towards the tip when `shift_along` >= 0; nothing to do is "keep".
fn expected_line(finger: &Value) -> String {
    let audit = &finger["audit"];
    if audit["basis"] == "none" {
        return "not judged (a thumb without a tip has no proportion)".into();
    }
    let mm = |v: &Value| format!("{:.1}", num(v) * 1000.0);
    // Moves the same way, one after the other, are said once: "the PIP 9.2 mm
    // and the DIP 4.1 mm towards the tip".
    let mut moves: Vec<(Vec<String>, &str)> = Vec::new();
    let mut held = Vec::new();
    for j in audit["joints"].as_array().unwrap() {
        let name = j["joint"].as_str().unwrap();
        if let Some(h) = j.get("held") {
            let why = match h["reason"].as_str().unwrap() {
                "bend" => "would leave its skin bend",
                "small" => "under the 1.0 mm tolerance",
                "knuckle" => "a knuckle",
                "pinned" => "pinned by --hold",
                "base" => "in range from its base",
                "base_opposes" => "its base puts it the other way",
                "short" => "the finger would stay outside the 50% region",
                "carry" => "its skin cannot follow it",
                other => panic!("unknown hold reason {other}"),
            };
            // A move that prints as 0.0 mm is no move; an MCP's is told by
            // its reason alone (the line's MCP distance is its base's).
            if mm(&h["shift"]) == "0.0" {
                continue;
            }
            if name == "MCP" {
                held.push(format!("the MCP ({why})"));
            } else {
                held.push(format!("the {name} {} mm ({why})", mm(&h["shift"])));
            }
        } else if j["fix"] == true {
            assert_eq!(j["explains"], true, "{j}");
            let towards = if num(&j["shift_along"]) >= 0.0 {
                "tip"
            } else {
                "root"
            };
            let w = format!("the {name} {} mm", mm(&j["shift"]));
            match moves.last_mut() {
                Some((ws, to)) if *to == towards => ws.push(w),
                _ => moves.push((vec![w], towards)),
            }
        }
    }
    let moves: Vec<String> = moves
        .iter()
        .map(|(ws, to)| format!("{} towards the {to}", and_list(ws)))
        .collect();
    let fits = audit["explanation"]["consistent"] == true;
    let mut parts = Vec::new();
    if !moves.is_empty() {
        let closest = if fits {
            ""
        } else {
            " (the closest: no move of up to two joints fits the X-rays)"
        };
        parts.push(format!("move {}{closest}", and_list(&moves)));
    }
    if !held.is_empty() {
        parts.push(format!("held: {}", and_list(&held)));
    }
    let line = match (parts.is_empty(), fits) {
        (false, _) => parts.join("; "),
        (true, true) => "keep".into(),
        (true, false) => "keep: no move of up to two joints fits the X-rays".into(),
    };
    // The MCP from the ray's base, whenever the base puts it outside (the
    // summary counts each such MCP).
    let check = &finger["metacarpal_check"];
    let outside = matches!(check["standing"].as_str(), Some("above" | "below"));
    if !outside {
        return line;
    }
    let base = match check["base"].as_str().unwrap() {
        "cmc" => "its CMC",
        _ => "the wrist",
    };
    let way = if check["standing"] == "above" {
        "distal"
    } else {
        "proximal"
    };
    let clause = format!(
        "the MCP from {base}: OUT, {} mm too {way}",
        mm(&check["by"])
    );
    if line == "keep" {
        format!("keep the finger; {clause}")
    } else {
        format!("{line}; {clause}")
    }
}

/// Asserts that the text audit of `rig` (with `extra` options) opens with one
/// line per finger of its JSON audit, in order, each its label then
/// [`expected_line`], within 100 columns; returns how many fingers moved or held.
fn assert_opening_agrees(wd: &Workdir, rig: &str, extra: &[&str]) -> usize {
    let mut args = vec!["audit", rig];
    args.extend_from_slice(extra);
    let text = wd.run(&args).ok().stdout.clone();
    args.extend(["--format", "json"]);
    let doc = wd.run(&args).ok().json();
    let lines = opening(&text);
    let fingers = fingers(&doc);
    assert_eq!(lines.len(), fingers.len(), "{rig}: {text}");
    for (line, f) in lines.iter().zip(fingers) {
        let label = label(f);
        let words = line
            .strip_prefix(&label)
            .unwrap_or_else(|| panic!("{rig}: {line:?} does not start with {label}"));
        assert!(words.starts_with("  "), "{rig}: {line:?}");
        assert_eq!(words.trim_start(), expected_line(f), "{rig}: {label}");
    }
    for l in text.lines() {
        assert!(l.chars().count() <= 100, "{rig}: wider than 100: {l:?}");
    }
    lines.iter().filter(|l| !l.ends_with("  keep")).count()
}

/// A rig of ../shared/rigs, or `None` with the reason printed.
fn shared_rig(path: &str) -> Option<String> {
    let full: PathBuf = manifest_dir().join("../shared/rigs").join(path);
    if full.is_file() {
        Some(full.display().to_string())
    } else {
        skip(format!("{} is absent", full.display()));
        None
    }
}

#[test]
fn the_opening_lines_agree_with_the_json_moves_on_real_rigs() {
    let Some(wd) = super::ray::with_atlas() else {
        return;
    };
    let mut rigs = Vec::new();
    for path in [
        "godot-openxr-humanoid-hands/RightHandHumanoid.gltf",
        "godot-xr-tools-hands/hand_r.gltf",
        "gdquest-mannequiny/mannequiny.glb",
        "webxr-generic-hand/right.glb",
    ] {
        rigs.extend(shared_rig(path));
    }
    if let Some(bytes) = vendored("data/rigs/webxr-generic-hand/left.glb") {
        wd.write("left.glb", &bytes);
        rigs.push("left.glb".into());
    }
    let mut not_kept = 0;
    for rig in &rigs {
        not_kept += assert_opening_agrees(&wd, rig, &[]);
        // --fix-mcp atlas moves MCPs: the opening follows what that fix does.
        not_kept += assert_opening_agrees(
            &wd,
            rig,
            &["--fix-mcp", "atlas", "--moves", "m.csv", "--force"],
        );
        not_kept += assert_opening_agrees(&wd, rig, &["--hold", "pip,ip"]);
    }
    // The rigs have fingers to move or hold (the check compared more than "keep").
    assert!(rigs.is_empty() || not_kept > 0);
}

/// The test rig with its index PIP 5 mm towards the tip, on a smooth skin
/// that bends at each joint (so the fix carries the weights with the joint):
/// the fix moves that PIP alone.
fn index_pip_off(wd: &Workdir) -> Vec<u8> {
    let mut spec = HandSpec::new(Naming::Mixamo).moved("index", 1, 0.5);
    spec.smooth = Some(Vec::new());
    let input = build(&spec);
    wd.write("hand.glb", &input);
    input
}

#[test]
fn the_opening_of_a_built_rig_names_its_move() {
    let wd = Workdir::with_paper_data();
    index_pip_off(&wd);
    assert_opening_agrees(&wd, "hand.glb", &[]);
    let text = wd
        .run(&["audit", "--explain", "hand.glb"])
        .ok()
        .stdout
        .clone();
    let lines = opening(&text);
    // Built with the index PIP 5.0 mm distal of X-ray 1b's (hand.rs): the
    // line names that joint and direction; the other fingers are X-ray 1b's own.
    let index = lines.iter().find(|l| l.starts_with("right index")).unwrap();
    assert!(
        index.contains("move the PIP ") && index.ends_with("mm towards the root"),
        "{index}"
    );
    for finger in ["thumb", "middle", "ring", "little"] {
        let line = lines
            .iter()
            .find(|l| l.starts_with(&format!("right {finger}")))
            .unwrap();
        assert!(line.ends_with("  keep"), "{line}");
    }
    // The details follow the opening.
    assert!(text.contains("\n\nRig audit of hand.glb"), "{text}");
}

/// The lines of the paragraph of `text` that starts with `start`, up to the
/// next line that is not indented.
fn paragraph<'a>(text: &'a str, start: &str) -> Vec<&'a str> {
    let mut lines = text.lines().skip_while(|l| !l.starts_with(start));
    let mut out: Vec<&str> = lines.next().into_iter().collect();
    out.extend(lines.take_while(|l| l.starts_with(' ')));
    out
}

#[test]
fn brief_prints_the_opening_and_the_result_line_only() {
    let wd = Workdir::with_paper_data();
    index_pip_off(&wd);
    // The expected lines are cut from the full output: its opening and its summary.
    let full = wd
        .run(&["audit", "--explain", "hand.glb"])
        .ok()
        .stdout
        .clone();
    let head: Vec<&str> = full.lines().take_while(|l| !l.is_empty()).collect();
    let summary = paragraph(&full, "Summary: ");
    assert!(!head.is_empty() && !summary.is_empty(), "{full}");
    let mut expected: Vec<&str> = head.clone();
    expected.extend(&summary);
    let brief = wd
        .run(&["audit", "hand.glb", "--brief"])
        .ok()
        .stdout
        .clone();
    assert_eq!(brief.lines().collect::<Vec<_>>(), expected, "{brief}");
    assert!(brief.ends_with('\n'));

    // With --fix: the opening on standard output, the fix's line on standard
    // error, as the full run writes it, and nothing else.
    let run = wd.run(&["audit", "--explain", "hand.glb", "--fix", "a.glb"]);
    let full_fix = run.ok().stderr.clone();
    let result = paragraph(&full_fix, "wrote a.glb: ");
    assert!(result[0].contains("1 joint moved"), "{full_fix}");
    let run = wd.run(&["audit", "hand.glb", "--fix", "b.glb", "--brief"]);
    let out = run.ok();
    assert_eq!(out.stdout.lines().collect::<Vec<_>>(), head);
    let stderr: Vec<String> = out
        .stderr
        .lines()
        .map(|l| l.replace("wrote b.glb", "wrote a.glb"))
        .collect();
    assert_eq!(stderr, result, "{}", out.stderr);
    assert_eq!(wd.read("a.glb"), wd.read("b.glb"), "the same fix");
    // --brief shortens the text; JSON has every value, so the two are refused together.
    wd.run(&["audit", "hand.glb", "--brief", "--format", "json"])
        .expect_code(2)
        .stderr_has("--brief");
}

/// The world position of node `name` in a GLB.
fn position(bytes: &[u8], name: &str) -> [f64; 3] {
    let (doc, _) = read_glb(bytes);
    super::node_position(&doc, name)
}

#[test]
fn hold_pip_keeps_the_pip_in_the_json_and_the_fixed_file() {
    let wd = Workdir::with_paper_data();
    let input = index_pip_off(&wd);
    let pip = "mixamorig:RightHandIndex2";
    // Unheld, the fix moves the index PIP (the precondition of the test).
    let doc = wd
        .run(&["audit", "hand.glb", "--fix", "free.glb", "--format", "json"])
        .ok()
        .json();
    assert_eq!(doc["fix"]["moved"][0]["node"], pip, "{}", doc["fix"]);
    // Back towards where it was built, to where the X-rays put it given the
    // other joints: near the 5 mm it was pushed (within 2 mm: the built
    // finger is not at the X-rays' mean), not only to the region's edge.
    let free = num(&joint_of(finger_of(&doc, "index"), "PIP")["shift"]);
    assert!(free > 0.003 && free < 0.007, "{free}");
    assert!(
        num(&doc["fix"]["fingers"][0]["t2"]) / num(&doc["fix"]["fingers"][0]["bound"]) < 0.1,
        "{}",
        doc["fix"]
    );

    let doc = wd
        .run(&[
            "audit", "hand.glb", "--hold", "pip", "--fix", "held.glb", "--format", "json",
        ])
        .ok()
        .json();
    let index = finger_of(&doc, "index");
    let j = joint_of(index, "PIP");
    assert_eq!(j["explains"], false, "{j}");
    assert_eq!(j["shift"], 0.0, "{j}");
    assert_held(j, "pinned", "held: pinned by --hold");
    // What it gives up is the move the unheld audit makes.
    assert_close(num(&j["held"]["shift"]), free, 1e-9, "the move given up");
    assert!(
        !index["audit"]["explanation"]["moved"]
            .as_array()
            .unwrap()
            .contains(&Value::from("PIP")),
        "{index}"
    );
    let moved: Vec<&str> = doc["fix"]["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap())
        .collect();
    // No PIP of any finger moves in the fixed file (none is written when
    // nothing moves).
    let fixed = if doc["fix"]["written"] == true {
        wd.read("held.glb")
    } else {
        assert!(moved.is_empty(), "{moved:?}");
        assert!(!wd.path().join("held.glb").exists());
        input.clone()
    };
    for finger in ["Index", "Middle", "Ring", "Pinky"] {
        let node = format!("mixamorig:RightHand{finger}2");
        assert!(!moved.contains(&node.as_str()), "{moved:?}");
        let (a, b) = (position(&input, &node), position(&fixed, &node));
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-7, "{node}: {a:?} -> {b:?}");
        }
    }
    // The text says so, in the opening and in the table.
    let text = wd
        .run(&["audit", "--explain", "hand.glb", "--hold", "pip"])
        .ok()
        .stdout
        .clone();
    let line = opening(&text)
        .into_iter()
        .find(|l| l.starts_with("right index"))
        .unwrap();
    assert!(
        line.contains(&format!(
            "the PIP {:.1} mm (pinned by --hold)",
            free * 1000.0
        )),
        "{line}"
    );
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains("held: pinned by --hold"), "{text}");
    assert_opening_agrees(&wd, "hand.glb", &["--hold", "pip"]);
}

#[test]
fn a_bad_hold_exits_2_naming_the_value() {
    let wd = Workdir::with_paper_data();
    index_pip_off(&wd);
    wd.run(&["audit", "--explain", "hand.glb", "--hold", "pip,knuckle"])
        .expect_code(2)
        .stderr_has("'knuckle'")
        .stderr_has("mcp, pip, dip, ip or tip");
    // Any case, with the fix too.
    wd.run(&[
        "audit",
        "--explain",
        "hand.glb",
        "--hold",
        "PIP,Dip",
        "--fix",
        "x.glb",
    ])
    .ok();
}

#[test]
fn with_only_outside_the_opening_holds_a_joint_inside_its_interval() {
    let wd = Workdir::with_paper_data();
    // The DIP alone explains the misfit, yet stands inside its own
    // interval, so --only-outside leaves it (the fix writes 0 moves).
    let input = index_dip_inside_yet_explaining();
    wd.write("index.glb", &input);
    let index = |args: &[&str]| -> String {
        let run = wd.run(args);
        opening(&run.ok().stdout)
            .into_iter()
            .find(|l| l.starts_with("right index"))
            .unwrap()
    };
    let free = index(&["audit", "--explain", "index.glb", "--fix", "a.glb"]);
    assert!(free.contains("move the DIP "), "{free}");
    let held = index(&[
        "audit",
        "--explain",
        "index.glb",
        "--fix",
        "b.glb",
        "--only-outside",
    ]);
    assert!(
        held.contains("held: the DIP ")
            && held.ends_with("mm (inside its own prediction interval; --only-outside)"),
        "{held}"
    );
    // Without a fix --only-outside decides nothing, and the line is the plain one.
    assert_eq!(
        index(&["audit", "--explain", "index.glb", "--only-outside"]),
        free
    );
}

#[test]
fn hold_mcp_keeps_the_mcps_that_fix_mcp_atlas_moves() {
    let Some(wd) = super::ray::with_atlas() else {
        return;
    };
    let Some(input) = vendored("data/rigs/webxr-generic-hand/right.glb") else {
        return;
    };
    wd.write("right.glb", &input);
    let mcp = "index-finger-phalanx-proximal";
    let fix = |out: &str, extra: &[&str]| -> Value {
        let mut args = vec!["audit", "right.glb", "--fix-mcp", "atlas", "--fix", out];
        args.extend_from_slice(extra);
        args.extend(["--format", "json"]);
        wd.run(&args).ok().json()
    };
    let moved = |doc: &Value| -> Vec<String> {
        doc["fix"]["moved"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["node"].as_str().unwrap().to_string())
            .collect()
    };
    // Unheld, the atlas moves the index MCP (its MCP lies outside from its CMC).
    let free = fix("free.glb", &[]);
    assert!(moved(&free).iter().any(|n| n == mcp), "{}", free["fix"]);
    let held = fix("held.glb", &["--hold", "mcp"]);
    let fixed = wd.read("held.glb");
    for f in fingers(&held) {
        let j = joint_of(f, "MCP");
        assert_eq!(j["explains"], false, "{j}");
        let node = f["joints"][0]["name"].as_str().unwrap();
        assert!(!moved(&held).iter().any(|n| n == node), "{node}");
        let (a, b) = (position(&input, node), position(&fixed, node));
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-7, "{node}: {a:?} -> {b:?}");
        }
    }
}
