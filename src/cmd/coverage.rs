//! `phalanx coverage`: how often each interval method really covers.

use super::args::{BootArgs, DataArgs, TextFormat, parse_sims};
use super::out;
use crate::analysis::Quantity;
use crate::analysis::coverage::{self, CoverageSettings};
use crate::analysis::population;
use crate::dataset::Dataset;
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;
use std::path::PathBuf;

/// Estimate by simulation how often each interval method really covers, at the data's n and from 3 to 50 X-rays
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Without --population: samples are drawn from a normal model fitted to each quantity; the \
                  table has one row per sample size: the data's own n (marked) and 3, 4, 5, 6, 8, 10, 15, 20, \
                  30 and 50 X-rays (--format json gives the simulation at the data's n for every finger and \
                  quantity). With --population DATASET: the dataset is taken as the population of hands, \
                  samples of each size in --n are drawn from its X-rays (with replacement), and each interval \
                  of each relative value J~k is scored against the population mean (the prediction interval \
                  against one further X-ray); the normal model's figure stands beside it. A random bootstrap \
                  (n of 8 and over) costs sims x resamples x n: lower --sims or --resamples for a quick look.\n\n\
                  Examples:\n  phalanx coverage\n  phalanx coverage --sims 20000 --format json\n  \
                  phalanx coverage --population data/atlas/measurements.csv --n 3,5,10,20,50"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Simulated datasets per sample size, 1 to 100000 (at most 10^10 resample-X-ray pairs in all)
    #[arg(long, default_value_t = 4000, value_parser = parse_sims, allow_negative_numbers = true)]
    sims: u64,
    /// Take this dataset as the population of hands and draw samples from its X-rays
    #[arg(long, value_name = "DATASET")]
    population: Option<PathBuf>,
    /// Sample sizes drawn from the population, comma-separated (with --population)
    #[arg(long = "n", value_name = "N,...", value_delimiter = ',', requires = "population", default_values_t = [3usize, 5, 10, 20, 50], value_parser = parse_size)]
    sizes: Vec<usize>,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

/// A sample size from 2 to a million X-rays.
fn parse_size(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (2..=1_000_000).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{text}' is not a sample size from 2 to 1000000; give e.g. 3,5,10,20,50"
        )),
    }
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
    if let Some(path) = &args.population {
        let data = Dataset::load(path)?;
        let mut sizes = args.sizes.clone();
        sizes.sort_unstable();
        sizes.dedup();
        let runs: Vec<(usize, usize)> = sizes.iter().map(|&n| (n, s.resamples)).collect();
        crate::analysis::budget::check_coverage_runs(&runs, s.sims, s.resamples)
            .map_err(Error::Usage)?;
        let study = population::of_dataset(&data, &sizes, &s, Quantity::is_relative);
        if study.quantities.is_empty() {
            return Err(Error::Usage(format!(
                "{} has no quantity with spread over 2 X-rays or more to draw samples from",
                data.path
            )));
        }
        let bytes = match args.format {
            TextFormat::Table => report::text::population(&data.path, &study, width).into_bytes(),
            TextFormat::Json => report::json::population(&data.path, &study)?,
        };
        out::print(&bytes)?;
        return Ok(0);
    }
    let data = crate::dataset::Dataset::load(&args.data.data)?;
    crate::analysis::budget::check_coverage(&data, &s, args.format == TextFormat::Table)
        .map_err(Error::Usage)?;
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
