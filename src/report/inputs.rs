//! The report's inputs gathered as `phalanx report` gathers them: the claims
//! checked, the reference rigs judged, the coverage simulated, the atlas and
//! the published table compared, and the parts on real rigs (audited, fixed,
//! deformed and rigged again in memory), from the paths and the analysis given.

use super::deform as deform_view;
use super::view::{
    AtlasInputs, DeformSection, LiteratureInputs, MadeSection, ReferenceAudit, ReportInputs,
};
use crate::analysis::claims::{self, ClaimResult};
use crate::analysis::coverage::{self, CoverageSettings, CurvePoint};
use crate::analysis::groups::Groups;
use crate::analysis::placement::{self, FingerPlacement};
use crate::analysis::region::ShapePriors;
use crate::analysis::region::calibration::{self, Cell, Setup};
use crate::analysis::{Analysis, Settings};
use crate::dataset::claims::Claims;
use crate::dataset::history::Snapshot;
use crate::dataset::{Dataset, Finger};
use crate::error::Error;
use crate::rig::deform::{Pose, Skinning};
use crate::rig::judge::{SoftTissue, WristRatios};
use crate::rig::reference::{self, ReferenceRig};
use crate::rig::session;
use crate::rig::{AuditOptions, AuditedRig};
use std::path::Path;

/// Sample sizes of the coverage measured on the atlas's hands.
const ATLAS_SIZES: [usize; 5] = [3, 5, 10, 20, 50];
/// Samples per size of that coverage, and the resamples of its random bootstraps (n of 8
/// and over): enough for a Monte-Carlo SE near 1% per value, cheap enough for a report.
/// `phalanx coverage --population` measures it with more.
const ATLAS_SIMS: usize = 500;
const ATLAS_RESAMPLES: usize = 200;

/// What the report is made from: the data and what is carried to the report as
/// it is, and the files the rest is computed from.
pub(crate) struct Request<'a> {
    pub dataset: Dataset,
    pub settings: Settings,
    /// The claims file of "Reproducing the paper".
    pub claims: &'a Path,
    /// Directory of reference rigs (`*.json`).
    pub rigs: &'a Path,
    /// The atlas's measurements; the wrist ratios are read beside them.
    pub atlas: &'a Path,
    /// A published summary table (its soft tissue, and "The paper against published measurements").
    pub literature: &'a Path,
    /// The rig audited and deformed, as it is and fixed.
    pub deform_rig: &'a Path,
    /// The rigged hand rigged again from its skin.
    pub made_rig: &'a Path,
    /// Simulated datasets for the coverage section.
    pub sims: usize,
    /// Whether the coverage curve is shown (HTML and Markdown only).
    pub show_coverage: bool,
    pub model_length: f64,
    pub groups: Option<Groups>,
    pub history_file: String,
    pub history: Vec<Snapshot>,
    pub since: Option<usize>,
    pub target: f64,
    pub timestamp: Option<String>,
}

/// Everything [`ReportInputs`] borrows, owned.
pub(crate) struct Gathered {
    analysis: Analysis,
    claims_file: String,
    claims: Vec<ClaimResult>,
    claims_note: Option<String>,
    coverage_settings: CoverageSettings,
    coverage: Vec<CurvePoint>,
    placements: Vec<FingerPlacement>,
    model_length: f64,
    timestamp: Option<String>,
    history_file: String,
    history: Vec<Snapshot>,
    since: Option<usize>,
    target: f64,
    groups: Option<Groups>,
    rigs: Vec<ReferenceAudit>,
    paper_xrays: (usize, usize),
    atlas: Option<AtlasInputs>,
    literature: Option<LiteratureInputs>,
    deform: Option<DeformSection>,
    made: Option<MadeSection>,
    shape: Option<ShapePriors>,
    calibration: Option<(Setup, Vec<Cell>)>,
}

