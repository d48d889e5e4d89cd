//! `phalanx history`: how the statistics moved, snapshot by snapshot.

use super::args::{DataArgs, HistoryArgs, TextFormat, parse_finger};
use super::out;
use crate::analysis::Quantity;
use crate::dataset::Finger;
use crate::error::Error;
use crate::report;

/// Show how the statistics moved, snapshot by snapshot
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx history\n  phalanx history --finger index --quantity rel_j1\n  phalanx history --format json"
)]
pub struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    /// Only this finger (thumb, index, middle, ring, little, or an alias)
    #[arg(long, value_parser = parse_finger)]
    finger: Option<Finger>,
    /// Only this quantity (rel_j1, rel_j2, rel_j3, total)
    #[arg(long, value_parser = parse_quantity)]
    quantity: Option<Quantity>,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

fn parse_quantity(text: &str) -> Result<Quantity, String> {
    Quantity::parse(text)
        .ok_or_else(|| format!("unknown quantity '{text}'; use rel_j1, rel_j2, rel_j3 or total"))
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let path = args.history.resolve(&args.data.data);
    let snaps = crate::dataset::history::read(&path)?;
    let bytes = match args.format {
        TextFormat::Table => {
            report::text::history(&path, &snaps, args.finger, args.quantity).into_bytes()
        }
        TextFormat::Json => report::json::history(&snaps, args.finger, args.quantity)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
