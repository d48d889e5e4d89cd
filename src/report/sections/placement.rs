//! Section 6, joint placement for a model of the report's length.

use super::common::{IntervalCells, is_paper};
use crate::analysis::placement::FingerPlacement;
use crate::dataset::Finger;
use crate::format::{exact, length_decimals, num};
use serde::Serialize;

/// Joint placement for a model of the report's length.
#[derive(Debug, Clone, Serialize)]
pub struct PlacementView {
    pub length: String,
    /// Whose example this is: the paper's over its X-rays, this dataset's otherwise.
    pub origin: String,
    pub joints: Vec<PlacementRow>,
    pub segments: Vec<PlacementRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct PlacementRow {
    pub finger: String,
    /// Joint (PIP, DIP, IP) or segment (J1, J2, J3).
    pub what: String,
    pub mean: String,
    pub min: String,
    pub max: String,
    pub range: String,
    #[serde(flatten)]
    pub intervals: IntervalCells,
}

pub(crate) fn placement(
    ps: &[FingerPlacement],
    length: f64,
    paper_xrays: (usize, usize),
    counts: &str,
) -> PlacementView {
    let d = length_decimals(length);
    let origin = if is_paper(paper_xrays) {
        "This is the paper's worked example, with the corrected mean.".to_string()
    } else {
        format!(
            "The paper works this example with its own X-rays; here the means are over the dataset's {counts}."
        )
    };
    let row = |finger: Finger, what: &str, p: &crate::analysis::placement::Placed| PlacementRow {
        finger: finger.name().to_string(),
        what: what.to_string(),
        mean: num(p.mean, d),
        min: num(p.min, d),
        max: num(p.max, d),
        range: num(p.range, d),
        intervals: IntervalCells::new(&p.intervals, d),
    };
    PlacementView {
        length: exact(length),
        origin,
        joints: ps
            .iter()
            .flat_map(|p| {
                p.joints
                    .iter()
                    .map(move |j| row(p.finger, j.joint.name(), &j.position))
            })
            .collect(),
        segments: ps
            .iter()
            .flat_map(|p| {
                p.segments
                    .iter()
                    .map(move |s| row(p.finger, &s.segment.to_uppercase(), &s.length))
            })
            .collect(),
    }
}