impl Gathered {
    /// The inputs of [`super::render`].
    pub(crate) fn inputs(&self) -> ReportInputs<'_> {
        ReportInputs {
            analysis: &self.analysis,
            claims_file: &self.claims_file,
            claims: &self.claims,
            claims_note: self.claims_note.as_deref(),
            coverage_settings: &self.coverage_settings,
            coverage: &self.coverage,
            placements: &self.placements,
            model_length: self.model_length,
            timestamp: self.timestamp.clone(),
            history_file: &self.history_file,
            history: &self.history,
            since: self.since,
            target: self.target,
            groups: self.groups.as_ref(),
            rigs: &self.rigs,
            paper_xrays: self.paper_xrays,
            atlas: self.atlas.as_ref(),
            literature: self.literature.as_ref(),
            deform: self.deform.as_ref(),
            made: self.made.as_ref(),
            shape: self.shape.as_ref(),
            calibration: self.calibration.as_ref().map(|(s, c)| (s, c.as_slice())),
        }
    }
}

/// Gathers the report's inputs: files are read in the order their errors are
/// reported (claims, reference rigs, atlas), the coverage's cost is checked,
/// then `analyse` analyses the data (the command shows its progress), and the
/// rest is computed from it, independent parts side by side.
pub(crate) fn gather(
    req: Request<'_>,
    analyse: impl FnOnce(&Dataset) -> Result<Analysis, Error>,
) -> Result<Gathered, Error> {
    let settings = req.settings;
    let dataset = req.dataset;
    let claims = Claims::load(req.claims)?;
    let (results, claims_note) = check_claims(&claims, &dataset);
    let paper_xrays = claims.named_in(&dataset);
    let references = reference::load_dir(req.rigs)?;
    // The section compares the data's X-rays, the paper's or a lab's, with the atlas.
    let atlas_data = if req.atlas.exists() {
        Some(Dataset::load(req.atlas)?)
    } else {
        None
    };
    // The simulations' bootstraps take as many resamples as their printed coverage needs
    // (coverage::SIM_RESAMPLES, at every size, the data's own too), not the analysis's.
    let cov_settings = CoverageSettings {
        sims: req.sims,
        resamples: settings.resamples.min(coverage::SIM_RESAMPLES),
        max_n: Some(coverage::REPORT_MAX_N),
        ..atlas_coverage(&settings)
    };
    crate::analysis::budget::check_coverage(&dataset, &cov_settings, req.show_coverage)
        .map_err(Error::Usage)?;
    let a = analyse(&dataset)?;
    let paper_data = dataset;
    // The fingertip's soft tissue of the published table, for rigs whose tips differ from the data's.
    let soft_tissue = session::soft_tissue_from(req.literature)?;
    // The atlas, over any data, as `audit` and `rig` take their default
    // metacarpals' dataset: the joint regions' shape borrows its
    // correlations, and its means place the MCPs of "A hand rigged from its
    // skin".
    let atlas_means = atlas_data
        .as_ref()
        .map(|atlas| crate::analysis::analyse_without_bootstrap(atlas, &settings));
    let shape = atlas_means
        .as_ref()
        .map(|atlas| atlas.shape_priors(crate::analysis::region::PRIOR_HANDS));
    let rigs = audit_references(references, &a, &soft_tissue, shape.as_ref());
    let calibration = calibration_of(&a, shape.as_ref());
    // The coverage curve and the atlas section are independent (their random streams are
    // keyed by seed, size and simulation, not by thread), so they run side by side: the
    // same numbers, with the serial parts of one overlapping the other.
    let (cov, atlas) = rayon::join(
        || {
            if req.show_coverage {
                coverage::curve(&coverage::data_sizes(&a, &cov_settings), &cov_settings)
            } else {
                Vec::new()
            }
        },
        || atlas_data.map(|atlas| atlas_inputs(&paper_data, atlas, &settings)),
    );
    let placements = placement::place_all(&a, req.model_length);
    let literature = literature_inputs(
        req.literature,
        req.atlas,
        &paper_data,
        atlas.as_ref(),
        settings.confidence,
    )?;
    drop(paper_data);
    let wrist = match &atlas_means {
        Some(_) => session::wrist_ratios_beside(req.atlas)?,
        None => None,
    };
    // The two parts on real rigs are independent: made side by side.
    let (deform, made) = rayon::join(
        || {
            deform_section(
                req.deform_rig,
                &a,
                &soft_tissue,
                atlas.as_ref().map(|x| (&x.analysis, wrist.as_ref())),
            )
        },
        || match &atlas_means {
            Some(atlas) => made_section(req.made_rig, &a, &soft_tissue, (atlas, wrist.as_ref())),
            None => Ok(None),
        },
    );
    let (deform, made) = (deform?, made?);
    Ok(Gathered {
        analysis: a,
        claims_file: claims.path,
        claims: results,
        claims_note,
        coverage_settings: cov_settings,
        coverage: cov,
        placements,
        model_length: req.model_length,
        timestamp: req.timestamp,
        history_file: req.history_file,
        history: req.history,
        since: req.since,
        target: req.target,
        groups: req.groups,
        rigs,
        paper_xrays,
        atlas,
        literature,
        deform,
        made,
        shape,
        calibration,
    })
}

