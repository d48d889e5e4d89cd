//! `phalanx snapshot`: record the current statistics in the history.

use super::args::{BootArgs, DataArgs, HistoryArgs};
use super::out;
use crate::error::Error;
use crate::track;

/// Record a snapshot of the current statistics in the history (after editing the data by hand)
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  phalanx snapshot\n  phalanx snapshot --data lab/hands.csv")]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    boot: BootArgs,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let path = args.history.resolve(&args.data.data);
    let snap = track::snapshot(&args.data.data, &path, &args.boot.settings()?)?;
    out::print(
        format!(
            "snapshot of {} ({} X-rays, sha256 {}) appended to {}\n",
            snap.dataset,
            snap.xrays,
            &snap.sha256[..12.min(snap.sha256.len())],
            path.display()
        )
        .as_bytes(),
    )?;
    Ok(0)
}
