//! `phalanx remove`: take X-rays out of the dataset, with a record in the history.

use super::args::{BootArgs, DataArgs, HistoryArgs, parse_finger};
use super::out;
use crate::dataset::Finger;
use crate::error::Error;
use crate::track::{self, RemoveRequest};

/// Take X-rays out of the dataset (locked, atomic) and record the removal in the history
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Removes every row of the X-rays named (or only their --finger row), keeping every other byte \
                  of the file, so removing what 'phalanx add' appended restores the dataset and its statistics \
                  exactly. The history records which rows went, and whether they had been added flagged. An X-ray \
                  the dataset lacks is refused and nothing is removed.\n\n\
                  Examples:\n  phalanx remove --xray L11 --note \"j1 typed 36.70 for 367.0\"\n  phalanx remove --xray 2a,2b\n  phalanx remove --xray 2b --finger ring"
)]
pub(crate) struct Args {
    /// The X-rays to remove, comma-separated
    #[arg(
        long,
        value_name = "ID[,ID...]",
        value_delimiter = ',',
        required = true
    )]
    xray: Vec<String>,
    /// Only this finger of them (thumb, index, middle, ring, little, or an alias)
    #[arg(long, value_parser = parse_finger)]
    finger: Option<Finger>,
    /// A note for the history record (e.g. why the rows go)
    #[arg(long, value_name = "TEXT")]
    note: Option<String>,
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    boot: BootArgs,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let mut xrays: Vec<String> = Vec::new();
    for x in &args.xray {
        let x = x.trim();
        if x.is_empty() {
            return Err(Error::Usage(
                "--xray: an empty X-ray id; give ids separated by commas, e.g. --xray 2a,2b".into(),
            ));
        }
        if !xrays.iter().any(|y| y == x) {
            xrays.push(x.to_string());
        }
    }
    let history = args.history.resolve(&args.data.data);
    let outcome = track::remove(&RemoveRequest {
        data: args.data.data.clone(),
        history: history.clone(),
        xrays,
        finger: args.finger,
        note: args.note.clone(),
        settings: args.boot.settings()?,
    })?;
    let rows: Vec<String> = outcome
        .removed
        .iter()
        .map(|r| {
            format!(
                "{} {} (line {}{})",
                r.xray,
                r.finger.name(),
                r.line,
                if r.meta.flagged.is_some() {
                    ", added flagged"
                } else {
                    ""
                }
            )
        })
        .collect();
    out::print(
        format!(
            "removed {} from {}: {}; {} -> {} X-rays; snapshot appended to {}\n",
            crate::report::track_words::rows(outcome.removed.len()),
            args.data.data.display(),
            rows.join(", "),
            outcome.xrays_before,
            outcome.xrays_after,
            history.display()
        )
        .as_bytes(),
    )?;
    Ok(0)
}
