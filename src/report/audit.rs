//! The words and tables of a rig audit (`phalanx audit`, and the report's rig section).
//!
//! Rig coordinates are taken as metres (the glTF unit) and shown in millimetres.

use crate::analysis::Quantity;
use crate::format::{level, num};
use crate::rig::judge::{Basis, FingerAudit, Standing};
use crate::rig::{AuditedFinger, AuditedRig};

/// Millimetres per rig unit (glTF units are metres).
pub(crate) const MM: f64 = 1000.0;

/// The caveats every audit carries.
pub(crate) const CAVEATS: [&str; 3] = [
    "The statistics come from X-rays of right hands; a left hand is judged as their mirror image.",
    "A rig's joints are rotation centres, while the X-ray lengths run between bone ends; the two differ by a few per cent, so read the prediction interval as a guide, not a verdict.",
    "A rig's tip usually sits at the skin and so includes the fingertip's soft tissue, which the distal phalanx on an X-ray does not; this lengthens a rig's last segment.",
];

/// "inside the X-ray range", "OUTSIDE: too far towards the tip, 2.10 mm beyond the
/// prediction interval", ...: how a joint stands.
pub(crate) fn joint_standing(s: Standing, scale: f64) -> String {
    match s {
        Standing::InRange => "inside the X-ray range".into(),
        Standing::InPrediction => "inside the prediction interval".into(),
        Standing::Above { by } => {
            format!(
                "OUTSIDE: too far towards the tip, {} mm beyond the prediction interval",
                num(by * scale, 2)
            )
        }
        Standing::Below { by } => {
            format!(
                "OUTSIDE: too close to the root, {} mm beyond the prediction interval",
                num(by * scale, 2)
            )
        }
    }
}

/// How a unitless value stands.
pub(crate) fn value_standing(s: Standing) -> String {
    match s {
        Standing::InRange => "inside the X-ray range".into(),
        Standing::InPrediction => "inside the prediction interval".into(),
        Standing::Above { by } => format!("OUTSIDE: {} above the prediction interval", num(by, 4)),
        Standing::Below { by } => format!("OUTSIDE: {} below the prediction interval", num(by, 4)),
    }
}

/// What a finger was judged on, in words.
pub(crate) fn basis_words(a: &FingerAudit) -> String {
    match a.basis {
        Basis::Relative => "judged on relative values (the rig has a tip)".into(),
        Basis::Ratio => "judged on J2/J1 only: the rig has no tip, so the finger's length, its DIP and J3 cannot be judged".into(),
        Basis::None => "not judged: a thumb without a tip has one segment, and one segment has no proportion".into(),
    }
}

/// A finger's heading: label, node names, segment lengths and length.
pub(crate) fn heading(f: &AuditedFinger) -> String {
    let names: Vec<&str> = f.chain.joints.iter().map(|j| j.name.as_str()).collect();
    let segments: Vec<String> = f
        .audit
        .segments
        .iter()
        .enumerate()
        .map(|(k, c)| format!("J{} {}", k + 1, num(c * MM, 2)))
        .collect();
    let length = f
        .audit
        .length
        .map(|l| format!(", length {} mm", num(l * MM, 2)))
        .unwrap_or_else(|| " mm".to_string());
    format!(
        "{} ({})\n  segments {}{length}",
        f.chain.label(),
        names.join(", "),
        segments.join(", ")
    )
}

/// The suggestion for one joint, in words.
pub(crate) fn suggestion(j: &crate::rig::judge::JointCheck) -> String {
    let towards = if j.shift_along >= 0.0 {
        "towards the tip"
    } else {
        "towards the root"
    };
    if j.shift * MM < 0.005 {
        "at the mean already".into()
    } else {
        format!(
            "move {} mm {towards}, to ({}, {}, {}) m in glTF world space (Y up)",
            num(j.shift * MM, 2),
            num(j.suggested[0], 5),
            num(j.suggested[1], 5),
            num(j.suggested[2], 5)
        )
    }
}

