//! JSON documents: the documented machine interface (`schema_version` 6).

use crate::analysis::claims::{CheckSummary, ClaimResult};
use crate::analysis::coverage::{CoverageSettings, QuantityCoverage};
use crate::analysis::groups::{Group, GroupSummary, Groups};
use crate::analysis::{Analysis, DatasetInfo, FingerAnalysis, Quantity, Settings};
use crate::dataset::Finger;
use crate::dataset::history::{Event, QuantityRecord, Snapshot};
use crate::error::Error;
use crate::stats::rng;
use schemars::JsonSchema;
use serde::Serialize;

/// Version of every JSON document phalanx writes; bumped whenever a field is
/// added or a field's meaning changes. 2: the audit's bend guard (`held`,
/// the moves not made). 3: a tipless finger's tip from the mesh
/// (`skin_tip.from_mesh`): such a finger is judged on relative values, with
/// `has_tip` false (the chain's) and `audit.has_tip` true (as judged); and
/// `held.reason` `base`, an MCP its ray's base puts in range. 4: a finger
/// with a tip is judged in the joint region of its relative joint positions
/// (`audit.region`); `explanation.consistent` and `explanation.score` are read
/// against that region, and the joints' and values' own standings stay as the
/// rig is, each alone. 5: the fix carries the skin's weights with its joints
/// (a moved bend's `reweighted`, `held.reason` `carry`), and `rig`'s document.
/// 6: a joint's `moves` is `explains` (the explanation moves it), and `fix`
/// says whether the fix moves it; the fix's `written` is false when it moves
/// no joint and writes no file.
pub const SCHEMA_VERSION: u32 = 6;

/// The settings block of every JSON document.
#[derive(Serialize, JsonSchema)]
pub(crate) struct SettingsView<'a> {
    pub resamples: usize,
    pub seed: u64,
    pub confidence: f64,
    pub rng: &'a str,
    pub phalanx_version: &'a str,
}

impl SettingsView<'static> {
    /// The settings block for analysis settings.
    pub(crate) fn of(s: &Settings) -> Self {
        SettingsView {
            resamples: s.resamples,
            seed: s.seed,
            confidence: s.confidence,
            rng: rng::RNG_NAME,
            phalanx_version: env!("CARGO_PKG_VERSION"),
        }
    }
}

/// The statistics document: `phalanx stats --format json` and `reports/stats.json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct StatsDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    dataset: &'a DatasetInfo,
    settings: SettingsView<'static>,
    fingers: &'a [FingerAnalysis],
    /// Rows added though flagged as likely errors (`add --accept-flagged`), in file order.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    flagged: &'a [crate::analysis::FlaggedRow],
    #[serde(skip_serializing_if = "Option::is_none")]
    groups: Option<GroupsDocument<'a>>,
}

/// Statistics per group (`--group-by`).
#[derive(Serialize, JsonSchema)]
struct GroupsDocument<'a> {
    by: &'a str,
    /// Known groups first, "unknown" last.
    groups: Vec<GroupSummary<'a>>,
    /// Each known group after the first against the first (differences b - a), as
    /// `phalanx compare` compares two cohorts.
    differences: Vec<GroupDifferenceDocument<'a>>,
}

/// One known group against the reference group.
#[derive(Serialize, JsonSchema)]
struct GroupDifferenceDocument<'a> {
    /// The reference group.
    a: &'a str,
    /// The group compared with it.
    b: &'a str,
    fingers: &'a [crate::analysis::compare::FingerComparison],
    notes: &'a [String],
}

fn to_bytes(value: &impl Serialize) -> Result<Vec<u8>, Error> {
    let mut out =
        serde_json::to_vec_pretty(value).map_err(|e| Error::render("cannot serialise JSON", e))?;
    out.push(b'\n');
    Ok(out)
}

/// The statistics document of `phalanx stats --format json` and `reports/stats.json`;
/// with `groups` (from `--group-by`) it gains a `groups` key.
pub fn stats(a: &Analysis, groups: Option<&Groups>) -> Result<Vec<u8>, Error> {
    let mut out = Vec::new();
    write_stats(&mut out, a, groups)?;
    Ok(out)
}

