//! Terminal output of `stats`, `check`, `coverage`, `history` and `place`,
//! fitted to the terminal's width by [`super::layout`].

use super::layout::{Align, Give, Grid, Hidden, Width, fit_text};
use super::phrases::{record_change, units_note};
use crate::analysis::claims::{CheckSummary, ClaimResult};
use crate::analysis::coverage::{CoverageSettings, CurvePoint};
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::dataset::history::Snapshot;
use crate::format::{
    decimals, exact, interval, interval_cells, length_decimals, level, num, opt, percent, signed,
    xrays,
};
use crate::rig::judge::data_tip_of;

/// The statistics of every finger, 4 decimals for relative values as in the paper.
///
/// Too wide for `width`, the percentile and BCa intervals go first, then the
/// range, the SE and the t interval, then (below about 75 columns) the min
/// and max: the mean, SD and prediction interval stay.
fn stats_body(a: &Analysis, width: Width, hidden: &mut Hidden, head: bool) -> String {
    let c = level(a.settings.confidence);
    let mut out = String::new();
    if head {
        out.push_str(&format!(
            "phalanx statistics of {} ({}, {} rows); confidence {c}, seed {}\n",
            a.dataset.path,
            xrays(a.dataset.xrays),
            a.dataset.rows,
            a.settings.seed
        ));
        for line in dataset_notes(a) {
            out.push_str(&format!("note: {line}\n"));
        }
        out.push_str(&flagged_text(a));
    }
    for f in &a.fingers {
        out.push_str(&format!(
            "\n{} - n = {}; bootstrap {}\n",
            f.finger.display_name(),
            xrays(f.n),
            crate::format::plan(f.bootstrap)
        ));
        let mut t = Grid::new()
            .col("quantity", Align::Left, Give::Keep)
            .col("mean", Align::Right, Give::Keep)
            // The paper's four statistics (mean, min, max, range) always stay; the
            // prediction interval gives way before the sd and the t interval.
            .col("min", Align::Right, Give::Keep)
            .col("max", Align::Right, Give::Keep)
            .col("range", Align::Right, Give::Keep)
            .col("sd", Align::Right, Give::Drop(6))
            .col("se", Align::Right, Give::Drop(3))
            .col("t CI", Align::Right, Give::Drop(5))
            .col("percentile CI", Align::Right, Give::Drop(1))
            .col("BCa CI", Align::Right, Give::Drop(2))
            .col("prediction", Align::Right, Give::Drop(4));
        for q in &f.quantities {
            let d = decimals(q.name.is_unitless());
            let mut row = vec![
                q.name.label().to_string(),
                num(q.mean, d),
                num(q.min, d),
                num(q.max, d),
                num(q.range, d),
                opt(q.sd, d),
                opt(q.se, d),
            ];
            row.extend(interval_cells(&q.intervals, d));
            t.row(row);
        }
        out.push_str(&t.render(width, 0, hidden));
        for q in &f.quantities {
            for n in &q.notes {
                out.push_str(&format!("note ({}): {n}\n", q.name.name()));
            }
        }
    }
    out
}

/// What a reader must know about a dataset's lengths before reading its statistics:
/// that pixel lengths are not averaged, that J in image units describes no physical
/// length, and where the fingertips are when recorded.
pub fn dataset_notes(a: &Analysis) -> Vec<String> {
    let mut notes = Vec::new();
    if a.pixel_lengths() {
        notes.push(PIXEL_NOTE.to_string());
    }
    if a.unit.as_deref() == Some("image units") {
        notes.push(IMAGE_UNITS_NOTE.to_string());
    }
    if let Some(n) = units_note(a) {
        notes.push(n);
    }
    notes.push(tips_note(a));
    notes
}