/// The region's calibration, simulated for the index finger (the paper's worked
/// example) with its prior, as the report's methods show it.
fn calibration_of(
    a: &Analysis,
    shape: Option<&crate::analysis::region::ShapePriors>,
) -> Option<(Setup, Vec<calibration::Cell>)> {
    Setup::of(
        a,
        Finger::Index,
        shape.and_then(|s| s.of(Finger::Index)),
        calibration::SIMULATIONS,
    )
    .map(|setup| (setup, calibration::simulate(&setup)))
}

/// The atlas section's inputs: the atlas analysed, compared with the data's X-rays,
/// and its coverage measured on its own hands.
fn atlas_inputs(data: &Dataset, atlas: Dataset, settings: &Settings) -> AtlasInputs {
    AtlasInputs {
        analysis: crate::analysis::analyse(&atlas, settings),
        cohorts: crate::analysis::compare::cohorts(data, &atlas, settings),
        population: crate::analysis::population::of_dataset(
            &atlas,
            &ATLAS_SIZES,
            &atlas_coverage(settings),
            crate::analysis::Quantity::is_relative,
        ),
    }
}

/// The settings of the coverage measured on the atlas's hands.
fn atlas_coverage(settings: &Settings) -> CoverageSettings {
    CoverageSettings {
        sims: ATLAS_SIMS,
        resamples: ATLAS_RESAMPLES,
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: None,
    }
}

/// The paper against a published table, and the atlas against it, with the atlas's
/// correlations assumed between the table's segments: only with the atlas (the correlations
/// come from it) and the table present, over the paper's X-rays.
fn literature_inputs(
    table: &Path,
    atlas_path: &Path,
    paper: &Dataset,
    atlas: Option<&AtlasInputs>,
    confidence: f64,
) -> Result<Option<LiteratureInputs>, Error> {
    use crate::analysis::literature::{self, Side};
    use crate::dataset::{CohortNotes, SummaryTable};
    let Some(atlas) = atlas else { return Ok(None) };
    if !table.exists() {
        return Ok(None);
    }
    let t = SummaryTable::load(table)?;
    let atlas_data = Dataset::load(atlas_path)?;
    let correlation = literature::correlations_from(&atlas_data);
    let notes_table = CohortNotes::beside(table)?;
    let notes_atlas = CohortNotes::beside(atlas_path)?;
    let mut p = literature::tables(Side::Data(paper), Side::Table(&t), &correlation, confidence);
    p.a.about = CohortNotes::beside(Path::new(&paper.path))?;
    p.b.about = notes_table.clone();
    let mut x = literature::tables(
        Side::Data(&atlas_data),
        Side::Table(&t),
        &correlation,
        confidence,
    );
    x.a.about = notes_atlas.clone();
    x.b.about = notes_table;
    let mut info = atlas.cohorts.b.clone();
    info.about = notes_atlas;
    Ok(Some(LiteratureInputs {
        paper: p,
        atlas: Some(x),
        atlas_info: Some(info),
    }))
}

/// Checks the claims. Claims about rows this dataset lacks (another lab's data,
/// say) cannot be checked: the report says so instead of failing.
fn check_claims(claims: &Claims, dataset: &Dataset) -> (Vec<ClaimResult>, Option<String>) {
    match claims.check_against(dataset) {
        Ok(()) => (claims::check(claims, dataset), None),
        Err(e) => (
            Vec::new(),
            Some(format!(
                "The claims were not checked: they refer to rows this dataset does not have ({} problem(s), the first: {}).",
                e.problems.len(),
                e.problems
                    .first()
                    .map_or(String::new(), |p| p.message.clone())
            )),
        ),
    }
}

