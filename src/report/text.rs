//! Terminal tables for `stats`, `check` and `coverage`.

use crate::analysis::claims::{CheckSummary, ClaimResult};
use crate::analysis::coverage::{CoverageSettings, QuantityCoverage};
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::dataset::history::Snapshot;
use crate::format::{
    decimals, exact, interval, interval_cells, length_decimals, level, num, opt, percent, signed,
};
use comfy_table::{CellAlignment, ContentArrangement, Table, presets};

/// A terminal table in Markdown style, columns from `right_from` on right-aligned.
pub(super) fn table(header: &[&str], right_from: usize) -> Table {
    let mut t = Table::new();
    t.load_style(presets::ASCII_MARKDOWN)
        .set_content_arrangement(ContentArrangement::Disabled)
        .set_header(header.to_vec());
    for i in right_from..header.len() {
        if let Some(c) = t.column_mut(i) {
            c.set_cell_alignment(CellAlignment::Right);
        }
    }
    t
}

/// The statistics of every finger, 4 decimals for relative values as in the paper.
pub(crate) fn stats(a: &Analysis) -> String {
    let c = level(a.settings.confidence);
    let mut out = format!(
        "phalanx statistics of {} ({} X-rays, {} rows); confidence {c}, seed {}\n",
        a.dataset.path, a.dataset.xrays, a.dataset.rows, a.settings.seed
    );
    for line in dataset_notes(a) {
        out.push_str(&format!("note: {line}\n"));
    }
    for f in &a.fingers {
        out.push_str(&format!(
            "\n{} - n = {}; bootstrap {}\n",
            f.finger.display_name(),
            f.n,
            f.bootstrap.describe()
        ));
        let mut t = table(
            &[
                "quantity",
                "mean",
                "min",
                "max",
                "range",
                "sd",
                "se",
                "t CI",
                "percentile CI",
                "BCa CI",
                "prediction",
            ],
            1,
        );
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
            t.add_row(row);
        }
        out.push_str(&t.to_string());
        out.push('\n');
        for q in &f.quantities {
            for n in &q.notes {
                out.push_str(&format!("note ({}): {n}\n", q.name.name()));
            }
        }
    }
    out
}

/// What a reader must know about a dataset's lengths before reading its statistics:
/// that pixel lengths are not averaged, and where the fingertips are when recorded.
pub fn dataset_notes(a: &Analysis) -> Vec<String> {
    let mut notes = Vec::new();
    if a.pixel_lengths() {
        notes.push(PIXEL_NOTE.to_string());
    }
    if a.tips.bone + a.tips.skin > 0 {
        notes.push(format!("fingertips: {}", a.tips.describe()));
    }
    notes
}

/// Why a dataset in pixels has no total length J.
pub const PIXEL_NOTE: &str = "lengths are in pixels (px) of images whose scale differs, so the total length J and the metacarpal are not comparable across X-rays and are not averaged; the relative values and ratios are. Import with --pixel-spacing MM for lengths in millimetres";

/// The statistics of the whole dataset, then of each group (`--group-by`).
pub(crate) fn stats_with_groups(a: &Analysis, groups: &[crate::analysis::groups::Group]) -> String {
    let mut out = stats(a);
    for g in groups {
        out.push_str(&format!(
            "\n==== {} = {} ({} X-ray{}) ====\n",
            g.by,
            g.label,
            g.xrays,
            if g.xrays == 1 { "" } else { "s" }
        ));
        if let Some(n) = &g.note {
            out.push_str(&format!("note: {n}\n"));
        }
        // Skip the group's own title line (the dataset line repeats the overall one).
        let body = stats(&g.analysis);
        out.push_str(
            body.split_once('\n')
                .map_or(body.as_str(), |(_, rest)| rest),
        );
    }
    out
}

