//! `phalanx compare`: two cohorts of X-rays, finger by finger.

use super::args::BootArgs;
use super::out;
use crate::analysis::compare;
use crate::dataset::Dataset;
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;
use clap::ValueEnum;
use std::path::PathBuf;

/// Compare two datasets finger by finger: differences, effect sizes and external coverage
#[derive(clap::Args, Debug)]
#[command(
    after_help = "For every finger and quantity both datasets measure: n, mean and SD of each; the difference \
                  B - A with a Welch t interval and a bootstrap interval (each cohort resampled on its own, \
                  seeded); Hedges' g with its interval; and the external coverage, the share of B's X-rays \
                  inside A's prediction interval for one new X-ray and of A's inside B's. Then a sentence per \
                  finger naming its largest differences, and the fingertip offset (a share of the finger's \
                  length) that would explain the difference of the last segment if one cohort measured to \
                  the skin and the other to the bone. Lengths are compared only in one physical unit.\n\n\
                  Examples:\n  phalanx compare data/measurements.csv data/atlas/measurements.csv\n  \
                  phalanx compare lab.csv data/atlas/measurements.csv --format json\n  \
                  phalanx compare a.csv b.csv --format csv --resamples 2000"
)]
pub struct Args {
    /// Dataset A (the reference; differences are B - A)
    #[arg(value_name = "A")]
    a: PathBuf,
    /// Dataset B
    #[arg(value_name = "B")]
    b: PathBuf,
    #[command(flatten)]
    boot: BootArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Table,
    Json,
    Csv,
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let a = Dataset::load(&args.a)?;
    let b = Dataset::load(&args.b)?;
    let c = compare::cohorts(&a, &b, &settings);
    if c.fingers.is_empty() {
        return Err(Error::Usage(format!(
            "{} and {} have no finger in common to compare",
            a.path, b.path
        )));
    }
    let bytes = match args.format {
        Format::Table => report::compare::text(&c, width).into_bytes(),
        Format::Json => report::json::compare(&c)?,
        Format::Csv => report::compare::csv(&c)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
