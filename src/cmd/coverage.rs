//! `phalanx coverage`: how often each interval method really covers.

use super::args::{BootArgs, DataArgs, TextFormat, parse_sims};
use super::out;
use crate::analysis::coverage::{self, CoverageSettings};
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;

/// Estimate by simulation how often each interval method really covers, at the data's n and from 3 to 50 X-rays
#[derive(clap::Args, Debug)]
#[command(
    after_help = "The table has one row per sample size: the data's own n (marked) and 3, 4, 5, 6, 8, 10, 15, 20, 30 and 50 X-rays. \
                  --format json gives the simulation at the data's n for every finger and quantity.\n\n\
                  Examples:\n  phalanx coverage\n  phalanx coverage --sims 20000 --format json"
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

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let s = CoverageSettings {
        sims: args.sims as usize,
        resamples: settings.resamples,
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: None,
    };
    let data = crate::dataset::Dataset::load(&args.data.data)?;
    super::report::check_coverage_budget(&data, &s, args.format == TextFormat::Table)?;
    super::within_budget(&data, &settings)?;
    let a = crate::analysis::analyse(&data, &settings);
    drop(data);
    let bytes = match args.format {
        TextFormat::Table => {
            let points = coverage::curve(&coverage::data_sizes(&a, &s), &s);
            let notes = coverage::not_simulated(&a, &s);
            report::text::coverage(&points, &s, &notes, width).into_bytes()
        }
        TextFormat::Json => {
            let rows = coverage::of_analysis(&a, &s);
            report::json::coverage(&a.dataset, &s, &rows)?
        }
    };
    out::print(&bytes)?;
    Ok(0)
}