/// The claim-by-claim check, then a summary line.
pub(crate) fn check(results: &[ClaimResult]) -> String {
    let mut t = table(&["claim", "where", "stated", "computed", "verdict"], 2);
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
        t.add_row(vec![
            r.id.clone(),
            r.location.clone(),
            r.stated_text.clone(),
            computed,
            r.verdict.label().to_string(),
        ]);
    }
    if let Some(c) = t.column_mut(4) {
        c.set_cell_alignment(CellAlignment::Left);
    }
    let mut out = t.to_string();
    out.push('\n');
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
    out
}

/// The simulated coverage of each interval method, per finger and quantity.
pub(crate) fn coverage(rows: &[QuantityCoverage], settings: &CoverageSettings) -> String {
    let mut t = table(
        &[
            "finger",
            "quantity",
            "n",
            "t",
            "percentile",
            "BCa",
            "prediction",
        ],
        2,
    );
    for r in rows {
        let mut row = vec![
            r.finger.name().to_string(),
            r.quantity.name().to_string(),
            r.n.to_string(),
        ];
        match &r.coverage {
            Some(c) => row.extend(c.methods.iter().map(|m| percent(m.coverage))),
            None => row.extend(std::iter::repeat_n(r.note.clone().unwrap_or_default(), 4)),
        }
        t.add_row(row);
    }
    format!(
        "Simulated coverage of nominal {} intervals ({sims} simulated datasets per sample size; normal model fitted to each quantity).\n\
         Confidence intervals are checked against the model mean; the prediction interval against one new draw.\n{t}\n",
        level(settings.confidence),
        sims = settings.sims
    )
}

