//! The words and tables of a rig audit (`phalanx audit`, and the report's rig section).
//!
//! Rig coordinates are taken as metres (the glTF unit) and shown in millimetres.

use super::layout::{Align, Give, Grid, Hidden, Width};
use crate::analysis::placement::Joint;
use crate::analysis::region::FIX_LEVEL;
use crate::analysis::{Interval, Quantity};
use crate::format::{level, num, percent};
use crate::rig::bend::Bend;
use crate::rig::judge::{
    Basis, FingerAudit, JointCheck, JudgeOptions, MetacarpalCheck, RayBase, RegionCheck,
    SoftTissue, Standing, TipKind,
};
use crate::rig::read::source::FbxSource;
use crate::rig::{AuditedFinger, AuditedRig};

/// Millimetres per rig unit (glTF units are metres).
pub(crate) const MM: f64 = 1000.0;

/// The caveats every audit carries, the last one on the fingertips of the data (`data`,
/// its path) as their tip column records them (`tips`): what they are, or, when the
/// column does not record one kind, what the audit takes them as and that its verdicts
/// rest on that.
pub(crate) fn caveats(tips: &JudgeOptions, data: &str) -> Vec<String> {
    const SOFT_TISSUE: &str = "the fingertip's soft tissue Buryanov & Kotiuk measured for \
        that finger (66 adults, 3.7 to 5.7 mm), as a share of the rig's finger; \
        --tip-soft-tissue MM sets one length for every finger instead";
    let tip = match tips.data_tips.single() {
        Some(TipKind::Skin) => format!(
            "A rig's tip usually sits at the skin, and so do the paper's X-ray tips (their tip \
             column, not stated by the paper: a test against Buryanov & Kotiuk 2010 rejects bone \
             tips and does not reject skin tips), so such a rig is compared as it is. Where a \
             rig's tips and the data's differ (one at the bone, the other at the skin), the last \
             segment is corrected by {SOFT_TISSUE}."
        ),
        Some(TipKind::Bone) => format!(
            "A rig's tip usually sits at the skin, while the X-ray tips of {data} are at the \
             bone (its tip column), so a rig's skin tip is compared with them corrected by \
             {SOFT_TISSUE}. A rig whose tips mark the bone (--tip bone) is compared as it is."
        ),
        None => {
            let described = tips.data_tips.describe();
            let recorded = match described.strip_prefix("mixed: ") {
                Some(rest) => format!("mixed ({rest})"),
                None => described,
            };
            format!(
                "A rig's tip usually sits at the skin. The X-ray tips of {data} are {recorded}, \
                 so they are all taken as {kind} tips (the usual landmark on an X-ray), and a \
                 rig's tips at the {other} are compared with them corrected by \
                 {SOFT_TISSUE}. \
                 The verdicts of the fingers with a tip rest on that assumption, since a last \
                 segment to the skin is longer than one to the bone by that soft tissue: record \
                 where the X-rays' tips were measured in the tip column (bone or skin).",
                kind = tips.data_tip.name(),
                other = match tips.data_tip {
                    TipKind::Bone => "skin",
                    TipKind::Skin => "bone",
                }
            )
        }
    };
    vec![
        "The statistics come from X-rays of right hands; a left hand is judged as their mirror image.".to_string(),
        "A rig's joints are rotation centres, while the X-ray lengths run between bone ends; the two differ by a few per cent, so read the prediction interval as a guide, not a verdict.".to_string(),
        tip,
    ]
}

/// `text` as one line starting with `first`; [`super::layout::fit_text`]
/// wraps it to the terminal's width at the end, continuing two columns further in.
fn para(text: &str, first: &str) -> String {
    format!("{first}{text}\n")
}

