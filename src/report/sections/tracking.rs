//! Section 9, tracking new X-rays: the records, what changed, and the X-rays still needed.

use super::inputs::ReportInputs;
use crate::analysis::{Analysis, Quantity};
use crate::dataset::history::Snapshot;
use crate::format::{decimals, level, num, opt, signed, xrays};
use serde::Serialize;

/// How the statistics moved as X-rays were added.
#[derive(Debug, Clone, Serialize)]
pub struct TrackingView {
    pub file: String,
    /// "7 records".
    pub snapshots: String,
    /// Set when there is nothing to compare yet.
    pub note: Option<String>,
    /// The two records compared, e.g. "record 7 (..., 16 X-rays) against record 1 (...)".
    pub compared: String,
    /// The records from the one compared against to the last, with what each changed.
    pub records: Vec<RecordView>,
    pub changes: Vec<ChangeRow>,
    pub target: String,
    /// The caption of the X-rays-needed table: its basis, named.
    pub needed_caption: String,
    /// The column of the second cohort's larger SD ("Atlas, where its SD is larger");
    /// `None`: no second cohort, no column.
    pub needed_other: Option<String>,
    pub needed: Vec<NeededRow>,
}

/// One record of the history: what made it and what it changed.
#[derive(Debug, Clone, Serialize)]
pub struct RecordView {
    pub number: String,
    pub time: String,
    pub event: String,
    pub xrays: String,
    pub change: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ChangeRow {
    pub finger: String,
    pub quantity: String,
    pub n: String,
    pub mean_before: String,
    pub mean_after: String,
    pub shift: String,
    pub width_before: String,
    pub width_after: String,
    pub width_change: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct NeededRow {
    pub finger: String,
    pub quantity: String,
    pub n: String,
    pub sd: String,
    /// The upper end of the SD's confidence interval.
    pub sd_upper: String,
    pub half_width: String,
    /// The headline: 80% assurance with sigma at `sd_upper` (Kupper and Hafner 1989).
    pub needed: String,
    /// X-rays still to measure for `needed`.
    pub more: String,
    /// The second cohort's larger SD and its figure on the same basis, "SD 0.0092: 21";
    /// empty where its SD is not larger.
    pub other: String,
    /// Plug-in, optimistic: the current SD taken as the truth.
    pub plug_in: String,
}

pub(crate) fn tracking(inputs: &ReportInputs<'_>) -> TrackingView {
    let snaps = inputs.history;
    let records = |from: usize| -> Vec<RecordView> {
        snaps
            .iter()
            .enumerate()
            .skip(from)
            .map(|(i, s)| RecordView {
                number: (i + 1).to_string(),
                time: s.time.clone(),
                event: s.event.to_string(),
                xrays: s.xrays.to_string(),
                change: crate::report::phrases::record_change(s),
            })
            .collect()
    };
    let (note, compared, changes, listed) = if snaps.len() < 2 {
        let count = match snaps.len() {
            0 => "No snapshot yet".to_string(),
            1 => "One snapshot".to_string(),
            k => format!("{k} snapshots"),
        };
        let note = format!(
            "{count} in {}: changes and plots appear once there are two. 'phalanx add' and 'phalanx remove' append one per change; 'phalanx snapshot' one on demand.",
            inputs.history_file
        );
        (Some(note), String::new(), Vec::new(), records(0))
    } else {
        let e = snaps.len() - 1;
        // --since is checked against the history before the report is built.
        let b = inputs.since.map_or(0, |n| n.saturating_sub(1)).min(e - 1);
        let compared = format!(
            "{} against {}",
            describe_snapshot(snaps, e),
            describe_snapshot(snaps, b)
        );
        (
            None,
            compared,
            change_rows(&snaps[b], &snaps[e]),
            records(b),
        )
    };
    TrackingView {
        file: inputs.history_file.to_string(),
        snapshots: match snaps.len() {
            1 => "1 snapshot".to_string(),
            k => format!("{k} snapshots"),
        },
        note,
        compared,
        records: listed,
        changes,
        target: num(inputs.target, 4),
        needed_caption: needed_caption(inputs),
        needed_other: inputs
            .atlas
            .map(|_| "The atlas, where its SD is larger".to_string()),
        needed: needed_rows(
            inputs.analysis,
            inputs.atlas.map(|x| &x.analysis),
            inputs.target,
        ),
    }
}

/// "record 3 (time, event, 7 X-rays)" for record `i` of `snaps`.
fn describe_snapshot(snaps: &[Snapshot], i: usize) -> String {
    let s = &snaps[i];
    format!(
        "snapshot {} ({}, {}, {})",
        i + 1,
        s.time,
        s.event,
        xrays(s.xrays)
    )
}

/// One row per finger and relative quantity: how it changed from `before` to `after`.
fn change_rows(before: &Snapshot, after: &Snapshot) -> Vec<ChangeRow> {
    crate::analysis::tracking::changes(before, after)
        .into_iter()
        .filter(|ch| ch.quantity != Quantity::Total)
        .map(|ch| {
            let d = decimals(ch.quantity.is_unitless());
            ChangeRow {
                finger: ch.finger.name().to_string(),
                quantity: ch.quantity.label().to_string(),
                n: format!("{} -> {}", ch.n_before, ch.n_after),
                mean_before: num(ch.mean_before, d),
                mean_after: num(ch.mean_after, d),
                shift: signed(ch.mean_shift, d),
                width_before: opt(ch.ci_width_before, d),
                width_after: opt(ch.ci_width_after, d),
                width_change: match (ch.ci_width_before, ch.ci_width_after) {
                    (Some(x), Some(y)) => signed(y - x, d),
                    _ => "n/a".to_string(),
                },
            }
        })
        .collect()
}

/// The caption of the X-rays-needed table: the target, the basis of the headline
/// figure, the second cohort beside it, and the plug-in named as optimistic.
fn needed_caption(inputs: &ReportInputs<'_>) -> String {
    use crate::analysis::tracking::ASSURANCE;
    let a = inputs.analysis;
    let c = a.settings.confidence;
    let atlas = inputs.atlas.map_or(String::new(), |x| {
        format!(
            " Where the atlas (section 11: {} of children's left hands, tips at the bone) gives a larger SD for the same finger and quantity, its SD and its figure on the same basis stand beside it: another cohort's spread, not this one's, but one measured on enough hands to pin it.",
            xrays(x.analysis.dataset.xrays)
        )
    });
    format!(
        "X-rays needed for a {conf} t interval of half-width {w} or less. {n} measure the SD itself only roughly, so the figure does not take the SD as the truth: it is the smallest n with P(t · S / √n ≤ W) ≥ {assurance} (Kupper and Hafner 1989, where (n − 1) S² / σ² is χ²(n − 1)) with σ at the upper end of the SD's {conf} confidence interval, s · √((n − 1) / q), q the {tail} quantile of χ²(n − 1). The true SD lies below that limit with {one_sided} confidence, and then a study of that size meets the target in at least {assurance} of cases. “Still to measure” counts towards that n.{atlas} The plug-in n takes the current SD as exact: it is optimistic, and meets the target in only about 50-65% of studies even when the SD is right.",
        conf = level(c),
        w = num(inputs.target, 4),
        n = xrays(a.dataset.xrays),
        assurance = level(ASSURANCE),
        tail = level((1.0 - c) / 2.0),
        one_sided = level((1.0 + c) / 2.0),
    )
}

/// The X-rays needed for a t interval of half-width `target`, per finger and
/// relative quantity: the headline (80% assurance at the SD's upper limit), the
/// second cohort's where its SD is larger, and the plug-in
/// ([`crate::analysis::tracking::needed_per_quantity`]).
fn needed_rows(a: &Analysis, other: Option<&Analysis>, target: f64) -> Vec<NeededRow> {
    let count = |n: Option<usize>| n.map_or_else(|| "n/a".to_string(), |n| n.to_string());
    crate::analysis::tracking::needed_per_quantity(a, other, target)
        .into_iter()
        .map(|r| {
            let q = r.quantity;
            NeededRow {
                finger: r.finger.name().to_string(),
                quantity: q.name.label().to_string(),
                n: q.n.to_string(),
                sd: opt(q.sd, 4),
                sd_upper: opt(r.sd_upper, 4),
                half_width: opt(q.intervals.ci_t.map(|i| i.width() / 2.0), 4),
                needed: count(r.needed),
                more: match r.needed {
                    Some(n) if n <= q.n => "reached".to_string(),
                    Some(n) => format!("{} more", n - q.n),
                    None => "n/a".to_string(),
                },
                other: r.larger.map_or(String::new(), |o| {
                    format!("SD {}: {}", num(o.sd, 4), count(o.needed))
                }),
                plug_in: count(r.plug_in),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use std::path::Path;

    /// The X-rays-needed rows with the atlas beside them: the headline on the SD's upper
    /// limit, the atlas's larger SD on the same basis (figures from
    /// tests/independent/xrays_needed.txt), nothing where the atlas's SD is smaller.
    #[test]
    fn needed_rows_name_the_atlas_where_its_sd_is_larger() {
        let Ok(atlas) = Dataset::load(Path::new("data/atlas/measurements.csv")) else {
            println!("skipped: data/atlas/measurements.csv could not be read");
            return;
        };
        let paper = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        let a = analyse(&paper, &Settings::default());
        let atlas = analyse(&atlas, &Settings::default());
        let rows = needed_rows(&a, Some(&atlas), 0.005);
        let row = |finger: &str, q: &str| {
            rows.iter()
                .find(|r| r.finger.starts_with(finger) && r.quantity.starts_with(q))
                .unwrap()
        };
        let j2 = row("index", "J~2");
        assert_eq!(
            (
                j2.sd.as_str(),
                j2.sd_upper.as_str(),
                j2.needed.as_str(),
                j2.more.as_str(),
                j2.other.as_str(),
                j2.plug_in.as_str()
            ),
            ("0.0039", "0.0113", "27", "22 more", "SD 0.0092: 21", "5")
        );
        assert_eq!(row("ring", "J~1").other, "SD 0.0103: 25");
        assert_eq!(row("thumb", "J~1").other, "SD 0.0182: 67");
        // The atlas's index J~1 SD (0.0111) is below the paper's (0.0131): nothing beside.
        assert_eq!(row("index", "J~1").other, "");
        assert!(
            needed_rows(&a, None, 0.005)
                .iter()
                .all(|r| r.other.is_empty())
        );
    }
}
