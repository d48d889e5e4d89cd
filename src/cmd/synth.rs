//! `phalanx synth`: a synthetic dataset.

use super::args::{ForceArgs, check_output_file, parse_seed, parse_whole};
use super::out;
use crate::analysis;
use crate::error::Error;
use crate::synth::{SynthOptions, generate};
use std::path::PathBuf;

/// Write a synthetic dataset (for benchmarks and tests; never mix it into real data)
#[derive(clap::Args, Debug)]
#[command(
    after_help = "The model (hand scale, per-finger totals and proportions from the paper's Table 1, \
                  correlated segments) is documented in src/synth.rs and the README.\n\n\
                  Examples:\n  phalanx synth --xrays 10000 --seed 1 --out /tmp/hands.csv\n  phalanx synth --xrays 20 --no-metadata"
)]
pub(crate) struct Args {
    /// Number of X-rays (hands), 1 to 1000000; each has the five fingers
    #[arg(long, value_name = "N", value_parser = parse_xrays, allow_negative_numbers = true)]
    xrays: u64,
    /// Seed of the generator, a whole number from 0 to 18446744073709551615
    #[arg(long, value_name = "S", default_value_t = analysis::DEFAULT_SEED, value_parser = parse_seed, allow_negative_numbers = true)]
    seed: u64,
    /// Output file (written atomically); standard output when absent
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Leave sex, age and side empty
    #[arg(long)]
    no_metadata: bool,
    #[command(flatten)]
    force: ForceArgs,
}

/// Most X-rays generated: 5 rows each, about 300 MB of CSV built in memory,
/// and the most that `stats` serves at its default 10,000 resamples.
const MAX_XRAYS: u64 = 1_000_000;

fn parse_xrays(text: &str) -> Result<u64, String> {
    parse_whole(text, 1, MAX_XRAYS, "; e.g. 1000")
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    if let Some(path) = &args.out {
        check_output_file("--out", path, args.force.force)?;
    }
    let bytes = generate(&SynthOptions {
        xrays: args.xrays as usize,
        seed: args.seed,
        metadata: !args.no_metadata,
    });
    match &args.out {
        Some(path) => crate::atomic::replace(path, &bytes).map_err(Error::write(path))?,
        None => out::print(&bytes)?,
    }
    Ok(0)
}
