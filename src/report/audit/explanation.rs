//! The audit's explanation: its heading, the opening, and each finger's line and steps.

use super::MM;
use super::words::*;
use crate::analysis::placement::Joint;
use crate::analysis::region::FIX_LEVEL;
use crate::format::{level, num};
use crate::report::layout::Width;
use crate::rig::judge::{Basis, FingerAudit, JointCheck, RayBase};
use crate::rig::{AuditedFinger, AuditedRig};

/// A finger's heading: label and node names (wrapped), then its segments.
pub(crate) fn heading(f: &AuditedFinger) -> String {
    let names: Vec<String> = f
        .chain
        .joints
        .iter()
        .map(|j| format!("{} ({})", j.name, j.joint.name()))
        .collect();
    let mut out = para(&format!("{}: {}", f.chain.label(), names.join(", ")), "");
    let a = &f.audit;
    let segments: Vec<String> = a
        .segments
        .iter()
        .enumerate()
        .map(|(k, c)| format!("J{} {}", k + 1, num(c * MM, 1)))
        .collect();
    let mut line = format!("segments {} mm", segments.join(", "));
    if a.tip_correction != 0.0
        && let Some(last) = a.compared.last()
    {
        line.push_str(&format!(
            "; compared J{} {} ({} mm soft tissue {})",
            a.compared.len(),
            num(last * MM, 1),
            num(a.tip_correction.abs() * MM, 1),
            if a.tip_correction > 0.0 {
                "off"
            } else {
                "added"
            }
        ));
    }
    if let Some(l) = a.length {
        line.push_str(&format!("; length {} mm", num(l * MM, 1)));
    }
    out.push_str(&para(&line, "  "));
    if let (Some(t), Some(node)) = (&f.skin_tip, f.chain.joints.last()) {
        let line = if t.from_mesh {
            format!(
                "tip: tip from the mesh, where the skin weighted to {} ends, {} mm past it (the \
                 rig has no tip node)",
                node.name,
                num(t.beyond_node * MM, 1)
            )
        } else {
            format!(
                "tip: the skin's end on the mesh, {} mm past {} (the tip node lies inside the \
                 skin)",
                num(t.beyond_node * MM, 1),
                node.name
            )
        };
        out.push_str(&para(&line, "  "));
    }
    out
}

/// The explanation of a finger's misfit, in words.
pub(crate) fn explanation_words(a: &FingerAudit) -> String {
    let e = &a.explanation;
    let soft = a.tip_correction != 0.0;
    if a.basis == Basis::None {
        return String::new();
    }
    if e.moved.is_empty() && e.consistent {
        let soft = if soft {
            ", the tip's soft tissue accounted for"
        } else {
            ""
        };
        let region = a.region.as_ref().map_or(String::new(), |r| {
            format!(
                " (inside the X-rays' {} joint region: {})",
                level(r.confidence),
                t2_words(r)
            )
        });
        return format!("Fits the X-rays as it is{soft}{region}.{}", held_words(a));
    }
    let moved: Vec<String> = a
        .joints
        .iter()
        .filter(|j| j.moves)
        .map(|j| {
            let side = if j.shift_along < 0.0 {
                "distal"
            } else {
                "proximal"
            };
            let web = if j.joint == Joint::Mcp && j.shift_along < 0.0 {
                " (at the finger web, not the knuckle?)"
            } else {
                ""
            };
            format!(
                "the {} sits {} mm {side} of where the X-rays put it given the other joints{web}",
                j.joint.name(),
                num(j.shift_along.abs() * MM, 1)
            )
        })
        .collect();
    let names = |moving: bool, article: bool| -> Vec<String> {
        a.joints
            .iter()
            .filter(|j| j.moves == moving)
            .map(|j| match (j.joint, article) {
                (Joint::Tip, _) => "the tip".to_string(),
                (k, true) => format!("the {}", k.name()),
                (k, false) => k.name().to_string(),
            })
            .collect()
    };
    let mut accounted = names(true, true);
    if soft {
        accounted.push("the soft tissue".into());
    }
    let others = names(false, false);
    let mut out = if e.consistent {
        let verb = |l: &[String]| if l.len() == 1 { "is" } else { "are" };
        format!(
            "Explanation: {}; {} {} consistent with the X-rays once {} {} accounted for.",
            and_list(&moved),
            and_list(&others),
            verb(&others),
            and_list(&accounted),
            verb(&accounted)
        )
    } else if moved.is_empty() {
        let at_bends = a.joints.iter().any(|j| {
            j.held
                .as_ref()
                .is_some_and(|h| h.reason != crate::rig::judge::HoldReason::Small)
        });
        if at_bends {
            "No move of the joints that are not held fits the X-rays, so the fix moves none."
                .to_string()
        } else {
            "No move of up to two joints fits the X-rays.".to_string()
        }
    } else {
        format!(
            "No move of up to two of the joints free to move lands the finger inside the X-rays' \
             {} joint region, where the fix puts a finger, so the fix moves none; the closest: {}{}.",
            level(FIX_LEVEL),
            and_list(&moved),
            e.score.map_or(String::new(), |x| format!(
                " (then {} of the way to the {} region's edge)",
                num(x, 2),
                a.region
                    .as_ref()
                    .map_or(String::new(), |r| level(r.confidence))
            ))
        )
    };
    out.push_str(&held_words(a));
    if !e.also.is_empty() {
        let alt: Vec<String> = e
            .also
            .iter()
            .map(|set| and_list(&set.iter().map(|j| j.name().to_string()).collect::<Vec<_>>()))
            .collect();
        out.push_str(&format!(
            " Moving the {} instead would also fit.",
            alt.join(" or the ")
        ));
    }
    out
}