/// Writes the statistics document to `w` as it is serialised (no copy in
/// memory: the document of 100,000 X-rays is over 100 MB).
pub fn write_stats(
    w: impl std::io::Write,
    a: &Analysis,
    groups: Option<&Groups>,
) -> Result<(), Error> {
    let mut w = std::io::BufWriter::new(w);
    let doc = StatsDocument {
        schema_version: SCHEMA_VERSION,
        dataset: &a.dataset,
        settings: SettingsView::of(&a.settings),
        fingers: &a.fingers,
        flagged: &a.flagged,
        groups: groups.map(|g| GroupsDocument {
            by: g.by,
            groups: g.groups.iter().map(Group::summary).collect(),
            differences: g
                .differences
                .iter()
                .map(|d| GroupDifferenceDocument {
                    a: &d.a,
                    b: &d.b,
                    fingers: &d.cohorts.fingers,
                    notes: &d.cohorts.notes,
                })
                .collect(),
        }),
    };
    serde_json::to_writer_pretty(&mut w, &doc)
        .map_err(|e| Error::render("cannot write the JSON statistics", e))?;
    std::io::Write::write_all(&mut w, b"\n")
        .and_then(|_| std::io::Write::flush(&mut w))
        .map_err(|e| Error::render("cannot write the JSON statistics", e))
}

/// The claims check: `phalanx check --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct CheckDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    dataset: &'a DatasetInfo,
    claims_file: &'a str,
    summary: CheckSummary,
    claims: &'a [ClaimResult],
}

/// The document of `phalanx check --format json`.
pub fn check(
    dataset: &DatasetInfo,
    claims_file: &str,
    results: &[ClaimResult],
) -> Result<Vec<u8>, Error> {
    to_bytes(&CheckDocument {
        schema_version: SCHEMA_VERSION,
        dataset,
        claims_file,
        summary: CheckSummary::of(results),
        claims: results,
    })
}

/// The simulated coverage of the intervals: `phalanx coverage --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct CoverageDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    dataset: &'a DatasetInfo,
    settings: &'a CoverageSettings,
    rng: &'a str,
    model: &'a str,
    quantities: &'a [QuantityCoverage],
}

/// What the coverage simulation assumes, for outputs.
pub(crate) const COVERAGE_MODEL: &str = "normal model N(mean, sd^2) fitted to each quantity; n values drawn per simulated dataset; confidence intervals checked against the model mean, the prediction interval against one further draw";

/// The document of `phalanx coverage --format json`.
pub fn coverage(
    dataset: &DatasetInfo,
    s: &CoverageSettings,
    q: &[QuantityCoverage],
) -> Result<Vec<u8>, Error> {
    to_bytes(&CoverageDocument {
        schema_version: SCHEMA_VERSION,
        dataset,
        settings: s,
        rng: rng::RNG_NAME,
        model: COVERAGE_MODEL,
        quantities: q,
    })
}

/// The values of one finger's quantity over the snapshots.
#[derive(Serialize, JsonSchema)]
struct HistorySeries<'a> {
    finger: Finger,
    quantity: Quantity,
    points: Vec<HistoryPoint<'a>>,
}

/// One snapshot's statistics of a quantity.
#[derive(Serialize, JsonSchema)]
struct HistoryPoint<'a> {
    snapshot: usize,
    time: &'a str,
    event: Event,
    sha256: &'a str,
    record: &'a QuantityRecord,
}

/// The statistics over time: `phalanx history --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct HistoryDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    /// Snapshots in the history file.
    snapshots: usize,
    /// Every record: what made it and what it changed.
    records: Vec<HistoryRecordView<'a>>,
    /// One series per finger and quantity.
    series: Vec<HistorySeries<'a>>,
}

/// One record of the history, without its statistics (those are in the series).
#[derive(Serialize, JsonSchema)]
pub(crate) struct HistoryRecordView<'a> {
    /// 1-based position in the history file.
    record: usize,
    time: &'a str,
    event: Event,
    sha256: &'a str,
    xrays: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    change: Option<&'a crate::dataset::history::ChangeRecord>,
    #[serde(skip_serializing_if = "Option::is_none")]
    note: Option<&'a str>,
}

