//! SVG plots of finished results (plotters). Each plot is a pure function
//! returning SVG text; drawing errors become [`Error`]s with context, never panics.
//!
//! Every SVG is self-contained and deterministic (same input, same bytes): a
//! white background, integer pixel coordinates, no clock, no random ids. Its
//! root `<svg>` has `role="img"`, `aria-labelledby="<id>-title"` and
//! `aria-describedby="<id>-desc"`; its first children are that `<title>` and
//! `<desc>`, ids prefixed by the plot's id so several plots can share a page.
//!
//! Fonts: plotters is built without a font backend (neither `ttf` nor
//! `ab_glyph`), so it lays text out with its built-in size estimate and never
//! reads a font file or asks the system for fonts. Text is written as SVG
//! `<text>` in the generic family `sans-serif`; the viewer picks the face.
//! Plotters' SVG backend XML-escapes text and attribute values itself, so text
//! is handed to it unescaped; the `<title>` and `<desc>`, written by this
//! module, are escaped by it (see `draw::escape`).

mod atlas;
mod coverage;
mod draw;
mod finger;
mod forest;
mod hand;
mod kinds;
mod rigs;
#[cfg(test)]
mod tests;
mod tracking;

use crate::analysis::placement::FingerPlacement;
use crate::analysis::{Analysis, FingerAnalysis};
use crate::error::Error;
pub use kinds::{Named, Plot, PlotKind};
pub(crate) use kinds::{TrackPoint, TrackSeries};

/// Per-finger plot: each X-ray's relative values as points, the mean and its intervals.
///
/// One panel per relative quantity (J~1, J~2[, J~3]) with its own x axis. Up to
/// 12 X-rays each point is labelled with its X-ray id; up to 2000 the points are
/// spread vertically by a fixed sequence; beyond, a histogram keeps the SVG small.
/// Beyond 12, only the X-rays worth naming are labelled ([`Named`]: none here, so
/// only those outside the prediction interval). Id `finger-<name>`.
pub fn finger_plot(f: &FingerAnalysis, confidence: f64) -> Result<Plot, Error> {
    finger::plot(f, confidence, &Named::default())
}

/// Hand diagram: the fingers as segments, each joint's mean position with range and prediction band.
///
/// Every finger is drawn upright at its model length, root joint (MCP) at 0 and
/// tip at L; distances are in model units. Id `hand`.
pub fn hand_diagram(placements: &[FingerPlacement], confidence: f64) -> Result<Plot, Error> {
    hand::plot(placements, confidence)
}

/// Forest plot of every quantity's intervals side by side.
///
/// One row per finger and relative quantity, one shared x axis (relative value). Id `forest`.
pub fn forest_plot(a: &Analysis) -> Result<Plot, Error> {
    forest::plot(a)
}

/// The relative quantities of one finger through a history, snapshot by snapshot
/// (numbered from 1), with the removals and the rows added though flagged.
pub(crate) fn track_series(
    history: &[crate::dataset::history::Snapshot],
    finger: crate::dataset::Finger,
) -> Vec<TrackSeries> {
    use crate::dataset::history::Event;
    let mut out: Vec<(crate::analysis::Quantity, TrackSeries)> = Vec::new();
    for (i, s) in history.iter().enumerate() {
        let flagged = s.change.as_ref().map_or(0, |c| {
            c.flagged.iter().filter(|r| r.finger == finger).count()
        });
        let flagged = if s.event == Event::Add { flagged } else { 0 };
        for q in s
            .quantities
            .iter()
            .filter(|q| q.finger == finger && q.quantity.is_relative())
        {
            let point = TrackPoint {
                snapshot: i + 1,
                removal: s.event == Event::Remove,
                flagged,
                xrays: q.n,
                mean: q.mean,
                ci: q.intervals.ci_t.map(|c| (c.low, c.high)),
            };
            match out.iter_mut().find(|(k, _)| *k == q.quantity) {
                Some((_, t)) => t.points.push(point),
                None => out.push((
                    q.quantity,
                    TrackSeries {
                        label: q.quantity.label().to_string(),
                        points: vec![point],
                    },
                )),
            }
        }
    }
    out.into_iter().map(|(_, t)| t).collect()
}

/// Tracking plot of one finger (id `tracking-<finger>`): for each relative quantity,
/// the mean against the number of X-rays with its t confidence band.
pub(crate) fn tracking_plot(
    finger: crate::dataset::Finger,
    series: &[TrackSeries],
    confidence: f64,
) -> Result<Plot, Error> {
    tracking::plot(finger, series, confidence)
}

pub(crate) use rigs::RigRatios;

/// Rig plot (id `rigs`): each rig's J2/J1 and J3/J2 per finger against the
/// X-rays' mean, observed range and prediction interval.
pub(crate) fn rigs_plot(a: &Analysis, rigs: &[RigRatios]) -> Result<Plot, Error> {
    rigs::plot(a, rigs)
}

/// Coverage plot (id `coverage`): each interval method's simulated coverage
/// against the number of X-rays (log axis), with the nominal level as a line.
pub fn coverage_plot(
    points: &[crate::analysis::coverage::CurvePoint],
    confidence: f64,
) -> Result<Plot, Error> {
    coverage::plot(points, confidence)
}

/// Atlas plot of one finger (id `atlas-<finger>`): the atlas's distribution of each
/// relative value as a binned strip, the paper's X-rays and prediction interval over it.
pub(crate) fn atlas_plot(
    paper: &FingerAnalysis,
    atlas: &FingerAnalysis,
    atlas_name: &str,
    confidence: f64,
) -> Result<Plot, Error> {
    atlas::plot(paper, atlas, atlas_name, confidence)
}

/// Every plot of a report, in display order: one per finger, the hand diagram, the forest plot.
pub fn all(a: &Analysis, placements: &[FingerPlacement]) -> Result<Vec<Plot>, Error> {
    all_named(a, placements, &Named::default())
}

/// [`all`], the finger plots naming the X-rays of `named` (and their outliers).
pub fn all_named(
    a: &Analysis,
    placements: &[FingerPlacement],
    named: &Named,
) -> Result<Vec<Plot>, Error> {
    let mut plots = Vec::new();
    for f in &a.fingers {
        plots.push(finger::plot(f, a.settings.confidence, named)?);
    }
    plots.push(hand_diagram(placements, a.settings.confidence)?);
    plots.push(forest_plot(a)?);
    Ok(plots)
}
