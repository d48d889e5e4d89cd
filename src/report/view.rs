//! The whole report's view: its sections put together, as the templates see it.
//!
//! Each section's view and builder live in [`super::sections`]; this file only
//! assembles them in the report's order.

pub use super::sections::deform::DeformSection;
pub use super::sections::inputs::{AtlasInputs, LiteratureInputs, ReferenceAudit, ReportInputs};
pub use super::sections::made::MadeSection;

use super::phrases::{self, counted};
use super::plots::Plot;
use super::sections::atlas::{AtlasView, atlas_title, atlas_view};
use super::sections::claims::{ClaimsView, claims};
use super::sections::common::DataName;
use super::sections::coverage::{CoverageView, coverage};
use super::sections::deform::DeformView;
use super::sections::derived::{DerivedFinger, derived};
use super::sections::figures::{PlotView, plot};
use super::sections::groups::{GroupsView, groups_view};
use super::sections::key_results::{KeyResults, key_results};
use super::sections::literature::{LiteratureView, literature_title, literature_view};
use super::sections::made::MadeView;
use super::sections::placement::{PlacementView, placement};
use super::sections::provenance::{
    CitationView, Item, SettingsText, citation, provenance, settings_text,
};
use super::sections::region::{self, RegionView};
use super::sections::rigs::{RigsView, rigs_view};
use super::sections::statistics::{FlaggedView, StatsFinger, flagged_rows, stats};
use super::sections::table1::{Table1View, table1};
use super::sections::toc::Toc;
use super::sections::tracking::{TrackingView, tracking};
use serde::Serialize;

/// Everything a report shows, ready to print.
#[derive(Debug, Clone, Serialize)]
pub struct ReportView {
    pub title: String,
    /// The sections present, numbered without gaps, for the contents and cross-references.
    pub toc: Toc,
    /// The box at the top: where the joints go, the misprints, which interval to use.
    pub key: KeyResults,
    /// How to cite the paper and phalanx.
    pub citation: CitationView,
    pub provenance: Vec<Item>,
    pub settings: SettingsText,
    pub table1: Table1View,
    pub derived: Vec<DerivedFinger>,
    pub stats: Vec<StatsFinger>,
    /// Rows added though flagged as likely errors, listed with the statistics.
    pub flagged: Vec<FlaggedView>,
    /// What the statistics section says about units (and why a total is missing).
    pub units_note: Option<String>,
    pub claims: ClaimsView,
    pub placement: PlacementView,
    pub coverage: CoverageView,
    pub tracking: TrackingView,
    /// Set when the report is grouped (`--group-by`).
    pub groups: Option<GroupsView>,
    /// Set when reference rigs were given.
    pub rigs: Option<RigsView>,
    /// Set when an atlas was given: "The paper against N atlas radiographs".
    pub atlas: Option<AtlasView>,
    /// Set when a published table was given: "The paper against published measurements".
    pub literature: Option<LiteratureView>,
    /// Set when the deformation rig was found: its audit and its skin as it is
    /// and as `audit --fix` writes it.
    pub deform: Option<DeformView>,
    /// Set when the hand to rig was found: its joints made from its skin
    /// against the artist's, and both rigs in the fist.
    pub made: Option<MadeView>,
    /// The joint region rigs are judged against: its shape and calibration.
    pub region: Option<RegionView>,
    pub plots: Vec<PlotView>,
}

/// Builds the view of a whole report.
pub fn build(inputs: &ReportInputs<'_>, plots: &[Plot]) -> ReportView {
    let a = inputs.analysis;
    let settings = settings_text(inputs);
    let provenance = provenance(inputs, &settings);
    let claims = claims(inputs.claims_file, inputs.claims, inputs.claims_note);
    let data = DataName::of(inputs.paper_xrays);
    let table1 = table1(a, inputs.paper_xrays);
    let toc = contents(inputs, data, &table1.heading);
    ReportView {
        title: "phalanx: finger joint statistics from hand X-rays".into(),
        key: key_results(inputs, &claims),
        citation: citation(),
        provenance,
        settings,
        table1,
        derived: a.fingers.iter().map(derived).collect(),
        stats: a.fingers.iter().map(stats).collect(),
        flagged: flagged_rows(a),
        units_note: phrases::units_note(a).map(|n| phrases::sentence(&n)),
        claims,
        placement: placement(
            inputs.placements,
            inputs.model_length,
            inputs.paper_xrays,
            &counted(a),
        ),
        coverage: coverage(inputs),
        tracking: tracking(inputs),
        groups: groups_view(inputs.groups, a.settings.confidence),
        rigs: rigs_view(inputs.rigs, &a.dataset.path, a.settings.confidence),
        atlas: inputs.atlas.map(|x| atlas_view(a, x, data, &toc)),
        literature: inputs.literature.map(|l| literature_view(l, data, &toc)),
        deform: inputs.deform.map(|d| d.view.clone()),
        made: inputs.made.map(|m| m.view.clone()),
        region: region::region_view(a, inputs.shape, inputs.calibration, &toc.section("rigs")),
        plots: plots.iter().map(plot).collect(),
        toc,
    }
}

/// The sections this report has, in order, numbered without gaps.
fn contents(inputs: &ReportInputs<'_>, data: DataName, measurements: &str) -> Toc {
    let s = |t: &str| Some(t.to_string());
    Toc::new(&[
        ("provenance", s("Provenance")),
        ("measurements", s(measurements)),
        ("derived", s("Derived values per X-ray")),
        ("statistics", s("Statistics")),
        ("claims", s("Reproducing the paper")),
        ("placement", s("Joint placement for a model")),
        ("plots", s("Plots")),
        ("coverage", s("How far to trust each interval")),
        ("tracking", s("Tracking new X-rays")),
        ("methods", s("Methods and caveats")),
        ("atlas", inputs.atlas.map(|x| atlas_title(data, x))),
        (
            "literature",
            inputs.literature.map(|_| literature_title(data)),
        ),
        ("rigs", s("Popular rigs against the X-rays")),
    ])
}
