//! What a report is built from: the finished results each section reads.

use super::deform::DeformSection;
use super::made::MadeSection;
use crate::analysis::Analysis;
use crate::analysis::claims::ClaimResult;
use crate::analysis::coverage::{CoverageSettings, CurvePoint};
use crate::analysis::groups::Groups;
use crate::analysis::placement::FingerPlacement;
use crate::analysis::population::PopulationStudy;
use crate::dataset::history::Snapshot;

/// Everything a report is built from.
pub struct ReportInputs<'a> {
    pub analysis: &'a Analysis,
    pub claims_file: &'a str,
    pub claims: &'a [ClaimResult],
    /// Why the claims were not checked, when they were not.
    pub claims_note: Option<&'a str>,
    pub coverage_settings: &'a CoverageSettings,
    /// The simulated coverage at each sample size (the data's and the curve's).
    pub coverage: &'a [CurvePoint],
    pub placements: &'a [FingerPlacement],
    pub model_length: f64,
    /// Added to the provenance only when asked for (`--timestamp`).
    pub timestamp: Option<String>,
    /// The history file and its snapshots, for the Tracking section.
    pub history_file: &'a str,
    pub history: &'a [Snapshot],
    /// The record "What changed" runs from (1-based); `None`: the first.
    pub since: Option<usize>,
    /// Target half-width of the confidence interval of a relative mean.
    pub target: f64,
    /// Statistics per group (`--group-by`); `None` when not grouped.
    pub groups: Option<&'a Groups>,
    /// Popular rigs judged against the statistics (`data/rigs`).
    pub rigs: &'a [ReferenceAudit],
    /// How many of the dataset's X-rays the claims name (the paper's), and how many it
    /// has: the titles say "Table 1" and "the paper's worked example" only when they
    /// are the same X-rays.
    pub paper_xrays: (usize, usize),
    /// The atlas compared with the data (`data/atlas`); `None`: no atlas section.
    pub atlas: Option<&'a AtlasInputs>,
    /// A published table compared with the data (`data/literature`); `None`: no section.
    pub literature: Option<&'a LiteratureInputs>,
    /// A real rig audited and deformed (`data/rigs/webxr-generic-hand/right.glb`);
    /// `None`: no such part.
    pub deform: Option<&'a DeformSection>,
    /// A rigged hand rigged again from its skin
    /// (`data/rigs/webxr-generic-hand/left.glb`); `None`: no such part.
    pub made: Option<&'a MadeSection>,
    /// The joint regions' prior shape (the atlas's correlations); `None`: the
    /// X-rays' own.
    pub shape: Option<&'a crate::analysis::region::ShapePriors>,
    /// The region's calibration simulated for the index finger: its setup and
    /// table ([`crate::analysis::region::calibration`]).
    pub calibration: Option<(
        &'a crate::analysis::region::calibration::Setup,
        &'a [crate::analysis::region::calibration::Cell],
    )>,
}

/// A reference rig with its judgement.
#[derive(Debug, Clone)]
pub struct ReferenceAudit {
    pub rig: crate::rig::reference::ReferenceRig,
    pub audit: crate::rig::AuditedRig,
}

/// What the section "The paper against N atlas radiographs" reads: the atlas analysed,
/// the paper (A) compared with it (B), and the coverage measured on its hands.
#[derive(Debug, Clone)]
pub struct AtlasInputs {
    pub analysis: Analysis,
    pub cohorts: crate::analysis::compare::Cohorts,
    pub population: PopulationStudy,
}

/// What the section "The paper against published measurements" reads: the paper (A)
/// against a published table (B), and, when the atlas is there, the atlas (A) against it.
#[derive(Debug, Clone)]
pub struct LiteratureInputs {
    pub paper: crate::analysis::literature::TableCohorts,
    pub atlas: Option<crate::analysis::literature::TableCohorts>,
    /// The atlas's description, for its line on why it differs.
    pub atlas_info: Option<crate::analysis::compare::CohortInfo>,
}
