//! `phalanx snapshot`: record the current statistics in the history.

use super::args::{BootArgs, DataArgs, HistoryArgs};
use super::out;
use crate::error::Error;
use crate::track::{self, SnapshotOutcome};

/// Record a snapshot of the current statistics in the history (after editing the data by hand)
#[derive(clap::Args, Debug)]
#[command(
    after_help = "A snapshot is written when the data (its SHA-256) or the settings differ from the \
                  history's last snapshot. When they do not, it says so and writes nothing, unless a note is \
                  given: then it appends a milestone, the last snapshot's statistics again with the note.\n\n\
                  Examples:\n  phalanx snapshot --note \"corrected 2b's ring by hand\"\n  phalanx snapshot --data lab/hands.csv"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// A note for the history record (e.g. what was edited by hand)
    #[arg(long, value_name = "TEXT")]
    note: Option<String>,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let path = args.history.resolve(&args.data.data);
    let outcome = track::snapshot(
        &args.data.data,
        &path,
        &args.boot.settings()?,
        args.note.clone(),
    )?;
    let text = match outcome {
        SnapshotOutcome::Written(snap) => format!(
            "snapshot of {} ({} X-rays, sha256 {}) appended to {}\n",
            snap.dataset,
            snap.xrays,
            &snap.sha256[..12.min(snap.sha256.len())],
            path.display()
        ),
        SnapshotOutcome::Unchanged { record, last } => format!(
            "no change since snapshot {record} of {} ({}, {}): the same data (sha256 {}) and settings; nothing written\n",
            path.display(),
            last.event,
            last.time,
            &last.sha256[..12.min(last.sha256.len())],
        ),
        SnapshotOutcome::Milestone { same, snap } => format!(
            "milestone snapshot {} appended to {}: the same data as snapshot {same} (sha256 {}, {} X-rays) and settings, with the note\n",
            same + 1,
            path.display(),
            &snap.sha256[..12.min(snap.sha256.len())],
            snap.xrays,
        ),
    };
    out::print(text.as_bytes())?;
    Ok(0)
}
