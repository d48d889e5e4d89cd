//! What the audit takes the X-rays' fingertips as when their tip column does not record
//! one kind: said in the text (a warning, the summary, the caveats) and in the JSON, and
//! the judgement it drives (the same rows recorded at the skin are judged otherwise).

use super::fingers;
use super::hand::{HandSpec, Naming, build};
use crate::common::*;
use serde_json::Value;

/// Terminal text unwrapped, so each paragraph is one line.
const WIDE: &[(&str, &str)] = &[("COLUMNS", "2000")];

/// The audit of the test hand (skin tips) against `data`, 4 mm of soft tissue between
/// bone and skin tips (no table is found in the test's directory).
fn audit(wd: &Workdir, data: &str, json: bool) -> Run {
    let mut args = vec![
        "audit",
        "hand.glb",
        "--data",
        data,
        "--tip-soft-tissue",
        "4",
    ];
    if json {
        args.extend(["--format", "json"]);
    } else {
        args.push("--explain");
    }
    let run = wd.run_env(&args, WIDE);
    run.ok();
    run
}

/// Each finger's T^2 in the joint region, by finger.
fn t2(doc: &Value) -> Vec<(String, f64)> {
    fingers(doc)
        .iter()
        .map(|f| {
            (
                f["finger"].as_str().unwrap().to_string(),
                num(&f["audit"]["region"]["t2"]),
            )
        })
        .collect()
}

const WARNING: &str = "lab.csv's fingertips are not recorded, so the audit takes them all as \
    bone tips (the usual landmark on an X-ray), and the verdicts of the fingers with a tip rest \
    on that assumption: a last segment to the skin is longer than one to the bone by the \
    fingertip's soft tissue. Record where the X-rays' tips were measured in lab.csv's tip column \
    (bone or skin)";

const CAVEAT: &str = "A rig's tip usually sits at the skin. The X-ray tips of lab.csv are not \
    recorded, so they are all taken as bone tips (the usual landmark on an X-ray), and a rig's \
    tips at the skin are compared with them corrected by the fingertip's soft tissue Buryanov & \
    Kotiuk measured for that finger (66 adults, 3.7 to 5.7 mm), as a share of the rig's finger; \
    --tip-soft-tissue MM sets one length for every finger instead. The verdicts of the fingers \
    with a tip rest on that assumption, since a last segment to the skin is longer than one to \
    the bone by that soft tissue: record where the X-rays' tips were measured in the tip column \
    (bone or skin).";

#[test]
fn unrecorded_tips_are_taken_as_bone_tips_and_the_audit_says_so() {
    let wd = Workdir::with_paper_data();
    wd.write("hand.glb", build(&HandSpec::new(Naming::Mixamo)));
    // The paper's rows without their tip column.
    wd.write("lab.csv", measurement_csv(&paper_rows()));

    let text = audit(&wd, "lab.csv", false).stdout.clone();
    assert!(text.contains(&format!("\nWarning: {WARNING}\n")), "{text}");
    assert!(
        text.contains(
            "The verdicts of the fingers with a tip take the X-rays' fingertips as bone tips, an \
             assumption: their tip column records none.\n"
        ),
        "{text}"
    );
    assert!(text.contains(&format!("\n  - {CAVEAT}\n")), "{text}");
    assert!(!text.contains("so do the paper's X-ray tips"), "{text}");
    // --brief keeps the assumption, in its summary.
    let brief = wd.run_env(
        &[
            "audit",
            "hand.glb",
            "--data",
            "lab.csv",
            "--tip-soft-tissue",
            "4",
            "--brief",
        ],
        WIDE,
    );
    brief
        .ok()
        .stdout_has("an assumption: their tip column records none.");

    let doc = audit(&wd, "lab.csv", true).json();
    let tips = &doc["rig"]["tips"];
    assert_eq!(tips["data_tip"], "bone");
    assert_eq!(
        tips["data_tips"],
        serde_json::json!({"bone": 0, "skin": 0, "unknown": 25})
    );
    assert_eq!(doc["rig"]["warnings"], serde_json::json!([WARNING]));
    assert_eq!(doc["caveats"][2], CAVEAT);

    // The same rows recorded at the skin (the paper's file): no assumption, and other
    // T^2 for every finger, the soft tissue no longer taken off the rig's last segment.
    let paper = audit(&wd, "data/measurements.csv", true).json();
    assert_eq!(paper["rig"]["tips"]["data_tip"], "skin");
    assert_eq!(paper["rig"]["warnings"], serde_json::json!([]));
    assert!(
        paper["caveats"][2]
            .as_str()
            .unwrap()
            .starts_with("A rig's tip usually sits at the skin, and so do the paper's X-ray tips"),
        "{}",
        paper["caveats"][2]
    );
    let (assumed, recorded) = (t2(&doc), t2(&paper));
    assert_eq!(assumed.len(), 5);
    for ((finger, a), (_, r)) in assumed.iter().zip(&recorded) {
        assert!(
            (a - r).abs() > 0.1,
            "{finger}: T^2 {a} taken as bone, {r} at the skin"
        );
    }
    let paper_text = audit(&wd, "data/measurements.csv", false).stdout.clone();
    assert!(!paper_text.contains("Warning:"), "{paper_text}");
    assert!(!paper_text.contains("assumption"), "{paper_text}");

    // Mixed: the rows at the skin and those not recorded are named, and all taken as bone.
    let mut mixed = paper_data();
    mixed.extend_from_slice(b"5a,index,352.1,201.4,178.0,,,,,image units,\n");
    wd.write("mixed.csv", mixed);
    let doc = audit(&wd, "mixed.csv", true).json();
    assert_eq!(doc["rig"]["tips"]["data_tip"], "bone");
    let w = doc["rig"]["warnings"][0].as_str().unwrap();
    assert!(
        w.starts_with(
            "mixed.csv's fingertips are mixed: 25 rows at the skin, 1 row not recorded, so the \
             audit takes them all as bone tips"
        ),
        "{w}"
    );
    assert!(
        doc["caveats"][2]
            .as_str()
            .unwrap()
            .contains("The X-ray tips of mixed.csv are mixed (25 rows at the skin, 1 row not recorded), so they are all taken as bone tips"),
        "{}",
        doc["caveats"][2]
    );
}
