//! View data: finished results turned into display strings for the templates.
//!
//! Templates never compute or format numbers; everything they show is a string
//! here. Built from analysis results only, never from raw measurement rows.

use super::plots::{Plot, PlotKind};
use crate::analysis::claims::{CheckSummary, ClaimResult, Verdict};
use crate::analysis::coverage::{CoverageSettings, CurvePoint, MethodCoverage, holds};
use crate::analysis::groups::{GroupDifference, Groups};
use crate::analysis::placement::FingerPlacement;
use crate::analysis::population::PopulationStudy;
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::dataset::history::Snapshot;
use crate::format::{
    decimals, exact, interval_cells, length_decimals, level, num, opt, percent, signed, xrays,
};
use crate::stats::bootstrap::Plan;
use crate::stats::{Intervals, rng};
use serde::Serialize;

/// Most X-rays listed row by row in the data tables; the rest are summarised.
pub const MAX_LISTED_XRAYS: usize = 100;

/// Everything a report shows, ready to print.
#[derive(Debug, Clone, Serialize)]
pub struct ReportView {
    pub title: String,
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
    pub region: Option<super::region::RegionView>,
    pub plots: Vec<PlotView>,
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

/// Statistics per group of X-rays.
#[derive(Debug, Clone, Serialize)]
pub struct GroupsView {
    /// The column grouped on.
    pub by: String,
    /// Known groups first, "unknown" last.
    pub groups: Vec<GroupView>,
    /// Each known group after the first against the first.
    pub differences: Vec<GroupDifferenceView>,
    /// The confidence level, e.g. "95%".
    pub confidence: String,
}

/// One known group against the reference group, as `compare` puts two cohorts.
#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceView {
    /// "male against female".
    pub title: String,
    pub id: String,
    pub a: String,
    pub b: String,
    pub fingers: Vec<GroupDifferenceFinger>,
    pub notes: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceFinger {
    pub finger: String,
    /// What differs, as `compare` says it.
    pub sentence: String,
    pub counts: String,
    pub rows: Vec<GroupDifferenceRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceRow {
    pub quantity: String,
    pub a: String,
    pub b: String,
    pub difference: String,
    pub welch: String,
    pub bootstrap: String,
    pub hedges: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupView {
    pub label: String,
    pub id: String,
    pub xrays: String,
    pub note: Option<String>,
    pub stats: Vec<StatsFinger>,
}

/// How the statistics moved as X-rays were added.
#[derive(Debug, Clone, Serialize)]
pub struct TrackingView {
    pub file: String,
    /// "7 records".
    pub snapshots: String,
    /// Set when there is nothing to compare yet.
    pub note: Option<String>,
    /// The two records compared, e.g. "record 7 (..., 16 X-rays) against record 1 (...)".
    pub compared: String,
    /// The records from the one compared against to the last, with what each changed.
    pub records: Vec<RecordView>,
    pub changes: Vec<ChangeRow>,
    pub target: String,
    /// The caption of the X-rays-needed table: its basis, named.
    pub needed_caption: String,
    /// The column of the second cohort's larger SD ("Atlas, where its SD is larger");
    /// `None`: no second cohort, no column.
    pub needed_other: Option<String>,
    pub needed: Vec<NeededRow>,
}

/// One record of the history: what made it and what it changed.
#[derive(Debug, Clone, Serialize)]
pub struct RecordView {
    pub number: String,
    pub time: String,
    pub event: String,
    pub xrays: String,
    pub change: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ChangeRow {
    pub finger: String,
    pub quantity: String,
    pub n: String,
    pub mean_before: String,
    pub mean_after: String,
    pub shift: String,
    pub width_before: String,
    pub width_after: String,
    pub width_change: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct NeededRow {
    pub finger: String,
    pub quantity: String,
    pub n: String,
    pub sd: String,
    /// The upper end of the SD's confidence interval.
    pub sd_upper: String,
    pub half_width: String,
    /// The headline: 80% assurance with sigma at `sd_upper` (Kupper and Hafner 1989).
    pub needed: String,
    /// X-rays still to measure for `needed`.
    pub more: String,
    /// The second cohort's larger SD and its figure on the same basis, "SD 0.0092: 21";
    /// empty where its SD is not larger.
    pub other: String,
    /// Plug-in, optimistic: the current SD taken as the truth.
    pub plug_in: String,
}

/// A label and its value.
#[derive(Debug, Clone, Serialize)]
pub struct Item {
    pub label: String,
    pub value: String,
}

fn item(label: &str, value: impl Into<String>) -> Item {
    Item {
        label: label.to_string(),
        value: value.into(),
    }
}

/// Settings as the prose of the report quotes them.
#[derive(Debug, Clone, Serialize)]
pub struct SettingsText {
    /// e.g. "95%".
    pub confidence: String,
    pub resamples: String,
    pub seed: String,
    pub rng: String,
    /// e.g. "5".
    pub xrays: String,
    /// How the bootstrap was done, per distinct plan (e.g. "exact: all 126 ...").
    pub bootstrap: String,
    pub model_length: String,
    /// Why the intervals are wide at this n (the t quantile against the normal one).
    pub width_reason: String,
    /// What unit the totals J are in, as a sentence ending the statistics intro.
    pub length_unit: String,
}

/// Table 1 of the paper: one row per X-ray, J1..J3 per finger.
#[derive(Debug, Clone, Serialize)]
pub struct Table1View {
    /// Column groups: finger display names with their segment headers.
    pub groups: Vec<Table1Group>,
    pub rows: Vec<Table1Row>,
    /// Set when only the first [`MAX_LISTED_XRAYS`] X-rays are listed.
    pub truncated: Option<String>,
    pub unit: String,
    /// True when the rows give different units: each row then names its own.
    pub units: bool,
    /// "Table 1: the measurements" over the paper's X-rays, "The measurements" otherwise.
    pub heading: String,
    /// Where the lengths come from, ending the section's first sentence.
    pub source: String,
    /// The Markdown anchor of the heading.
    pub anchor: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Table1Group {
    pub finger: String,
    pub segments: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Table1Row {
    pub xray: String,
    /// The row's unit, when the dataset mixes units (else empty: the unit is `Table1View::unit`).
    pub unit: String,
    /// Every length, group by group; "-" where the X-ray lacks that finger.
    pub cells: Vec<String>,
}

/// Eqs. (1)-(4) per X-ray for one finger.
#[derive(Debug, Clone, Serialize)]
pub struct DerivedFinger {
    pub finger: String,
    pub id: String,
    /// Headers of the relative columns: "J~1", "J~2"[, "J~3"].
    pub relative_headers: Vec<String>,
    pub rows: Vec<DerivedRow>,
    pub truncated: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct DerivedRow {
    pub xray: String,
    pub total: String,
    pub relative: Vec<String>,
}

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

/// The four intervals of a table row as text (keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`).
#[derive(Debug, Clone, Serialize)]
pub struct IntervalCells {
    pub ci_t: String,
    pub ci_percentile: String,
    pub ci_bca: String,
    pub pi: String,
}

impl IntervalCells {
    /// The cells of `iv` with `d` decimals (from `format::interval_cells`).
    pub fn new(iv: &Intervals, d: usize) -> IntervalCells {
        let [ci_t, ci_percentile, ci_bca, pi] = interval_cells(iv, d);
        IntervalCells {
            ci_t,
            ci_percentile,
            ci_bca,
            pi,
        }
    }
}

/// The claim-by-claim check.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimsView {
    pub file: String,
    /// Why the claims were not checked, when they were not.
    pub note: Option<String>,
    pub summary: String,
    pub rows: Vec<ClaimRow>,
    /// Claims that disagree, with their causes.
    pub misprints: Vec<ClaimRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ClaimRow {
    pub id: String,
    /// HTML id of the claim's table row (`claim-` and the id, other characters as `-`).
    pub anchor: String,
    pub location: String,
    pub refers_to: String,
    pub stated: String,
    pub computed: String,
    pub verdict: String,
    /// CSS class: `match`, `rounded`, `erratum`, `mismatch`.
    pub class: String,
    pub cause: String,
    pub erratum_note: String,
}

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

/// Simulated coverage per method, one row per sample size.
#[derive(Debug, Clone, Serialize)]
pub struct CoverageView {
    pub sims: String,
    /// Resamples per simulated dataset at the data's own n and elsewhere, in words.
    pub resamples: String,
    /// Why the simulations take the resamples they take, for the methods.
    pub method: String,
    /// What the simulation says at the data's n, and which interval to use.
    pub summary: String,
    /// Sample sizes of the data not simulated (n = 1, or beyond the report's limit).
    pub notes: Vec<String>,
    pub rows: Vec<CoverageRow>,
    /// Coverage measured on real hands, beside the simulation (set when an
    /// atlas of measured hands is given; `None` otherwise).
    pub real: Option<RealCoverageView>,
}

/// The coverage of every method at one sample size.
#[derive(Debug, Clone, Serialize)]
pub struct CoverageRow {
    /// "5 X-rays".
    pub n: String,
    pub t: String,
    pub percentile: String,
    pub bca: String,
    pub prediction: String,
    /// True for the data's own n.
    pub this_data: bool,
}

/// Coverage measured on real hands (an atlas of X-ray measurements) rather
/// than simulated from a normal model.
#[derive(Debug, Clone, Serialize)]
pub struct RealCoverageView {
    /// Where the hands come from.
    pub source: String,
    /// How the coverage was measured.
    pub note: String,
    pub rows: Vec<CoverageRow>,
}

/// The "Key results" box at the top of the report.
#[derive(Debug, Clone, Serialize)]
pub struct KeyResults {
    /// What the X-rays count: "16 X-rays; 15 for the thumb, index, middle and little".
    pub xrays: String,
    /// Set when rows flagged as likely errors are in the data: which, and where listed.
    pub flagged: Option<String>,
    /// The confidence level, e.g. "95%".
    pub confidence: String,
    /// Each finger's inner joints as shares of the finger's length.
    pub placements: Vec<KeyPlacement>,
    pub misprints: KeyMisprints,
    /// Which interval to use, from the coverage simulation.
    pub intervals: String,
    /// Where the paper's fingertips are, from a published table (when one was compared).
    pub fingertips: Option<String>,
}

/// One finger's joints as shares of its length, root joint (MCP) to tip.
#[derive(Debug, Clone, Serialize)]
pub struct KeyPlacement {
    pub finger: String,
    /// "PIP at 48.5% (44.5% to 52.5%); DIP at ...": the mean and the prediction interval.
    pub joints: String,
}

/// The claims that disagree with the data.
#[derive(Debug, Clone, Serialize)]
pub struct KeyMisprints {
    /// "8 of the paper's 30 numbers disagree with its Table 1 (8 recorded errata, 0 new)."
    pub summary: String,
    pub items: Vec<KeyMisprint>,
}

/// One disagreeing claim, linked to its row of the claims table.
#[derive(Debug, Clone, Serialize)]
pub struct KeyMisprint {
    pub id: String,
    /// The claims table row's HTML id.
    pub anchor: String,
    /// "Sec. 2, eq. (6): stated 0.4946, recomputed 0.484636".
    pub text: String,
}

/// How to cite the paper and phalanx.
#[derive(Debug, Clone, Serialize)]
pub struct CitationView {
    /// Authors of the paper.
    pub paper_authors: String,
    pub paper_title: String,
    /// Where it appeared, as far as the paper's text says.
    pub paper_venue: String,
    /// phalanx, its version and where its citation metadata are.
    pub phalanx: String,
}

/// The paper's authors, as its title page gives them.
pub const PAPER_AUTHORS: &str = "E. Chaudhry, L. H. You, X. Jin and Jian J. Zhang";
/// The paper's title.
pub const PAPER_TITLE: &str =
    "Statistical Analysis of Joint Determination for Skeleton Driven Animation of Human Hands";
/// The paper's venue: its text names none.
pub const PAPER_VENUE: &str = "conference paper (National Centre for Computer Animation, Bournemouth University, UK; State Key Lab of CAD & CG, Zhejiang University, China); the paper's text names no venue, year or pages";

/// One plot: inline SVG for HTML, a file link for Markdown.
#[derive(Debug, Clone, Serialize)]
pub struct PlotView {
    pub id: String,
    pub kind: PlotKind,
    pub title: String,
    pub description: String,
    /// Path relative to the report directory, e.g. `plots/hand.svg`.
    pub file: String,
    pub svg: String,
    /// The description's first sentence, shown under the plot.
    pub caption: String,
    /// The rest of the description (every value in words), folded away in HTML.
    pub details: String,
}

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

/// A real rig in the report: its audit (the metacarpals included) and its
/// skin deformed as it is and as `audit --fix` writes it, with the figures.
#[derive(Debug, Clone)]
pub struct DeformSection {
    pub view: DeformView,
    /// The PNG figures, under `plots/`.
    pub figures: Vec<super::writer::OutputFile>,
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

/// A hand rigged from its skin in the report (`rig --replace-fingers`, in
/// memory): the view, and its figures under `plots/`.
#[derive(Debug, Clone)]
pub struct MadeSection {
    pub view: MadeView,
    /// The PNG figures, under `plots/`.
    pub figures: Vec<super::writer::OutputFile>,
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

/// A reference rig with its judgement.
#[derive(Debug, Clone)]
pub struct ReferenceAudit {
    pub rig: crate::rig::reference::ReferenceRig,
    pub audit: crate::rig::AuditedRig,
}

/// The section "Popular rigs against the X-rays".
#[derive(Debug, Clone, Serialize)]
pub struct RigsView {
    pub rigs: Vec<RigView>,
    pub caveats: Vec<String>,
}

/// One reference rig.
#[derive(Debug, Clone, Serialize)]
pub struct RigView {
    pub id: String,
    pub name: String,
    pub source: String,
    pub url: String,
    pub notes: String,
    /// "2 of 5 judged fingers outside the 95% joint region", ...
    pub summary: String,
    pub fingers: Vec<RigFingerView>,
}

/// One finger of a reference rig.
#[derive(Debug, Clone, Serialize)]
pub struct RigFingerView {
    pub finger: String,
    /// J~1 / J~2 / J~3 (or "no tip").
    pub relative: String,
    pub ratio_j2_j1: String,
    pub ratio_j3_j2: String,
    /// One phrase, naming whatever lies outside the prediction interval.
    pub standing: String,
}

/// Builds the view of a whole report.
pub fn build(inputs: &ReportInputs<'_>, plots: &[Plot]) -> ReportView {
    let a = inputs.analysis;
    let settings = settings_text(inputs);
    let mut provenance = vec![
        item("Dataset", a.dataset.path.clone()),
        item("SHA-256", a.dataset.sha256.clone()),
        item("X-rays", a.dataset.xrays.to_string()),
        item("Measurement rows", a.dataset.rows.to_string()),
        item("Claims file", inputs.claims_file),
        item("phalanx version", env!("CARGO_PKG_VERSION")),
        item("Seed", a.settings.seed.to_string()),
        item("Resamples asked for", a.settings.resamples.to_string()),
        item("Bootstrap", settings.bootstrap.clone()),
        item("Confidence", settings.confidence.clone()),
        item("Random number generator", rng::RNG_NAME),
    ];
    if let Some(t) = &inputs.timestamp {
        provenance.push(item("Generated", t.clone()));
    }
    let claims = claims(inputs.claims_file, inputs.claims, inputs.claims_note);
    ReportView {
        title: "phalanx: finger joint statistics from hand X-rays".into(),
        key: key_results(inputs, &claims),
        citation: citation(),
        provenance,
        settings,
        table1: table1(a, inputs.paper_xrays),
        derived: a.fingers.iter().map(derived).collect(),
        stats: a.fingers.iter().map(stats).collect(),
        flagged: flagged_rows(a),
        units_note: super::phrases::units_note(a).map(|n| sentence(&n)),
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
        atlas: inputs.atlas.map(|x| atlas_view(a, x)),
        literature: inputs.literature.map(literature_view),
        deform: inputs.deform.map(|d| d.view.clone()),
        made: inputs.made.map(|m| m.view.clone()),
        region: super::region::region_view(a, inputs.shape, inputs.calibration),
        plots: plots.iter().map(plot).collect(),
    }
}

/// A note as a sentence: capitalised, ending in a full stop.
fn sentence(note: &str) -> String {
    let mut c = note.chars();
    let mut s: String = match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    };
    if !s.ends_with('.') {
        s.push('.');
    }
    s
}

/// "a", "a and b", "a, b and c".
fn and_list(items: &[&str]) -> String {
    match items.split_last() {
        None => String::new(),
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// What the X-rays count, said once for the report: "16 X-rays" when every finger has
/// them all, else "16 X-rays; 15 for the thumb, index, middle and little" (each smaller
/// count with its fingers).
pub fn counted(a: &Analysis) -> String {
    let total = a.dataset.xrays;
    let mut out = xrays(total);
    let mut sizes: Vec<usize> = a
        .fingers
        .iter()
        .map(|f| f.n)
        .filter(|&n| n != total)
        .collect();
    sizes.sort_unstable_by(|x, y| y.cmp(x));
    sizes.dedup();
    let parts: Vec<String> = sizes
        .iter()
        .map(|&n| {
            let names: Vec<&str> = a
                .fingers
                .iter()
                .filter(|f| f.n == n)
                .map(|f| f.finger.name())
                .collect();
            format!("{n} for the {}", and_list(&names))
        })
        .collect();
    if !parts.is_empty() {
        out.push_str("; ");
        out.push_str(&parts.join(", "));
    }
    out
}

/// The rows added though flagged, for the statistics section.
fn flagged_rows(a: &Analysis) -> Vec<FlaggedView> {
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

/// What unit the totals J are in, as the statistics section says it. In image units
/// (pixels of images of no common scale) it says that J's spread, intervals and
/// prediction interval describe no physical length, and where that is seen; `paper`: the
/// data are the paper's X-rays, whose sources its section 2 names.
fn length_unit(a: &Analysis, paper: bool) -> String {
    if a.mixed_units() {
        "The rows give their lengths in more than one unit: J is shown only for a finger whose X-rays share one.".to_string()
    } else if a.pixel_lengths() {
        "The lengths are per-image pixels, so J is not averaged.".to_string()
    } else {
        match &a.unit {
            Some(u) if u == "image units" => {
                let sources = if paper {
                    "the paper took its X-ray images \"from internet and hospitals\" (its section 2) and gives no scale"
                } else {
                    "the rows give no scale"
                };
                // The spread of one finger's J, as the table below prints it.
                let seen = a
                    .fingers
                    .iter()
                    .find(|f| f.finger == Finger::Index)
                    .or(a.fingers.first())
                    .and_then(|f| {
                        let q = f.quantities.iter().find(|q| q.name == Quantity::Total)?;
                        Some(format!(
                            "; the {}'s J runs from {} to {}",
                            f.finger.name(),
                            num(q.min, decimals(false)),
                            num(q.max, decimals(false))
                        ))
                    })
                    .unwrap_or_default();
                format!(
                    "J is in image units, pixels of each X-ray as published: {sources}, so an image unit need not be the same length on two X-rays{seen}. J's spread therefore pools the images' scales with the hands' sizes, and its SD, t interval and prediction interval describe no physical length: they are shown because the paper gives J, not as sizes of hands. The relative values are ratios within one image, so the scale cancels from them."
                )
            }
            Some(u) => format!("J is in {u}."),
            None => "J is in the dataset's unit (the rows name none).".to_string(),
        }
    }
}

fn settings_text(inputs: &ReportInputs<'_>) -> SettingsText {
    let a = inputs.analysis;
    let mut plans: Vec<String> = a.fingers.iter().map(|f| f.bootstrap.describe()).collect();
    plans.dedup();
    SettingsText {
        confidence: level(a.settings.confidence),
        resamples: a.settings.resamples.to_string(),
        seed: a.settings.seed.to_string(),
        rng: rng::RNG_NAME.to_string(),
        xrays: a.dataset.xrays.to_string(),
        bootstrap: plans.join("; "),
        model_length: exact(inputs.model_length),
        width_reason: width_reason(a),
        length_unit: length_unit(a, is_paper(inputs.paper_xrays)),
    }
}

/// "With n = 5 the 95% t quantile is 2.78 (4 degrees of freedom), not the normal 1.96."
fn width_reason(a: &Analysis) -> String {
    let crate::analysis::WidthReason { n, t, z } = a.width_reason();
    let c = a.settings.confidence;
    match t {
        Some(t) => format!(
            "With n = {n} X-rays the {} t quantile is {} ({} degrees of freedom), not the normal {}.",
            level(c),
            num(t, 2),
            n - 1,
            num(z, 2)
        ),
        None => format!(
            "With n = {n} X-ray{} no interval can be estimated.",
            if n == 1 { "" } else { "s" }
        ),
    }
}

/// The paper's finger order in Table 1: grooming (index), middle, ring, little, thumb.
const TABLE1_ORDER: [Finger; 5] = [
    Finger::Index,
    Finger::Middle,
    Finger::Ring,
    Finger::Little,
    Finger::Thumb,
];

fn truncation(total: usize) -> Option<String> {
    (total > MAX_LISTED_XRAYS).then(|| {
        format!(
            "The first {MAX_LISTED_XRAYS} of {total} X-rays are listed; the statistics use all of them."
        )
    })
}

/// True when the dataset holds exactly the X-rays the paper's claims name.
fn is_paper((named, xrays): (usize, usize)) -> bool {
    named > 0 && named == xrays
}

fn table1(a: &Analysis, paper_xrays: (usize, usize)) -> Table1View {
    let (named, xrays) = paper_xrays;
    let (heading, source) = if is_paper(paper_xrays) {
        (
            "Table 1: the measurements".to_string(),
            "as printed in the paper's Table 1".to_string(),
        )
    } else if named == 0 {
        (
            "The measurements".to_string(),
            format!("as in the dataset ({xrays} X-rays, none of them the paper's)"),
        )
    } else {
        (
            "The measurements".to_string(),
            format!(
                "as in the dataset: the {named} X-rays of the paper's Table 1 and {} added since",
                xrays - named
            ),
        )
    };
    let fingers: Vec<_> = TABLE1_ORDER.iter().filter_map(|&f| a.finger(f)).collect();
    let groups = fingers
        .iter()
        .map(|f| Table1Group {
            finger: f.finger.display_name().to_string(),
            segments: (1..=f.finger.segments()).map(|k| format!("J{k}")).collect(),
        })
        .collect();
    // X-rays in order of first appearance across the fingers.
    let mut ids: Vec<&str> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for f in &fingers {
        for x in &f.xrays {
            if seen.insert(&*x.xray) {
                ids.push(&x.xray);
            }
        }
    }
    let lookup: Vec<std::collections::HashMap<&str, &[f64]>> = fingers
        .iter()
        .map(|f| {
            f.xrays
                .iter()
                .map(|x| (&*x.xray, x.lengths.as_slice()))
                .collect()
        })
        .collect();
    let units: std::collections::HashMap<&str, &str> = fingers
        .iter()
        .flat_map(|f| f.xrays.iter())
        .filter_map(|x| Some((&*x.xray, x.unit.as_deref()?)))
        .collect();
    let mixed = a.mixed_units();
    let rows = ids
        .iter()
        .take(MAX_LISTED_XRAYS)
        .map(|id| Table1Row {
            xray: id.to_string(),
            unit: if mixed {
                units.get(id).map_or("none named", |u| u).to_string()
            } else {
                String::new()
            },
            cells: fingers
                .iter()
                .zip(&lookup)
                .flat_map(|(f, map)| match map.get(id) {
                    Some(ls) => ls.iter().map(|l| num(*l, 2)).collect::<Vec<_>>(),
                    None => vec!["-".to_string(); f.finger.segments()],
                })
                .collect(),
        })
        .collect();
    Table1View {
        groups,
        rows,
        truncated: truncation(ids.len()),
        unit: match (&a.unit, mixed) {
            (_, true) => "the unit each row names (its column 'unit')".to_string(),
            (Some(u), _) if u == "image units" => {
                "image units (pixels of the X-ray images, not millimetres)".to_string()
            }
            (Some(u), _) => u.clone(),
            (None, _) => "the dataset's unit (its rows name none)".to_string(),
        },
        units: mixed,
        anchor: format!(
            "2-{}",
            heading
                .to_ascii_lowercase()
                .replace(':', "")
                .replace(' ', "-")
        ),
        heading,
        source,
    }
}

fn derived(f: &crate::analysis::FingerAnalysis) -> DerivedFinger {
    DerivedFinger {
        finger: f.finger.display_name().to_string(),
        id: f.finger.name().to_string(),
        relative_headers: (1..=f.finger.segments())
            .map(|k| format!("J~{k}"))
            .collect(),
        rows: f
            .xrays
            .iter()
            .take(MAX_LISTED_XRAYS)
            .map(|x| DerivedRow {
                xray: x.xray.to_string(),
                total: num(x.total, 2),
                relative: x.relative.iter().map(|r| num(*r, 4)).collect(),
            })
            .collect(),
        truncated: truncation(f.xrays.len()),
    }
}

fn plan_text(p: Plan) -> String {
    p.describe()
}

fn stats(f: &crate::analysis::FingerAnalysis) -> StatsFinger {
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
        finger: f.finger.display_name().to_string(),
        id: f.finger.name().to_string(),
        n: xrays(f.n),
        bootstrap: plan_text(f.bootstrap),
        rows,
        notes,
    }
}

fn claims(file: &str, results: &[ClaimResult], note: Option<&str>) -> ClaimsView {
    let rows: Vec<ClaimRow> = results
        .iter()
        .map(|r| {
            let computed = match (r.verdict, r.computed_rounded) {
                (Verdict::MatchesRounded, Some(x)) => format!(
                    "{} (from rounded values: {})",
                    num(r.computed, r.decimals + 2),
                    num(x, r.decimals)
                ),
                // Counts (printed without decimals) stay whole numbers.
                _ if r.decimals == 0 && r.computed.fract() == 0.0 => num(r.computed, 0),
                _ => num(r.computed, r.decimals + 2),
            };
            ClaimRow {
                id: r.id.clone(),
                anchor: claim_anchor(&r.id),
                location: r.location.clone(),
                refers_to: r.refers_to.clone(),
                stated: r.stated_text.clone(),
                computed,
                verdict: r.verdict.label().to_string(),
                class: match r.verdict {
                    Verdict::Matches => "match",
                    Verdict::MatchesRounded => "rounded",
                    Verdict::KnownErratum => "erratum",
                    Verdict::Mismatch => "mismatch",
                }
                .to_string(),
                cause: r.cause.clone().unwrap_or_default(),
                erratum_note: r.erratum_note.clone().unwrap_or_default(),
            }
        })
        .collect();
    let s = CheckSummary::of(results);
    ClaimsView {
        file: file.to_string(),
        note: note.map(str::to_string),
        summary: format!(
            "{} claims: {} match, {} match from rounded values (as the paper computes), {} known errata, {} new mismatches.",
            s.claims, s.matches, s.matches_rounded, s.known_errata, s.mismatches
        ),
        misprints: rows
            .iter()
            .filter(|r| !r.cause.is_empty())
            .cloned()
            .collect(),
        rows,
    }
}

fn placement(
    ps: &[FingerPlacement],
    length: f64,
    paper_xrays: (usize, usize),
    counts: &str,
) -> PlacementView {
    let d = length_decimals(length);
    let origin = if is_paper(paper_xrays) {
        "This is the paper's worked example, with the corrected mean. (The index is the paper's 'grooming' finger.)".to_string()
    } else {
        format!(
            "The paper works this example with its own X-rays; here the means are over the dataset's {counts}. (The index is the paper's 'grooming' finger.)"
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

/// The coverage of method `name` at one point, if simulated.
fn method<'c>(p: &'c CurvePoint, name: &str) -> Option<&'c MethodCoverage> {
    p.coverage.methods.iter().find(|m| m.method == name)
}

/// A method's coverage as a percentage, "n/a" when not simulated.
fn coverage_cell(p: &CurvePoint, name: &str) -> String {
    method(p, name).map_or_else(|| "n/a".to_string(), |m| percent(m.coverage))
}

/// Which interval to use, read off the simulation at the data's smallest n:
/// which methods hold their nominal level there ([`holds`]) and which fall
/// short. `None` when the data's n was not simulated.
pub fn interval_advice(points: &[CurvePoint]) -> Option<String> {
    interval_advice_of(points, None)
}

/// [`interval_advice`], naming the fingers whose n it is when `a` says some fingers
/// have more X-rays ("At n = 15 X-rays (the thumb, index, middle and little; the ring
/// has 16)").
pub fn interval_advice_of(points: &[CurvePoint], a: Option<&Analysis>) -> Option<String> {
    let p = points.iter().filter(|p| p.in_data).min_by_key(|p| p.n)?;
    let whose = a
        .filter(|a| a.fingers.iter().any(|f| f.n != p.n))
        .map(|a| {
            let at: Vec<&str> = a
                .fingers
                .iter()
                .filter(|f| f.n == p.n)
                .map(|f| f.finger.name())
                .collect();
            let mut others: Vec<usize> = a
                .fingers
                .iter()
                .map(|f| f.n)
                .filter(|&n| n != p.n)
                .collect();
            others.sort_unstable();
            others.dedup();
            let more = match others.as_slice() {
                [one] => format!("{one}"),
                [lo, .., hi] => format!("{lo} to {hi}"),
                [] => String::new(),
            };
            format!(
                " (the n of the {}; the other fingers have {more})",
                and_list(&at)
            )
        })
        .unwrap_or_default();
    let t = method(p, "t")?;
    let pi = method(p, "prediction")?;
    let name = |m: &str| match m {
        "t" => "t",
        "percentile" => "bootstrap percentile",
        "bca" => "BCa",
        _ => "prediction",
    };
    let short: Vec<String> = p
        .coverage
        .methods
        .iter()
        .filter(|m| !holds(m))
        .map(|m| format!("{} ({})", name(m.method), percent(m.coverage)))
        .collect();
    let mut s = format!(
        "At n = {}{whose}, the t interval covers the mean {} of the time and the prediction interval holds {} of new hands, against a nominal {}",
        xrays(p.n),
        percent(t.coverage),
        percent(pi.coverage),
        level(t.nominal)
    );
    match short.as_slice() {
        [] => s.push_str("; every method holds its level at this size."),
        [one] => s.push_str(&format!("; the {one} interval under-covers.")),
        many => s.push_str(&format!(
            "; the {} intervals under-cover.",
            match many.split_last() {
                Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
                None => String::new(),
            }
        )),
    }
    s.push(' ');
    s.push_str(match (holds(t), holds(pi)) {
        (true, true) => {
            "Use the t interval for the mean of all hands and the prediction interval for where a new hand falls."
        }
        (true, false) => {
            "Use the t interval for the mean of all hands; the prediction interval is too narrow at this size."
        }
        (false, true) => {
            "Use the prediction interval for where a new hand falls; no confidence interval of the mean holds its level at this size."
        }
        (false, false) => "No interval holds its level at this size: read them as rough guides.",
    });
    Some(s)
}

/// Why the coverage simulations take fewer resamples than the statistics: the Monte-Carlo
/// error of the printed figures (see [`crate::analysis::coverage::SIM_RESAMPLES`]).
fn simulation_method(s: &CoverageSettings, asked: usize) -> String {
    let se = |p: f64| 100.0 * (p * (1.0 - p) / s.sims.max(1) as f64).sqrt();
    // The bootstrap's bias on the percentile coverage: about 70 / B points (0.35 measured at
    // B = 200 against 10,000; the endpoint noise is of order 1 / B).
    let curve = crate::analysis::coverage::CURVE_RESAMPLES;
    let b = s.resamples.min(curve);
    let bias = 70.0 / b.max(1) as f64;
    let measured = if b == curve {
        " (measured against 10000 resamples: 0.3 to 0.5 points at 10 to 50 X-rays)"
    } else {
        ""
    };
    format!(
        "each simulated dataset is bootstrapped with {b} resamples{} (the statistics above use the {asked} asked for), chosen by the Monte-Carlo error of the printed coverage. From {} simulated datasets a coverage near 95% has a Monte-Carlo SE of {:.2} points, one near 85% of {:.2}; the bootstrap's own noise lowers the percentile and BCa coverage by about 70 / B points at B resamples, {bias:.2} here{measured}, {:.1} times the SE near 95%. More resamples would move no printed figure beyond that noise, at a cost that grows with them. The t and prediction intervals do not use the bootstrap.",
        if s.resamples > curve {
            format!(", {} at this data's n", s.resamples)
        } else {
            String::new()
        },
        s.sims,
        se(0.95),
        se(0.85),
        bias / se(0.95).max(1e-9),
    )
}

fn coverage(inputs: &ReportInputs<'_>) -> CoverageView {
    let s = inputs.coverage_settings;
    let points = inputs.coverage;
    let data: Vec<String> = points
        .iter()
        .filter(|p| p.in_data)
        .map(|p| xrays(p.n))
        .collect();
    let notes = crate::analysis::coverage::not_simulated(inputs.analysis, s);
    let summary = interval_advice_of(points, Some(inputs.analysis)).unwrap_or_else(|| {
        "Coverage could not be simulated at this data's size (fewer than 2 X-rays, or more than the report simulates).".to_string()
    });
    CoverageView {
        sims: s.sims.to_string(),
        resamples: {
            let data = if data.is_empty() {
                "not simulated".to_string()
            } else {
                data.join(", ")
            };
            let curve = crate::analysis::coverage::CURVE_RESAMPLES;
            if s.resamples <= curve {
                format!(
                    "{} bootstrap resamples per simulated dataset at every size, this data's n ({data}) included, or the exact enumeration where it needs fewer",
                    s.resamples
                )
            } else {
                format!(
                    "{} bootstrap resamples per simulated dataset at this data's n ({data}), at most {curve} at the other sizes",
                    s.resamples
                )
            }
        },
        method: simulation_method(s, inputs.analysis.settings.resamples),
        summary,
        notes,
        rows: points
            .iter()
            .map(|p| CoverageRow {
                n: xrays(p.n),
                t: coverage_cell(p, "t"),
                percentile: coverage_cell(p, "percentile"),
                bca: coverage_cell(p, "bca"),
                prediction: coverage_cell(p, "prediction"),
                this_data: p.in_data,
            })
            .collect(),
        real: inputs.atlas.map(real_coverage),
    }
}

/// The coverage of each method measured on the atlas's hands (the mean over its
/// relative values per sample size), for the coverage section, beside the simulation.
fn real_coverage(atlas: &AtlasInputs) -> RealCoverageView {
    let p = &atlas.population;
    let rows = pooled_rows(p)
        .into_iter()
        .filter(|r| !r.normal)
        .map(|r| {
            let [t, percentile, bca, prediction] = r.cells;
            CoverageRow {
                n: xrays(r.n),
                t,
                percentile,
                bca,
                prediction,
                this_data: false,
            }
        })
        .collect();
    let population = p.quantities.first().map_or(0, |q| q.population);
    RealCoverageView {
        source: format!("samples drawn from the {population} X-rays of the atlas"),
        note: format!(
            "Each figure is the mean over the atlas's {} relative values of how often the interval held the atlas's mean (the prediction interval: one further atlas X-ray), from {} samples per size; the atlas section below has the details.",
            p.quantities.len(),
            p.settings.sims
        ),
        rows,
    }
}

/// The HTML id of a claim's table row: `claim-` and its id, characters other
/// than ASCII letters, digits, `-` and `_` written as `-`.
fn claim_anchor(id: &str) -> String {
    let slug: String = id
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    format!("claim-{slug}")
}

/// The "Key results" box: joints as shares of the finger, the misprints, which interval to use.
fn key_results(inputs: &ReportInputs<'_>, claims: &ClaimsView) -> KeyResults {
    let a = inputs.analysis;
    let c = level(a.settings.confidence);
    let placements = inputs
        .placements
        .iter()
        .map(|p| {
            let share = |x: f64| percent(x / p.length);
            let joints: Vec<String> = p
                .joints
                .iter()
                .map(|j| {
                    let pi = j.position.intervals.pi.map_or_else(
                        || "no prediction interval with one X-ray".to_string(),
                        |i| format!("{} to {}", share(i.low), share(i.high)),
                    );
                    format!("{} at {} ({pi})", j.joint.name(), share(j.position.mean))
                })
                .collect();
            KeyPlacement {
                finger: p.finger.display_name().to_string(),
                joints: joints.join("; "),
            }
        })
        .collect();
    let s = CheckSummary::of(inputs.claims);
    let misprints = KeyMisprints {
        summary: if let Some(note) = &claims.note {
            note.clone()
        } else if claims.misprints.is_empty() {
            format!(
                "All {} numbers the paper states agree with its Table 1.",
                s.claims
            )
        } else {
            format!(
                "{} of the paper's {} stated numbers disagree with its Table 1 ({} recorded errata, {} new); the causes are in section 5.",
                claims.misprints.len(),
                s.claims,
                s.known_errata,
                s.mismatches
            )
        },
        items: claims
            .misprints
            .iter()
            .map(|m| KeyMisprint {
                id: m.id.clone(),
                anchor: m.anchor.clone(),
                text: format!(
                    "{}: stated {}, recomputed {}",
                    m.location, m.stated, m.computed
                ),
            })
            .collect(),
    };
    let flagged = match a.flagged.as_slice() {
        [] => None,
        rows => {
            let list: Vec<String> = rows
                .iter()
                .map(|f| format!("{} {}", f.xray, f.finger.name()))
                .collect();
            Some(format!(
                "{} of the data {} added though flagged as a likely measurement or typing error: {}. The numbers below include {}; check {} (section 4 lists why each was flagged, and how to take it out).",
                if rows.len() == 1 {
                    "1 row".to_string()
                } else {
                    format!("{} rows", rows.len())
                },
                if rows.len() == 1 { "was" } else { "were" },
                list.join(", "),
                if rows.len() == 1 { "it" } else { "them" },
                if rows.len() == 1 { "it" } else { "them" },
            ))
        }
    };
    KeyResults {
        xrays: counted(a),
        flagged,
        confidence: c,
        placements,
        misprints,
        intervals: interval_advice_of(inputs.coverage, Some(a)).unwrap_or_else(|| {
            "The coverage of the intervals could not be simulated at this data's size.".to_string()
        }),
        fingertips: inputs.literature.and_then(key_fingertips),
    }
}

/// The key result on the fingertips: where the paper's are taken, and what the test does
/// and does not show, in one paragraph.
fn key_fingertips(l: &LiteratureInputs) -> Option<String> {
    let v = l.paper.tips.as_ref()?;
    let name = table_name(&l.paper.b);
    let ranges = |pick: fn(&crate::analysis::literature::TipFinding) -> f64| {
        let xs: Vec<f64> = v.fingers.iter().map(pick).collect();
        let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (slo, shi) = ranges(|t| t.soft_share);
    let nearest = v.nearest_to_rejection().map_or(String::new(), |(t, i)| {
        format!(
            "; the {}'s interval ends at {}",
            t.finger.name(),
            crate::format::signed(i.high, decimals(true))
        )
    });
    Some(match v.overall {
        Some(crate::analysis::literature::Fit::Skin) => format!(
            "The paper's fingertips are taken at the skin, not at the end of the bone. Against {name}, a Welch test of each finger's last segment rejects bone alone on all {} fingers at every assumed correlation from 0 to 0.9, and does not reject bone plus the fingertip's soft tissue (not rejected is not shown equal{nearest}). The paper does not say where its tips are; its rows record the skin because of this test. The soft tissue is {} to {} of a finger measured to the skin, so a rig's tip at the skin compares with the paper as it is, and a tip at the bone needs that share added.",
            v.fingers.len(),
            percent(slo),
            percent(shi),
        ),
        Some(crate::analysis::literature::Fit::Bone) => format!(
            "The paper's fingertips are taken at the end of the bone: against {name}, its last segment rejects bone plus soft tissue on all {} fingers and does not reject bone alone (not rejected is not shown equal).",
            v.fingers.len()
        ),
        _ => format!(
            "Where the paper's fingertips are is not settled by {name}: the fingers do not reject one tip and leave the other at every assumed correlation from 0 to 0.9."
        ),
    })
}

/// "Buryanov & Kotiuk 2010", or the table's file.
fn table_name(s: &crate::analysis::literature::SideInfo) -> String {
    s.about
        .as_ref()
        .and_then(|a| a.name.clone())
        .unwrap_or_else(|| s.path.clone())
}

/// How to cite the paper and phalanx.
fn citation() -> CitationView {
    CitationView {
        paper_authors: PAPER_AUTHORS.to_string(),
        paper_title: PAPER_TITLE.to_string(),
        paper_venue: PAPER_VENUE.to_string(),
        phalanx: format!(
            "phalanx {}, finger-joint statistics from hand X-rays (MIT OR Apache-2.0); citation metadata in CITATION.cff",
            env!("CARGO_PKG_VERSION")
        ),
    }
}

fn plot(p: &Plot) -> PlotView {
    let (caption, details) = match p.description.split_once(". ") {
        Some((first, rest)) => (format!("{first}."), rest.to_string()),
        None => (p.description.clone(), String::new()),
    };
    PlotView {
        caption,
        details,
        id: p.id.clone(),
        kind: p.kind,
        title: p.title.clone(),
        description: p.description.clone(),
        file: format!("plots/{}.svg", p.id),
        svg: p.svg.clone(),
    }
}

fn tracking(inputs: &ReportInputs<'_>) -> TrackingView {
    let snaps = inputs.history;
    let records = |from: usize| -> Vec<RecordView> {
        snaps
            .iter()
            .enumerate()
            .skip(from)
            .map(|(i, s)| RecordView {
                number: (i + 1).to_string(),
                time: s.time.clone(),
                event: s.event.to_string(),
                xrays: s.xrays.to_string(),
                change: super::phrases::record_change(s),
            })
            .collect()
    };
    let (note, compared, changes, listed) = if snaps.len() < 2 {
        let count = match snaps.len() {
            0 => "No snapshot yet".to_string(),
            1 => "One snapshot".to_string(),
            k => format!("{k} snapshots"),
        };
        let note = format!(
            "{count} in {}: changes and plots appear once there are two. 'phalanx add' and 'phalanx remove' append one per change; 'phalanx snapshot' one on demand.",
            inputs.history_file
        );
        (Some(note), String::new(), Vec::new(), records(0))
    } else {
        let e = snaps.len() - 1;
        // --since is checked against the history before the report is built.
        let b = inputs.since.map_or(0, |n| n.saturating_sub(1)).min(e - 1);
        let compared = format!(
            "{} against {}",
            describe_snapshot(snaps, e),
            describe_snapshot(snaps, b)
        );
        (
            None,
            compared,
            change_rows(&snaps[b], &snaps[e]),
            records(b),
        )
    };
    TrackingView {
        file: inputs.history_file.to_string(),
        snapshots: match snaps.len() {
            1 => "1 snapshot".to_string(),
            k => format!("{k} snapshots"),
        },
        note,
        compared,
        records: listed,
        changes,
        target: num(inputs.target, 4),
        needed_caption: needed_caption(inputs),
        needed_other: inputs
            .atlas
            .map(|_| "The atlas, where its SD is larger".to_string()),
        needed: needed_rows(
            inputs.analysis,
            inputs.atlas.map(|x| &x.analysis),
            inputs.target,
        ),
    }
}

/// "record 3 (time, event, 7 X-rays)" for record `i` of `snaps`.
fn describe_snapshot(snaps: &[Snapshot], i: usize) -> String {
    let s = &snaps[i];
    format!(
        "snapshot {} ({}, {}, {})",
        i + 1,
        s.time,
        s.event,
        xrays(s.xrays)
    )
}

/// One row per finger and relative quantity: how it changed from `before` to `after`.
fn change_rows(before: &Snapshot, after: &Snapshot) -> Vec<ChangeRow> {
    crate::analysis::tracking::changes(before, after)
        .into_iter()
        .filter(|ch| ch.quantity != Quantity::Total)
        .map(|ch| {
            let d = decimals(ch.quantity.is_unitless());
            ChangeRow {
                finger: ch.finger.display_name().to_string(),
                quantity: ch.quantity.label().to_string(),
                n: format!("{} -> {}", ch.n_before, ch.n_after),
                mean_before: num(ch.mean_before, d),
                mean_after: num(ch.mean_after, d),
                shift: signed(ch.mean_shift, d),
                width_before: opt(ch.ci_width_before, d),
                width_after: opt(ch.ci_width_after, d),
                width_change: match (ch.ci_width_before, ch.ci_width_after) {
                    (Some(x), Some(y)) => signed(y - x, d),
                    _ => "n/a".to_string(),
                },
            }
        })
        .collect()
}

/// The caption of the X-rays-needed table: the target, the basis of the headline
/// figure, the second cohort beside it, and the plug-in named as optimistic.
fn needed_caption(inputs: &ReportInputs<'_>) -> String {
    use crate::analysis::tracking::ASSURANCE;
    let a = inputs.analysis;
    let c = a.settings.confidence;
    let atlas = inputs.atlas.map_or(String::new(), |x| {
        format!(
            " Where the atlas (section 11: {} of children's left hands, tips at the bone) gives a larger SD for the same finger and quantity, its SD and its figure on the same basis stand beside it: another cohort's spread, not this one's, but one measured on enough hands to pin it.",
            xrays(x.analysis.dataset.xrays)
        )
    });
    format!(
        "X-rays needed for a {conf} t interval of half-width {w} or less. {n} measure the SD itself only roughly, so the figure does not take the SD as the truth: it is the smallest n with P(t · S / √n ≤ W) ≥ {assurance} (Kupper and Hafner 1989, where (n − 1) S² / σ² is χ²(n − 1)) with σ at the upper end of the SD's {conf} confidence interval, s · √((n − 1) / q), q the {tail} quantile of χ²(n − 1). The true SD lies below that limit with {one_sided} confidence, and then a study of that size meets the target in at least {assurance} of cases. “Still to measure” counts towards that n.{atlas} The plug-in n takes the current SD as exact: it is optimistic, and meets the target in only about 50-65% of studies even when the SD is right.",
        conf = level(c),
        w = num(inputs.target, 4),
        n = xrays(a.dataset.xrays),
        assurance = level(ASSURANCE),
        tail = level((1.0 - c) / 2.0),
        one_sided = level((1.0 + c) / 2.0),
    )
}

/// The X-rays needed for a t interval of half-width `target`, per finger and
/// relative quantity: the headline (80% assurance at the SD's upper limit), the
/// second cohort's where its SD is larger, and the plug-in
/// ([`crate::analysis::tracking::needed_per_quantity`]).
fn needed_rows(a: &Analysis, other: Option<&Analysis>, target: f64) -> Vec<NeededRow> {
    let count = |n: Option<usize>| n.map_or_else(|| "n/a".to_string(), |n| n.to_string());
    crate::analysis::tracking::needed_per_quantity(a, other, target)
        .into_iter()
        .map(|r| {
            let q = r.quantity;
            NeededRow {
                finger: r.finger.display_name().to_string(),
                quantity: q.name.label().to_string(),
                n: q.n.to_string(),
                sd: opt(q.sd, 4),
                sd_upper: opt(r.sd_upper, 4),
                half_width: opt(q.intervals.ci_t.map(|i| i.width() / 2.0), 4),
                needed: count(r.needed),
                more: match r.needed {
                    Some(n) if n <= q.n => "reached".to_string(),
                    Some(n) => format!("{} more", n - q.n),
                    None => "n/a".to_string(),
                },
                other: r.larger.map_or(String::new(), |o| {
                    format!("SD {}: {}", num(o.sd, 4), count(o.needed))
                }),
                plug_in: count(r.plug_in),
            }
        })
        .collect()
}

fn groups_view(groups: Option<&Groups>, confidence: f64) -> Option<GroupsView> {
    let all = groups?;
    Some(GroupsView {
        by: all.by.to_string(),
        confidence: level(confidence),
        differences: all
            .differences
            .iter()
            .enumerate()
            .map(|(i, d)| group_difference(d, i))
            .collect(),
        groups: all
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| GroupView {
                label: g.label.clone(),
                id: format!("group-{}", i + 1),
                xrays: g.xrays.to_string(),
                note: g.note.clone(),
                stats: g
                    .analysis
                    .fingers
                    .iter()
                    .map(|f| {
                        let mut v = stats(f);
                        v.id = format!("group-{}-{}", i + 1, v.id);
                        v
                    })
                    .collect(),
            })
            .collect(),
    })
}

/// The view of one group difference: per finger `compare`'s sentence and its table.
fn group_difference(d: &GroupDifference, i: usize) -> GroupDifferenceView {
    use super::compare as cmp;
    use super::compare_words::Names;
    let c = &d.cohorts;
    let names = Names { a: &d.a, b: &d.b };
    GroupDifferenceView {
        title: format!("{} against {}", d.b, d.a),
        id: format!("group-difference-{}", i + 1),
        a: d.a.clone(),
        b: d.b.clone(),
        fingers: c
            .fingers
            .iter()
            .map(|f| GroupDifferenceFinger {
                finger: f.finger.display_name().to_string(),
                sentence: cmp::finger_sentence(f, names, c.settings.confidence),
                counts: format!("{}: {}, {}: {}", d.a, xrays(f.n_a), d.b, xrays(f.n_b)),
                rows: f
                    .quantities
                    .iter()
                    .map(|q| {
                        let (k, x) = (q.quantity, &q.comparison);
                        GroupDifferenceRow {
                            quantity: k.label().to_string(),
                            a: cmp::mean_sd(x.a.mean, x.a.sd, k),
                            b: cmp::mean_sd(x.b.mean, x.b.sd, k),
                            difference: cmp::difference_cell(x, k),
                            welch: cmp::welch_cell(x, k),
                            bootstrap: cmp::bootstrap_cell(x, k),
                            hedges: cmp::hedges_cell(x),
                        }
                    })
                    .collect(),
            })
            .collect(),
        notes: c.notes.clone(),
    }
}

/// The section on reference rigs, judged against the data at `data` (its path).
fn rigs_view(rigs: &[ReferenceAudit], data: &str, confidence: f64) -> Option<RigsView> {
    use super::audit::{finger_summary, value_of};
    use crate::rig::judge::Basis;
    let first = rigs.first()?;
    let views = rigs
        .iter()
        .map(|r| {
            let judged = r
                .audit
                .fingers
                .iter()
                .filter(|f| f.audit.basis != Basis::None)
                .count();
            let fingers = r
                .audit
                .fingers
                .iter()
                .map(|f| {
                    let a = &f.audit;
                    let rel: Vec<String> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
                        .iter()
                        .filter_map(|&q| value_of(a, q).map(|v| num(v, 4)))
                        .collect();
                    let ratio = |q| value_of(a, q).map_or("n/a".to_string(), |v| num(v, 4));
                    RigFingerView {
                        finger: f.chain.finger.name().to_string(),
                        relative: if rel.is_empty() {
                            "n/a (no tip)".into()
                        } else {
                            rel.join(" / ")
                        },
                        ratio_j2_j1: ratio(Quantity::RatioJ2J1),
                        ratio_j3_j2: ratio(Quantity::RatioJ3J2),
                        standing: finger_summary(a),
                    }
                })
                .collect();
            RigView {
                id: r.rig.id.clone(),
                name: r.rig.name.clone(),
                source: r.rig.source.clone(),
                url: r.rig.url.clone(),
                notes: std::iter::once(r.rig.notes.clone())
                    .chain(r.audit.notes.iter().cloned())
                    .filter(|n| !n.is_empty())
                    .collect::<Vec<_>>()
                    .join(" "),
                summary: format!(
                    "{} of {judged} judged fingers outside {}",
                    r.audit.outside(),
                    super::audit::outside_of(&r.audit, confidence)
                ),
                fingers,
            }
        })
        .collect();
    Some(RigsView {
        rigs: views,
        caveats: super::audit::caveats(&first.audit.tips, data),
    })
}

/// What the section "The paper against N atlas radiographs" reads: the atlas analysed,
/// the paper (A) compared with it (B), and the coverage measured on its hands.
#[derive(Debug, Clone)]
pub struct AtlasInputs {
    pub analysis: Analysis,
    pub cohorts: crate::analysis::compare::Cohorts,
    pub population: PopulationStudy,
}

/// The section "The paper against N atlas radiographs".
#[derive(Debug, Clone, Serialize)]
pub struct AtlasView {
    pub title: String,
    /// The Markdown anchor of the section's heading.
    pub anchor: String,
    /// The two cohorts, one line each.
    pub cohorts: Vec<String>,
    /// What differs between the cohorts, in plain words.
    pub differs: String,
    pub comparison: Vec<AtlasCompareRow>,
    /// One sentence per finger, then the fingertip sentences.
    pub sentences: Vec<String>,
    pub external: Vec<AtlasExternalRow>,
    pub external_summary: String,
    pub population_intro: String,
    pub population: Vec<AtlasPopulationRow>,
    pub proportions_intro: String,
    pub proportions: Vec<AtlasProportionRow>,
    pub notes: Vec<String>,
}

/// One finger and quantity of the comparison table.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasCompareRow {
    pub finger: String,
    pub quantity: String,
    pub paper: String,
    pub atlas: String,
    pub difference: String,
    pub welch: String,
    pub bootstrap: String,
    pub hedges: String,
}

/// One finger and quantity of the external coverage.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasExternalRow {
    pub finger: String,
    pub quantity: String,
    pub paper_pi: String,
    pub atlas_in_paper: String,
    pub atlas_pi: String,
    pub paper_in_atlas: String,
}

/// One sample size and model of the coverage on real hands.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasPopulationRow {
    pub n: String,
    pub model: String,
    pub t: String,
    pub percentile: String,
    pub bca: String,
    pub prediction: String,
    pub bootstrap: String,
}

/// One finger's whole-hand proportions from its metacarpal.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasProportionRow {
    pub finger: String,
    pub n: String,
    pub mc_j: String,
    pub mc_j_pi: String,
    pub j1_mc: String,
    pub j1_mc_pi: String,
}

/// The section "The paper against N atlas radiographs" from the paper's analysis and the atlas's.
fn atlas_view(paper: &Analysis, atlas: &AtlasInputs) -> AtlasView {
    use super::compare::cohort_line;
    let c = &atlas.cohorts;
    let p = &atlas.population;
    let confidence = paper.settings.confidence;
    let (comparison, external, (inside, tested)) = atlas_comparison(c);
    let external_summary = format!(
        "Over every finger and relative value, {} of the atlas's values ({inside} of {tested}) lie inside the paper's {} prediction interval for one new hand, which promises {}.",
        percent(inside as f64 / tested.max(1) as f64),
        level(confidence),
        level(confidence),
    );
    let proportions_intro = format!(
        "Where the MCP sits: the paper measures the fingers only, the atlas also the metacarpal (CMC to MCP). mc/J is the metacarpal's length over the finger's (J1 + J2 + J3), J1/mc the first phalanx over the metacarpal: for a rig, the MCP lies (mc/J) L from the CMC for a finger of length L. Mean (SD) and the {} prediction interval for one new hand, over the atlas's X-rays.",
        level(confidence)
    );
    let title = format!("The paper against {} atlas radiographs", c.b.xrays);
    AtlasView {
        anchor: format!("11-{}", title.to_ascii_lowercase().replace(' ', "-")),
        title,
        cohorts: vec![
            format!("The paper: {}", cohort_line(&c.a)),
            format!("The atlas: {}", cohort_line(&c.b)),
        ],
        differs: format!(
            "The cohorts differ in more than their size. The atlas (the Digital Hand Atlas, {} radiographs) holds children and adolescents aged 0 to 18, all left hands, with {}; its lengths are pixels of images of different scale, so only relative values compare. The paper's {} X-rays are right hands, measured in Matlab, of people whose sex and age it does not give; it does not say whether its fingertips are at the bone or the skin, and its data record them at the skin because a test against published adult measurements rejects bone tips and does not reject skin tips (section 12). A difference below may come from growth, from the side or the person, or from where the tip was clicked.",
            c.b.xrays,
            crate::dataset::landmarks::ATLAS_LANDMARKS,
            c.a.xrays
        ),
        comparison,
        sentences: atlas_sentences(c, confidence),
        external,
        external_summary,
        population_intro: atlas_population_intro(p, confidence),
        population: atlas_population(p),
        proportions_intro,
        proportions: atlas_proportions(&atlas.analysis),
        notes: c.notes.iter().chain(&p.notes).cloned().collect(),
    }
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

/// The section "The paper against published measurements".
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureView {
    pub title: String,
    /// The Markdown anchor of the section's heading.
    pub anchor: String,
    /// The published table: its citation and sample.
    pub source: String,
    /// One line per cohort on why it differs from the paper.
    pub cohorts: Vec<String>,
    /// Where the fingertips are: the table of the issue, with intervals.
    pub tips: Vec<LiteratureTipRow>,
    pub tip_finding: String,
    /// One sentence per finger: the evidence.
    pub tip_evidence: Vec<String>,
    /// What it changes for a rig audit.
    pub audit: String,
    /// The correlation assumed between the table's segments, and the verdicts at 0 and 0.9.
    pub correlation: String,
    /// The paper beside the table to the skin, the atlas beside it to the bone.
    pub side: Vec<LiteratureSideRow>,
    pub side_intro: String,
    /// One sentence per finger of the paper against the table.
    pub sentences: Vec<String>,
    pub notes: Vec<String>,
}

/// One finger's last segment: the paper's, the table's bone only and bone plus soft tissue.
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureTipRow {
    pub finger: String,
    pub paper: String,
    pub bone: String,
    pub skin: String,
    /// "bone plus soft tissue (tip at the skin)".
    pub fits: String,
    /// The fit at each correlation: "0: skin; 0.85: skin; 0.9: skin".
    pub sweep: String,
}

/// One finger and quantity: the paper and the table to the skin, the atlas and the table
/// to the bone, with the verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureSideRow {
    pub finger: String,
    pub quantity: String,
    pub paper: String,
    pub table_skin: String,
    /// The verdict at 0, the assumed correlation and 0.9.
    pub paper_verdict: String,
    pub atlas: String,
    pub table_bone: String,
    pub atlas_verdict: String,
}

/// The section "The paper against published measurements".
fn literature_view(l: &LiteratureInputs) -> LiteratureView {
    use super::compare_table::{
        Profile, correlation_line, differs_in, estimate_cell, fit_words, table_finger_sentence,
        tip_finding_sentence, tip_overall, trim_rho, verdict_cell,
    };
    use super::compare_words::{Names, short};
    let p = &l.paper;
    let name = table_name(&p.b);
    let names = Names {
        a: "the paper",
        b: &name,
    };
    let about = p.b.about.clone().unwrap_or_default();
    let source = format!(
        "{}: {}. What was measured: {}.",
        about.citation.clone().unwrap_or_else(|| p.b.path.clone()),
        about
            .sample
            .clone()
            .unwrap_or_else(|| "sample not described".to_string()),
        about
            .landmarks
            .clone()
            .unwrap_or_else(|| "not described".to_string()),
    );
    let paper_profile = Profile::of_side(&p.a);
    let table_profile = Profile::of_side(&crate::analysis::literature::SideInfo {
        table_tip: None,
        ..p.b.clone()
    });
    let mut cohorts = vec![format!(
        "{name} differs from the paper in {}.",
        differs_in(&paper_profile, &table_profile)
    )];
    if let Some(info) = &l.atlas_info {
        cohorts.push(format!(
            "{} differs from the paper in {}.",
            info.about
                .as_ref()
                .and_then(|a| a.name.clone())
                .map(|n| {
                    let mut c = n.chars();
                    c.next().map_or(String::new(), |f| {
                        f.to_uppercase().collect::<String>() + c.as_str()
                    })
                })
                .unwrap_or_else(|| "The atlas".to_string()),
            differs_in(&paper_profile, &Profile::of_data(info))
        ));
    }
    let conf = level(p.confidence);
    let (tips, tip_finding, tip_evidence) = match &p.tips {
        Some(v) => (
            v.fingers
                .iter()
                .map(|t| LiteratureTipRow {
                    finger: format!("{} {}", t.finger.name(), t.quantity.symbol()),
                    paper: estimate_cell(&t.data, t.quantity),
                    bone: estimate_cell(&t.bone, t.quantity),
                    skin: estimate_cell(&t.skin, t.quantity),
                    fits: fit_words(t.fit).to_string(),
                    sweep: t
                        .sweep
                        .iter()
                        .map(|(r, f)| {
                            format!(
                                "{}: {}",
                                trim_rho(*r),
                                f.and_then(|f| f.tip()).map_or("n/a", |t| t.name())
                            )
                        })
                        .collect::<Vec<_>>()
                        .join("; "),
                })
                .collect(),
            tip_overall(v, names),
            v.fingers
                .iter()
                .map(|t| tip_finding_sentence(t, names, p.confidence))
                .chain(std::iter::once(format!(
                    "Each difference is {name}'s ratio minus the paper's mean, with its {conf} Welch-type interval (both uncertainties): a tip is rejected when that interval excludes 0, and not rejected when it holds 0, which at {} is not a finding that the two are equal.",
                    xrays(p.a.n.unwrap_or(0))
                )))
                .collect(),
        ),
        None => (
            Vec::new(),
            format!("{name} gives no fingertip soft tissue, so the paper's tips cannot be placed."),
            Vec::new(),
        ),
    };
    let soft: Vec<String> = p
        .tips
        .iter()
        .flat_map(|v| &v.fingers)
        .map(|t| format!("{} {}", t.finger.name(), percent(t.soft_share)))
        .collect();
    let audit = format!(
        "What it changes for a rig audit: the paper's last segment is taken to end at the skin, so a rig's last segment is compared with it as it is when the rig's tips are at the skin (the end of the finger's mesh), and no soft tissue is to be trimmed off. A rig whose tips sit at the end of the bone needs the fingertip's soft tissue added before it is compared: {name} measures it at {} of a finger measured to the skin, a share that scales with the rig's finger in any unit. A fixed offset in millimetres does not: a rig in the wrong unit would lose most of a segment to it. The audits of section 13 follow this: they read each dataset's tips from its tip column, compare skin tips with skin tips as they are, and where one side's tips are at the bone (the atlas's, for the MCP judged from its CMC or the wrist) correct the last segment by that finger's share.",
        soft.join(", ")
    );
    let mut side = Vec::new();
    for f in &p.fingers {
        let atlas_f = l
            .atlas
            .as_ref()
            .and_then(|a| a.fingers.iter().find(|g| g.finger == f.finger));
        for q in &f.quantities {
            let aq = atlas_f.and_then(|g| g.quantities.iter().find(|x| x.quantity == q.quantity));
            side.push(LiteratureSideRow {
                finger: f.finger.name().to_string(),
                quantity: short(q.quantity).to_string(),
                paper: estimate_cell(&q.a, q.quantity),
                table_skin: estimate_cell(&q.b, q.quantity),
                paper_verdict: verdict_cell(&q.sweep),
                atlas: aq.map_or("n/a".into(), |x| estimate_cell(&x.a, q.quantity)),
                table_bone: aq.map_or("n/a".into(), |x| estimate_cell(&x.b, q.quantity)),
                atlas_verdict: aq.map_or("n/a".into(), |x| verdict_cell(&x.sweep)),
            });
        }
    }
    let tip_word = match p.b.table_tip {
        Some(crate::dataset::TipKind::Skin) => {
            "to the skin (its soft tissue added), as the paper's rows record skin tips"
        }
        _ => "to the end of the bone",
    };
    let side_intro = format!(
        "Each cohort beside {name} measured to the same fingertip: the paper's X-rays (mean and {conf} t interval) against {name}'s ratios of means {tip_word}; the atlas (bone tips) against {name} to the bone. A verdict says whether the {conf} interval of the difference excludes 0 (differs) or holds it (not rejected: no difference shown, which is not equality shown), the same at correlations 0, the assumed one and 0.9 unless each is named."
    );
    LiteratureView {
        title: "The paper against published measurements".to_string(),
        anchor: "12-the-paper-against-published-measurements".to_string(),
        source,
        cohorts,
        tips,
        tip_finding,
        tip_evidence,
        audit,
        correlation: correlation_line(&p.correlation),
        side,
        side_intro,
        sentences: p
            .fingers
            .iter()
            .map(|f| table_finger_sentence(f, names))
            .collect(),
        notes: p.notes.clone(),
    }
}

/// The comparison rows of every finger and quantity, the external-validity rows of the
/// relative ones, and how many atlas values lie inside the paper's prediction interval (of how
/// many tested).
fn atlas_comparison(
    c: &crate::analysis::compare::Cohorts,
) -> (Vec<AtlasCompareRow>, Vec<AtlasExternalRow>, (usize, usize)) {
    use super::compare::{
        bootstrap_cell, coverage_cell, difference_cell, hedges_cell, mean_sd, welch_cell,
    };
    use super::compare_words::short;
    let d = |q: Quantity| decimals(q.is_unitless());
    let mut comparison = Vec::new();
    let mut external = Vec::new();
    let (mut inside, mut tested) = (0usize, 0usize);
    for f in &c.fingers {
        for qc in &f.quantities {
            let (q, cmp) = (qc.quantity, &qc.comparison);
            comparison.push(AtlasCompareRow {
                finger: f.finger.name().to_string(),
                quantity: short(q).to_string(),
                paper: mean_sd(cmp.a.mean, cmp.a.sd, q),
                atlas: mean_sd(cmp.b.mean, cmp.b.sd, q),
                difference: difference_cell(cmp, q),
                welch: welch_cell(cmp, q),
                bootstrap: bootstrap_cell(cmp, q),
                hedges: hedges_cell(cmp),
            });
            if q.is_relative() {
                if let Some(e) = &cmp.b_in_a {
                    inside += e.inside;
                    tested += e.of;
                }
                external.push(AtlasExternalRow {
                    finger: f.finger.name().to_string(),
                    quantity: short(q).to_string(),
                    paper_pi: crate::format::interval(cmp.b_in_a.map(|e| e.interval), d(q)),
                    atlas_in_paper: coverage_cell(cmp.b_in_a.as_ref()),
                    atlas_pi: crate::format::interval(cmp.a_in_b.map(|e| e.interval), d(q)),
                    paper_in_atlas: coverage_cell(cmp.a_in_b.as_ref()),
                });
            }
        }
    }
    (comparison, external, (inside, tested))
}

/// One sentence per finger, then one per finger's last segment (the tip).
fn atlas_sentences(c: &crate::analysis::compare::Cohorts, confidence: f64) -> Vec<String> {
    use super::compare::{finger_sentence, tip_sentence};
    use super::compare_words::Names;
    let names = Names {
        a: "the paper",
        b: "the atlas",
    };
    let mut sentences: Vec<String> = c
        .fingers
        .iter()
        .map(|f| finger_sentence(f, names, confidence))
        .collect();
    for f in &c.fingers {
        if let Some(last) = &f.last_segment {
            sentences.push(format!(
                "{}: {}",
                f.finger.name(),
                tip_sentence(last, c, names)
            ));
        }
    }
    sentences
}

/// The text above the coverage on real hands: what was drawn and the Monte-Carlo SE.
fn atlas_population_intro(p: &PopulationStudy, confidence: f64) -> String {
    let xrays = p.quantities.first().map_or(0, |q| q.population);
    format!(
        "The atlas taken as the population of hands ({xrays} X-rays): {} samples of each size n drawn from its X-rays with replacement, every interval built as the statistics build it, and counted when it holds the atlas's mean (the prediction interval: one further atlas X-ray). Each figure is the mean over the {} relative values; beside it, the normal model's figure. Monte-Carlo SE about {} per value at {}.",
        p.settings.sims,
        p.quantities.len(),
        percent((confidence * (1.0 - confidence) / p.settings.sims.max(1) as f64).sqrt()),
        level(confidence),
    )
}

/// Per sample size, the coverage on atlas hands and, below it, the normal model's.
fn atlas_population(p: &PopulationStudy) -> Vec<AtlasPopulationRow> {
    pooled_rows(p)
        .into_iter()
        .map(|r| {
            let [t, percentile, bca, prediction] = r.cells;
            let (n, model) = if r.normal {
                (String::new(), "normal model")
            } else {
                (r.n.to_string(), "atlas hands")
            };
            AtlasPopulationRow {
                n,
                model: model.to_string(),
                t,
                percentile,
                bca,
                prediction,
                bootstrap: r.bootstrap,
            }
        })
        .collect()
}

/// One row of a pooled coverage table: at one sample size, the coverage on the
/// population's hands (each method's mean over the quantities), or the normal model's
/// coverage in the row beneath it.
pub(crate) struct PooledRow {
    pub n: usize,
    /// The normal model's row, beneath its size's row of real hands.
    pub normal: bool,
    /// t, percentile, BCa and prediction as percentages ("n/a" where none was measured).
    pub cells: [String; 4],
    /// The bootstrap at this size ("exact (126)", "random (10000)"; empty when unknown).
    pub bootstrap: String,
}

/// The pooled coverage rows of a population study, per size in order: the real hands'
/// row, then the normal model's when it was simulated at that size.
pub(crate) fn pooled_rows(p: &PopulationStudy) -> Vec<PooledRow> {
    const METHODS: [&str; 4] = ["t", "percentile", "bca", "prediction"];
    let pooled = p.pooled();
    let mut rows = Vec::new();
    for (k, &n) in p.sizes.iter().enumerate() {
        let bootstrap = p
            .normal
            .get(k)
            .map_or_else(String::new, |c| plan_short(c.bootstrap));
        rows.push(PooledRow {
            n,
            normal: false,
            cells: METHODS.map(|m| {
                pooled
                    .iter()
                    .find(|x| x.n == n && x.method == m)
                    .map_or_else(|| "n/a".to_string(), |x| percent(x.mean))
            }),
            bootstrap: bootstrap.clone(),
        });
        if let Some(normal) = p.normal.iter().find(|c| c.n == n) {
            rows.push(PooledRow {
                n,
                normal: true,
                cells: METHODS.map(|m| {
                    normal
                        .methods
                        .iter()
                        .find(|x| x.method == m)
                        .map_or_else(|| "n/a".to_string(), |x| percent(x.coverage))
                }),
                bootstrap,
            });
        }
    }
    rows
}

/// Each finger's mc/J and J1/mc over the atlas's X-rays (fingers without both are left out).
fn atlas_proportions(analysis: &Analysis) -> Vec<AtlasProportionRow> {
    use super::compare::mean_sd;
    let mut proportions = Vec::new();
    for f in &analysis.fingers {
        let get = |q: Quantity| f.quantities.iter().find(|s| s.name == q);
        let (Some(mc_j), Some(j1_mc)) = (get(Quantity::RatioMcJ), get(Quantity::RatioJ1Mc)) else {
            continue;
        };
        proportions.push(AtlasProportionRow {
            finger: f.finger.name().to_string(),
            n: mc_j.n.to_string(),
            mc_j: mean_sd(mc_j.mean, mc_j.sd, Quantity::RatioMcJ),
            mc_j_pi: crate::format::interval(mc_j.intervals.pi, 4),
            j1_mc: mean_sd(j1_mc.mean, j1_mc.sd, Quantity::RatioJ1Mc),
            j1_mc_pi: crate::format::interval(j1_mc.intervals.pi, 4),
        });
    }
    proportions
}

/// "exact (126)", "random (200)".
fn plan_short(p: Plan) -> String {
    match p {
        Plan::Exact { distinct } => format!("exact ({distinct})"),
        Plan::Random { resamples } => format!("random ({resamples})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use std::path::Path;

    /// The X-rays-needed rows with the atlas beside them: the headline on the SD's upper
    /// limit, the atlas's larger SD on the same basis (figures from
    /// tests/independent/xrays_needed.txt), nothing where the atlas's SD is smaller.
    #[test]
    fn needed_rows_name_the_atlas_where_its_sd_is_larger() {
        let Ok(atlas) = Dataset::load(Path::new("data/atlas/measurements.csv")) else {
            println!("skipped: data/atlas/measurements.csv could not be read");
            return;
        };
        let paper = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        let a = analyse(&paper, &Settings::default());
        let atlas = analyse(&atlas, &Settings::default());
        let rows = needed_rows(&a, Some(&atlas), 0.005);
        let row = |finger: &str, q: &str| {
            rows.iter()
                .find(|r| r.finger.starts_with(finger) && r.quantity.starts_with(q))
                .unwrap()
        };
        let j2 = row("index", "J~2");
        assert_eq!(
            (
                j2.sd.as_str(),
                j2.sd_upper.as_str(),
                j2.needed.as_str(),
                j2.more.as_str(),
                j2.other.as_str(),
                j2.plug_in.as_str()
            ),
            ("0.0039", "0.0113", "27", "22 more", "SD 0.0092: 21", "5")
        );
        assert_eq!(row("ring", "J~1").other, "SD 0.0103: 25");
        assert_eq!(row("thumb", "J~1").other, "SD 0.0182: 67");
        // The atlas's index J~1 SD (0.0111) is below the paper's (0.0131): nothing beside.
        assert_eq!(row("index", "J~1").other, "");
        assert!(
            needed_rows(&a, None, 0.005)
                .iter()
                .all(|r| r.other.is_empty())
        );
    }
}
