//! Section 13's real rig: its audit and its skin deformed as it is and as `audit --fix`
//! writes it (the view; [`crate::report::deform`] builds it).

use serde::Serialize;

/// A real rig in the report: its audit (the metacarpals included) and its
/// skin deformed as it is and as `audit --fix` writes it, with the figures.
#[derive(Debug, Clone)]
pub struct DeformSection {
    pub view: DeformView,
    /// The PNG figures, under `plots/`.
    pub figures: Vec<crate::report::writer::OutputFile>,
}

/// What the report shows of a real rig's audit and deformation.
#[derive(Debug, Clone, Serialize)]
pub struct DeformView {
    /// The rig file.
    pub rig: String,
    /// Pose and skinning in one sentence.
    pub pose: String,
    /// What the fix moves, in one sentence.
    pub moved: String,
    /// True when the fix moves a joint: only then are A and B compared.
    pub compared: bool,
    /// Why they are not compared, when the fix moves nothing (else empty).
    pub not_compared: String,
    /// How "outside the region" and "the fix moves no joint" fit together (empty when
    /// every finger is inside).
    pub tolerance: String,
    /// The audit, one row per finger.
    pub audit: Vec<DeformAuditRow>,
    /// Remarks of the audit (how the chains were found, fingers left out).
    pub audit_notes: Vec<String>,
    pub hands: Vec<DeformHandView>,
    /// What the measures can and cannot tell.
    pub can_tell: String,
    pub caveats: Vec<String>,
}

/// One finger of the audited rig.
#[derive(Debug, Clone, Serialize)]
pub struct DeformAuditRow {
    pub finger: String,
    /// J~1 / J~2 / J~3 (or "n/a (no tip)").
    pub relative: String,
    /// Against the X-rays, in one phrase.
    pub standing: String,
    pub metacarpal: MetacarpalView,
}

/// The whole ray: the MCP judged from the CMC against the atlas's metacarpals.
#[derive(Debug, Clone, Serialize)]
pub struct MetacarpalView {
    /// The node the MCP is judged from, or why it is not judged.
    pub node: String,
    /// The rig's metacarpal and finger lengths, mm.
    pub lengths: String,
    /// mc/J and J1/mc against the atlas, one string each.
    pub values: Vec<String>,
    /// Where the atlas puts the MCP from the CMC, and how the rig's stands.
    pub mcp: String,
}

/// One hand of the deformation comparison.
#[derive(Debug, Clone, Serialize)]
pub struct DeformHandView {
    pub side: String,
    pub rows: Vec<DeformRowView>,
    /// "B deforms better at 4 joints, ...".
    pub summary: String,
    /// Per joint where one rig is better: by which measures and by how much.
    pub reasons: Vec<String>,
    pub figure: DeformFigureView,
}

/// One joint of both rigs.
#[derive(Debug, Clone, Serialize)]
pub struct DeformRowView {
    pub finger: String,
    pub joint: String,
    pub angle: String,
    pub loss_a: String,
    pub loss_b: String,
    pub x_a: String,
    pub x_b: String,
    pub p95_a: String,
    pub p95_b: String,
    pub fold_a: String,
    pub fold_b: String,
    pub better: String,
}

/// A PNG figure: a data URI for the self-contained HTML, a file for Markdown.
#[derive(Debug, Clone, Serialize)]
pub struct DeformFigureView {
    pub id: String,
    /// Path relative to the report directory, e.g. `plots/deform-webxr-generic-hand-right.png`.
    pub file: String,
    pub data_uri: String,
    pub width: String,
    pub height: String,
    pub alt: String,
    pub caption: String,
}
