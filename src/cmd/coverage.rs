//! `phalanx coverage`: how often each interval method really covers.

use super::args::{BootArgs, DataArgs, TextFormat, parse_sims};
use super::out;
use crate::analysis::coverage::{self, CoverageSettings};
use crate::error::Error;
use crate::report;

/// Estimate by simulation how often each interval method really covers at the data's n
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx coverage\n  phalanx coverage --sims 20000 --format json"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Simulated datasets per sample size, 1 to 100000 (at most 10^10 resample-X-ray pairs in all)
    #[arg(long, default_value_t = 4000, value_parser = parse_sims, allow_negative_numbers = true)]
    sims: u64,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let s = CoverageSettings {
        sims: args.sims as usize,
        resamples: settings.resamples,
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: None,
    };
    let data = crate::dataset::Dataset::load(&args.data.data)?;
    super::report::check_coverage_budget(&data, &s)?;
    super::within_budget(&data, &settings)?;
    let a = crate::analysis::analyse(&data, &settings);
    drop(data);
    let rows = coverage::of_analysis(&a, &s);
    let bytes = match args.format {
        TextFormat::Table => report::text::coverage(&rows, &s).into_bytes(),
        TextFormat::Json => report::json::coverage(&a.dataset, &s, &rows)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
