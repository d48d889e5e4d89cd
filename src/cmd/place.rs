//! `phalanx place`: where to put the joints of a model finger.

use super::args::{BootArgs, CorrelationArgs, DataArgs, TextFormat, parse_finger, parse_length};
use super::out;
use crate::analysis::placement;
use crate::dataset::Finger;
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;

/// Where to put the joints of a model finger of a given length (from its root joint)
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Positions are measured from the finger's root joint (MCP): PIP at J~1 x L, DIP at (J~1 + J~2) x L, \
                  the tip at L; the thumb's IP joint at J~1 x L. Lengths are in your model's units.\n\n\
                  With --reference, the positions come from another cohort: a dataset with per-hand values \
                  (e.g. the atlas, data/atlas/measurements.csv) or a published summary table \
                  (data/literature/); from a table they are its ratios of means, the tip at the skin when it \
                  gives the fingertip's soft tissue, and the intervals rest on an assumed correlation between \
                  its segments (--correlation, --correlation-from), which the output states.\n\n\
                  Examples:\n  phalanx place --finger index --length 1000\n  phalanx place --finger index --length 80 --reference data/literature/buryanov-kotiuk-2010.csv\n  phalanx place --hand thumb=5.1,index=7.9,middle=8.6,ring=8.1,little=6.4\n  phalanx place --finger ring --length 81.5 --format json"
)]
pub(crate) struct Args {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Place from this cohort instead of --data: a dataset (e.g. data/atlas/measurements.csv) or a summary table (e.g. data/literature/buryanov-kotiuk-2010.csv)
    #[arg(long, value_name = "DATA|TABLE")]
    reference: Option<std::path::PathBuf>,
    #[command(flatten)]
    correlation: CorrelationArgs,
    /// The finger (with --length)
    #[arg(long, value_parser = parse_finger, requires = "length", conflicts_with = "hand")]
    finger: Option<Finger>,
    /// The model finger's total length, root joint to tip (with --finger): greater than 0, at most 1e9
    #[arg(long, value_parser = parse_length, requires = "finger", allow_negative_numbers = true)]
    length: Option<f64>,
    /// Several fingers at once: FINGER=LENGTH,... (e.g. thumb=5.1,index=7.9), each length greater than 0, at most 1e9
    #[arg(long, value_name = "FINGER=L,...", value_parser = parse_hand)]
    hand: Option<Hand>,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

/// Model finger lengths given with `--hand`.
#[derive(Debug, Clone, PartialEq)]
struct Hand(Vec<(Finger, f64)>);

fn parse_hand(text: &str) -> Result<Hand, String> {
    let mut out: Vec<(Finger, f64)> = Vec::new();
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (f, l) = part
            .split_once('=')
            .ok_or_else(|| format!("'{part}' is not FINGER=LENGTH; e.g. index=7.9"))?;
        let finger = parse_finger(f)?;
        let length = parse_length(l.trim())?;
        if out.iter().any(|(g, _)| *g == finger) {
            return Err(format!("{finger} is given twice"));
        }
        out.push((finger, length));
    }
    if out.is_empty() {
        return Err("give at least one FINGER=LENGTH, e.g. index=7.9".into());
    }
    Ok(Hand(out))
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let wanted = match (args.finger, args.length, &args.hand) {
        (Some(f), Some(l), None) => vec![(f, l)],
        (None, None, Some(h)) => h.0.clone(),
        _ => {
            return Err(Error::Usage(
                "give --finger and --length, or --hand FINGER=L,... (see phalanx place --help)"
                    .into(),
            ));
        }
    };
    let settings = args.boot.settings()?;
    let data = match &args.reference {
        None => args.data.data.clone(),
        Some(r) => match crate::dataset::Source::load(r)? {
            crate::dataset::Source::Table(t) => return place_from_table(args, &t, &wanted, width),
            crate::dataset::Source::Data(_) => r.clone(),
        },
    };
    let a = super::load_and_analyse(&data, &settings)?;
    let mut placements = Vec::new();
    for (f, l) in wanted {
        placements.push(placement::place(&a, f, l).ok_or_else(|| {
            Error::Usage(format!(
                "{} has no {f} rows to place it from",
                a.dataset.path
            ))
        })?);
    }
    let bytes = match args.format {
        TextFormat::Table => {
            report::text::placement(&placements, a.settings.confidence, width).into_bytes()
        }
        TextFormat::Json => report::json::placement(&a, &placements)?,
    };
    out::print(&bytes)?;
    Ok(0)
}

/// `place --reference TABLE`: the joints from a summary table's ratios of means.
fn place_from_table(
    args: &Args,
    table: &crate::dataset::SummaryTable,
    wanted: &[(Finger, f64)],
    width: Width,
) -> Result<i32, Error> {
    let correlation = args.correlation.correlation()?;
    let confidence = args.boot.settings()?.confidence;
    let mut ps = Vec::new();
    for &(f, l) in wanted {
        let p = placement::place_from_table(table, f, l, correlation.of(f), confidence)
            .map_err(|e| Error::Usage(format!("{}: {e}; it cannot place the {f}", table.path)))?;
        ps.push(p);
    }
    let bytes = match args.format {
        TextFormat::Table => report::text::table_placement(
            &table.path,
            &ps,
            &report::compare_table::correlation_line(&correlation),
            confidence,
            width,
        )
        .into_bytes(),
        TextFormat::Json => report::json::table_placement(table, &correlation, confidence, &ps)?,
    };
    out::print(&bytes)?;
    Ok(0)
}
