//! SVG plots of finished results (plotters). Each plot is a pure function
//! returning SVG text; drawing errors become [`Error`]s with context, never panics.

use crate::analysis::placement::FingerPlacement;
use crate::analysis::{Analysis, FingerAnalysis};
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
pub fn finger_plot(_f: &FingerAnalysis, _confidence: f64) -> Result<Plot, Error> {
    Err(Error::render("finger plot", "not yet implemented"))
}

/// Hand diagram: the fingers as segments, each joint's mean position with range and prediction band.
pub fn hand_diagram(_placements: &[FingerPlacement], _confidence: f64) -> Result<Plot, Error> {
    Err(Error::render("hand diagram", "not yet implemented"))
}

/// Forest plot of every quantity's intervals side by side.
pub fn forest_plot(_a: &Analysis) -> Result<Plot, Error> {
    Err(Error::render("forest plot", "not yet implemented"))
}

/// Every plot of a report, in display order: one per finger, the hand diagram, the forest plot.
pub fn all(a: &Analysis, placements: &[FingerPlacement]) -> Result<Vec<Plot>, Error> {
    let mut plots = Vec::new();
    for f in &a.fingers {
        plots.push(finger_plot(f, a.settings.confidence)?);
    }
    plots.push(hand_diagram(placements, a.settings.confidence)?);
    plots.push(forest_plot(a)?);
    Ok(plots)
}