/// Where the dataset's fingertips are, when its rows record it, and what is assumed of
/// the rows that do not: they pool with the others, and the rig audits take every tip as
/// [`data_tip_of`]'s kind, which their verdicts rest on.
pub fn tips_note(a: &Analysis) -> String {
    let t = &a.tips;
    if t.single().is_some() {
        return format!("fingertips: {}", t.describe());
    }
    let assumed = data_tip_of(t).name();
    let audits = format!(
        "'phalanx audit' and the report's rigs take every tip here as a {assumed} tip, \
         so their verdicts rest on that assumption"
    );
    match (t.bone + t.skin, t.unknown) {
        (_, 0) => format!("fingertips: {}; {audits}", t.describe()),
        (0, _) => format!(
            "fingertips: not recorded (no row of {} gives a tip); {audits}. Record where they \
             were measured in a tip column (bone or skin)",
            a.dataset.path
        ),
        _ => format!(
            "fingertips: {} ({} of {}); the statistics pool the rows without a tip with the \
             others as if measured to the same tip, and {audits}. Record where they were \
             measured in their tip column (bone or skin)",
            t.describe(),
            a.untipped.with_word(),
            a.dataset.path
        ),
    }
}

/// The note on J in image units (the paper's unit), which is averaged as the paper does.
pub const IMAGE_UNITS_NOTE: &str = "J (total length) is in image units, pixels of X-ray images with no common scale: its SD and intervals pool the images' scales with the hands' sizes and describe no physical length. The relative values and ratios are ratios within one image, so the scale cancels from them";

/// Why a dataset in pixels has no total length J.
pub const PIXEL_NOTE: &str = "lengths are in pixels (px) of images whose scale differs, so the total length J and the metacarpal are not comparable across X-rays and are not averaged; the relative values and ratios are. Import with --pixel-spacing MM for lengths in millimetres";

/// The rows of the data added though flagged as likely errors, when there are: each
/// with its line and why, and how to take it out.
pub(crate) fn flagged_text(a: &Analysis) -> String {
    if a.flagged.is_empty() {
        return String::new();
    }
    let mut out = format!(
        "flagged: {} of the data {} added though flagged as a likely error (add --accept-flagged); check {}, and take out a wrong one with 'phalanx remove --xray ID --finger F':\n",
        if a.flagged.len() == 1 {
            "1 row".to_string()
        } else {
            format!("{} rows", a.flagged.len())
        },
        if a.flagged.len() == 1 { "was" } else { "were" },
        if a.flagged.len() == 1 { "it" } else { "them" },
    );
    for f in &a.flagged {
        out.push_str(&format!(
            "  - X-ray {} {} (line {}): {}\n",
            f.xray,
            f.finger.name(),
            f.line,
            f.reason
        ));
    }
    out
}