/// The document of `phalanx history --format json`: one series per finger and quantity.
pub fn history(
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
) -> Result<Vec<u8>, Error> {
    let keys = crate::analysis::tracking::selected(snaps, finger, quantity);
    let series: Vec<HistorySeries<'_>> = keys
        .iter()
        .map(|(f, q)| HistorySeries {
            finger: *f,
            quantity: *q,
            points: snaps
                .iter()
                .enumerate()
                .filter_map(|(i, s)| {
                    let record = s
                        .quantities
                        .iter()
                        .find(|r| &r.finger == f && &r.quantity == q)?;
                    Some(HistoryPoint {
                        snapshot: i + 1,
                        time: &s.time,
                        event: s.event,
                        sha256: &s.sha256,
                        record,
                    })
                })
                .collect(),
        })
        .collect();
    to_bytes(&HistoryDocument {
        schema_version: SCHEMA_VERSION,
        snapshots: snaps.len(),
        records: snaps
            .iter()
            .enumerate()
            .map(|(i, s)| HistoryRecordView {
                record: i + 1,
                time: &s.time,
                event: s.event,
                sha256: &s.sha256,
                xrays: s.xrays,
                change: s.change.as_ref(),
                note: s.note.as_deref(),
            })
            .collect(),
        series,
    })
}

/// Joint positions for model fingers: `phalanx place --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct PlacementDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    dataset: &'a DatasetInfo,
    settings: SettingsView<'static>,
    placements: &'a [crate::analysis::placement::FingerPlacement],
}

/// The document of `phalanx place --format json`.
pub fn placement(
    a: &Analysis,
    ps: &[crate::analysis::placement::FingerPlacement],
) -> Result<Vec<u8>, Error> {
    to_bytes(&PlacementDocument {
        schema_version: SCHEMA_VERSION,
        dataset: &a.dataset,
        settings: SettingsView::of(&a.settings),
        placements: ps,
    })
}

/// Joints placed from a summary table: `phalanx place --reference TABLE --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct TablePlacementDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    /// The table's path and SHA-256.
    reference: &'a str,
    sha256: &'a str,
    confidence: f64,
    /// The correlation assumed between the table's segments, in words.
    correlation_assumption: String,
    correlation: &'a crate::analysis::literature::Correlation,
    placements: &'a [crate::analysis::placement::TablePlacement],
}

/// The document of `phalanx place --reference TABLE --format json`.
pub fn table_placement(
    table: &crate::dataset::SummaryTable,
    correlation: &crate::analysis::literature::Correlation,
    confidence: f64,
    ps: &[crate::analysis::placement::TablePlacement],
) -> Result<Vec<u8>, Error> {
    to_bytes(&TablePlacementDocument {
        schema_version: SCHEMA_VERSION,
        reference: &table.path,
        sha256: &table.sha256,
        confidence,
        correlation_assumption: super::compare_table::correlation_line(correlation),
        correlation,
        placements: ps,
    })
}

/// What `audit --fix` did, for the audit document.
#[derive(Serialize, JsonSchema)]
pub struct FixView<'a> {
    pub output: &'a str,
    /// False when the fix moves no joint: no file is written.
    pub written: bool,
    /// Moved joints: node name and distance moved, in rig units.
    pub moved: Vec<MovedView<'a>>,
    pub warnings: &'a [String],
    /// Every moved joint's distance to where its skin bends, before the fix
    /// and after it (the written copy, judged again).
    pub bends: Vec<MovedBendView<'a>>,
    /// Joints the re-audit flags as far from their bend that the rig as given did not.
    pub new_bend_defects: &'a [String],
    /// Every finger with a moved joint, judged again from the written copy.
    pub fingers: Vec<MovedFingerView<'a>>,
}

/// A finger the fix moved, as the re-audit judges it.
#[derive(Serialize, JsonSchema)]
pub struct MovedFingerView<'a> {
    /// The finger, as "right index".
    pub finger: &'a str,
    /// T^2 of its relative joint positions after the fix (null: judged on J2/J1).
    pub t2: Option<f64>,
    /// The region's bound (null: judged on J2/J1).
    pub bound: Option<f64>,
    /// Inside the region (or J2/J1's prediction interval) after the fix.
    pub inside: bool,
}

/// A moved joint's distance to where its skin bends, in rig units (`null`: no bend found).
#[derive(Serialize, JsonSchema)]
pub struct MovedBendView<'a> {
    pub node: &'a str,
    /// The joint, as "right index PIP".
    pub joint: &'a str,
    pub before: Option<f64>,
    pub after: Option<f64>,
    /// Vertices whose weights the fix changed, nearest this joint (0: the
    /// weights stay as painted).
    pub reweighted: usize,
}