/// The history of each selected quantity, snapshot by snapshot.
pub(crate) fn history(
    path: &std::path::Path,
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
) -> String {
    if snaps.is_empty() {
        return format!(
            "No snapshots in {} yet: 'phalanx add' records one per addition, 'phalanx snapshot' one on demand.\n",
            path.display()
        );
    }
    let mut out = format!("{} snapshots in {}\n", snaps.len(), path.display());
    for (f, q) in crate::analysis::tracking::selected(snaps, finger, quantity) {
        let d = decimals(q.is_unitless());
        out.push_str(&format!("\n{f} {}\n", q.label()));
        let mut t = table(
            &[
                "#",
                "time",
                "event",
                "n",
                "mean",
                "sd",
                "t CI",
                "CI width",
                "mean shift",
            ],
            3,
        );
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
            t.add_row(vec![
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
        if let Some(c) = t.column_mut(1) {
            c.set_cell_alignment(CellAlignment::Left);
        }
        if let Some(c) = t.column_mut(2) {
            c.set_cell_alignment(CellAlignment::Left);
        }
        out.push_str(&t.to_string());
        out.push('\n');
    }
    out
}

/// Joint positions and segment lengths of model fingers, one table each.
pub(crate) fn placement(
    ps: &[crate::analysis::placement::FingerPlacement],
    confidence: f64,
) -> String {
    let c = level(confidence);
    let mut out = String::new();
    for p in ps {
        out.push_str(&format!(
            "{} - model length {} (from {} X-rays); positions from the root joint (MCP at 0, tip at {})\n",
            p.finger.display_name(),
            exact(p.length),
            p.n,
            exact(p.length)
        ));
        let mut t = table(
            &[
                "",
                "mean",
                "min",
                "max",
                "range",
                &format!("t CI {c}"),
                "percentile CI",
                "BCa CI",
                "prediction",
            ],
            1,
        );
        let rows = p
            .joints
            .iter()
            .map(|j| (format!("{} joint", j.joint.name()), &j.position))
            .chain(
                p.segments
                    .iter()
                    .map(|s| (format!("segment {}", s.segment.to_uppercase()), &s.length)),
            )
            .chain(
                p.metacarpal
                    .iter()
                    .map(|m| ("MCP from the CMC".to_string(), &m.position)),
            );
        let d = length_decimals(p.length);
        for (what, v) in rows {
            let mut row = vec![
                what,
                num(v.mean, d),
                num(v.min, d),
                num(v.max, d),
                num(v.range, d),
            ];
            row.extend(interval_cells(&v.intervals, d));
            t.add_row(row);
        }
        if let Some(col) = t.column_mut(0) {
            col.set_cell_alignment(CellAlignment::Left);
        }
        out.push_str(&t.to_string());
        out.push('\n');
        if let Some(m) = &p.metacarpal {
            out.push_str(&format!(
                "MCP from the CMC: the metacarpal, (mc/J) x {}, from the {} X-rays that measure it; the CMC is the metacarpal's base at the wrist\n",
                exact(p.length),
                m.n
            ));
        }
        out.push('\n');
    }
    out
}

/// The coverage measured on a population of hands: every method's coverage over the
/// quantities per sample size beside the normal model's, then each quantity's per size.
pub fn population(path: &str, study: &crate::analysis::population::PopulationStudy) -> String {
    let s = &study.settings;
    let c = level(s.confidence);
    let xrays = study.quantities.first().map_or(0, |q| q.population);
    let mut out = String::new();
    for l in super::compare::wrap(
        &format!(
            "Coverage of nominal {c} intervals on real hands: {path} taken as the population ({xrays} X-rays), {sims} samples of each size drawn from its X-rays with replacement. Confidence intervals are scored against the population mean, the prediction interval against one further X-ray. Monte-Carlo SE: about {se} at {c}.",
            sims = s.sims,
            se = percent((s.confidence * (1.0 - s.confidence) / s.sims as f64).sqrt()),
        ),
        100,
    ) {
        out.push_str(&l);
        out.push('\n');
    }
    let mut t = table(
        &["n", "", "t", "percentile", "BCa", "prediction", "bootstrap"],
        2,
    );
    let pooled = study.pooled();
    for (k, &n) in study.sizes.iter().enumerate() {
        let cell = |m: &str| {
            pooled
                .iter()
                .find(|p| p.n == n && p.method == m)
                .map_or_else(|| "n/a".to_string(), |p| percent(p.mean))
        };
        let plan = study
            .normal
            .get(k)
            .map_or(String::new(), |c| plan_short(c.bootstrap));
        t.add_row(vec![
            n.to_string(),
            "real hands (mean)".to_string(),
            cell("t"),
            cell("percentile"),
            cell("bca"),
            cell("prediction"),
            plan.clone(),
        ]);
        if let Some(normal) = study.normal.iter().find(|c| c.n == n) {
            let mut row = vec![String::new(), "normal model".to_string()];
            row.extend(normal.methods.iter().map(|m| percent(m.coverage)));
            row.push(plan);
            t.add_row(row);
        }
    }
    if let Some(col) = t.column_mut(1) {
        col.set_cell_alignment(CellAlignment::Left);
    }
    out.push_str(&format!(
        "\nOver the {} quantities (their mean coverage), and the normal model:\n{t}\n",
        study.quantities.len()
    ));
    for &n in &study.sizes {
        let mut t = table(
            &["finger", "quantity", "t", "percentile", "BCa", "prediction"],
            2,
        );
        for q in &study.quantities {
            let Some(cov) = q.by_n.iter().find(|c| c.n == n) else {
                continue;
            };
            let mut row = vec![q.finger.name().to_string(), q.quantity.name().to_string()];
            row.extend(cov.methods.iter().map(|m| percent(m.coverage)));
            t.add_row(row);
        }
        out.push_str(&format!("\nn = {n}\n{t}\n"));
    }
    for n in &study.notes {
        out.push_str(&format!("note: {n}\n"));
    }
    out
}

/// "exact (126)", "random (10000)".
fn plan_short(p: crate::stats::bootstrap::Plan) -> String {
    match p {
        crate::stats::bootstrap::Plan::Exact { distinct } => format!("exact ({distinct})"),
        crate::stats::bootstrap::Plan::Random { resamples } => format!("random ({resamples})"),
    }
}