/// The statistics of the whole dataset, then of each group (`--group-by`), known groups
/// first, then the differences between the known groups.
pub(crate) fn stats_with_groups(
    a: &Analysis,
    groups: Option<&crate::analysis::groups::Groups>,
    width: Width,
) -> String {
    let mut hidden = Hidden::new();
    let mut out = stats_body(a, width, &mut hidden, true);
    for g in groups.map_or(&[][..], |g| &g.groups) {
        out.push_str(&format!(
            "\n==== {} = {} ({}) ====\n",
            g.by,
            g.label,
            xrays(g.xrays)
        ));
        if let Some(n) = &g.note {
            out.push_str(&format!("note: {n}\n"));
        }
        out.push_str(&stats_body(&g.analysis, width, &mut hidden, false));
    }
    for d in groups.map_or(&[][..], |g| &g.differences) {
        out.push_str(&group_difference(
            groups.map_or("", |g| g.by),
            d,
            width,
            &mut hidden,
        ));
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// One known group against the reference group, per finger: a sentence (as `compare`
/// says it), then per quantity each group's mean (SD), the difference with its Welch and
/// bootstrap intervals, and Hedges' g.
fn group_difference(
    by: &str,
    d: &crate::analysis::groups::GroupDifference,
    width: Width,
    hidden: &mut Hidden,
) -> String {
    use super::compare as cmp;
    use super::compare_words::{Names, short};
    let c = &d.cohorts;
    let lv = level(c.settings.confidence);
    let mut out = format!(
        "\n==== {by}: {} against {} (differences {} - {}) ====\n",
        d.b, d.a, d.b, d.a
    );
    let names = Names {
        a: d.a.as_str(),
        b: d.b.as_str(),
    };
    for f in &c.fingers {
        out.push_str(&format!(
            "\n{} ({}: {}, {}: {})\n",
            cmp::finger_sentence(f, names, c.settings.confidence),
            d.a,
            xrays(f.n_a),
            d.b,
            xrays(f.n_b)
        ));
        // Each group's means are in its own tables above.
        let mut t = Grid::new()
            .col("quantity", Align::Left, Give::Keep)
            .col(format!("{} - {}", d.b, d.a), Align::Right, Give::Keep)
            .col(format!("Welch {lv}"), Align::Right, Give::Keep)
            .col(format!("bootstrap {lv}"), Align::Right, Give::Drop(2))
            .col("Hedges' g", Align::Right, Give::Drop(1));
        for q in &f.quantities {
            let (k, cmpn) = (q.quantity, &q.comparison);
            t.row(vec![
                short(k).to_string(),
                cmp::difference_cell(cmpn, k),
                cmp::welch_cell(cmpn, k),
                cmp::bootstrap_cell(cmpn, k),
                cmp::hedges_cell(cmpn),
            ]);
        }
        out.push_str(&t.render(width, 0, hidden));
    }
    for n in &c.notes {
        out.push_str(&format!("note: {n}\n"));
    }
    out
}

/// The claim-by-claim check, then a summary line. Too wide for `width`, the
/// "where" and "verdict" columns wrap.
pub(crate) fn check(results: &[ClaimResult], width: Width) -> String {
    let mut t = Grid::new()
        .col("claim", Align::Left, Give::Keep)
        .col("where", Align::Left, Give::Wrap)
        .col("stated", Align::Right, Give::Keep)
        .col("computed", Align::Right, Give::Keep)
        .col("verdict", Align::Left, Give::Wrap);
    for r in results {
        let computed = match r.computed_rounded {
            Some(x) if r.verdict == crate::analysis::claims::Verdict::MatchesRounded => {
                format!(
                    "{} (rounded: {})",
                    num(r.computed, r.decimals + 2),
                    num(x, r.decimals)
                )
            }
            _ if r.decimals == 0 && r.computed.fract() == 0.0 => num(r.computed, 0),
            _ => num(r.computed, r.decimals + 2),
        };
        t.row(vec![
            r.id.clone(),
            r.location.clone(),
            r.stated_text.clone(),
            computed,
            r.verdict.label().to_string(),
        ]);
    }
    let mut hidden = Hidden::new();
    let mut out = t.render(width, 0, &mut hidden);
    let explained: Vec<&ClaimResult> = results.iter().filter(|r| r.cause.is_some()).collect();
    if !explained.is_empty() {
        out.push_str("\nWhy the disagreements:\n");
        for r in explained {
            out.push_str(&format!(
                "- {} ({}): {}\n",
                r.id,
                r.refers_to,
                r.cause.as_deref().unwrap_or("")
            ));
            if let Some(note) = r.erratum_note.as_deref().filter(|n| !n.is_empty()) {
                out.push_str(&format!("  recorded erratum: {note}\n"));
            }
        }
    }
    let s = CheckSummary::of(results);
    out.push_str(&format!(
        "\n{} claims: {} match, {} match from rounded values, {} known errata, {} new mismatches\n",
        s.claims, s.matches, s.matches_rounded, s.known_errata, s.mismatches
    ));
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// The simulated coverage of each interval method, one row per sample size
/// (the dataset's own sizes marked), then why any of the data's sizes is not
/// simulated (`notes`) and which interval to use.
pub(crate) fn coverage(
    points: &[CurvePoint],
    settings: &CoverageSettings,
    notes: &[String],
    width: Width,
) -> String {
    let mut t = Grid::new()
        .col("n (X-rays)", Align::Right, Give::Keep)
        .col("t CI", Align::Right, Give::Keep)
        .col("percentile CI", Align::Right, Give::Keep)
        .col("BCa CI", Align::Right, Give::Keep)
        .col("prediction", Align::Right, Give::Keep)
        .col("", Align::Left, Give::Wrap);
    for p in points {
        let mut row = vec![p.n.to_string()];
        row.extend(p.coverage.methods.iter().map(|m| percent(m.coverage)));
        row.push(if p.in_data { "this data" } else { "" }.to_string());
        t.row(row);
    }
    let mut hidden = Hidden::new();
    let table = t.render(width, 0, &mut hidden);
    let data: Vec<String> = points
        .iter()
        .filter(|p| p.in_data)
        .map(|p| xrays(p.n))
        .collect();
    let mut out = format!(
        "Simulated coverage of nominal {} intervals: {sims} simulated datasets per sample size from a normal model \
         (coverage depends on n alone). Confidence intervals are checked against the model mean; the prediction \
         interval against one new draw. The bootstrap uses {} resamples at this data's n ({}) and at most {} elsewhere.\n",
        level(settings.confidence),
        settings.resamples,
        if data.is_empty() {
            "none simulated".to_string()
        } else {
            data.join(", ")
        },
        crate::analysis::coverage::CURVE_RESAMPLES,
        sims = settings.sims
    );
    out.push_str(&table);
    for n in notes {
        out.push_str(&format!("note: {n}\n"));
    }
    if let Some(advice) = super::phrases::interval_advice(points) {
        out.push('\n');
        out.push_str(&advice);
        out.push('\n');
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// How many quantities the compact history shows when the user picks none.
pub(crate) const MOVED_SHOWN: usize = 6;

/// How many records the compact history lists (the latest), before saying how many more.
pub(crate) const RECORDS_SHOWN: usize = 12;

/// The history: by default the records (the latest [`RECORDS_SHOWN`], each with what it
/// changed) and one table of the quantities that moved most from the first record to
/// the last ([`MOVED_SHOWN`] of them), or of the ones `finger` and `quantity` pick; one
/// quantity picked, its table record by record. `all` gives every selected quantity's
/// table, record by record. Too wide for `width`, the CI width goes first, then the SD,
/// the event and the shift.
pub(crate) fn history(
    path: &std::path::Path,
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
    all: bool,
    width: Width,
) -> String {
    if snaps.is_empty() {
        return fit_text(
            &format!(
                "No snapshots in {} yet: 'phalanx add' and 'phalanx remove' record one per change, 'phalanx snapshot' one on demand.\n",
                path.display()
            ),
            width,
        );
    }
    let mut hidden = Hidden::new();
    let mut out = format!(
        "{} snapshot{} in {}, {} to {}\n",
        snaps.len(),
        if snaps.len() == 1 { "" } else { "s" },
        path.display(),
        snaps[0].time,
        snaps[snaps.len() - 1].time
    );
    let one = finger.is_some() && quantity.is_some();
    if all || one {
        for (f, q) in crate::analysis::tracking::selected(snaps, finger, quantity) {
            out.push_str(&format!("\n{f} {}\n", q.label()));
            out.push_str(&quantity_table(snaps, f, q, width, &mut hidden));
        }
        if one {
            out.push_str(&records_list(snaps, width));
        }
    } else {
        out.push_str(&records_list(snaps, width));
        out.push_str(&moved_table(snaps, finger, quantity, width, &mut hidden));
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// The records, one line each (the latest [`RECORDS_SHOWN`]): number, time, event,
/// X-rays, what changed.
fn records_list(snaps: &[Snapshot], width: Width) -> String {
    let skip = snaps.len().saturating_sub(RECORDS_SHOWN);
    let mut out = String::from("\n");
    if skip > 0 {
        out.push_str(&format!(
            "(snapshots 1 to {skip} not listed; --all shows every one)\n"
        ));
    }
    for (i, s) in snaps.iter().enumerate().skip(skip) {
        let change = record_change(s);
        out.push_str(&format!(
            "#{} {} {}, {}{}\n",
            i + 1,
            s.time,
            s.event,
            xrays(s.xrays),
            if change.is_empty() {
                String::new()
            } else {
                format!(": {change}")
            }
        ));
    }
    fit_text(&out, width)
}

/// One quantity record by record: mean, SD, t interval, its width, the shift from the
/// record before.
fn quantity_table(
    snaps: &[Snapshot],
    f: Finger,
    q: Quantity,
    width: Width,
    hidden: &mut Hidden,
) -> String {
    let d = decimals(q.is_unitless());
    let mut t = Grid::new()
        .col("#", Align::Right, Give::Keep)
        .col("time", Align::Left, Give::Keep)
        .col("event", Align::Left, Give::Drop(3))
        .col("n", Align::Right, Give::Keep)
        .col("mean", Align::Right, Give::Keep)
        .col("sd", Align::Right, Give::Drop(2))
        .col("t CI", Align::Right, Give::Keep)
        .col("CI width", Align::Right, Give::Drop(1))
        .col("mean shift", Align::Right, Give::Drop(4));
    let mut previous: Option<f64> = None;
    for (i, s) in snaps.iter().enumerate() {
        let Some(r) = s
            .quantities
            .iter()
            .find(|r| r.finger == f && r.quantity == q)
        else {
            continue;
        };
        let ci = r.intervals.ci_t;
        t.row(vec![
            (i + 1).to_string(),
            s.time.clone(),
            s.event.to_string(),
            r.n.to_string(),
            num(r.mean, d),
            opt(r.sd, d),
            interval(ci, d),
            opt(ci.map(|c| c.width()), d),
            previous.map_or_else(|| "-".to_string(), |p| signed(r.mean - p, d)),
        ]);
        previous = Some(r.mean);
    }
    t.render(width, 0, hidden)
}

/// The quantities that moved most from the first record to the last (or those picked),
/// one row each: X-rays, mean, shift, shift in SDs, t interval, first and last.
fn moved_table(
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
    width: Width,
    hidden: &mut Hidden,
) -> String {
    let (first, last) = (&snaps[0], &snaps[snaps.len() - 1]);
    let moved = crate::analysis::tracking::moved(first, last, finger, quantity);
    let picked = finger.is_some() || quantity.is_some();
    let shown = if picked {
        moved.len()
    } else {
        moved.len().min(MOVED_SHOWN)
    };
    let mut out = if picked {
        format!(
            "\nFrom snapshot 1 to {} ({}; shift in SDs of snapshot 1):\n",
            snaps.len(),
            match (finger, quantity) {
                (Some(f), None) => format!("the {f}'s quantities"),
                (None, Some(q)) => format!("{} of every finger", q.label()),
                _ => "the quantities picked".to_string(),
            }
        )
    } else {
        format!(
            "\nThe {shown} quantities that moved most from snapshot 1 to {} (shift in SDs of snapshot 1; \
             --finger and --quantity pick others, --all shows every quantity snapshot by snapshot):\n",
            snaps.len()
        )
    };
    let mut t = Grid::new()
        .col("finger", Align::Left, Give::Keep)
        .col("quantity", Align::Left, Give::Keep)
        .col("n", Align::Right, Give::Keep)
        .col("mean", Align::Right, Give::Keep)
        .col("shift", Align::Right, Give::Keep)
        .col("SDs", Align::Right, Give::Drop(2))
        .col("t CI first", Align::Right, Give::Drop(1))
        .col("t CI last", Align::Right, Give::Keep);
    for m in moved.iter().take(shown) {
        let d = decimals(m.quantity.is_unitless());
        t.row(vec![
            m.finger.name().to_string(),
            m.quantity.label().to_string(),
            format!("{} -> {}", m.before.n, m.after.n),
            format!("{} -> {}", num(m.before.mean, d), num(m.after.mean, d)),
            signed(m.after.mean - m.before.mean, d),
            m.standardised
                .map_or_else(|| "-".to_string(), |z| signed(z, 1)),
            interval(m.before.intervals.ci_t, d),
            interval(m.after.intervals.ci_t, d),
        ]);
    }
    if snaps.len() == 1 {
        out.push_str("(one snapshot: nothing has moved yet)\n");
    }
    out.push_str(&t.render(width, 0, hidden));
    out
}

/// Joint positions and segment lengths of model fingers, one table each. Too
/// wide for `width`, the percentile and BCa intervals go first, then the
/// range, the max and the min.
pub(crate) fn placement(
    ps: &[crate::analysis::placement::FingerPlacement],
    confidence: f64,
    width: Width,
) -> String {
    let c = level(confidence);
    let mut hidden = Hidden::new();
    let mut out = String::new();
    for p in ps {
        out.push_str(&format!(
            "{} - model length {} (from {}); positions from the root joint (MCP at 0, tip at {})\n",
            p.finger.display_name(),
            exact(p.length),
            xrays(p.n),
            exact(p.length)
        ));
        let d = length_decimals(p.length);
        let t = placement_grid(
            &[
                ("mean".to_string(), Give::Keep),
                ("min".to_string(), Give::Drop(5)),
                ("max".to_string(), Give::Drop(4)),
                ("range".to_string(), Give::Drop(3)),
                (format!("t CI {c}"), Give::Keep),
                ("percentile CI".to_string(), Give::Drop(1)),
                ("BCa CI".to_string(), Give::Drop(2)),
                ("prediction".to_string(), Give::Keep),
            ],
            PlacedRows {
                joints: p
                    .joints
                    .iter()
                    .map(|j| (j.joint.name(), &j.position))
                    .collect(),
                segments: p.segments.iter().map(|s| (s.segment, &s.length)).collect(),
                metacarpal: p.metacarpal.as_ref().map(|m| &m.position),
            },
            |v| {
                let mut row = vec![
                    num(v.mean, d),
                    num(v.min, d),
                    num(v.max, d),
                    num(v.range, d),
                ];
                row.extend(interval_cells(&v.intervals, d));
                row
            },
        );
        out.push_str(&t.render(width, 0, &mut hidden));
        if let Some(m) = &p.metacarpal {
            out.push_str(&format!(
                "MCP from the CMC: the metacarpal, (mc/J) x {}, from the {} X-rays that measure it; the CMC is the metacarpal's base at the wrist\n",
                exact(p.length),
                m.n
            ));
        }
        out.push('\n');
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// The rows of one finger's placement: its joints, its segments, and the MCP from the CMC
/// when the metacarpal is measured.
struct PlacedRows<'v, V> {
    joints: Vec<(&'static str, &'v V)>,
    segments: Vec<(&'v str, &'v V)>,
    metacarpal: Option<&'v V>,
}

/// The one grid of a finger's placement, for the data's placement and a table's: a label
/// column, then `heads` (right-aligned), one row per joint, segment and the MCP from the
/// CMC, each row's cells from `cells`.
fn placement_grid<V>(
    heads: &[(String, Give)],
    rows: PlacedRows<'_, V>,
    cells: impl Fn(&V) -> Vec<String>,
) -> Grid {
    let mut t = Grid::new().col("", Align::Left, Give::Keep);
    for (head, give) in heads {
        t = t.col(head.clone(), Align::Right, *give);
    }
    let labelled = rows
        .joints
        .into_iter()
        .map(|(joint, v)| (format!("{joint} joint"), v))
        .chain(
            rows.segments
                .into_iter()
                .map(|(s, v)| (format!("segment {}", s.to_uppercase()), v)),
        )
        .chain(rows.metacarpal.map(|v| ("MCP from the CMC".to_string(), v)));
    for (what, v) in labelled {
        let mut row = vec![what];
        row.extend(cells(v));
        t.row(row);
    }
    t
}

/// Joint positions placed from a summary table, one table per finger, with the sentence
/// the intervals rest on (the correlation assumed between the table's segments).
pub(crate) fn table_placement(
    table: &str,
    ps: &[crate::analysis::placement::TablePlacement],
    correlation: &str,
    confidence: f64,
    width: Width,
) -> String {
    let c = level(confidence);
    let mut hidden = Hidden::new();
    let mut out = String::new();
    for p in ps {
        out.push_str(&format!(
            "{} - model length {} (from the means of {}, {} hands); positions from the root joint (MCP at 0, tip at {}, {})\n",
            p.finger.display_name(),
            exact(p.length),
            table,
            p.n.map_or("n not given".to_string(), |n| n.to_string()),
            exact(p.length),
            match p.tip {
                crate::dataset::TipKind::Skin => "the tip at the skin: the table's soft tissue included",
                crate::dataset::TipKind::Bone => "the tip at the end of the bone: the table gives no soft tissue",
            }
        ));
        let d = length_decimals(p.length);
        let t = placement_grid(
            &[
                ("ratio of means".to_string(), Give::Keep),
                (format!("t CI {c}"), Give::Keep),
                ("prediction".to_string(), Give::Keep),
            ],
            PlacedRows {
                joints: p
                    .joints
                    .iter()
                    .map(|j| (j.joint.name(), &j.position))
                    .collect(),
                segments: p.segments.iter().map(|(s, v)| (&**s, v)).collect(),
                metacarpal: p.metacarpal.as_ref(),
            },
            |v| vec![num(v.mean, d), interval(v.ci, d), interval(v.pi, d)],
        );
        out.push_str(&t.render(width, 0, &mut hidden));
        if let Some(w) = &p.why {
            out.push_str(&format!("no interval: {w}\n"));
        }
        out.push_str(&format!(
            "The intervals rest on an assumed correlation of {} between the table's segments of this finger.\n\n",
            crate::format::trimmed(p.rho, 2)
        ));
    }
    out.push_str(&format!("{correlation}\n"));
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// The coverage measured on a population of hands: every method's coverage over the
/// quantities per sample size beside the normal model's, then each quantity's per size.
pub fn population(
    path: &str,
    study: &crate::analysis::population::PopulationStudy,
    width: Width,
) -> String {
    let s = &study.settings;
    let c = level(s.confidence);
    let xrays = study.quantities.first().map_or(0, |q| q.population);
    let mut hidden = Hidden::new();
    let mut out = format!(
        "Coverage of nominal {c} intervals on real hands: {path} taken as the population ({xrays} X-rays), {sims} samples of each size drawn from its X-rays with replacement. Confidence intervals are scored against the population mean, the prediction interval against one further X-ray. Monte-Carlo SE: about {se} at {c}.\n",
        sims = s.sims,
        se = percent(s.mc_se(s.confidence)),
    );
    let mut t = Grid::new()
        .col("n", Align::Left, Give::Keep)
        .col("", Align::Left, Give::Keep)
        .col("t", Align::Right, Give::Keep)
        .col("percentile", Align::Right, Give::Keep)
        .col("BCa", Align::Right, Give::Keep)
        .col("prediction", Align::Right, Give::Keep)
        .col("bootstrap", Align::Right, Give::Drop(1));
    for r in super::phrases::pooled_rows(study) {
        let (n, model) = if r.normal {
            (String::new(), "normal model")
        } else {
            (r.n.to_string(), "real hands (mean)")
        };
        let mut row = vec![n, model.to_string()];
        row.extend(r.cells);
        row.push(r.bootstrap);
        t.row(row);
    }
    out.push_str(&format!(
        "\nOver the {} quantities (their mean coverage), and the normal model:\n",
        study.quantities.len()
    ));
    out.push_str(&t.render(width, 0, &mut hidden));
    for &n in &study.sizes {
        let mut t = Grid::new()
            .col("finger", Align::Left, Give::Keep)
            .col("quantity", Align::Left, Give::Keep)
            .col("t", Align::Right, Give::Keep)
            .col("percentile", Align::Right, Give::Keep)
            .col("BCa", Align::Right, Give::Keep)
            .col("prediction", Align::Right, Give::Keep);
        for q in &study.quantities {
            let Some(cov) = q.by_n.iter().find(|c| c.n == n) else {
                continue;
            };
            let mut row = vec![q.finger.name().to_string(), q.quantity.name().to_string()];
            row.extend(cov.methods.iter().map(|m| percent(m.coverage)));
            t.row(row);
        }
        out.push_str(&format!("\nn = {n}\n"));
        out.push_str(&t.render(width, 0, &mut hidden));
    }
    for n in &study.notes {
        out.push_str(&format!("note: {n}\n"));
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}
