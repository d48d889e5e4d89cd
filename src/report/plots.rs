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
mod rigs;
#[cfg(test)]
mod tests;
mod tracking;

use crate::analysis::placement::FingerPlacement;
use crate::analysis::{Analysis, FingerAnalysis};
use crate::dataset::Finger;
use crate::error::Error;
use serde::Serialize;

/// Which kind of plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlotKind {
    /// One finger: each X-ray's relative values as points, the mean and its intervals.
    Finger,
    /// The five fingers as segments with each joint's mean position and its bands.
    Hand,
    /// Every quantity's intervals side by side.
    Forest,
    /// One finger's means with their confidence band against the number of X-rays.
    Tracking,
    /// Popular rigs' segment ratios against the X-rays.
    Rigs,
    /// Each interval method's simulated coverage against the number of X-rays.
    Coverage,
    /// One finger's relative values in an atlas, binned, with the paper's X-rays over them.
    Atlas,
}

/// One rendered plot.
#[derive(Debug, Clone, Serialize)]
pub struct Plot {
    /// File stem, unique within a report (e.g. `finger-index`); also the prefix of SVG ids.
    pub id: String,
    pub kind: PlotKind,
    /// Human title (also the SVG `<title>`).
    pub title: String,
    /// One-paragraph description for screen readers (also the SVG `<desc>`).
    pub description: String,
    /// The complete SVG document.
    pub svg: String,
}

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

/// The X-rays worth naming in the plots: labels stay legible at any n because only
/// these are labelled once there are more than a dozen X-rays (with the X-rays whose
/// value lies outside the prediction interval).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Named {
    /// Rows added though flagged as likely errors: (X-ray, finger).
    pub flagged: Vec<(String, Finger)>,
    /// The X-rays of the newest addition (the history's last `add`).
    pub newest: Vec<String>,
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

/// One snapshot of one quantity: the number of X-rays, the mean, its t interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrackPoint {
    pub xrays: usize,
    pub mean: f64,
    pub ci: Option<(f64, f64)>,
}

/// The history of one relative quantity of a finger, in snapshot order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TrackSeries {
    /// Display label, e.g. "J~1 = J1/J".
    pub label: String,
    pub points: Vec<TrackPoint>,
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

/// "the thumb", "the index finger", "the ring finger" (the report names the paper's
/// "grooming" finger once, in its key results).
fn finger_phrase(f: Finger) -> String {
    match f {
        Finger::Thumb => "the thumb".to_string(),
        Finger::Index => "the index finger".to_string(),
        other => format!("the {} finger", other.name()),
    }
}
