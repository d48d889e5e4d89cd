//! `phalanx report`: analyse, check, simulate, render everything in memory, then write.

use super::args::{
    BootArgs, DEFAULT_CLAIMS, DataArgs, GroupArgs, HistoryArgs, parse_length, parse_sims,
};
use crate::analysis::claims::{self, ClaimResult};
use crate::analysis::coverage::{self, CoverageSettings};
use crate::analysis::{Analysis, placement};
use crate::dataset::Dataset;
use crate::dataset::claims::Claims;
use crate::error::Error;
use crate::report::deform as deform_view;
use crate::report::render::Templates;
use crate::report::view::{
    AtlasInputs, DeformSection, LiteratureInputs, MadeSection, ReferenceAudit, ReportInputs,
};
use crate::report::writer::OutputFile;
use crate::report::{self, Formats};
use crate::rig::deform::{Pose, Skinning};
use crate::rig::judge::{SoftTissue, WristRatios};
use crate::rig::reference::{self, ReferenceRig};
use crate::rig::session;
use crate::rig::{AuditOptions, AuditedRig};
use clap::ValueEnum;
use std::path::{Path, PathBuf};

/// Default directory of reference rigs for the report.
const DEFAULT_RIGS: &str = "data/rigs";
/// The atlas of the section "The paper against N atlas radiographs".
const DEFAULT_ATLAS: &str = "data/atlas/measurements.csv";
/// The published table of the section "The paper against published measurements".
const DEFAULT_LITERATURE: &str = "data/literature/buryanov-kotiuk-2010.csv";
/// The real rig whose audit and deformation the report shows (MIT, vendored).
const DEFAULT_DEFORM_RIG: &str = "data/rigs/webxr-generic-hand/right.glb";
/// The rigged hand the report rigs again from its skin (MIT, vendored).
const DEFAULT_MADE_RIG: &str = "data/rigs/webxr-generic-hand/left.glb";
/// Sample sizes of the coverage measured on the atlas's hands.
const ATLAS_SIZES: [usize; 5] = [3, 5, 10, 20, 50];
/// Samples per size of that coverage, and the resamples of its random bootstraps (n of 8
/// and over): enough for a Monte-Carlo SE near 1% per value, cheap enough for a report.
/// `phalanx coverage --population` measures it with more.
const ATLAS_SIMS: usize = 500;
const ATLAS_RESAMPLES: usize = 200;