/// Judges each reference rig against the statistics, as `audit` does (skin tips).
fn audit_references(
    references: Vec<ReferenceRig>,
    a: &Analysis,
    soft_tissue: &SoftTissue,
    shape: Option<&crate::analysis::region::ShapePriors>,
) -> Vec<ReferenceAudit> {
    let options = AuditOptions {
        soft_tissue: soft_tissue.clone(),
        shape: shape.cloned(),
        ..AuditOptions::default()
    };
    references
        .into_iter()
        .map(|rig| {
            let audit = AuditedRig::with(&rig.name, &rig.chains, &[], a, &options, None);
            ReferenceAudit { rig, audit }
        })
        .collect()
}

/// The part on a real rig: its audit (each MCP judged from its metacarpal
/// against the atlas, when there is one) and its skin in the fist (linear
/// blend), as it is and as `audit --fix` writes it, compared as
/// `phalanx deform RIG --fix --out DIR` does. `None` when the file is absent.
fn deform_section(
    rig: &Path,
    a: &Analysis,
    soft_tissue: &SoftTissue,
    atlas: Option<(&Analysis, Option<&WristRatios>)>,
) -> Result<Option<DeformSection>, Error> {
    if !rig.exists() {
        return Ok(None);
    }
    let pose = Pose::fist();
    let req = session::deform_request(rig, &pose, Skinning::Lbs);
    let fixed = session::fix_in_memory_with(rig, None, a, soft_tissue, atlas)?;
    let (da, db, verdicts) = session::compare_fixed(&fixed, rig, &req)?;
    let (files, renders) = deform_view::figures(&da, Some(&db), true)?;
    let slug = slug(rig);
    Ok(Some(deform_view::section(deform_view::SectionInputs {
        a: &da,
        b: &db,
        verdicts: &verdicts,
        pose: &pose,
        method: Skinning::Lbs,
        moved: &fixed.moved,
        audit: &fixed.audited,
        atlas: atlas.is_some(),
        confidence: a.settings.confidence,
        figures: files.into_iter().zip(renders).collect(),
        stem: &format!("deform-{slug}"),
    })))
}

/// The part on a hand rigged from its skin: `rig` rigged again as `phalanx
/// rig RIG --replace-fingers` rigs it (in memory; its MCPs from `atlas`'s
/// means and wrist ratios, as `rig` places them from its default
/// metacarpals' dataset), beside the rig as given, both in the fist.
/// `None` when the file is absent.
fn made_section(
    rig: &Path,
    a: &Analysis,
    soft_tissue: &SoftTissue,
    atlas: (&Analysis, Option<&WristRatios>),
) -> Result<Option<MadeSection>, Error> {
    use crate::rig::make::{MakeOptions, names::Names, write::WriteOptions};
    if !rig.exists() {
        return Ok(None);
    }
    let loaded = crate::rig::Rig::load(rig, None)?;
    let make = MakeOptions {
        side: None,
        wrist: None,
        fingers: None,
        write: WriteOptions {
            names: Names::Openxr,
            replace_fingers: true,
            glb: true,
        },
    };
    let label = format!("{} (as rig --replace-fingers writes it)", rig.display());
    let rigged = session::rig_in_memory(
        &loaded,
        &label,
        a,
        Some(atlas),
        soft_tissue,
        &make,
        crate::analysis::region::PRIOR_HANDS,
    )?;
    let copy = crate::rig::GltfFile::from_bytes(&label, &rigged.made.written.bytes)?;
    let pose = Pose::fist();
    let req = session::deform_request(rig, &pose, Skinning::Lbs);
    let (da, db, verdicts) = session::compare_parsed(&loaded.file, &copy, rig, &req)?;
    let side = rigged.made.hand.side;
    let artist: Vec<_> = loaded
        .chains
        .iter()
        .filter(|c| c.side.is_none_or(|s| s == side))
        .cloned()
        .collect();
    let stem = format!("made-{}-{}", slug(rig), side.name());
    let font = deform_view::label_font();
    Ok(Some(super::rig::made_section(
        super::rig::MadeInputs {
            rig: &rig.display().to_string(),
            artist: &artist,
            rigged: &rigged,
            a: &da,
            b: &db,
            verdicts: &verdicts,
            pose: &pose,
            method: Skinning::Lbs,
            stem: &stem,
        },
        font.as_deref(),
    )?))
}

/// A rig file's name for the report's figures: its folder's name (else
/// its own), lower case, each other character a dash.
fn slug(rig: &Path) -> String {
    rig.parent()
        .and_then(|p| p.file_name())
        .or_else(|| rig.file_stem())
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}