/// The terminal report of `phalanx audit`.
pub(crate) fn text(rig: &AuditedRig, data: &str, n_note: &str, confidence: f64) -> String {
    let c = level(confidence);
    let mut out = format!(
        "Rig audit of {} against {data} ({n_note}); lengths in mm (glTF units are metres), {c} prediction intervals\n",
        rig.label
    );
    for f in &rig.fingers {
        out.push_str(&format!("\n{}\n  {}\n", heading(f), basis_words(&f.audit)));
        if f.audit.joints.is_empty() {
            continue;
        }
        let pi_head = format!("prediction {c}");
        let header = ["", "rig", "X-ray mean", "X-ray range", &pi_head, "standing"];
        // Left-aligned throughout, as the standings are sentences.
        let mut t = super::text::table(&header, header.len());
        for j in &f.audit.joints {
            t.add_row(vec![
                format!("{} from root (mm)", j.joint.name()),
                num(j.measured * MM, 2),
                num(j.expected * MM, 2),
                format!(
                    "[{}, {}]",
                    num(j.range.low * MM, 2),
                    num(j.range.high * MM, 2)
                ),
                j.pi.map_or("n/a".into(), |p| {
                    format!("[{}, {}]", num(p.low * MM, 2), num(p.high * MM, 2))
                }),
                joint_standing(j.standing, MM),
            ]);
        }
        for v in &f.audit.values {
            t.add_row(vec![
                v.quantity.label().to_string(),
                num(v.measured, 4),
                num(v.mean, 4),
                format!("[{}, {}]", num(v.range.low, 4), num(v.range.high, 4)),
                v.pi.map_or("n/a".into(), |p| {
                    format!("[{}, {}]", num(p.low, 4), num(p.high, 4))
                }),
                value_standing(v.standing),
            ]);
        }
        for line in t.to_string().lines() {
            out.push_str("  ");
            out.push_str(line);
            out.push('\n');
        }
        for j in &f.audit.joints {
            out.push_str(&format!(
                "  suggested {}: {}\n",
                j.joint.name(),
                suggestion(j)
            ));
        }
    }
    if !rig.notes.is_empty() {
        out.push_str("\nNotes:\n");
        for n in &rig.notes {
            out.push_str(&format!("  - {n}\n"));
        }
    }
    let judged = rig
        .fingers
        .iter()
        .filter(|f| f.audit.basis != Basis::None)
        .count();
    out.push_str(&format!(
        "\nSummary: {} of {} judged fingers have a joint or proportion outside the {c} prediction interval.\n",
        rig.outside(),
        judged
    ));
    out.push_str("Caveats:\n");
    for c in CAVEATS {
        out.push_str(&format!("  - {c}\n"));
    }
    out
}

/// The standing of a whole finger in one phrase, naming whatever lies outside.
pub(crate) fn finger_summary(a: &FingerAudit) -> String {
    if a.basis == Basis::None {
        return "not judged (no tip)".into();
    }
    let mut outside = Vec::new();
    for j in &a.joints {
        match j.standing {
            Standing::Above { by } => outside.push(format!(
                "{} {} mm too far towards the tip",
                j.joint.name(),
                num(by * MM, 2)
            )),
            Standing::Below { by } => outside.push(format!(
                "{} {} mm too close to the root",
                j.joint.name(),
                num(by * MM, 2)
            )),
            _ => {}
        }
    }
    for v in &a.values {
        match v.standing {
            Standing::Above { by } => {
                outside.push(format!("{} {} above", v.quantity.symbol(), num(by, 4)))
            }
            Standing::Below { by } => {
                outside.push(format!("{} {} below", v.quantity.symbol(), num(by, 4)))
            }
            _ => {}
        }
    }
    let all_in_range = a
        .joints
        .iter()
        .map(|j| j.standing)
        .chain(a.values.iter().map(|v| v.standing))
        .all(|s| s == Standing::InRange);
    if !outside.is_empty() {
        format!("outside the prediction interval: {}", outside.join("; "))
    } else if all_in_range {
        "inside the X-ray range".into()
    } else {
        "inside the prediction interval".into()
    }
}

/// The measured value of `q` for a finger, when judged.
pub(crate) fn value_of(a: &FingerAudit, q: Quantity) -> Option<f64> {
    a.values
        .iter()
        .find(|v| v.quantity == q)
        .map(|v| v.measured)
}
