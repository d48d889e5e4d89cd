//! The report's part on a real rig: its audit with the metacarpals, and its skin deformed
//! as it is and as `audit --fix` writes it ([`crate::report::sections::deform`]'s view).

use super::figures::*;
use super::text::*;
use crate::format::{num, trimmed};
use crate::report::audit::MM;
use crate::report::sections::deform::{
    DeformAuditRow, DeformFigureView, DeformHandView, DeformRowView, DeformSection, DeformView,
    MetacarpalView,
};
use crate::report::writer::OutputFile;
use crate::rig::AuditedRig;
use crate::rig::deform::file::{FileDeformation, HandDeformation};
use crate::rig::deform::verdict::JointVerdict;
use crate::rig::deform::{Pose, Skinning};
use crate::rig::judge::{MetacarpalCheck, RayBase};
use crate::rig::naming::Side;

/// What the deformation measures can and cannot tell, for the report.
pub(crate) const CAN_TELL: &str = "What the measures can tell: where the skin collapses (loss; linear blend \
skinning loses 1 - cos(theta/2) of a joint's section, 29% at 90 degrees, wherever the weights blend), where \
it folds relative to the joint (fold), how much it stretches (p95) and whether it passes through itself (x). \
What they cannot tell: whether a joint is anatomically right. The fix moves the skin weights with the joints \
but does not remodel the mesh, so a joint moved away from the edge loops it was modelled at can deform worse \
even where it matches the bones: read a worse score as \"check the topology around the moved joint\", not as \
\"the statistics are wrong\".";

/// A real rig deformed as it is (A) and as `audit --fix` writes it (B), with
/// its audit: what [`section`] turns into the report's part.
pub(crate) struct SectionInputs<'a> {
    pub a: &'a FileDeformation,
    pub b: &'a FileDeformation,
    pub verdicts: &'a [(Side, Vec<JointVerdict>)],
    pub pose: &'a Pose,
    pub method: Skinning,
    /// The joints the fix moves (node, distance in m).
    pub moved: &'a [(String, f64)],
    /// The rig as given, judged (its metacarpals too, when an atlas was given).
    pub audit: &'a AuditedRig,
    /// Whether an atlas was given to judge the metacarpals against.
    pub atlas: bool,
    pub confidence: f64,
    /// The figures of [`figure`], one per hand, in `a`'s hand order.
    pub figures: Vec<(OutputFile, RenderView)>,
    /// File name stem under `plots/`, e.g. `deform-webxr-generic-hand`.
    pub stem: &'a str,
}

/// The report's part on a real rig: the view, and the figures under `plots/`
/// (the HTML embeds them as data URIs, so it stays one self-contained file).
pub(crate) fn section(s: SectionInputs<'_>) -> DeformSection {
    use base64::Engine;
    let mut files = Vec::new();
    let mut hands = Vec::new();
    for (side, joints) in s.verdicts {
        let (Some(ha), Some(hb)) = (
            s.a.hands.iter().find(|h| h.chains.side == *side),
            s.b.hands.iter().find(|h| h.chains.side == *side),
        ) else {
            continue;
        };
        let Some((png, render)) = s.figures.iter().find(|(_, r)| r.side == *side) else {
            continue;
        };
        let name = format!("{}-{}", s.stem, side.name());
        let file = format!("plots/{name}.png");
        let data_uri = format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&png.bytes)
        );
        files.push(OutputFile::new(&file, png.bytes.clone()));
        hands.push(DeformHandView {
            side: side.name().to_string(),
            rows: joint_rows(ha, hb, joints),
            summary: verdict_summary(joints),
            reasons: reasons(joints),
            figure: DeformFigureView {
                id: name,
                file,
                data_uri,
                width: render.width.to_string(),
                height: render.height.to_string(),
                alt: format!(
                    "The {} hand in the pose as it is (left) and as audit --fix writes it (right), \
                     from the side (top) and from above (bottom), coloured by strain",
                    side.name()
                ),
                caption: format!(
                    "The {} hand posed, as it is (A, left) and as audit --fix writes it (B, right), \
                     from the side (top row) and from above (bottom row). Colour: edge strain \
                     |ln(posed/rest edge length)|, grey 0, amber 0.1, red 0.25 and more. {CAN_TELL}",
                    side.name()
                ),
            },
        });
    }
    DeformSection {
        view: DeformView {
            rig: s.a.label.clone(),
            pose: pose_line(s.pose, s.method).trim_end().to_string(),
            moved: moved_words(s.moved),
            compared: s.moved.iter().any(|(_, d)| *d > 0.0),
            not_compared: not_compared(s.moved),
            tolerance: tolerance_words(s.audit, s.confidence),
            audit: audit_rows(s.audit, s.atlas, s.confidence),
            audit_notes: s
                .audit
                .notes
                .iter()
                .chain(&s.audit.warnings)
                .cloned()
                .collect(),
            hands,
            can_tell: CAN_TELL.to_string(),
            caveats: CAVEATS.iter().map(|c| c.to_string()).collect(),
        },
        figures: files,
    }
}

