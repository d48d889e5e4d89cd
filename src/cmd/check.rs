//! `phalanx check`: every number the paper states, recomputed.

use super::args::{DEFAULT_CLAIMS, DataArgs, TextFormat};
use super::out;
use crate::analysis::DatasetInfo;
use crate::analysis::claims::{self, CheckSummary};
use crate::dataset::Dataset;
use crate::dataset::claims::Claims;
use crate::error::{EXIT_FAILURE, Error};
use crate::report;
use crate::report::layout::Width;
use std::path::PathBuf;

/// Recompute every number the paper states and explain each disagreement
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Exits 0 when every claim matches or is a recorded erratum, 1 when a new mismatch appears.\n\n\
                  Examples:\n  phalanx check\n  phalanx check --claims my_claims.csv --format json"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    /// The claims file (one row per number the paper states)
    #[arg(long, value_name = "PATH", default_value = DEFAULT_CLAIMS)]
    claims: PathBuf,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let dataset = Dataset::load(&args.data.data)?;
    let claims = Claims::load(&args.claims)?;
    claims.check_against(&dataset)?;
    let results = claims::check(&claims, &dataset);
    let bytes = match args.format {
        TextFormat::Table => report::text::check(&results, width).into_bytes(),
        TextFormat::Json => {
            report::json::check(&DatasetInfo::of(&dataset), &claims.path, &results)?
        }
    };
    out::print(&bytes)?;
    let s = CheckSummary::of(&results);
    if s.mismatches > 0 {
        eprintln!(
            "phalanx: {} claim(s) disagree with the data and are not recorded as errata",
            s.mismatches
        );
        return Ok(EXIT_FAILURE);
    }
    Ok(0)
}
