//! `phalanx report`: analyse, check, simulate, render everything in memory, then write.

use super::args::{
    BootArgs, DEFAULT_CLAIMS, DataArgs, GroupArgs, HistoryArgs, parse_length, parse_sims,
};
use crate::dataset::Dataset;
use crate::error::Error;
use crate::report::render::Templates;
use crate::report::writer::OutputFile;
use crate::report::{self, Formats};
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
    let formats = formats(&args.format);
    let timestamp = args
        .timestamp
        .then(|| humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string());
    let request = report::inputs::Request {
        dataset,
        settings,
        claims: &args.claims,
        rigs: &args.rigs,
        atlas: &args.atlas,
        literature: &args.literature,
        deform_rig: &args.deform_rig,
        made_rig: &args.made_rig,
        sims: args.sims as usize,
        // The coverage is shown in HTML and Markdown only.
        show_coverage: formats.html || formats.markdown,
        model_length: args.model_length,
        groups,
        history_file: history_path.display().to_string(),
        history,
        since: args.since.map(|n| n as usize),
        target: args.target,
        timestamp,
    };
    let gathered = report::inputs::gather(request, |dataset| {
        let a = super::analyse_showing_progress(dataset, &settings, quiet)?;
        super::warn_implausible(&a);
        Ok(a)
    })?;
    let inputs = gathered.inputs();
    let files = report::render(&inputs, formats, &templates)?;
    write(&args.out, &files)?;
    Ok(0)
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
