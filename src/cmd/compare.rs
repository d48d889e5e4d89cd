//! `phalanx compare`: two cohorts of X-rays, finger by finger.

use super::args::{BootArgs, CorrelationArgs, TableFormat, TipArgs};
use super::out;
use crate::analysis::{compare, literature};
use crate::dataset::{CohortNotes, Dataset, Source};
use crate::error::Error;
use crate::report;
use crate::report::layout::Width;
use std::path::PathBuf;

/// Compare two cohorts finger by finger: its conclusion first, then differences, effect sizes and coverage
#[derive(clap::Args, Debug)]
#[command(
    after_help = "The output leads with its conclusion: one sentence overall and one per finger, then how \
                  the cohorts differ (age, side, fingertip, landmarks, from their rows and from the \
                  description X.cohort.csv beside a file X.csv), then the tables.\n\n\
                  Two datasets: for every finger and quantity both measure, n, mean and SD of each; the \
                  difference B - A with a Welch t interval and a bootstrap interval (each cohort resampled \
                  on its own, seeded); Hedges' g with its interval; and the external coverage, the share of \
                  B's X-rays inside A's prediction interval for one new X-ray and of A's inside B's; and the \
                  fingertip offset (a share of the finger's length) that would explain the difference of the \
                  last segment if one cohort measured to the skin and the other to the bone.\n\n\
                  A published summary table (finger,segment,mean,sd,n,unit; see data/literature/) on either \
                  side: its ratio of means for each quantity, with a delta-method standard error under an \
                  assumed correlation between segments (by default each finger's mean correlation of \
                  segment lengths in --correlation-from; --correlation R sets one), B - A with a Welch-type \
                  interval, and the verdict at correlations 0 and 0.9 beside the assumed one. When the table \
                  gives the fingertip's soft tissue, the dataset's last segment is set against the table's \
                  bone only and bone plus soft tissue, and the output says which it fits. Lengths are \
                  compared only in one physical unit. Rows of one dataset whose fingertips differ (bone \
                  with skin) are refused unless --mixed-tips.\n\n\
                  Examples:\n  phalanx compare data/measurements.csv data/atlas/measurements.csv\n  \
                  phalanx compare data/measurements.csv data/literature/buryanov-kotiuk-2010.csv\n  \
                  phalanx compare lab.csv data/literature/buryanov-kotiuk-2010.csv --correlation 0.6\n  \
                  phalanx compare lab.csv data/atlas/measurements.csv --format json\n  \
                  phalanx compare a.csv b.csv --format csv --resamples 2000"
)]
pub struct Args {
    /// Cohort A, a dataset or a summary table (the reference; differences are B - A)
    #[arg(value_name = "A")]
    a: PathBuf,
    /// Cohort B, a dataset or a summary table
    #[arg(value_name = "B")]
    b: PathBuf,
    #[command(flatten)]
    boot: BootArgs,
    #[command(flatten)]
    correlation: CorrelationArgs,
    #[command(flatten)]
    tips: TipArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
    /// Leave out of B the X-rays it shares with A (the same rows), which are refused otherwise
    #[arg(long)]
    drop_shared: bool,
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let settings = args.boot.settings()?;
    let a = Source::load(&args.a)?;
    let b = Source::load(&args.b)?;
    for s in [&a, &b] {
        if let Source::Data(d) = s {
            args.tips.check(d)?;
        }
    }
    let (notes_a, notes_b) = (CohortNotes::beside(&args.a)?, CohortNotes::beside(&args.b)?);
    let bytes = match (&a, &b) {
        (Source::Data(x), Source::Data(y)) => {
            let own = independent(x, y, args.drop_shared)?;
            let mut c = compare::cohorts(x, own.as_ref().unwrap_or(y), &settings);
            if c.fingers.is_empty() {
                return Err(no_common(&a, &b));
            }
            (c.a.about, c.b.about) = (notes_a, notes_b);
            match args.format {
                TableFormat::Table => report::compare::text(&c, width).into_bytes(),
                TableFormat::Json => report::json::compare(&c)?,
                TableFormat::Csv => report::compare::csv(&c)?,
            }
        }
        _ => {
            let correlation = args.correlation.correlation()?;
            let mut c = literature::tables(side(&a), side(&b), &correlation, settings.confidence);
            if c.fingers.is_empty() {
                return Err(no_common(&a, &b));
            }
            (c.a.about, c.b.about) = (notes_a, notes_b);
            match args.format {
                TableFormat::Table => report::compare_table::text(&c, width).into_bytes(),
                TableFormat::Json => report::json::compare_table(&c)?,
                TableFormat::Csv => report::compare_table::csv(&c)?,
            }
        }
    };
    out::print(&bytes)?;
    Ok(0)
}

/// B without the X-rays it shares with A when asked (`--drop-shared`, said on stderr),
/// `None` when they share none; shared X-rays are refused otherwise: two cohorts that
/// hold the same hands are not independent.
fn independent(a: &Dataset, b: &Dataset, drop: bool) -> Result<Option<Dataset>, Error> {
    let shared = compare::shared_xrays(a, b);
    if shared.is_empty() {
        return Ok(None);
    }
    let n = shared.len();
    let which = shared_words(&shared);
    let total = b.xray_count();
    if !drop {
        return Err(Error::Usage(format!(
            "{} and {} share {n} of B's {total} X-ray{} (the same rows): {which}. Two cohorts that hold the same hands are not independent, so their differences and intervals would mean nothing. Compare B's own X-rays with --drop-shared (B without them), or compare A with a file of B's new rows only",
            a.path,
            b.path,
            if total == 1 { "" } else { "s" },
        )));
    }
    if n == total {
        return Err(Error::Usage(format!(
            "every X-ray of {} is one of {} ({which}): with --drop-shared nothing is left to compare",
            b.path, a.path
        )));
    }
    let mut own = b.clone();
    own.rows.retain(|r| !shared.iter().any(|s| *s.b == *r.xray));
    eprintln!(
        "note: B ({}) without the {n} X-ray{} it shares with A ({}): {which}; {} X-rays of B compared",
        b.path,
        if n == 1 { "" } else { "s" },
        a.path,
        own.xray_count()
    );
    Ok(Some(own))
}

/// "X-rays 1-5" (the same ids in both), or "B's 7 is A's 1, ..." where they differ.
fn shared_words(shared: &[compare::SharedXray]) -> String {
    if shared.iter().all(|s| s.a == s.b) {
        let ids: Vec<&str> = shared.iter().map(|s| s.b.as_str()).collect();
        let noun = if ids.len() == 1 { "X-ray" } else { "X-rays" };
        return format!("{noun} {}", crate::dataset::append::id_ranges(&ids));
    }
    let pairs: Vec<String> = shared
        .iter()
        .map(|s| {
            if s.a == s.b {
                format!("{} in both", s.b)
            } else {
                format!("B's {} is A's {}", s.b, s.a)
            }
        })
        .collect();
    pairs.join(", ")
}

fn no_common(a: &Source, b: &Source) -> Error {
    Error::Usage(format!(
        "{} and {} have no finger in common to compare",
        a.path(),
        b.path()
    ))
}

fn side(s: &Source) -> literature::Side<'_> {
    match s {
        Source::Data(d) => literature::Side::Data(d),
        Source::Table(t) => literature::Side::Table(t),
    }
}