/// "in range", "OUT, 5.3 mm too distal": how a joint stands, short for the table
/// (to 0.1 mm: see [`crate::rig::judge::MOVE_TOLERANCE`] for what 5 X-rays support).
pub(crate) fn joint_standing(s: Standing, scale: f64) -> String {
    match s {
        Standing::InRange => "in range".into(),
        Standing::InPrediction => "in prediction".into(),
        Standing::Above { by } => format!("OUT, {} mm too distal", num(by * scale, 1)),
        Standing::Below { by } => format!("OUT, {} mm too proximal", num(by * scale, 1)),
    }
}

/// How a unitless value stands, short for the table.
pub(crate) fn value_standing(s: Standing) -> String {
    match s {
        Standing::InRange => "in range".into(),
        Standing::InPrediction => "in prediction".into(),
        Standing::Above { by } => format!("OUT, {} above", num(by, 4)),
        Standing::Below { by } => format!("OUT, {} below", num(by, 4)),
    }
}

/// What a finger was judged on, in words.
pub(crate) fn basis_words(a: &FingerAudit, mesh_tip: bool) -> String {
    match a.basis {
        Basis::Relative if mesh_tip => "judged on relative values (tip from the mesh)".into(),
        Basis::Relative => "judged on relative values (the rig has a tip)".into(),
        Basis::Ratio => "judged on J2/J1 only: the rig has no tip, so the finger's length, its DIP and J3 cannot be judged".into(),
        Basis::None => "not judged: a thumb without a tip has one segment, and one segment has no proportion".into(),
    }
}

/// How the tips are compared, in words: whether the rig's tips and the
/// data's agree (nothing trimmed), and what bridges them when they do not.
pub(crate) fn tip_words(t: &JudgeOptions) -> String {
    let rig = t.rig_tip.name();
    let data = match t.data_tips.single() {
        Some(k) => format!(
            "the X-rays' tips are {} tips (the data's tip column)",
            k.name()
        ),
        None => format!(
            "the X-rays' tips are {} in the data's tip column, taken as {} tips",
            t.data_tips.describe(),
            t.data_tip.name()
        ),
    };
    if t.rig_tip == t.data_tip {
        return format!(
            "Rig tips read as {rig} tips and {data}: alike, so nothing is trimmed and each last \
             segment is compared as it is."
        );
    }
    let longer = if t.rig_tip == TipKind::Skin {
        "shorter"
    } else {
        "longer"
    };
    match &t.soft_tissue {
        SoftTissue::Length { length } => format!(
            "Rig tips read as {rig} tips and {data}: each last segment is compared {} mm \
             {longer} for the fingertip's soft tissue (--tip-soft-tissue).",
            num(length * MM, 1)
        ),
        SoftTissue::Table {
            source,
            name,
            fingers,
            ..
        } => {
            let shares: Vec<f64> = fingers.iter().map(|f| f.share(t.rig_tip)).collect();
            let low = shares.iter().copied().fold(f64::INFINITY, f64::min);
            let high = shares.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            format!(
                "Rig tips read as {rig} tips and {data}: each last segment is compared {longer} \
                 by the fingertip's soft tissue {} measured for that finger, as a share of the \
                 rig's finger ({} to {} of its length), so a rig in any unit is judged alike.",
                name.as_deref().map_or_else(
                    || format!("that {source}"),
                    |n| format!("that {n} ({source})")
                ),
                percent(low),
                percent(high)
            )
        }
        SoftTissue::Unknown => format!(
            "Rig tips read as {rig} tips and {data}, and no figure for the fingertip's soft \
             tissue between the two is known, so the fingers with a tip are not judged."
        ),
    }
}

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

/// The suggestion for one joint, in words.
pub(crate) fn suggestion(j: &crate::rig::judge::JointCheck) -> String {
    let towards = if j.shift_along >= 0.0 {
        "towards the tip"
    } else {
        "towards the root"
    };
    format!(
        "move {} {} mm {towards}, to ({}, {}, {}) m",
        j.joint.name(),
        num(j.shift * MM, 1),
        num(j.suggested[0], 5),
        num(j.suggested[1], 5),
        num(j.suggested[2], 5)
    )
}

