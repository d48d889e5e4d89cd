//! `phalanx import`: landmark annotations in, measurement rows out.

use super::args::{BootArgs, ForceArgs, HistoryArgs, TipArg, check_output_file};
use super::out;
use crate::dataset::Dataset;
use crate::dataset::landmarks::{self, ImportOptions, Layout, Side};
use crate::error::Error;
use crate::report::track_words;
use crate::track::{self, AddRequest, NewRows};
use clap::ValueEnum;
use std::path::PathBuf;

/// Turn landmark annotations (joint positions on radiographs) into measurement rows
#[derive(clap::Args, Debug)]
#[command(
    after_help = "One row per image and finger: J1, J2, J3 (J1, J2 for the thumb) as the distances between \
                  consecutive joints, and the metacarpal mc (CMC to MCP) where the CMC is marked. Lengths are \
                  in pixels (unit px) unless --pixel-spacing gives millimetres per pixel.\n\n\
                  Layouts: atlas37, the Digital Hand Atlas's headerless 37-landmark CSV (left hands, tips at \
                  the bone); coco, COCO keypoints JSON with the 21-point hand (names as MediaPipe's, plain \
                  ones like index_pip, or the standard order; COCO-WholeBody's lefthand_kpts/righthand_kpts); \
                  long, a CSV image,landmark,x,y.\n\n\
                  Every problem of the file is reported with its image, landmark and line or JSON path, and \
                  nothing is written. A finger an image does not annotate is left out with a note.\n\n\
                  Examples:\n  phalanx import data/atlas/landmarks.csv --layout atlas37 --out data/atlas/measurements.csv\n  \
                  phalanx import hands.json --layout coco --side right --tip skin --source \"lab 2026\"\n  \
                  phalanx import marks.csv --layout long --pixel-spacing 0.1 --into lab.csv"
)]
pub struct Args {
    /// The landmark file
    #[arg(value_name = "FILE")]
    file: PathBuf,
    /// How the landmarks are laid out in the file
    #[arg(long, value_enum)]
    layout: LayoutArg,
    /// The side of every hand (default: left for atlas37, unknown otherwise)
    #[arg(long, value_enum)]
    side: Option<SideArg>,
    /// Millimetres per pixel: lengths are scaled to mm
    #[arg(
        long,
        value_name = "MM",
        conflicts_with = "unit",
        allow_negative_numbers = true
    )]
    pixel_spacing: Option<f64>,
    /// Unit name of the (unscaled) lengths (default px)
    #[arg(long, value_name = "NAME")]
    unit: Option<String>,
    /// Text for every row's source column
    #[arg(long, value_name = "TEXT")]
    source: Option<String>,
    /// Where the fingertip landmarks are (default: bone for atlas37, unknown otherwise)
    #[arg(long, value_enum)]
    tip: Option<TipArg>,
    /// Write a new measurement file (atomically) instead of standard output
    #[arg(long, value_name = "FILE", conflicts_with = "into")]
    out: Option<PathBuf>,
    /// Append the rows to this dataset, as 'phalanx add' does (validated, locked, atomic, with a snapshot)
    #[arg(long, value_name = "DATASET")]
    into: Option<PathBuf>,
    /// With --into: add rows flagged as likely errors too (refused otherwise), recorded as flagged
    #[arg(long, requires = "into")]
    accept_flagged: bool,
    /// With --into: refuse flagged rows (the default; kept for scripts)
    #[arg(
        long,
        requires = "into",
        hide = true,
        conflicts_with = "accept_flagged"
    )]
    strict: bool,
    /// With --into: a note for the history record
    #[arg(long, value_name = "TEXT", requires = "into")]
    note: Option<String>,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    boot: BootArgs,
    #[command(flatten)]
    force: ForceArgs,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum LayoutArg {
    Atlas37,
    Coco,
    Long,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SideArg {
    Left,
    Right,
}

impl Args {
    /// The import options, checked: a usage error names what is wrong.
    fn options(&self) -> Result<ImportOptions, Error> {
        let options = ImportOptions {
            side: self.side.map(|s| match s {
                SideArg::Left => Side::Left,
                SideArg::Right => Side::Right,
            }),
            pixel_spacing: self.pixel_spacing,
            unit: self.unit.clone(),
            source: self.source.clone(),
            tip: self.tip.map(TipArg::kind),
        };
        options.validate().map_err(Error::Usage)?;
        Ok(options)
    }

    fn layout(&self) -> Layout {
        match self.layout {
            LayoutArg::Atlas37 => Layout::Atlas37,
            LayoutArg::Coco => Layout::Coco,
            LayoutArg::Long => Layout::Long,
        }
    }
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let options = args.options()?;
    let settings = args.boot.settings()?;
    if let Some(path) = &args.out {
        check_output_file("--out", path, args.force.force)?;
    }
    let import = landmarks::import_file(args.layout(), &args.file, &options)?;
    for note in &import.notes {
        eprintln!("note: {note}");
    }
    let mut bytes = Vec::new();
    landmarks::write_csv(&import.rows, &mut bytes)
        .map_err(|e| Error::render("writing the imported rows", e))?;
    let summary = format!(
        "{} row{} from {} hand{} in {}",
        import.rows.len(),
        if import.rows.len() == 1 { "" } else { "s" },
        import.hands,
        if import.hands == 1 { "" } else { "s" },
        args.file.display()
    );
    match (&args.out, &args.into) {
        (Some(path), _) => {
            crate::atomic::replace(path, &bytes).map_err(Error::write(path))?;
            eprintln!("phalanx: imported {summary} to {}", path.display());
        }
        (None, Some(data)) => {
            // The rows as a dataset (they pass its checks), then the path of 'add'.
            let rows = Dataset::from_bytes(&args.file.display().to_string(), &bytes)?;
            let history = args.history.resolve(data);
            let outcome = track::add(&AddRequest {
                data: data.clone(),
                history: history.clone(),
                rows: NewRows::Rows(rows),
                accept_flagged: args.accept_flagged && !args.strict,
                note: args.note.clone(),
                mixed_tips: false,
                tip: None,
                settings,
            })?;
            for line in super::added_messages(&outcome, data) {
                eprintln!("{line}");
            }
            out::print(
                format!(
                    "imported {summary} into {}: {} -> {} X-rays{}; snapshot appended to {}\n",
                    data.display(),
                    outcome.xrays_before,
                    outcome.xrays_after,
                    track_words::flagged(outcome.flags.len()),
                    history.display()
                )
                .as_bytes(),
            )?;
        }
        (None, None) => {
            out::print(&bytes)?;
            eprintln!("phalanx: imported {summary}");
        }
    }
    Ok(0)
}
