//! Section 4, the statistics table of each finger and the rows added though flagged.

use super::common::IntervalCells;
use crate::analysis::Analysis;
use crate::format::{decimals, num, opt, percent, xrays};
use serde::Serialize;

/// The statistics table of one finger.
#[derive(Debug, Clone, Serialize)]
pub struct StatsFinger {
    pub finger: String,
    pub id: String,
    pub n: String,
    pub bootstrap: String,
    pub rows: Vec<StatsRow>,
    pub notes: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct StatsRow {
    pub quantity: String,
    pub mean: String,
    pub min: String,
    pub max: String,
    pub range: String,
    pub sd: String,
    pub se: String,
    pub median: String,
    pub cv: String,
    #[serde(flatten)]
    pub intervals: IntervalCells,
}

pub(crate) fn stats(f: &crate::analysis::FingerAnalysis) -> StatsFinger {
    let rows = f
        .quantities
        .iter()
        .map(|q| {
            let d = decimals(q.name.is_unitless());
            StatsRow {
                quantity: q.name.label().to_string(),
                mean: num(q.mean, d),
                min: num(q.min, d),
                max: num(q.max, d),
                range: num(q.range, d),
                sd: opt(q.sd, d),
                se: opt(q.se, d),
                median: num(q.median, d),
                cv: q.cv.map_or_else(|| "n/a".to_string(), percent),
                intervals: IntervalCells::new(&q.intervals, d),
            }
        })
        .collect();
    let notes = crate::analysis::plausible::swapped_segments(f)
        .into_iter()
        .chain(f.quantities.iter().flat_map(|q| {
            q.notes
                .iter()
                .map(move |n| format!("{}: {n}", q.name.label()))
        }))
        .collect();
    StatsFinger {
        finger: f.finger.name().to_string(),
        id: f.finger.name().to_string(),
        n: xrays(f.n),
        bootstrap: crate::format::plan(f.bootstrap),
        rows,
        notes,
    }
}

/// A row of the data added though flagged as a likely error.
#[derive(Debug, Clone, Serialize)]
pub struct FlaggedView {
    pub xray: String,
    pub finger: String,
    pub line: String,
    pub reason: String,
    /// The command that takes it out.
    pub remove: String,
}

/// The rows added though flagged, for the statistics section.
pub(crate) fn flagged_rows(a: &Analysis) -> Vec<FlaggedView> {
    a.flagged
        .iter()
        .map(|f| FlaggedView {
            xray: f.xray.to_string(),
            finger: f.finger.name().to_string(),
            line: f.line.to_string(),
            reason: f.reason.clone(),
            remove: format!(
                "phalanx remove --xray {} --finger {}",
                f.xray,
                f.finger.name()
            ),
        })
        .collect()
}