/// "A, B and C".
fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
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

/// The joints a fix holds, one sentence each, with the words every output
/// gives for them ([`crate::rig::judge::Held::words`]): " The PIP is held:
/// it sits where its skin bends, 0.2 mm (...)."; empty when none is held.
pub(crate) fn held_words(a: &FingerAudit) -> String {
    a.joints
        .iter()
        .filter_map(|j| {
            j.held
                .as_ref()
                .map(|h| format!(" The {} is {}.", j.joint.name(), h.words))
        })
        .collect()
}

/// Where the skin bends, in words: one clause per joint.
pub(crate) fn bend_words(bends: &[Bend], tolerance: f64) -> String {
    let parts: Vec<String> = bends
        .iter()
        .map(|b| match b.offset {
            None => format!("{} not found ({} vertices)", b.joint.name(), b.vertices),
            Some(o) => {
                let side = if o >= 0.0 { "distal" } else { "proximal" };
                let flag = if b.flagged {
                    format!(" (beyond {} mm: a rig defect)", num(tolerance * MM, 1))
                } else {
                    String::new()
                };
                format!(
                    "{} {} mm {side}{flag}",
                    b.joint.name(),
                    num(o.abs() * MM, 1)
                )
            }
        })
        .collect();
    format!("Skin bends (from each joint): {}.", parts.join(", "))
}

/// Each ratio of the ray against the atlas (mc/J and J1/mc from a CMC, w/J from the
/// wrist), in words: the measured value, the atlas's mean and prediction interval, the
/// standing.
pub(crate) fn metacarpal_values(m: &MetacarpalCheck, c: &str) -> Vec<String> {
    let value = |symbol: &str, measured: f64, mean: f64, pi: Option<Interval>, standing| {
        format!(
            "{symbol} {} (atlas mean {}, {c} prediction {}: {})",
            num(measured, 4),
            num(mean, 4),
            pi.map_or("n/a".into(), |p| format!(
                "[{}, {}]",
                num(p.low, 4),
                num(p.high, 4)
            )),
            value_standing(standing)
        )
    };
    m.values
        .iter()
        .map(|v| value(v.quantity.symbol(), v.measured, v.mean, v.pi, v.standing))
        .chain(
            m.wrist_over_length
                .iter()
                .map(|y| value("w/J", y.measured, y.mean, y.pi, y.standing)),
        )
        .collect()
}

/// The MCP judged from the CMC against the atlas's metacarpals, in words.
pub(crate) fn metacarpal_words(m: &MetacarpalCheck, c: &str) -> String {
    let mm = |x: f64| num(x * MM, 1);
    let values = metacarpal_values(m, c);
    let pi = m.pi.map_or("n/a".into(), |p| {
        format!("[{}, {}] mm", mm(p.low), mm(p.high))
    });
    let at = format!(
        "({}, {}, {}) m",
        num(m.suggested[0], 5),
        num(m.suggested[1], 5),
        num(m.suggested[2], 5)
    );
    match m.base {
        RayBase::Cmc => format!(
            "Metacarpal ({}): mc {} mm, J {} mm; {}. MCP from the CMC: {}; the atlas puts it {} mm \
             from the CMC ({c} prediction {pi}; CMC and tip held), at {at}.",
            m.node,
            m.mc.map_or("n/a".into(), mm),
            mm(m.length),
            values.join("; "),
            joint_standing(m.standing, MM),
            mm(m.expected),
        ),
        RayBase::Wrist => format!(
            "Wrist ({}; no metacarpal): wrist to MCP w {} mm, J {} mm; {}. MCP from the wrist: {}; \
             the atlas puts it {} mm from the wrist ({c} prediction {pi}; wrist and tip held), at \
             {at}.",
            m.node,
            mm(m.to_mcp),
            mm(m.length),
            values.join("; "),
            joint_standing(m.standing, MM),
            mm(m.expected),
        ),
    }
}

