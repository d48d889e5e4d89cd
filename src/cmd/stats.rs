//! `phalanx stats`: the statistics of every finger.

use super::args::{BootArgs, DataArgs, GroupArgs, TableFormat, TipArgs};
use super::out;
use crate::dataset::Dataset;
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;

/// Statistics of every finger: the paper's (mean, min, max, range) and beyond
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx stats\n  phalanx stats --format json > stats.json\n  phalanx stats --format csv --resamples 20000 --seed 7 --confidence 0.9"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    #[command(flatten)]
    groups: GroupArgs,
    #[command(flatten)]
    tips: TipArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
}

pub(crate) fn run(args: &Args, quiet: bool, width: Width) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let by = args.groups.group_by()?;
    let dataset = Dataset::load(&args.data.data)?;
    args.tips.check(&dataset)?;
    let a = super::analyse_showing_progress(&dataset, &settings, quiet)?;
    super::warn_implausible(&a);
    let groups = super::groups_of(&dataset, by.as_ref(), &settings);
    drop(dataset);
    match args.format {
        TableFormat::Table => {
            out::print(report::text::stats_with_groups(&a, groups.as_ref(), width).as_bytes())?
        }
        // Streamed: the document of a large dataset is not held in memory.
        TableFormat::Json => out::stream(|w| report::json::write_stats(w, &a, groups.as_ref()))?,
        TableFormat::Csv => out::print(&report::csv_out::stats(&a, groups.as_ref())?)?,
    }
    Ok(0)
}