/// Render the HTML and Markdown report with SVG plots, and stats.json
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Writes DIR/index.html (self-contained), DIR/report.md, DIR/plots/*.svg and DIR/stats.json.\n\
                  Files are replaced atomically; a failed run leaves the previous report as it was.\n\n\
                  Examples:\n  phalanx report\n  phalanx report --out /tmp/site --model-length 87.5 --format html\n  phalanx report --templates my_templates/"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    /// The claims file checked in the "Reproducing the paper" section
    #[arg(long, value_name = "PATH", default_value = DEFAULT_CLAIMS)]
    claims: PathBuf,
    /// Output directory
    #[arg(long, value_name = "DIR", default_value = "reports")]
    out: PathBuf,
    #[command(flatten)]
    boot: BootArgs,
    /// Total length of the model finger for the joint-placement section, in model units (greater than 0, at most 1e9)
    #[arg(long, value_name = "L", default_value_t = 1000.0, value_parser = parse_length, allow_negative_numbers = true)]
    model_length: f64,
    /// Formats to write, comma-separated
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [Format::Html, Format::Md, Format::Json])]
    format: Vec<Format>,
    /// Directory with report.html.tera and/or report.md.tera overriding the built-in templates
    #[arg(long, value_name = "DIR")]
    templates: Option<PathBuf>,
    /// Add the generation time (UTC) to the provenance; the report is then no longer reproducible byte for byte
    #[arg(long)]
    timestamp: bool,
    /// Simulated datasets for the coverage section, 1 to 100000 (at most 10^10 resample-X-ray pairs in all)
    #[arg(long, default_value_t = 4000, value_parser = parse_sims, allow_negative_numbers = true)]
    sims: u64,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    groups: GroupArgs,
    /// Directory of reference rigs (*.json) for "Popular rigs against the X-rays"; absent = no section
    #[arg(long, value_name = "DIR", default_value = DEFAULT_RIGS)]
    rigs: PathBuf,
    /// Measurements of an atlas for "The paper against N atlas radiographs"; absent = no section
    #[arg(long, value_name = "PATH", default_value = DEFAULT_ATLAS)]
    atlas: PathBuf,
    /// A published summary table for "The paper against published measurements" (its segments' correlations are taken from the atlas); absent = no section
    #[arg(long, value_name = "PATH", default_value = DEFAULT_LITERATURE)]
    literature: PathBuf,
    /// A rigged hand (glTF) audited and deformed as it is and as `audit --fix` writes it, in "Popular rigs"; absent = no such part
    #[arg(long, value_name = "PATH", default_value = DEFAULT_DEFORM_RIG)]
    deform_rig: PathBuf,
    /// A rigged hand (glTF) rigged again from its skin as `rig --replace-fingers` does (in memory) and shown beside the artist's rig, in "Popular rigs" (needs --atlas); absent = no such part
    #[arg(long, value_name = "PATH", default_value = DEFAULT_MADE_RIG)]
    made_rig: PathBuf,
    /// Target half-width of the confidence interval of a relative mean, for "X-rays needed": greater than 0, at most 1
    #[arg(long, value_name = "W", default_value_t = 0.005, value_parser = parse_target, allow_negative_numbers = true)]
    target: f64,
    /// "What changed" in the Tracking section runs from this snapshot of the history (1 is the first, the default) to the last
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..), allow_negative_numbers = true)]
    since: Option<u64>,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Html,
    Md,
    Json,
}

fn parse_target(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(t) if t > 0.0 && t <= 1.0 => Ok(t),
        _ => Err(format!(
            "'{text}' is not a half-width greater than 0 and at most 1 (relative values lie between 0 and 1); give e.g. 0.005"
        )),
    }
}

pub(crate) fn run(args: &Args, quiet: bool) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    check_out_dir(&args.out)?;
    let templates = match &args.templates {
        Some(dir) => Templates::from_dir(dir)?,
        None => Templates::builtin()?,
    };
    let by = args.groups.group_by()?;
    let dataset = Dataset::load(&args.data.data)?;
    let groups = super::groups_of(&dataset, by.as_ref(), &settings);
    let history_path = args.history.resolve(&args.data.data);
    let history = crate::dataset::history::read(&history_path)?;
    if let Some(n) = args.since
        && (history.len() < 2 || n as usize >= history.len())
    {
        return Err(Error::Usage(format!(
            "--since {n}: {} has {} snapshot{}; 'What changed' runs from a snapshot before the last, so give 1 to {}",
            history_path.display(),
            history.len(),
            if history.len() == 1 { "" } else { "s" },
            history.len().saturating_sub(1).max(1)
        )));
    }
    let claims = Claims::load(&args.claims)?;
    let (results, claims_note) = check_claims(&claims, &dataset);
    let paper_xrays = claims.named_in(&dataset);
    let references = reference::load_dir(&args.rigs)?;
    // The section compares the paper's X-rays with the atlas: over other data it is left out.
    let is_paper = paper_xrays.0 > 0 && paper_xrays.0 == paper_xrays.1;
    let atlas_data = if is_paper && args.atlas.exists() {
        Some(Dataset::load(&args.atlas)?)
    } else {
        None
    };
    // The simulations' bootstraps take as many resamples as their printed coverage needs
    // (coverage::SIM_RESAMPLES, at every size, the data's own too), not the analysis's.
    let cov_settings = CoverageSettings {
        sims: args.sims as usize,
        resamples: settings.resamples.min(coverage::SIM_RESAMPLES),
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: Some(coverage::REPORT_MAX_N),
    };
    let formats = formats(&args.format);
    // The coverage is shown in HTML and Markdown only.
    let show_coverage = formats.html || formats.markdown;
    crate::analysis::budget::check_coverage(&dataset, &cov_settings, show_coverage)
        .map_err(Error::Usage)?;
    let a = super::analyse_showing_progress(&dataset, &settings, quiet)?;
    super::warn_implausible(&a);
    let paper_data = dataset;
    // The fingertip's soft tissue of the published table, for rigs whose tips differ from the data's.
    let soft_tissue = super::soft_tissue_from(&args.literature)?;
    // The atlas, over any data, as `audit` and `rig` take their default
    // metacarpals' dataset: the joint regions' shape borrows its
    // correlations, and its means place the MCPs of "A hand rigged from its
    // skin".
    let atlas_means = match &atlas_data {
        Some(atlas) => Some(crate::analysis::analyse_without_bootstrap(atlas, &settings)),
        None if args.atlas.is_file() => Some(crate::analysis::analyse_without_bootstrap(
            &Dataset::load(&args.atlas)?,
            &settings,
        )),
        None => None,
    };
    let shape = atlas_means
        .as_ref()
        .map(|atlas| atlas.shape_priors(crate::analysis::region::PRIOR_HANDS));
    let rigs = audit_references(references, &a, &soft_tissue, shape.as_ref());
    // The region's calibration, simulated for the index finger (the paper's
    // worked example) with its prior, as the report's methods show it.
    let calibration = crate::analysis::region::calibration::Setup::of(
        &a,
        crate::dataset::Finger::Index,
        shape
            .as_ref()
            .and_then(|s| s.of(crate::dataset::Finger::Index)),
        crate::analysis::region::calibration::SIMULATIONS,
    )
    .map(|setup| {
        (
            setup,
            crate::analysis::region::calibration::simulate(&setup),
        )
    });
    // The coverage curve and the atlas section are independent (their random streams are
    // keyed by seed, size and simulation, not by thread), so they run side by side: the
    // same numbers, with the serial parts of one overlapping the other.
    let (cov, atlas) = rayon::join(
        || {
            if show_coverage {
                coverage::curve(&coverage::data_sizes(&a, &cov_settings), &cov_settings)
            } else {
                Vec::new()
            }
        },
        || {
            atlas_data.map(|atlas| {
                let pop = CoverageSettings {
                    sims: ATLAS_SIMS,
                    resamples: ATLAS_RESAMPLES,
                    ..cov_settings
                };
                AtlasInputs {
                    analysis: crate::analysis::analyse(&atlas, &settings),
                    cohorts: crate::analysis::compare::cohorts(&paper_data, &atlas, &settings),
                    population: crate::analysis::population::of_dataset(
                        &atlas,
                        &ATLAS_SIZES,
                        &CoverageSettings { max_n: None, ..pop },
                        crate::analysis::Quantity::is_relative,
                    ),
                }
            })
        },
    );
    let placements = placement::place_all(&a, args.model_length);
    let literature = literature_inputs(
        &args.literature,
        &args.atlas,
        &paper_data,
        atlas.as_ref(),
        settings.confidence,
    )?;
    drop(paper_data);
    let wrist = match &atlas_means {
        Some(_) => session::wrist_ratios_beside(&args.atlas)?,
        None => None,
    };
    // The two parts on real rigs are independent: made side by side.
    let (deform, made) = rayon::join(
        || {
            deform_section(
                &args.deform_rig,
                &a,
                &soft_tissue,
                atlas.as_ref().map(|x| (&x.analysis, wrist.as_ref())),
            )
        },
        || match &atlas_means {
            Some(atlas) => made_section(&args.made_rig, &a, &soft_tissue, (atlas, wrist.as_ref())),
            None => Ok(None),
        },
    );
    let (deform, made) = (deform?, made?);
    let timestamp = args
        .timestamp
        .then(|| humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string());
    let inputs = ReportInputs {
        analysis: &a,
        claims_file: &claims.path,
        claims: &results,
        claims_note: claims_note.as_deref(),
        coverage_settings: &cov_settings,
        coverage: &cov,
        placements: &placements,
        model_length: args.model_length,
        timestamp,
        history_file: &history_path.display().to_string(),
        history: &history,
        since: args.since.map(|n| n as usize),
        target: args.target,
        groups: groups.as_ref(),
        rigs: &rigs,
        paper_xrays,
        atlas: atlas.as_ref(),
        literature: literature.as_ref(),
        deform: deform.as_ref(),
        made: made.as_ref(),
        shape: shape.as_ref(),
        calibration: calibration.as_ref().map(|(s, c)| (s, c.as_slice())),
    };
    let files = report::render(&inputs, formats, &templates)?;
    write(&args.out, &files)?;
    Ok(0)
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

/// Refuses an output directory that is a file (or lies under one) before any work.
fn check_out_dir(out: &Path) -> Result<(), Error> {
    let existing = out
        .ancestors()
        .filter(|p| !p.as_os_str().is_empty())
        .find(|p| p.exists());
    match existing {
        Some(p) if !p.is_dir() => Err(Error::Usage(if p == out {
            format!(
                "--out {}: this is a file, not a directory; give a directory for the report (it is created when missing)",
                out.display()
            )
        } else {
            format!(
                "--out {}: {} is a file, not a directory; give a directory for the report (it is created when missing)",
                out.display(),
                p.display()
            )
        })),
        _ => Ok(()),
    }
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
    Ok(Some(report::rig::made_section(
        report::rig::MadeInputs {
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

/// The report files asked for with --format.
fn formats(asked: &[Format]) -> Formats {
    Formats {
        html: asked.contains(&Format::Html),
        markdown: asked.contains(&Format::Md),
        json: asked.contains(&Format::Json),
    }
}

/// Writes the files and says which on standard error.
fn write(dir: &Path, files: &[OutputFile]) -> Result<(), Error> {
    report::writer::write_all(dir, files)?;
    let names: Vec<String> = files.iter().map(|f| f.path.display().to_string()).collect();
    eprintln!(
        "phalanx: wrote {} file{} to {}: {}",
        files.len(),
        if files.len() == 1 { "" } else { "s" },
        dir.display(),
        names.join(", ")
    );
    Ok(())
}