/// The table of one finger: each joint (mm from the rig's MCP) and each value,
/// fitted to `width` (the X-ray range goes first, then the standings wrap).
fn finger_table(
    a: &FingerAudit,
    ray: Option<&MetacarpalCheck>,
    c: &str,
    width: Width,
    hidden: &mut Hidden,
) -> String {
    let mm = |x: f64| num(x * MM, 1);
    let interval =
        |i: Interval, f: &dyn Fn(f64) -> String| format!("[{}, {}]", f(i.low), f(i.high));
    let mut t = Grid::new()
        .col("", Align::Left, Give::Keep)
        .col("rig", Align::Right, Give::Keep)
        .col("X-ray mean", Align::Right, Give::Keep)
        .col("X-ray range", Align::Left, Give::Drop(1))
        .col(format!("prediction {c}"), Align::Left, Give::Keep)
        .col("standing", Align::Left, Give::Wrap);
    for j in &a.joints {
        t.row(vec![
            format!("{} (mm)", j.joint.name()),
            mm(j.measured),
            mm(j.expected),
            interval(j.range, &mm),
            j.pi.map_or("n/a".into(), |p| interval(p, &mm)),
            joint_given(a, j),
        ]);
    }
    if let Some(m) = ray {
        // The MCP from its ray's base, against the atlas (mm from the base).
        let from = match m.base {
            RayBase::Cmc => "CMC",
            RayBase::Wrist => "wrist",
        };
        t.row(vec![
            format!("MCP from {from} (mm)"),
            mm(m.to_mcp),
            mm(m.expected),
            interval(m.range, &mm),
            m.pi.map_or("n/a".into(), |p| interval(p, &mm)),
            joint_standing(m.standing, MM),
        ]);
    }
    let v4 = |x: f64| num(x, 4);
    for v in &a.values {
        t.row(vec![
            v.quantity.symbol().to_string(),
            v4(v.measured),
            v4(v.mean),
            interval(v.range, &v4),
            v.pi.map_or("n/a".into(), |p| interval(p, &v4)),
            given(a, value_standing(v.standing), v.standing.is_consistent()),
        ]);
    }
    if let Some(row) = region_row(a) {
        t.row(row);
    }
    t.render(width, 2, hidden)
}

/// A row's standing given the finger's explanation, with the rig's own
/// standing `as_is` beside it where the two differ, labelled "as the rig
/// is", so a row never contradicts the explanation under the table: a row
/// outside as the rig is that fits once the explanation's joints move says
/// so ("fits once the MCP moves (as the rig is: OUT, 0.2 mm too distal)").
fn given(a: &FingerAudit, as_is: String, consistent: bool) -> String {
    let e = &a.explanation;
    if consistent || !e.consistent {
        return as_is;
    }
    if e.moved.is_empty() {
        // The finger is inside the joint region as it is: this row's own
        // interval, the rest of the finger as the rig has it, is read against
        // the whole vector, not alone.
        return format!("fits: the finger is inside the joint region (alone: {as_is})");
    }
    let names: Vec<String> = e
        .moved
        .iter()
        .map(|j| format!("the {}", j.name()))
        .collect();
    format!(
        "fits once {} move{} (as the rig is: {as_is})",
        and_list(&names),
        if names.len() == 1 { "s" } else { "" }
    )
}

/// A region check's T^2 against its bound, and, for a finger with a shape,
/// T^2 on the X-rays' own covariance beside it: "T^2 9.0 of at most 7.7",
/// "T^2 7.5 of at most 25.5; on the X-rays' own shape (r 0.97, not 0.74):
/// 57.3, outside".
pub(crate) fn t2_words(r: &RegionCheck) -> String {
    let mut out = format!("T^2 {} of at most {}", num(r.t2, 1), num(r.bound, 1));
    if let Some(shape) = &r.shape
        && shape.prior.is_some()
    {
        out.push_str(&format!(
            "; on the X-rays' own shape (r {}, not {}): {}, {}",
            num(shape.own.correlation, 2),
            num(shape.correlation, 2),
            num(shape.own.t2, 1),
            if shape.own.inside {
                "inside"
            } else {
                "outside"
            }
        ));
    }
    out
}

