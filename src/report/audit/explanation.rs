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

/// The explanation of a finger's misfit, in words: the fit as it is, or
/// the joints that move and what the rest then is ([`moved_words`],
/// [`misfit_words`]), the joints held, and the other sets that would fit.
pub(crate) fn explanation_words(a: &FingerAudit) -> String {
    let e = &a.explanation;
    if a.basis == Basis::None {
        return String::new();
    }
    if e.moved.is_empty() && e.consistent {
        let soft = if a.tip_correction != 0.0 {
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
    let mut out = misfit_words(a, &moved_words(a));
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

/// Each joint the explanation moves, where it sits against where the X-rays
/// put it given the other joints; an MCP distal of that place is said to lie
/// where one placed at the finger web would.
fn moved_words(a: &FingerAudit) -> Vec<String> {
    a.joints
        .iter()
        .filter(|j| j.moves)
        .map(|j| {
            let side = if j.shift_along < 0.0 {
                "distal"
            } else {
                "proximal"
            };
            let web = if j.joint == Joint::Mcp && j.shift_along < 0.0 {
                " (distal of the knuckle, where an MCP placed at the finger web lies)"
            } else {
                ""
            };
            format!(
                "the {} sits {} mm {side} of where the X-rays put it given the other joints{web}",
                j.joint.name(),
                num(j.shift_along.abs() * MM, 1)
            )
        })
        .collect()
}

/// The explanation's sentence for a finger that does not fit as it is:
/// `moved` ([`moved_words`]) and the joints then consistent, or why no move
/// is made.
fn misfit_words(a: &FingerAudit, moved: &[String]) -> String {
    let e = &a.explanation;
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
    if e.consistent {
        let mut accounted = names(true, true);
        if a.tip_correction != 0.0 {
            accounted.push("the soft tissue".into());
        }
        let others = names(false, false);
        let verb = |l: &[String]| if l.len() == 1 { "is" } else { "are" };
        return format!(
            "Explanation: {}; {} {} consistent with the X-rays once {} {} accounted for.",
            and_list(moved),
            and_list(&others),
            verb(&others),
            and_list(&accounted),
            verb(&accounted)
        );
    }
    if moved.is_empty() {
        let at_bends = a.joints.iter().any(|j| {
            j.held
                .as_ref()
                .is_some_and(|h| h.reason != crate::rig::judge::HoldReason::Small)
        });
        return if at_bends {
            "No move of the joints that are not held fits the X-rays, so the fix moves none."
                .to_string()
        } else {
            "No move of up to two joints fits the X-rays.".to_string()
        };
    }
    format!(
        "No move of up to two of the joints free to move lands the finger inside the X-rays' \
         {} joint region, where the fix puts a finger, so the fix moves none; the closest: {}{}.",
        level(FIX_LEVEL),
        and_list(moved),
        e.score.map_or(String::new(), |x| format!(
            " (then {} of the way to the {} region's edge)",
            num(x, 2),
            a.region
                .as_ref()
                .map_or(String::new(), |r| level(r.confidence))
        ))
    )
}

/// What the fix does with one joint, for the line per finger.
pub(super) enum Step {
    /// "the PIP 3.1 mm", towards the "tip" (or "root"): the fix makes this move.
    Move(String, &'static str),
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
        if shown_zero(h.shift) {
            // A move that prints as 0.0 mm is no move: nothing to say.
            return None;
        }
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
    Some(Step::Move(
        format!("the {} {} mm", j.joint.name(), mm(j.shift)),
        if j.shift_along >= 0.0 { "tip" } else { "root" },
    ))
}

/// A finger's verdict and its move in a few words: "keep", "move the PIP
/// 3.1 mm towards the tip", "held: the IP 2.7 mm (it would leave its skin
/// bend)", or both, root first; read off each joint's move ([`step`]) and the
/// explanation, so it says what the table's rows, the explanation's words
/// and the JSON say.
///
/// A held MCP is named with its reason only: the line gives no MCP distance
/// but its base's ([`base_clause`]).
pub(crate) fn finger_line(a: &FingerAudit, only_outside: bool) -> String {
    if a.basis == Basis::None {
        return "not judged (a thumb without a tip has no proportion)".into();
    }
    let mut moves: Vec<(Vec<String>, &str)> = Vec::new();
    let mut held = Vec::new();
    for j in &a.joints {
        match step(j, only_outside) {
            Some(Step::Move(w, to)) => match moves.last_mut() {
                // Moves the same way are said once: "the PIP 9.2 mm and the
                // DIP 4.1 mm towards the tip".
                Some((ws, last)) if *last == to => ws.push(w),
                _ => moves.push((vec![w], to)),
            },
            Some(Step::Held(_)) if j.joint == Joint::Mcp => {
                if let Some(h) = &j.held {
                    held.push(format!("the MCP ({})", h.reason.short()));
                }
            }
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
        let moves: Vec<String> = moves
            .iter()
            .map(|(ws, to)| format!("{} towards the {to}", and_list(ws)))
            .collect();
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
/// puts the MCP outside the atlas's prediction interval: "the MCP from its
/// CMC: OUT, 4.4 mm too proximal", the words of the table's row. Every MCP
/// the summary counts outside from its base is named so, whether or not the
/// finger's own line names the MCP.
pub(crate) fn base_clause(f: &AuditedFinger) -> Option<String> {
    let m = f.metacarpal_check.as_ref()?;
    if m.standing.is_consistent() {
        return None;
    }
    let base = match m.base {
        RayBase::Cmc => "its CMC",
        RayBase::Wrist => "the wrist",
    };
    Some(format!(
        "the MCP from {base}: {}",
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
