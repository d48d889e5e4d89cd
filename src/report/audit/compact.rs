//! The audit's default text, short enough to read in a minute: the opening,
//! one compact table per finger (its joints, the rig against the X-rays, one
//! verdict column), the explanation said once, and the summary. `--explain`
//! gives the full text ([`super::text`]).

use super::MM;
use super::explanation::{explanation_words, opening};
use super::table::summary;
use super::words::{and_list, joint_standing, para, shown_zero, value_standing};
use crate::analysis::Interval;
use crate::format::{level, num};
use crate::report::layout::{Width, fit_text};
use crate::rig::judge::{Basis, FingerAudit, JointCheck, MetacarpalCheck, RayBase};
use crate::rig::{AuditedFinger, AuditedRig};

/// One row of a finger's table: label, rig, X-ray mean, prediction, verdict.
type Row = [String; 5];

/// The default text of `phalanx audit`, fitted to `width`: the [`opening`]
/// (with `only_outside` as `--only-outside` with a fix), a line on what the
/// tables hold, each finger's table and explanation, and the summary.
pub(crate) fn compact(
    rig: &AuditedRig,
    data: &str,
    n_note: &str,
    confidence: f64,
    only_outside: bool,
    width: Width,
) -> String {
    let c = level(confidence);
    let mut out = opening(rig, only_outside, width);
    out.push_str(&para(
        &format!(
            "Against {data} ({n_note}), mm from the MCP, {c} prediction; --explain: every value."
        ),
        "",
    ));
    for w in &rig.warnings {
        out.push_str(&para(&format!("Warning: {w}"), ""));
    }
    out.push('\n');
    let mut body = String::new();
    for f in &rig.fingers {
        body.push_str(&finger_block(f, &c, width));
    }
    out.push_str(&fit_text(&body, width));
    out.push('\n');
    out.push_str(&para(&summary(rig, confidence), ""));
    fit_text(&out, width)
}

/// A finger's table and, when it does not fit as it is, its explanation.
fn finger_block(f: &AuditedFinger, c: &str, width: Width) -> String {
    let a = &f.audit;
    let label = f.chain.label();
    if a.basis == Basis::None || a.joints.is_empty() {
        return para(
            &format!("{label}: not judged (a thumb without a tip has no proportion)"),
            "",
        );
    }
    let mut rows: Vec<Row> = Vec::new();
    if let Some(m) = &f.metacarpal_check {
        rows.push(base_row(a, m));
    }
    for j in &a.joints {
        if j.joint == crate::analysis::placement::Joint::Mcp
            && (f.metacarpal_check.is_some() || !named(j))
        {
            continue;
        }
        rows.push(joint_row(a, j));
    }
    let verdict = match &a.region {
        Some(r) => region_verdict(a, r),
        None => {
            rows.extend(value_rows(a));
            "verdict".into()
        }
    };
    let head: Row = [
        label,
        "rig".into(),
        "mean".into(),
        format!("prediction {c}"),
        verdict,
    ];
    let mut out = render(&head, &rows, width);
    if told_by_rows(a) {
        return out;
    }
    out.push_str(&para(&explanation(a), "  "));
    out
}

/// True when the rows say all the explanation says: the finger fits as it
/// is, or the fix makes each of the explanation's moves (the rows give them)
/// and none is an MCP distal of where the X-rays put it.
fn told_by_rows(a: &FingerAudit) -> bool {
    let e = &a.explanation;
    if e.moved.is_empty() {
        return e.consistent;
    }
    e.consistent
        && a.joints.iter().filter(|j| j.moves).all(|j| {
            j.fix && !(j.joint == crate::analysis::placement::Joint::Mcp && j.shift_along < 0.0)
        })
}

/// The finger's verdict, in its table's head: T^2 of the relative joint
/// positions against the joint region's bound, and what the fix's moves make of it.
fn region_verdict(a: &FingerAudit, r: &crate::rig::judge::RegionCheck) -> String {
    let as_is = if r.inside {
        format!("T^2 {} <= {}: inside", num(r.t2, 1), num(r.bound, 1))
    } else {
        format!("T^2 {} > {}: OUT", num(r.t2, 1), num(r.bound, 1))
    };
    once_moved(a, as_is, r.inside)
}