/// One moved joint.
#[derive(Serialize, JsonSchema)]
pub struct MovedView<'a> {
    pub node: &'a str,
    pub shift: f64,
}

/// A rig's finger joints judged against the X-rays: `phalanx audit --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct AuditDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    dataset: &'a DatasetInfo,
    settings: SettingsView<'static>,
    /// Units of every length and position: "m".
    units: &'static str,
    /// What the rig file was when it was FBX, read as glTF in metres and +Y up.
    #[serde(skip_serializing_if = "Option::is_none")]
    fbx: Option<FbxView<'a>>,
    rig: &'a crate::rig::AuditedRig,
    /// Fingers with a joint or value outside the prediction interval.
    fingers_outside: usize,
    /// What to bear in mind, the last on the data's fingertips: what the audit took them
    /// as when their tip column does not record one kind, and that the verdicts rest on it.
    caveats: Vec<String>,
    /// What `--fix` did (only with `--fix`).
    #[serde(skip_serializing_if = "Option::is_none")]
    fix: Option<FixView<'a>>,
}

/// An FBX rig file, for the audit document: what it was before it was
/// converted to metres and +Y up.
#[derive(Serialize, JsonSchema)]
pub(crate) struct FbxView<'a> {
    /// The FBX version (7500 for 7.5).
    version: u32,
    /// "binary" or "ascii".
    encoding: &'static str,
    /// Metres per file unit (the file's UnitScaleFactor / 100).
    unit_m: f64,
    /// The file's axes, as "-X right, +Y up, -Z front".
    axes: &'a str,
}

/// The audit document of a rig session, with what the fix did.
pub fn audit(audit: &crate::rig::session::Audit) -> Result<Vec<u8>, Error> {
    let fix = audit.fix.as_ref().map(|fix| FixView {
        output: fix.output.to_str().unwrap_or("(non-UTF-8 path)"),
        written: fix.written,
        moved: fix
            .moved
            .iter()
            .map(|(node, shift)| MovedView {
                node,
                shift: *shift,
            })
            .collect(),
        warnings: &fix.warnings,
        bends: fix
            .bends
            .iter()
            .map(|b| MovedBendView {
                node: &b.node,
                joint: &b.joint,
                before: b.before,
                after: b.after,
                reweighted: b.reweighted,
            })
            .collect(),
        new_bend_defects: &fix.new_defects,
        fingers: fix
            .fingers
            .iter()
            .map(|f| MovedFingerView {
                finger: &f.label,
                t2: f.t2.map(|t| t.0),
                bound: f.t2.map(|t| t.1),
                inside: f.inside,
            })
            .collect(),
    });
    audit_document(&audit.analysis, &audit.rig, audit.fbx.as_ref(), fix)
}

/// The document of `phalanx audit --format json`.
fn audit_document(
    a: &Analysis,
    rig: &crate::rig::AuditedRig,
    fbx: Option<&crate::rig::read::source::FbxSource>,
    fix: Option<FixView<'_>>,
) -> Result<Vec<u8>, Error> {
    to_bytes(&AuditDocument {
        schema_version: SCHEMA_VERSION,
        dataset: &a.dataset,
        settings: SettingsView::of(&a.settings),
        units: "m",
        fbx: fbx.map(|s| FbxView {
            version: s.version,
            encoding: if s.ascii { "ascii" } else { "binary" },
            unit_m: s.unit_meters,
            axes: &s.axes,
        }),
        rig,
        fingers_outside: rig.outside(),
        caveats: super::audit::caveats(&rig.tips, &a.dataset.path),
        fix,
    })
}

/// Two cohorts compared: `phalanx compare A B --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct CompareDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    settings: SettingsView<'static>,
    /// How the statistics are defined, in words.
    method: &'static str,
    a: &'a crate::analysis::compare::CohortInfo,
    b: &'a crate::analysis::compare::CohortInfo,
    fingers: Vec<CompareFinger<'a>>,
    notes: &'a [String],
}

/// One finger of the comparison document, with its sentence.
#[derive(Serialize, JsonSchema)]
struct CompareFinger<'a> {
    #[serde(flatten)]
    comparison: &'a crate::analysis::compare::FingerComparison,
    summary: String,
}

