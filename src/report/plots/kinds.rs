//! The plots' shared types: what a plot is, which kind, the X-rays worth naming, a tracked
//! series; a leaf below every plot file, so that none imports `plots.rs`.

use crate::dataset::Finger;
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

/// One snapshot of one quantity: its number in the history (1-based), the number of
/// X-rays, the mean, its t interval, and what the snapshot's change did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrackPoint {
    pub snapshot: usize,
    /// The snapshot records a removal of rows.
    pub removal: bool,
    /// Rows of this finger the snapshot's change added though flagged as likely errors.
    pub flagged: usize,
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

/// "the thumb", "the index finger", "the ring finger" (the report names the paper's
/// "grooming" finger once, in its key results).
pub(super) fn finger_phrase(f: Finger) -> String {
    match f {
        Finger::Thumb => "the thumb".to_string(),
        Finger::Index => "the index finger".to_string(),
        other => format!("the {} finger", other.name()),
    }
}