/// Both rigs' measures per joint, with the verdict.
pub(super) fn joint_rows(
    ha: &HandDeformation,
    hb: &HandDeformation,
    joints: &[JointVerdict],
) -> Vec<DeformRowView> {
    joints
        .iter()
        .filter_map(|v| {
            let (ja, jb) = (find(ha, v)?, find(hb, v)?);
            Some(DeformRowView {
                finger: v.finger.name().to_string(),
                joint: v.joint.name().to_string(),
                angle: trimmed(ja.angle, 1),
                loss_a: loss(ja.volume_loss),
                loss_b: loss(jb.volume_loss),
                x_a: ja.self_intersections.to_string(),
                x_b: jb.self_intersections.to_string(),
                p95_a: strain(ja.strain_p95),
                p95_b: strain(jb.strain_p95),
                fold_a: mm(ja.crease_offset),
                fold_b: mm(jb.crease_offset),
                better: better(v.overall).to_string(),
            })
        })
        .collect()
}

/// What the fix moves, in one sentence.
pub(super) fn moved_words(moved: &[(String, f64)]) -> String {
    if moved.is_empty() {
        return "The fix moves no joint: A and B are the same rig.".into();
    }
    let parts: Vec<String> = moved
        .iter()
        .map(|(node, d)| format!("{node} by {} mm", num(d * MM, 2)))
        .collect();
    format!(
        "The fix moves {} {}, taking the skin weights with {}: {}.",
        moved.len(),
        if moved.len() == 1 { "joint" } else { "joints" },
        if moved.len() == 1 { "it" } else { "them" },
        parts.join(", ")
    )
}

/// Why the deformation is not compared when the fix moves nothing, in one sentence (empty
/// when it moves a joint).
fn not_compared(moved: &[(String, f64)]) -> String {
    if moved.iter().any(|(_, d)| *d > 0.0) {
        return String::new();
    }
    "The fix moves no joint, so A and B would be the same rig: their deformation is not compared."
        .to_string()
}

/// Where "outside the joint region" meets "the fix moves no joint": the two tests
/// differ, said when a finger is outside (empty otherwise).
fn tolerance_words(audit: &AuditedRig, confidence: f64) -> String {
    if audit.outside() == 0 {
        return String::new();
    }
    format!(
        "Outside and moved are two tests: audit calls a finger outside when it lies beyond the {} joint region (or a value beyond its prediction interval), while --fix moves a joint only where moving the fewest joints puts the finger inside the {} region, as typical as half of all hands; a finger outside with no such move is left as it is.",
        crate::format::level(confidence),
        crate::format::level(crate::analysis::region::FIX_LEVEL),
    )
}

/// The audit of the rig, one row per finger, its metacarpal included.
pub(super) fn audit_rows(audit: &AuditedRig, atlas: bool, confidence: f64) -> Vec<DeformAuditRow> {
    use crate::analysis::Quantity;
    use crate::report::audit::{finger_summary, value_of};
    let c = crate::format::level(confidence);
    audit
        .fingers
        .iter()
        .map(|f| {
            let rel: Vec<String> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
                .iter()
                .filter_map(|&q| value_of(&f.audit, q).map(|v| num(v, 4)))
                .collect();
            let metacarpal = match (&f.metacarpal_check, &f.chain.metacarpal) {
                (Some(m), _) => metacarpal_view(m, &c),
                (None, None) => unjudged("no metacarpal in the rig"),
                (None, Some(_)) if !atlas => unjudged("not judged: no atlas was given"),
                (None, Some(_)) => unjudged("not judged (see the notes)"),
            };
            DeformAuditRow {
                finger: f.chain.finger.name().to_string(),
                relative: if rel.is_empty() {
                    "n/a (no tip)".into()
                } else {
                    rel.join(" / ")
                },
                standing: finger_summary(&f.audit),
                metacarpal,
            }
        })
        .collect()
}

pub(super) fn unjudged(why: &str) -> MetacarpalView {
    MetacarpalView {
        node: why.to_string(),
        lengths: String::new(),
        values: Vec::new(),
        mcp: String::new(),
    }
}

/// What a [`MetacarpalCheck`] holds, as strings (lengths in mm).
pub(super) fn metacarpal_view(m: &MetacarpalCheck, c: &str) -> MetacarpalView {
    use crate::report::audit::{joint_standing, metacarpal_values};
    let values = metacarpal_values(m, c);
    let mm2 = |x: f64| num(x * MM, 2);
    MetacarpalView {
        node: m.node.clone(),
        lengths: match m.mc {
            Some(mc) => format!("mc {} mm, J {} mm", mm2(mc), mm2(m.length)),
            None => format!("wrist to MCP {} mm, J {} mm", mm2(m.to_mcp), mm2(m.length)),
        },
        values,
        mcp: format!(
            "{}; the atlas puts it {} mm from the {} ({c} prediction {})",
            joint_standing(m.standing, MM),
            mm2(m.expected),
            match m.base {
                RayBase::Cmc => "CMC",
                RayBase::Wrist => "wrist",
            },
            m.pi.map_or("n/a".into(), |p| format!(
                "[{}, {}] mm",
                mm2(p.low),
                mm2(p.high)
            ))
        ),
    }
}