/// What the comparison document's numbers are.
pub const COMPARE_METHOD: &str = "differences are B - A; Welch t interval of the difference of means (Welch-Satterthwaite df); percentile bootstrap interval with each cohort's X-rays resampled on its own; Hedges' g with the Hedges-Olkin large-sample interval; b_in_a: B's X-rays inside A's prediction interval for one new X-ray, a_in_b the reverse; last_segment: the fingertip offset d that would explain the last segment's difference, share_of_a = d over the length to the skin tip, share_of_bone = d over the length to the bone tip";

/// The document of `phalanx compare --format json`: every statistic of every finger and
/// quantity, and the sentence of each finger.
pub fn compare(c: &crate::analysis::compare::Cohorts) -> Result<Vec<u8>, Error> {
    let names = super::compare_words::Names::AB;
    to_bytes(&CompareDocument {
        schema_version: SCHEMA_VERSION,
        settings: SettingsView::of(&c.settings),
        method: COMPARE_METHOD,
        a: &c.a,
        b: &c.b,
        fingers: c
            .fingers
            .iter()
            .map(|f| CompareFinger {
                comparison: f,
                summary: super::compare::finger_sentence(f, names, c.settings.confidence),
            })
            .collect(),
        notes: &c.notes,
    })
}

/// A cohort compared with a summary table: `phalanx compare A TABLE --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct TableCompareDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    /// How the statistics are defined, in words.
    method: &'static str,
    /// The overall sentence, then one per finger.
    conclusion: Vec<String>,
    /// The correlation assumed between the table's segments, in words.
    correlation_assumption: String,
    #[serde(flatten)]
    cohorts: &'a crate::analysis::literature::TableCohorts,
}

/// What the table comparison's numbers are.
pub const TABLE_COMPARE_METHOD: &str = "differences are B - A; a dataset's estimate is its mean over X-rays with the t interval (SE = SD / sqrt(n)); a summary table's is the ratio of its means with a delta-method SE under the stated correlation between segments and a t interval on n - 1 df (n: the smallest n of the segments used), and the prediction interval from the first-order SD of one hand's ratio; the interval of B - A is Welch-type (SE = sqrt(SE_A^2 + SE_B^2), Welch-Satterthwaite df); not_rejected: that interval holds 0 (equal means not rejected, which is not equality shown; false: it excludes 0, the two differ); untestable: the quantities without an interval, and how many point values of the side without one lie outside the other side's t interval; sweep: the same at correlations 0, the assumed one and 0.9; tips: the data's last segment against the table's to the bone and to the skin (soft tissue added to the distal phalanx and to the finger), fit: which of the two is not rejected while the other is";

/// The document of `phalanx compare A TABLE --format json`.
pub fn compare_table(c: &crate::analysis::literature::TableCohorts) -> Result<Vec<u8>, Error> {
    let names = super::compare_words::Names::AB;
    let mut conclusion = vec![super::compare_table::table_overall(c, names)];
    conclusion.extend(
        c.fingers
            .iter()
            .map(|f| super::compare_table::table_finger_sentence(f, names)),
    );
    to_bytes(&TableCompareDocument {
        schema_version: SCHEMA_VERSION,
        method: TABLE_COMPARE_METHOD,
        conclusion,
        correlation_assumption: super::compare_table::correlation_line(&c.correlation),
        cohorts: c,
    })
}

/// What the population simulation does, for outputs.
pub const POPULATION_MODEL: &str = "the dataset is the population of hands: samples of n X-rays drawn with replacement, one further X-ray drawn for the prediction interval; quantities of the same X-rays share each sample and its bootstrap; confidence intervals checked against the population mean; the normal model (coverage depends on n alone) beside it";

/// Coverage measured on a real population of hands:
/// `phalanx coverage --population DATASET --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct PopulationDocument<'a> {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    /// The dataset taken as the population.
    population: &'a str,
    rng: &'a str,
    /// What the simulation does, in words.
    model: &'a str,
    #[serde(flatten)]
    study: &'a crate::analysis::population::PopulationStudy,
    /// Each method's coverage per sample size over the quantities (mean, min, max).
    pooled: Vec<crate::analysis::population::Pooled>,
}

/// The document of `phalanx coverage --population DATASET --format json`.
pub fn population(
    path: &str,
    study: &crate::analysis::population::PopulationStudy,
) -> Result<Vec<u8>, Error> {
    to_bytes(&PopulationDocument {
        schema_version: SCHEMA_VERSION,
        population: path,
        rng: rng::RNG_NAME,
        model: POPULATION_MODEL,
        study,
        pooled: study.pooled(),
    })
}
