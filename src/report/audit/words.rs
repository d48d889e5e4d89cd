//! The words of one finger's audit: how each value, joint, tip and metacarpal stands,
//! and the caveats.

use super::MM;
use crate::analysis::{Interval, Quantity};
use crate::format::{level, num, percent};
use crate::rig::AuditedRig;
use crate::rig::bend::Bend;
use crate::rig::judge::{
    Basis, FingerAudit, JointCheck, JudgeOptions, MetacarpalCheck, RayBase, RegionCheck,
    SoftTissue, Standing, TipKind,
};
use crate::rig::read::source::FbxSource;

/// `text` as one line starting with `first`; [`crate::report::layout::fit_text`]
/// wraps it to the terminal's width at the end, continuing two columns further in.
pub(super) fn para(text: &str, first: &str) -> String {
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

/// True when a length prints as 0.0 mm (to 0.1 mm).
pub(super) fn shown_zero(x: f64) -> bool {
    (x * MM * 10.0).round() == 0.0
}

/// "A, B and C".
pub(super) fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
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

/// A row's standing given the finger's explanation, with the rig's own
/// standing `as_is` beside it where the two differ, labelled "as the rig
/// is", so a row never contradicts the explanation under the table: a row
/// outside as the rig is that fits once the explanation's joints move says
/// so ("fits once the MCP moves (as the rig is: OUT, 0.2 mm too distal)").
pub(super) fn given(a: &FingerAudit, as_is: String, consistent: bool) -> String {
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
    // A move the fix does not make is not one the row can wait for.
    let made = e
        .moved
        .iter()
        .all(|k| a.joint(*k).is_some_and(|j| j.fix_moves()));
    if !made {
        return as_is;
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

/// A joint's standing given the explanation ([`given`]): a joint the
/// explanation moves says by how much and whether the fix makes the move or
/// holds it, with its standing as the rig is.
pub(super) fn joint_given(a: &FingerAudit, j: &JointCheck) -> String {
    let as_is = joint_standing(j.standing, MM);
    if !a.explanation.moved.contains(&j.joint) {
        let g = given(a, as_is, j.standing.is_consistent());
        // A joint an earlier explanation would have moved, held (off its
        // bend, pinned), the explanation then sought without it.
        return match &j.held {
            Some(h) if !shown_zero(h.shift) => format!("{g}; {}", h.words),
            _ => g,
        };
    }
    let mm = num(j.shift * MM, 1);
    match &j.held {
        Some(h) if shown_zero(h.shift) => as_is,
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

/// How the joint regions' shape was made, for the methods paragraph: S*
/// with the correlation pooled with the prior cohort's, or the X-rays' own S.
pub(crate) fn shape_words(rig: &AuditedRig) -> String {
    match &rig.tips.shape {
        Some(shape) if shape.hands > 0.0 => format!(
            "S* is the X-rays' covariance of u with their variances and its correlation pooled \
             with {}'s ({} hands, weighted as {}): r* = (m r0 + (n - 1) r_S) / (m + n - 1), \
             since 5 X-rays hardly fix the correlation (the prior borrows no variance, so the \
             bound stays the X-rays'; simulated, at most 5% of normal fingers fall outside \
             whatever the true correlation, docs/internals.md). Each verdict also gives T^2 on \
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

/// The measured value of `q` for a finger, when judged.
pub(crate) fn value_of(a: &FingerAudit, q: Quantity) -> Option<f64> {
    a.values
        .iter()
        .find(|v| v.quantity == q)
        .map(|v| v.measured)
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