/// What the fix does with one joint, for the line per finger.
pub(super) enum Step {
    /// "the PIP 3.1 mm towards the tip": the fix makes this move.
    Move(String),
    /// "the IP 2.7 mm (it would leave its skin bend)": a move the fix does not make.
    Held(String),
}

/// What the fix does with joint `j`, read off the fields the table and the
/// JSON give (`held`, [`JointCheck::fix_moves`], `shift`, `shift_along`);
/// with `only_outside` (`--only-outside` with a fix), a joint inside the
/// prediction interval is not moved, as the fix decides. `None`: nothing.
pub(super) fn step(j: &JointCheck, only_outside: bool) -> Option<Step> {
    let mm = |x: f64| num(x * MM, 1);
    if let Some(h) = &j.held {
        return Some(Step::Held(format!(
            "the {} {} mm ({})",
            j.joint.name(),
            mm(h.shift),
            h.reason.short()
        )));
    }
    if !j.fix_moves() {
        return None;
    }
    if only_outside && j.standing.is_consistent() {
        return Some(Step::Held(format!(
            "the {} {} mm (inside its own prediction interval; --only-outside)",
            j.joint.name(),
            mm(j.shift)
        )));
    }
    Some(Step::Move(format!(
        "the {} {} mm towards the {}",
        j.joint.name(),
        mm(j.shift),
        if j.shift_along >= 0.0 { "tip" } else { "root" }
    )))
}

/// A finger's verdict and its move in a few words: "keep", "move the PIP
/// 3.1 mm towards the tip", "held: the IP 2.7 mm (it would leave its skin
/// bend)", or both, root first; read off each joint's move ([`step`]) and the
/// explanation, so it says what the table's rows, the explanation's words
/// and the JSON say.
pub(crate) fn finger_line(a: &FingerAudit, only_outside: bool) -> String {
    if a.basis == Basis::None {
        return "not judged (a thumb without a tip has no proportion)".into();
    }
    let (mut moves, mut held) = (Vec::new(), Vec::new());
    for j in &a.joints {
        match step(j, only_outside) {
            Some(Step::Move(w)) => moves.push(w),
            Some(Step::Held(w)) => held.push(w),
            None => {}
        }
    }
    let fits = a.explanation.consistent;
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
    match (parts.is_empty(), fits) {
        (false, _) => parts.join("; "),
        (true, true) => "keep".into(),
        (true, false) => "keep: no move of up to two joints fits the X-rays".into(),
    }
}

/// What the finger's ray base says of its MCP, for the opening line, when it
/// puts the MCP outside the atlas's prediction interval and the finger's own
/// line does not name the MCP (it neither moves nor holds it): "the MCP from
/// its CMC: OUT, 4.4 mm too proximal (--fix-mcp atlas places it)", the words
/// of the table's row. An MCP the base puts in range and the finger would move
/// is held instead ([`crate::rig::AuditedRig::judge_rays`]), so the line and the row agree.
pub(crate) fn base_clause(f: &AuditedFinger) -> Option<String> {
    let m = f.metacarpal_check.as_ref()?;
    if m.standing.is_consistent() {
        return None;
    }
    let named = f
        .audit
        .joint(Joint::Mcp)
        .is_some_and(|j| j.held.is_some() || j.fix_moves());
    if named {
        return None;
    }
    let base = match m.base {
        RayBase::Cmc => "its CMC",
        RayBase::Wrist => "the wrist",
    };
    Some(format!(
        "the MCP from {base}: {} (--fix-mcp atlas places it)",
        joint_standing(m.standing, MM)
    ))
}

/// The audit's opening: one line per finger, its label then [`finger_line`],
/// in the rig's order (either hand's fingers named by side when the joint
/// names say it), each wrapped under its words to fit `width`.
pub(crate) fn opening(rig: &AuditedRig, only_outside: bool, width: Width) -> String {
    let labels: Vec<String> = rig.fingers.iter().map(|f| f.chain.label()).collect();
    let pad = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) + 2;
    let mut out = String::new();
    for (f, label) in rig.fingers.iter().zip(&labels) {
        let mut verdict = finger_line(&f.audit, only_outside);
        if let Some(base) = base_clause(f) {
            verdict = if verdict == "keep" {
                format!("keep the finger; {base}")
            } else {
                format!("{verdict}; {base}")
            };
        }
        let line = format!("{label:<pad$}{verdict}");
        match width {
            Width::Fit(max) => {
                let hanging = " ".repeat(pad);
                let options = textwrap::Options::new(max)
                    .subsequent_indent(&hanging)
                    .word_splitter(textwrap::WordSplitter::NoHyphenation);
                out.push_str(&textwrap::fill(&line, options));
            }
            _ => out.push_str(&line),
        }
        out.push('\n');
    }
    out
}
