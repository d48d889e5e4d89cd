//! One judgement per ray: the finger's own proportions and its MCP from the
//! wrist or CMC weighed together, so no two parts of the output contradict
//! each other (issue: the Daz-style middle finger that got "MCP too distal"
//! from the finger and "MCP in range" from the wrist).

use super::hand::{HandSpec, Naming, build};
use super::{finger_of, fingers, joint_of};
use crate::common::*;
use serde_json::Value;

/// The Daz-like case: the middle finger's PIP 8 mm and DIP 6 mm too proximal
/// with the tip where it was, so the finger alone reads its MCP as too distal
/// (at the finger's web), while the wrist, untouched, puts the MCP in range.
/// The palm is 3% longer than built (the built middle MCP sits 1.0 mm below
/// the wrist's 95% prediction interval, [94.1, 102.2] mm, at 93.1 mm).
fn daz_like() -> Vec<u8> {
    let mut spec = HandSpec::new(Naming::Mixamo)
        .moved("middle", 1, -0.8)
        .moved("middle", 2, 0.2)
        .moved("middle", 3, 0.6);
    spec.palm = 1.03;
    build(&spec)
}

#[test]
fn the_daz_like_middle_finger_moves_its_pip_and_dip_not_the_mcp_the_wrist_puts_in_range() {
    let Some(wd) = super::ray::with_atlas() else {
        return;
    };
    wd.write("daz.glb", daz_like());
    // The finger alone (no atlas: --metacarpals none is not an option, so a
    // workdir without it) names the MCP.
    let alone = Workdir::new();
    alone.copy_paper_data();
    alone.write("daz.glb", daz_like());
    let doc = alone
        .run(&["audit", "daz.glb", "--format", "json"])
        .ok()
        .json();
    let middle = finger_of(&doc, "middle");
    assert!(
        middle["audit"]["explanation"]["moved"]
            .as_array()
            .unwrap()
            .contains(&Value::from("MCP")),
        "the finger alone should name the MCP: {}",
        middle["audit"]["explanation"]
    );

    let doc = wd
        .run(&["audit", "daz.glb", "--format", "json"])
        .ok()
        .json();
    let middle = finger_of(&doc, "middle");
    let check = &middle["metacarpal_check"];
    assert_eq!(check["base"], "wrist", "{check}");
    assert!(
        check["standing"] == "in_range" || check["standing"] == "in_prediction",
        "{check}"
    );
    let mcp = joint_of(middle, "MCP");
    assert_eq!(mcp["held"]["reason"], "base", "{mcp}");
    assert_eq!(mcp["moves"], false, "{mcp}");
    let moved: Vec<&str> = middle["audit"]["explanation"]["moved"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(!moved.contains(&"MCP"), "{moved:?}");
    assert!(moved.contains(&"PIP"), "{moved:?}");
    // The explanation moves the PIP towards the tip, about the 8 mm it was
    // moved back (within the prediction interval's give).
    let pip = joint_of(middle, "PIP");
    assert!(num(&pip["shift_along"]) > 0.003, "{pip}");

    // The text: the opening holds the MCP for its base and moves the PIP, and
    // adds no base clause (the base agrees with the line).
    let text = wd.run(&["audit", "daz.glb"]).ok().stdout.clone();
    let line = text
        .lines()
        .find(|l| l.starts_with("right middle") || l.starts_with("middle"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(line.contains("the MCP"), "{line}");
    assert!(text.contains("(in range from its base)"), "{text}");
    assert!(!line.contains("--fix-mcp atlas places it"), "{line}");
    let words = mcp["held"]["words"].as_str().unwrap();
    assert!(
        words.starts_with("held: from the wrist (mixamorig:RightHand) the atlas puts it in range"),
        "{words}"
    );
    let explanation = text
        .split("right middle:")
        .nth(1)
        .and_then(|s| s.split("Explanation:").nth(1))
        .unwrap_or_else(|| panic!("{text}"));
    let flat = explanation.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains(words.trim_start_matches("held: ")), "{flat}");

    // --fix writes the PIP's move and leaves the MCP where it is.
    let out = wd
        .run(&["audit", "daz.glb", "--fix", "fixed.glb", "--format", "json"])
        .ok()
        .json();
    let written: Vec<String> = out["fix"]["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap_or_default().to_string())
        .collect();
    let names: Vec<String> = fingers(&doc)
        .iter()
        .filter(|f| f["finger"] == "middle")
        .flat_map(|f| f["joints"].as_array().unwrap().clone())
        .map(|j| {
            format!(
                "{}={}",
                j["joint"].as_str().unwrap(),
                j["name"].as_str().unwrap()
            )
        })
        .collect();
    let node = |joint: &str| {
        names
            .iter()
            .find_map(|n| n.strip_prefix(&format!("{joint}=")))
            .unwrap()
            .to_string()
    };
    assert!(!written.contains(&node("MCP")), "{written:?}");
    assert!(written.contains(&node("PIP")), "{written:?}");
}