/// The explanation of a finger that does not fit as it is, once: the joints
/// it moves against where the X-rays put them given the others, the joints
/// the fix holds (their rows say why), and the other sets that would fit.
fn explanation(a: &FingerAudit) -> String {
    let e = &a.explanation;
    if !e.consistent {
        return explanation_words(a);
    }
    let moved: Vec<&JointCheck> = a.joints.iter().filter(|j| j.moves).collect();
    let parts: Vec<String> = moved
        .iter()
        .map(|j| {
            let web = j.joint == crate::analysis::placement::Joint::Mcp && j.shift_along < 0.0;
            format!(
                "the {} {} mm {}{}",
                j.joint.name(),
                num(j.shift_along.abs() * MM, 1),
                if j.shift_along < 0.0 {
                    "distal"
                } else {
                    "proximal"
                },
                if web { " (as at the finger web)" } else { "" }
            )
        })
        .collect();
    let others: Vec<&str> = a
        .joints
        .iter()
        .filter(|j| !j.moves)
        .map(|j| j.joint.name())
        .collect();
    let mut out = format!(
        "Explanation: given the other joints, the rig has {} of where the X-rays put {}; {} \
         then fit.",
        and_list(&parts),
        if parts.len() == 1 { "it" } else { "them" },
        and_list(&others.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    );
    let held: Vec<String> = moved
        .iter()
        .filter(|j| !j.fix)
        .map(|j| j.joint.name().to_string())
        .collect();
    match held.len() {
        0 => {}
        n if n == moved.len() && n == 2 => out.push_str(" The fix holds both."),
        _ => out.push_str(&format!(" The fix holds the {}.", and_list(&held))),
    }
    out
}

/// True when the explanation or a hold names the joint with a move that
/// prints as more than 0.0 mm.
fn named(j: &JointCheck) -> bool {
    j.fix || j.held.as_ref().is_some_and(|h| !shown_zero(h.shift))
}

/// "[41.1, 48.5]", each end by `f`.
fn interval(i: Option<Interval>, f: &dyn Fn(f64) -> String) -> String {
    i.map_or("n/a".into(), |p| format!("[{}, {}]", f(p.low), f(p.high)))
}

/// The MCP from its ray's base against the atlas, with what the fix does of
/// the MCP.
fn base_row(a: &FingerAudit, m: &MetacarpalCheck) -> Row {
    let mm = |x: f64| num(x * MM, 1);
    let from = match m.base {
        RayBase::Cmc => "MCP from CMC",
        RayBase::Wrist => "MCP from wrist",
    };
    let as_is = joint_standing(m.standing, MM);
    // The MCP's hold is told by its reason only: its length is the finger's
    // own measure of the MCP, and this row gives the base's.
    let verdict = match a.joint(crate::analysis::placement::Joint::Mcp) {
        Some(j) if j.fix => with_fix(as_is, j),
        Some(j) => match &j.held {
            Some(h) if !shown_zero(h.shift) => format!("{as_is}; held"),
            _ => as_is,
        },
        None => as_is,
    };
    [
        from.into(),
        mm(m.to_mcp),
        mm(m.expected),
        interval(m.pi, &mm),
        verdict,
    ]
}

/// A joint along the finger (mm from the rig's MCP).
fn joint_row(a: &FingerAudit, j: &JointCheck) -> Row {
    let mm = |x: f64| num(x * MM, 1);
    let as_is = joint_standing(j.standing, MM);
    let verdict = if named(j) {
        with_fix(as_is, j)
    } else {
        once_moved(a, as_is, j.standing.is_consistent())
    };
    [
        j.joint.name().to_string(),
        mm(j.measured),
        mm(j.expected),
        interval(j.pi, &mm),
        verdict,
    ]
}

/// `as_is` with the fix's move of `j` ("; move 2.7 mm towards the root"),
/// or its hold ("; held: would leave its skin bend"); a move that prints as
/// 0.0 mm is no move.
fn with_fix(as_is: String, j: &JointCheck) -> String {
    if j.fix {
        return format!(
            "{as_is}; move {} mm towards the {}",
            num(j.shift * MM, 1),
            if j.shift_along >= 0.0 { "tip" } else { "root" }
        );
    }
    match &j.held {
        Some(h) if !shown_zero(h.shift) => {
            // Its reason is the opening line's.
            format!("{as_is}; held ({} mm)", num(h.shift * MM, 1))
        }
        _ => as_is,
    }
}

/// `as_is`, and, for a row outside its interval whose finger fits once the
/// fix makes the explanation's moves, "fits once the IP moves"; never a move
/// the fix does not make.
fn once_moved(a: &FingerAudit, as_is: String, consistent: bool) -> String {
    let e = &a.explanation;
    let made = !e.moved.is_empty() && e.moved.iter().all(|k| a.joint(*k).is_some_and(|j| j.fix));
    if consistent || !e.consistent || !made {
        return as_is;
    }
    format!("{as_is}; fits after the moves")
}

/// A finger without a joint region (no tip): each value against its interval.
fn value_rows(a: &FingerAudit) -> Vec<Row> {
    let v4 = |x: f64| num(x, 4);
    a.values
        .iter()
        .map(|v| {
            [
                v.quantity.symbol().to_string(),
                v4(v.measured),
                v4(v.mean),
                interval(v.pi, &v4),
                once_moved(a, value_standing(v.standing), v.standing.is_consistent()),
            ]
        })
        .collect()
}

/// The table: the head (the finger's label first) at the margin, the rows
/// two columns in, the verdict wrapped under itself to fit `width`.
fn render(head: &Row, rows: &[Row], width: Width) -> String {
    let mut w = [0usize; 4];
    for (k, wk) in w.iter_mut().enumerate() {
        let head_k = head[k].chars().count();
        let body = rows.iter().map(|r| r[k].chars().count()).max().unwrap_or(0)
            + if k == 0 { 2 } else { 0 };
        *wk = head_k.max(body);
    }
    let line = |r: &Row, indent: &str| -> String {
        let label = format!("{indent}{}", r[0]);
        format!(
            "{label:<w0$}  {:>w1$}  {:>w2$}  {:<w3$}  ",
            r[1],
            r[2],
            r[3],
            w0 = w[0],
            w1 = w[1],
            w2 = w[2],
            w3 = w[3]
        )
    };
    let mut out = String::new();
    for (r, indent) in std::iter::once((head, "")).chain(rows.iter().map(|r| (r, "  "))) {
        let first = line(r, indent);
        let text = format!("{first}{}", r[4]);
        match width {
            Width::Fit(max) if text.chars().count() > max => {
                let hanging = " ".repeat(first.chars().count());
                let options = textwrap::Options::new(max)
                    .subsequent_indent(&hanging)
                    .word_splitter(textwrap::WordSplitter::NoHyphenation);
                out.push_str(&textwrap::fill(&text, options));
            }
            _ => out.push_str(text.trim_end()),
        }
        out.push('\n');
    }
    out
}
