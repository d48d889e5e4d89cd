//! `phalanx add`: new X-rays into the dataset, with a snapshot in the history.

use super::args::{BootArgs, DataArgs, HistoryArgs, TipArg};
use super::out;
use crate::error::Error;
use crate::report::track_words;
use crate::track::{self, AddRequest, NewRows};
use std::path::PathBuf;

/// Add new X-rays to the dataset (validated, locked, atomic) and record a snapshot
#[derive(clap::Args, Debug)]
#[command(
    after_help = "New rows pass every check of the dataset and may not repeat an (xray, finger) already there; \
                  on any problem nothing is added. A row is flagged as a likely measurement or typing error \
                  when a relative value J~k lies outside its prediction interval at level 1 - 0.01/k (k segments; a genuine row \
                  is flagged at most 1% of the time), or a length is over 3.16 (sqrt 10) times or under 1/3.16 times the median \
                  of that length in the same unit (a misplaced decimal point). Flagged rows are refused, each with its line \
                  and why (exit 2, nothing added); --accept-flagged adds them, recorded as flagged in the dataset's \
                  'flagged' column and in the history. 'phalanx remove' takes rows out again.\n\n\
                  Rows may give their lengths in another unit than the dataset's (relative values pool across units), \
                  and columns the dataset lacks (mc, tip, unit, ...): they are added to its header.\n\n\
                  Every row is written with where its fingertip was measured (the tip column): its own tip, else --tip, \
                  else the one its X-ray's rows record, else the one every row of the dataset records, which add then \
                  names. Into a dataset whose tips are mixed or not recorded, rows without a tip are refused: give \
                  --tip bone or --tip skin. A row whose own tip differs from --tip is refused, and so are rows at the \
                  bone into a dataset at the skin (or the reverse) unless --mixed-tips.\n\n\
                  Examples:\n  phalanx add new_xrays.csv --note \"batch 2 from the March session\"\n  \
                  phalanx add lab_xrays.csv --tip bone --data lab.csv\n  phalanx add --xray 2a --finger index --lengths 352.1,201.4,178.0 --sex female --age 34\n  phalanx add --accept-flagged --xray 2a --finger thumb --lengths 270.1,233.9"
)]
pub(crate) struct Args {
    /// CSV file of new rows, in the dataset's format (with a header)
    #[arg(value_name = "FILE.csv", conflicts_with_all = ["xray", "finger", "lengths"])]
    file: Option<PathBuf>,
    /// X-ray id of one new row
    #[arg(long, requires_all = ["finger", "lengths"])]
    xray: Option<String>,
    /// Finger of the new row
    #[arg(long, requires_all = ["xray", "lengths"])]
    finger: Option<String>,
    /// Segment lengths J1,J2[,J3] of the new row (J3 not for the thumb)
    #[arg(long, value_name = "J1,J2[,J3]", requires_all = ["xray", "finger"], allow_hyphen_values = true)]
    lengths: Option<String>,
    /// Sex of the hand (female, male, ...)
    #[arg(long)]
    sex: Option<String>,
    /// Age in years, from 0 to 150
    #[arg(long, allow_negative_numbers = true)]
    age: Option<String>,
    /// left or right
    #[arg(long)]
    side: Option<String>,
    /// Where the measurement comes from
    #[arg(long)]
    source: Option<String>,
    /// Unit of the lengths (e.g. mm; another than the dataset's is fine)
    #[arg(long)]
    unit: Option<String>,
    /// Where the fingertips of the new rows were measured; rows that give no tip take it
    #[arg(long, value_enum)]
    tip: Option<TipArg>,
    /// Add rows flagged as likely errors too (refused otherwise); they are recorded as flagged
    #[arg(long)]
    accept_flagged: bool,
    /// Refuse rows flagged as likely errors (the default; kept for scripts)
    #[arg(long, hide = true, conflicts_with = "accept_flagged")]
    strict: bool,
    /// A note for the history record (e.g. where the X-rays come from)
    #[arg(long, value_name = "TEXT")]
    note: Option<String>,
    /// Add rows whose fingertips differ from the dataset's (bone with skin), which is refused otherwise
    #[arg(long)]
    mixed_tips: bool,
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    #[command(flatten)]
    boot: BootArgs,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    let rows = new_rows(args)?;
    let history = args.history.resolve(&args.data.data);
    let outcome = track::add(&AddRequest {
        data: args.data.data.clone(),
        history: history.clone(),
        rows,
        accept_flagged: args.accept_flagged && !args.strict,
        note: args.note.clone(),
        mixed_tips: args.mixed_tips,
        tip: args.tip.map(TipArg::kind),
        settings: args.boot.settings()?,
    })?;
    for line in super::added_messages(&outcome, &args.data.data) {
        eprintln!("{line}");
    }
    out::print(
        format!(
            "added {} to {}: {} -> {} X-rays{}; snapshot appended to {}\n",
            track_words::rows(outcome.added),
            args.data.data.display(),
            outcome.xrays_before,
            outcome.xrays_after,
            track_words::flagged(outcome.flags.len()),
            history.display()
        )
        .as_bytes(),
    )?;
    Ok(0)
}

/// The new rows: a file, or one row from the options.
fn new_rows(args: &Args) -> Result<NewRows, Error> {
    match (&args.file, &args.xray, &args.finger, &args.lengths) {
        (Some(f), ..) => Ok(NewRows::File(f.clone())),
        (None, Some(x), Some(f), Some(l)) => Ok(NewRows::Fields(row_fields(args, x, f, l)?)),
        _ => Err(Error::Usage(
            "give a CSV file of new rows, or --xray, --finger and --lengths for one row (see phalanx add --help)".into(),
        )),
    }
}

/// The (column, value) pairs of a row given as options.
fn row_fields(
    args: &Args,
    xray: &str,
    finger: &str,
    lengths: &str,
) -> Result<Vec<(&'static str, String)>, Error> {
    let mut parts: Vec<String> = lengths.split(',').map(|p| p.trim().to_string()).collect();
    if parts.len() < 2 || parts.len() > 3 {
        return Err(Error::Usage(format!(
            "--lengths '{lengths}': give 2 (thumb) or 3 (other fingers) comma-separated lengths, e.g. 352.1,201.4,178.0"
        )));
    }
    parts.resize(3, String::new());
    let mut fields = vec![
        ("xray", xray.to_string()),
        ("finger", finger.to_string()),
        ("j1", parts[0].clone()),
        ("j2", parts[1].clone()),
        ("j3", parts[2].clone()),
    ];
    for (name, v) in [
        ("sex", &args.sex),
        ("age", &args.age),
        ("side", &args.side),
        ("source", &args.source),
        ("unit", &args.unit),
    ] {
        if let Some(v) = v {
            fields.push((name, v.clone()));
        }
    }
    Ok(fields)
}
