//! `phalanx coverage`: how often each interval method really covers.

use super::args::{BootArgs, DataArgs, TextFormat};
use super::out;
use crate::analysis::coverage::{self, CoverageSettings};
use crate::error::Error;
use crate::report;

/// Estimate by simulation how often each interval method really covers at the data's n
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx coverage\n  phalanx coverage --sims 20000 --format json"
)]
pub struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Simulated datasets per sample size
    #[arg(long, default_value_t = 4000, value_parser = clap::value_parser!(u64).range(1..))]
    sims: u64,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let a = super::load_and_analyse(&args.data.data, &settings)?;
    let s = CoverageSettings {
        sims: args.sims as usize,
        resamples: settings.resamples,
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: None,
    };
    let rows = coverage::of_analysis(&a, &s);
    let bytes = match args.format {
        TextFormat::Table => report::text::coverage(&rows, &s).into_bytes(),
        TextFormat::Json => report::json::coverage(&a.dataset, &s, &rows)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
