//! Section 13's hand rigged from its skin: the made joints against the artist's, and
//! both rigs in the fist (the view; [`crate::report::rig`] builds it).

use super::deform::DeformFigureView;
use serde::Serialize;

/// A hand rigged from its skin in the report (`rig --replace-fingers`, in
/// memory): the view, and its figures under `plots/`.
#[derive(Debug, Clone)]
pub struct MadeSection {
    pub view: MadeView,
    /// The PNG figures, under `plots/`.
    pub figures: Vec<crate::report::writer::OutputFile>,
}

/// What the report shows of a rigged hand rigged again from its skin: the
/// made joints against the artist's, and both rigs in the fist.
#[derive(Debug, Clone, Serialize)]
pub struct MadeView {
    /// The rig file.
    pub rig: String,
    /// The command that rigs the hand as the part does.
    pub command: String,
    /// What it made, in one sentence that follows the command.
    pub made: String,
    /// Per finger: the made joints' distances from the artist's, and the audit.
    pub rows: Vec<MadeRow>,
    /// What the part shows, one sentence each.
    pub sentences: Vec<String>,
    /// The made joints and the artist's on the skin.
    pub joints: DeformFigureView,
    /// Both rigs posed in the fist.
    pub fist: DeformFigureView,
    /// Pose and skinning in one sentence.
    pub pose: String,
    /// Which rig deforms better in the fist, in one sentence.
    pub fist_summary: String,
}

/// One finger of a hand rigged from its skin.
#[derive(Debug, Clone, Serialize)]
pub struct MadeRow {
    pub finger: String,
    /// The made joint's distance from the artist's, mm ("n/a": the finger
    /// has no such joint, or the artist's rig none to compare with).
    pub mcp: String,
    /// PIP, or the thumb's IP.
    pub pip: String,
    pub dip: String,
    pub tip: String,
    /// The written copy's audit: inside or outside, T^2 of its bound.
    pub audit: String,
}