/// The joint region's row: T^2 of the relative joint positions as the rig is,
/// against the region's bound (the finger's verdict; see [`given`]).
fn region_row(a: &FingerAudit) -> Option<Vec<String>> {
    let r = a.region.as_ref()?;
    let standing = if r.inside {
        "in the joint region".to_string()
    } else {
        given(a, "OUT of the joint region".into(), false)
    };
    Some(vec![
        "joint positions (T^2)".into(),
        num(r.t2, 1),
        "0".into(),
        String::new(),
        format!("<= {}", num(r.bound, 1)),
        standing,
    ])
}

/// A joint's standing given the explanation ([`given`]): a joint the
/// explanation moves says by how much and whether the fix makes the move or
/// holds it, with its standing as the rig is.
fn joint_given(a: &FingerAudit, j: &JointCheck) -> String {
    let as_is = joint_standing(j.standing, MM);
    if !a.explanation.moved.contains(&j.joint) {
        let g = given(a, as_is, j.standing.is_consistent());
        // A joint an earlier explanation would have moved, held (off its
        // bend, pinned), the explanation then sought without it.
        return match &j.held {
            Some(h) => format!("{g}; {}", h.words),
            None => g,
        };
    }
    let mm = num(j.shift * MM, 1);
    match &j.held {
        Some(h) => format!("{} (as the rig is: {as_is})", h.words),
        None => format!(
            "moves {mm} mm towards the {} (as the rig is: {as_is})",
            if j.shift_along >= 0.0 { "tip" } else { "root" }
        ),
    }
}

/// What the rig file's units and axes are, for the audit's header: glTF's
/// metres and +Y up, or what an FBX file was and how it was converted.
pub(crate) fn units_words(fbx: Option<&FbxSource>) -> String {
    match fbx {
        None => "glTF units are metres, world space Y up".into(),
        Some(src) => format!(
            "read from {} FBX {} with ufbx: its units ({}) and axes ({}) converted to metres and \
             world space +Y up, the bind pose from its skin clusters; FBX cannot be written, so \
             --moves FILE.csv, not --fix, gives the fix",
            if src.ascii { "ASCII" } else { "binary" },
            src.version,
            unit_words(src.unit_meters),
            src.axes
        ),
    }
}

/// A file unit of `m` metres in words: `metres`, `centimetres`, ... for the
/// common ones, else `0.3048 m each`.
pub(crate) fn unit_words(m: f64) -> String {
    let named = [
        (1.0, "metres"),
        (0.01, "centimetres"),
        (0.001, "millimetres"),
        (0.0254, "inches"),
        (0.1, "decimetres"),
    ];
    match named.iter().find(|(u, _)| (m / u - 1.0).abs() < 1e-9) {
        Some((_, name)) => (*name).to_string(),
        None => format!("{} m each", crate::format::trimmed(m, 6)),
    }
}

/// What the fix does with one joint, for the line per finger.
enum Step {
    /// "the PIP 3.1 mm towards the tip": the fix makes this move.
    Move(String),
    /// "the IP 2.7 mm (it would leave its skin bend)": a move the fix does not make.
    Held(String),
}

