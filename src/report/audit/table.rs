//! The audit's full text (`--explain`): the finger tables, the summary and the brief form.

use super::MM;
use super::explanation::*;
use super::words::*;
use crate::analysis::Interval;
use crate::analysis::region::FIX_LEVEL;
use crate::format::{level, num};
use crate::report::layout::{Align, Give, Grid, Hidden, Width};
use crate::rig::AuditedRig;
use crate::rig::judge::{Basis, FingerAudit, MetacarpalCheck, RayBase};
use crate::rig::read::source::FbxSource;

/// The table of one finger: each joint (mm from the rig's MCP) and each value,
/// fitted to `width` (the X-ray range goes first, then the standings wrap).
pub(super) fn finger_table(
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

/// The joint region's row: T^2 of the relative joint positions as the rig is,
/// against the region's bound (the finger's verdict; see [`given`]).
pub(super) fn region_row(a: &FingerAudit) -> Option<Vec<String>> {
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
            " {} over {} mm from where the skin bends.",
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
        out.push_str(&crate::report::layout::fit_text(
            &para(&summary(rig, confidence), ""),
            width,
        ));
    }
    out
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
    crate::report::layout::fit_text(&out, width)
}
