//! `phalanx history`: how the statistics moved, snapshot by snapshot.

use super::args::{DataArgs, HistoryArgs, TextFormat, parse_finger};
use super::out;
use crate::analysis::Quantity;
use crate::dataset::Finger;
use crate::dataset::history::Snapshot;
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;

/// Show how the statistics moved, snapshot by snapshot
#[derive(clap::Args, Debug)]
#[command(
    after_help = "By default: the snapshots (each with the X-rays it added or removed, the file, the rows let in \
                  flagged, the note) and one table of the quantities that moved most from the first snapshot to the \
                  last; --finger and --quantity pick the quantities (both: that one, snapshot by snapshot); --all \
                  shows every quantity snapshot by snapshot.\n\n\
                  Examples:\n  phalanx history\n  phalanx history --finger index --quantity rel_j1\n  phalanx history --all --finger ring\n  phalanx history --format json"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    history: HistoryArgs,
    /// Only this finger (thumb, index, middle, ring, little, or an alias)
    #[arg(long, value_parser = parse_finger)]
    finger: Option<Finger>,
    /// Only this quantity: rel_j1, rel_j2, rel_j3 (not the thumb), ratio_j2_j1, ratio_j3_j2 (not the thumb) or total
    #[arg(long, value_parser = parse_quantity)]
    quantity: Option<Quantity>,
    /// Every selected quantity's table, snapshot by snapshot
    #[arg(long)]
    all: bool,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

fn parse_quantity(text: &str) -> Result<Quantity, String> {
    Quantity::parse(text).ok_or_else(|| {
        let names: Vec<&str> = Quantity::ALL.iter().map(|q| q.name()).collect();
        format!("unknown quantity '{text}'; use one of {}", names.join(", "))
    })
}

/// Why `--finger`/`--quantity` select nothing from non-empty snapshots.
fn why_empty(
    path: &std::path::Path,
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
) -> String {
    let names = |qs: &[Quantity]| qs.iter().map(|q| q.name()).collect::<Vec<_>>().join(", ");
    if let (Some(f), Some(q)) = (finger, quantity)
        && !Quantity::of(f).contains(&q)
    {
        return format!(
            "the {f} has no {} ({} segments); its quantities are {}",
            q.name(),
            f.segments(),
            names(Quantity::of(f))
        );
    }
    let mut fingers: Vec<&str> = Vec::new();
    for r in snaps.iter().flat_map(|s| &s.quantities) {
        if !fingers.contains(&r.finger.name()) {
            fingers.push(r.finger.name());
        }
    }
    let what = match (finger, quantity) {
        (Some(f), Some(q)) => format!("{f} {}", q.name()),
        (Some(f), None) => format!("{f} rows"),
        (None, Some(q)) => q.name().to_string(),
        (None, None) => "quantities".to_string(),
    };
    format!(
        "none of the {} snapshots in {} has {what} (fingers recorded: {})",
        snaps.len(),
        path.display(),
        if fingers.is_empty() {
            "none".to_string()
        } else {
            fingers.join(", ")
        }
    )
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    // Outside the checkout the default history is missing too: say why, not "no snapshots yet".
    if args.history.path.is_none()
        && let Some(e) = super::args::missing_default(&args.data.data)
    {
        return Err(e);
    }
    let path = args.history.resolve(&args.data.data);
    let snaps = crate::dataset::history::read(&path)?;
    if !snaps.is_empty()
        && crate::analysis::tracking::selected(&snaps, args.finger, args.quantity).is_empty()
    {
        return Err(Error::Usage(format!(
            "nothing to show: {}",
            why_empty(&path, &snaps, args.finger, args.quantity)
        )));
    }
    let bytes = match args.format {
        TextFormat::Table => {
            report::text::history(&path, &snaps, args.finger, args.quantity, args.all, width)
                .into_bytes()
        }
        TextFormat::Json => report::json::history(&snaps, args.finger, args.quantity)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