/// What the fix does with joint `j`, read off the fields the table and the
/// JSON give (`held`, [`JointCheck::fix_moves`], `shift`, `shift_along`);
/// with `only_outside` (`--only-outside` with a fix), a joint inside the
/// prediction interval is not moved, as the fix decides. `None`: nothing.
fn step(j: &JointCheck, only_outside: bool) -> Option<Step> {
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

/// What a finger is outside of when [`AuditedRig::outside`] counts it: the
/// joint region for the fingers with a tip, J2/J1's prediction interval for
/// those without ("the 95% joint region", "the 95% joint region (without a
/// tip: J2/J1's prediction interval)", "the 95% prediction interval").
pub(crate) fn outside_of(rig: &AuditedRig, confidence: f64) -> String {
    let c = level(confidence);
    let judged = || rig.fingers.iter().filter(|f| f.audit.basis != Basis::None);
    let region = judged().any(|f| f.audit.region.is_some());
    let interval = judged().any(|f| f.audit.region.is_none());
    match (region, interval) {
        (true, false) => format!("the {c} joint region"),
        (true, true) => {
            format!("the {c} joint region (without a tip: J2/J1's prediction interval)")
        }
        (false, _) => format!("the {c} prediction interval"),
    }
}

/// The audit's summary, one paragraph: the fingers outside the joint region
/// ([`outside_of`]), the MCPs outside it from their rays' bases, the joints off their bends.
pub(crate) fn summary(rig: &AuditedRig, confidence: f64) -> String {
    let c = level(confidence);
    let judged = rig
        .fingers
        .iter()
        .filter(|f| f.audit.basis != Basis::None)
        .count();
    let mut summary = format!(
        "Summary: {} of {} judged fingers lie outside {} of the X-rays.",
        rig.outside(),
        judged,
        outside_of(rig, confidence)
    );
    if rig.fingers.iter().any(|f| f.metacarpal_check.is_some()) {
        summary.push_str(&format!(
            " {} outside the atlas's {c} prediction interval from their CMC or wrist.",
            crate::format::count(rig.metacarpals_outside(), "MCP lies", "MCPs lie")
        ));
    }
    if rig.fingers.iter().any(|f| !f.bends.is_empty()) {
        summary.push_str(&format!(
            " {} more than {} mm from where their skin bends.",
            crate::format::count(rig.bends_flagged(), "inner joint lies", "inner joints lie"),
            num(rig.bend_tolerance * MM, 1)
        ));
    }
    if rig.tips.data_tip_assumed() && rig.fingers.iter().any(|f| f.audit.basis == Basis::Relative) {
        summary.push_str(&format!(
            " The verdicts of the fingers with a tip take the X-rays' fingertips as {} tips, an \
             assumption: their tip column records {}.",
            rig.tips.data_tip.name(),
            match rig.tips.data_tips.describe().strip_prefix("mixed: ") {
                Some(rest) => format!("a mix ({rest})"),
                None => "none".to_string(),
            }
        ));
    }
    summary
}

/// `audit --brief`: the [`opening`] and, with `with_summary`, the [`summary`], fitted to `width`.
pub(crate) fn brief(
    rig: &AuditedRig,
    confidence: f64,
    only_outside: bool,
    with_summary: bool,
    width: Width,
) -> String {
    let mut out = opening(rig, only_outside, width);
    if with_summary {
        out.push_str(&super::layout::fit_text(
            &para(&summary(rig, confidence), ""),
            width,
        ));
    }
    out
}

/// How the joint regions' shape was made, for the methods paragraph: S*
/// with the correlation pooled with the prior cohort's, or the X-rays' own S.
pub(crate) fn shape_words(rig: &AuditedRig) -> String {
    match &rig.tips.shape {
        Some(shape) if shape.hands > 0.0 => format!(
            "S* is the X-rays' covariance of u with their variances and its correlation pooled \
             with {}'s ({} hands, weighted as {}): r* = (m r0 + (n - 1) r_S) / (m + n - 1), \
             since 5 X-rays hardly fix the correlation (the prior borrows no variance, so the \
             bound stays the X-rays'; simulated, at most 5% of normal fingers fall outside \
             whatever the true correlation, ARCHITECTURE.md). Each verdict also gives T^2 on \
             the X-rays' own S (--prior-hands 0 judges on it).",
            shape.source,
            crate::format::xrays(shape.n).replace(" X-rays", ""),
            crate::format::count(shape.hands.round() as usize, "hand", "hands")
        ),
        _ => "S* is the X-rays' own covariance of u (no prior shape: --prior-hands 0, or no \
              atlas found)."
            .to_string(),
    }
}

/// The terminal report of `phalanx audit`, fitted to `width` (tables give way
/// as [`super::layout`] says; the other lines wrap): the [`opening`] (with
/// `only_outside` as `--only-outside` with a fix), then the details and the
/// methods.
pub(crate) fn text(
    rig: &AuditedRig,
    fbx: Option<&FbxSource>,
    data: &str,
    n_note: &str,
    confidence: f64,
    only_outside: bool,
    width: Width,
) -> String {
    let mut hidden = Hidden::new();
    let c = level(confidence);
    let mut out = opening(rig, only_outside, width);
    out.push('\n');
    out.push_str(&para(
        &format!("Rig audit of {} against {data} ({n_note})", rig.label),
        "",
    ));
    out.push_str(&para(
        &format!(
            "Joints in mm along each finger from the rig's MCP (distal = towards the tip; {}); \
             {c} prediction intervals. {}",
            units_words(fbx),
            tip_words(&rig.tips)
        ),
        "",
    ));
    if rig.fingers.iter().any(|f| f.audit.region.is_some()) {
        out.push_str(&para(
            &format!(
                "A finger with a tip is judged as one vector: its relative joint positions u = \
                 (J~1, J~1 + J~2) (the thumb's J~1) against the X-rays' {c} joint prediction \
                 region, T^2 = (u - u_bar)' [S* (1 + 1/n)]^-1 (u - u_bar) at most p (n - 1) / \
                 (n - p) times the {c} quantile of F(p, n - p) (normal proportions, independent \
                 hands). {} Its explanation is the fewest joints, each placed where the finger \
                 is most likely given the joints that stay, that bring it inside the X-rays' {} \
                 region (as typical as half of all hands, so that it stays inside as X-rays are \
                 added); a move that would leave it outside that is not made. Each row gives \
                 one joint or value against its own interval, read against that verdict.",
                shape_words(rig),
                level(FIX_LEVEL)
            ),
            "",
        ));
    }
    for w in &rig.warnings {
        out.push_str(&para(&format!("Warning: {w}"), ""));
    }
    for f in &rig.fingers {
        out.push('\n');
        out.push_str(&heading(f));
        let a = &f.audit;
        out.push_str(&para(
            &basis_words(a, f.skin_tip.as_ref().is_some_and(|t| t.from_mesh)),
            "  ",
        ));
        if a.joints.is_empty() {
            continue;
        }
        out.push_str(&finger_table(
            a,
            f.metacarpal_check.as_ref(),
            &c,
            width,
            &mut hidden,
        ));
        out.push_str(&para(&explanation_words(a), "  "));
        for j in a.joints.iter().filter(|j| j.fix_moves()) {
            out.push_str(&para(&suggestion(j), "  "));
        }
        if !f.bends.is_empty() {
            out.push_str(&para(&bend_words(&f.bends, rig.bend_tolerance), "  "));
        }
        if let Some(m) = &f.metacarpal_check {
            out.push_str(&para(&metacarpal_words(m, &c), "  "));
        }
    }
    if !rig.notes.is_empty() {
        out.push_str("\nNotes:\n");
        for n in &rig.notes {
            out.push_str(&para(n, "  - "));
        }
    }
    out.push('\n');
    out.push_str(&para(&summary(rig, confidence), ""));
    out.push_str("Caveats:\n");
    for c in caveats(&rig.tips, data) {
        out.push_str(&para(&c, "  - "));
    }
    hidden.append_to(&mut out, width);
    super::layout::fit_text(&out, width)
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
                num(by * MM, 1)
            )),
            Standing::Below { by } => outside.push(format!(
                "{} {} mm too close to the root",
                j.joint.name(),
                num(by * MM, 1)
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
    let region = a.region.as_ref().map(|r| {
        let words = format!("the {} joint region ({})", level(r.confidence), t2_words(r));
        (words, r.inside)
    });
    if let Some((words, true)) = &region {
        // The finger's verdict is the region's; a joint or value outside its
        // own interval alone is read against the whole vector.
        return if outside.is_empty() {
            format!("inside {words}")
        } else {
            format!("inside {words}; alone: {}", outside.join("; "))
        };
    }
    if !outside.is_empty() || region.is_some() {
        let fewest: Vec<String> = a
            .joints
            .iter()
            .filter(|j| j.fix_moves())
            .map(|j| {
                format!(
                    "{} {} mm towards the {}",
                    j.joint.name(),
                    num(j.shift * MM, 1),
                    if j.shift_along < 0.0 { "root" } else { "tip" }
                )
            })
            .collect();
        let explained = if fewest.is_empty() {
            String::new()
        } else {
            format!("; fewest joints to move: {}", fewest.join(", "))
        };
        match region {
            Some((words, _)) if outside.is_empty() => format!("outside {words}{explained}"),
            Some((words, _)) => format!("outside {words}: {}{explained}", outside.join("; ")),
            None => format!(
                "outside the prediction interval: {}{explained}",
                outside.join("; ")
            ),
        }
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

/// Each moved finger's T^2 against its bound, judged again `when` ("after
/// the fix"): "; each moved finger after the fix: right index T^2 1.2 of 25.5
/// (0.05), right ring T^2 30.1 of 25.5 (1.18, outside)"; empty for none.
pub(crate) fn moved_fingers_words(
    fingers: &[crate::rig::session::MovedFinger],
    when: &str,
) -> String {
    if fingers.is_empty() {
        return String::new();
    }
    let each: Vec<String> = fingers
        .iter()
        .map(|f| match f.t2 {
            Some((t2, bound)) => format!(
                "{} T^2 {} of {} ({}{})",
                f.label,
                num(t2, 1),
                num(bound, 1),
                num(t2 / bound, 2),
                if f.inside { "" } else { ", outside" }
            ),
            None => format!(
                "{} {}",
                f.label,
                if f.inside { "inside" } else { "outside" }
            ),
        })
        .collect();
    format!("; each moved finger {when}: {}", each.join(", "))
}

/// What the result line of `audit --fix` adds after its counts: each moved
/// finger's T^2 against its bound in the re-audit ("; each moved finger
/// after the fix: right index T^2 1.2 of 25.5 (0.05)"), every moved joint's
/// distance to where its skin bends before and after ("right index PIP 0.2
/// mm -> 0.4 mm"), and any bend defect the re-audit flags that the rig as
/// given did not have.
pub(crate) fn fix_after_words(fix: &crate::rig::session::FixOutcome) -> String {
    let mm = |d: Option<f64>| {
        d.map_or("not found".to_string(), |x| {
            format!("{} mm", num(x * MM, 1))
        })
    };
    let mut out = moved_fingers_words(&fix.fingers, "after the fix");
    if !fix.bends.is_empty() {
        let each: Vec<String> = fix
            .bends
            .iter()
            .map(|b| {
                let carried = match b.reweighted {
                    0 => String::new(),
                    n => format!(" ({n} vertices reweighted)"),
                };
                format!("{} {} -> {}{carried}", b.joint, mm(b.before), mm(b.after))
            })
            .collect();
        out.push_str(&format!(
            "; each moved joint's distance to where its skin bends, before -> after: {}",
            each.join(", ")
        ));
    }
    if fix.new_defects.is_empty() {
        out.push_str("; no new bend defect");
    } else {
        out.push_str(&format!(
            "; new bend defects the original did not have: {} (further than the bend tolerance \
             from where their skin bends)",
            and_list(&fix.new_defects)
        ));
    }
    out
}
