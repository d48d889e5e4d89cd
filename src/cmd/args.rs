//! Option groups and value parsers shared by several commands.
//!
//! Every option value is checked here, where it is parsed: what reaches the
//! library is valid.

use crate::analysis::groups::{self, GroupBy};
use crate::analysis::{self, Settings, budget};
use crate::dataset::Finger;
use crate::error::Error;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

/// Default measurement file.
pub(crate) const DEFAULT_DATA: &str = "data/measurements.csv";
/// Default claims file.
pub(crate) const DEFAULT_CLAIMS: &str = "data/paper_claims.csv";

/// What to say when a default input is missing: most likely phalanx runs
/// outside its checkout, where `data/` is not. `None` for any other path, or
/// when the file is there.
pub(crate) fn missing_default(path: &Path) -> Option<Error> {
    let option = if path == Path::new(DEFAULT_DATA) {
        "--data"
    } else if path == Path::new(DEFAULT_CLAIMS) {
        "--claims"
    } else {
        return None;
    };
    if path.exists() {
        return None;
    }
    let here = std::env::current_dir()
        .map(|d| d.display().to_string())
        .unwrap_or_else(|_| "the current directory".to_string());
    Some(Error::Usage(format!(
        "{} is not in {here}: phalanx reads data/ from the directory it runs in. \
         Run it from the phalanx checkout (the directory with Cargo.toml and data/), or give {option} PATH",
        path.display()
    )))
}

/// A command's error, with what to do when it is a default input that does
/// not exist ([`missing_default`]); other errors pass through.
pub(crate) fn outside_checkout(e: Error) -> Error {
    match &e {
        Error::Data(d) if d.problems.iter().all(|p| p.line.is_none()) => {
            missing_default(Path::new(&d.file)).unwrap_or(e)
        }
        _ => e,
    }
}

/// The dataset to read.
#[derive(Args, Debug, Clone)]
pub(crate) struct DataArgs {
    /// Measurement CSV (columns xray,finger,j1,j2,j3[,mc,sex,age,side,source,unit,tip])
    #[arg(long, value_name = "PATH", default_value = DEFAULT_DATA)]
    pub(crate) data: PathBuf,
}

/// Bootstrap and interval settings.
#[derive(Args, Debug, Clone, Copy)]
pub(crate) struct BootArgs {
    /// Bootstrap resamples, 1 to 1000000 (exact enumeration is used when it needs fewer; at most 10^10 resample-X-ray pairs)
    #[arg(long, value_name = "B", default_value_t = analysis::DEFAULT_RESAMPLES, value_parser = parse_resamples, allow_negative_numbers = true)]
    pub(crate) resamples: usize,
    /// Seed of the random streams (ChaCha8), a whole number from 0 to 18446744073709551615
    #[arg(long, value_name = "S", default_value_t = analysis::DEFAULT_SEED, value_parser = parse_seed, allow_negative_numbers = true)]
    pub(crate) seed: u64,
    /// Confidence level of every interval, from 0.0001 to 0.9999
    #[arg(long, value_name = "C", default_value_t = analysis::DEFAULT_CONFIDENCE, value_parser = parse_confidence, allow_negative_numbers = true)]
    pub(crate) confidence: f64,
}

impl BootArgs {
    /// The analysis settings, checked (the value parsers have refused bad values already).
    pub(crate) fn settings(&self) -> Result<Settings, Error> {
        Settings::new(self.resamples, self.seed, self.confidence).map_err(Error::Usage)
    }
}

/// Grouping of X-rays (the paper's future work: statistics by sex and age).
#[derive(Args, Debug, Clone)]
pub(crate) struct GroupArgs {
    /// Also compute every statistic per group of X-rays
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub(crate) group_by: Option<GroupColumn>,
    /// Age band edges in years for --group-by age: comma-separated, strictly ascending, each from 0 to 150
    #[arg(long, value_name = "EDGES", default_value = "0,18,40,65", value_parser = parse_age_bins, allow_negative_numbers = true)]
    pub(crate) age_bins: AgeBins,
}

/// Age band edges, as given with `--age-bins`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AgeBins(pub(crate) Vec<f64>);

/// Comma-separated age band edges: each a number of years from 0 to 150, strictly ascending.
pub(crate) fn parse_age_bins(text: &str) -> Result<AgeBins, String> {
    let usage =
        "give comma-separated ages in years from 0 to 150, strictly ascending, e.g. 0,18,40,65";
    let mut edges = Vec::new();
    for part in text.split(',').map(str::trim) {
        match part.parse::<f64>() {
            Ok(e) if e.is_finite() && (0.0..=150.0).contains(&e) => edges.push(e),
            _ if part.is_empty() => return Err(format!("'{text}' has an empty edge; {usage}")),
            _ => return Err(format!("'{part}' is not an age from 0 to 150; {usage}")),
        }
    }
    if edges.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!("'{text}' is not strictly ascending; {usage}"));
    }
    Ok(AgeBins(edges))
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum GroupColumn {
    Sex,
    Age,
    Side,
}

impl GroupArgs {
    /// The grouping asked for, validated.
    pub(crate) fn group_by(&self) -> Result<Option<GroupBy>, Error> {
        Ok(match self.group_by {
            None => None,
            Some(GroupColumn::Sex) => Some(GroupBy::Sex),
            Some(GroupColumn::Side) => Some(GroupBy::Side),
            Some(GroupColumn::Age) => {
                groups::validate_age_bins(&self.age_bins.0).map_err(Error::Usage)?;
                Some(GroupBy::Age(self.age_bins.0.clone()))
            }
        })
    }
}

/// The history file.
#[derive(Args, Debug, Clone)]
pub(crate) struct HistoryArgs {
    /// History file (JSON Lines); default: history.jsonl beside the dataset
    #[arg(long = "history", value_name = "PATH")]
    pub(crate) path: Option<PathBuf>,
}

impl HistoryArgs {
    /// The history file for a dataset.
    pub(crate) fn resolve(&self, data: &Path) -> PathBuf {
        self.path
            .clone()
            .unwrap_or_else(|| crate::dataset::history::default_path(data))
    }
}

/// Output format of the commands that print a table, a JSON document or CSV
/// (`stats`, `compare`).
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TableFormat {
    Table,
    Json,
    Csv,
}

/// Output format of the commands that print a table or a JSON document.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TextFormat {
    Table,
    Json,
}

/// A finger name or alias.
pub(crate) fn parse_finger(text: &str) -> Result<Finger, String> {
    Finger::parse(text).ok_or_else(|| format!("unknown finger '{text}'; use {}", Finger::ACCEPTED))
}

/// Largest length accepted for a model finger (`--length`, `--hand`, `--model-length`).
pub(crate) const MAX_LENGTH: f64 = 1e9;

/// A model length: greater than 0 and at most 1e9.
pub(crate) fn parse_length(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(l) if l.is_finite() && l > 0.0 && l <= MAX_LENGTH => Ok(l),
        _ => Err(format!(
            "'{text}' is not a length greater than 0 and at most 1e9 (in your model's units); give e.g. 1000"
        )),
    }
}

/// A whole number from `lo` to `hi`; the error states the range and `hint`.
pub(crate) fn parse_whole(text: &str, lo: u64, hi: u64, hint: &str) -> Result<u64, String> {
    match text.trim().parse::<u64>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!(
            "'{text}' is not a whole number from {lo} to {hi}{hint}"
        )),
    }
}

/// Smallest and largest confidence level accepted.
pub(crate) const CONFIDENCE_RANGE: (f64, f64) = (0.0001, 0.9999);

fn parse_confidence(text: &str) -> Result<f64, String> {
    let (lo, hi) = CONFIDENCE_RANGE;
    match text.trim().parse::<f64>() {
        Ok(c) if (lo..=hi).contains(&c) => Ok(c),
        _ => Err(format!(
            "'{text}' is not a confidence level from {lo} to {hi} (strictly between 0 and 1); give e.g. 0.95"
        )),
    }
}

fn parse_resamples(text: &str) -> Result<usize, String> {
    parse_whole(
        text,
        1,
        budget::MAX_RESAMPLES as u64,
        "; the default is 10000",
    )
    .map(|b| b as usize)
}

/// A seed: any 64-bit unsigned whole number.
pub(crate) fn parse_seed(text: &str) -> Result<u64, String> {
    parse_whole(text, 0, u64::MAX, "; e.g. 20130101")
}

/// Simulated datasets: 1 to [`budget::MAX_SIMS`].
pub(crate) fn parse_sims(text: &str) -> Result<u64, String> {
    parse_whole(text, 1, budget::MAX_SIMS as u64, "; the default is 4000")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_age_bins_parse_to_the_library_default() {
        assert_eq!(
            parse_age_bins("0,18,40,65").unwrap().0,
            groups::DEFAULT_AGE_BINS.to_vec()
        );
        assert!(
            parse_age_bins("0;18")
                .unwrap_err()
                .contains("comma-separated")
        );
        assert!(
            parse_age_bins("18,0")
                .unwrap_err()
                .contains("strictly ascending")
        );
        assert!(parse_age_bins("0,,18").unwrap_err().contains("empty edge"));
        assert!(parse_age_bins("151").unwrap_err().contains("from 0 to 150"));
    }
}

/// The default dataset a summary table's correlations between segments are taken from.
pub(crate) const DEFAULT_CORRELATION_FROM: &str = "data/atlas/measurements.csv";

/// The correlation assumed between the segments of a summary table (which gives none).
#[derive(Args, Debug, Clone)]
pub(crate) struct CorrelationArgs {
    /// Correlation assumed between any two segments of a summary table's finger, from 0 to 1 (default: measured on --correlation-from)
    #[arg(long, value_name = "R", value_parser = parse_correlation, allow_negative_numbers = true, conflicts_with = "correlation_from")]
    pub(crate) correlation: Option<f64>,
    /// Dataset with per-hand values whose segment-length correlations a summary table is assumed to share
    #[arg(long, value_name = "PATH", default_value = DEFAULT_CORRELATION_FROM)]
    pub(crate) correlation_from: PathBuf,
}

impl CorrelationArgs {
    /// The assumed correlation: given, or measured on the dataset named (refused with the
    /// way out when the default dataset is not there).
    pub(crate) fn correlation(&self) -> Result<analysis::literature::Correlation, Error> {
        if let Some(r) = self.correlation {
            return Ok(analysis::literature::Correlation::given(r));
        }
        if self.correlation_from == Path::new(DEFAULT_CORRELATION_FROM)
            && !self.correlation_from.exists()
        {
            return Err(Error::Usage(format!(
                "a summary table gives no correlations between its segments, and {DEFAULT_CORRELATION_FROM} (whose per-hand correlations are assumed by default) is not in the current directory; run from the phalanx checkout, or give --correlation-from PATH (a dataset with per-hand values) or --correlation R"
            )));
        }
        let data = crate::dataset::Dataset::load(&self.correlation_from)?;
        Ok(analysis::literature::correlations_from(&data))
    }
}

/// A correlation from 0 to 1.
fn parse_correlation(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(r) if (0.0..=1.0).contains(&r) => Ok(r),
        _ => Err(format!(
            "'{text}' is not a correlation from 0 to 1 (e.g. 0.5)"
        )),
    }
}

/// Where fingertip landmarks are, as an option (`--tip bone|skin`).
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TipArg {
    Bone,
    Skin,
}

impl TipArg {
    /// The tip kind named.
    pub(crate) fn kind(self) -> crate::dataset::TipKind {
        match self {
            TipArg::Bone => crate::dataset::TipKind::Bone,
            TipArg::Skin => crate::dataset::TipKind::Skin,
        }
    }
}

/// Whether rows whose fingertips differ (bone with skin) may be pooled.
#[derive(Args, Debug, Clone, Copy)]
pub(crate) struct TipArgs {
    /// Pool rows whose fingertips differ (some at the bone, some at the skin), which is refused otherwise
    #[arg(long)]
    pub(crate) mixed_tips: bool,
}

impl TipArgs {
    /// Refuses a dataset that mixes bone and skin tips, unless --mixed-tips.
    pub(crate) fn check(&self, data: &crate::dataset::Dataset) -> Result<(), Error> {
        if self.mixed_tips {
            return Ok(());
        }
        match crate::dataset::tip::pooling_problem(&[(&data.path, &data.rows)], "--mixed-tips") {
            Some(m) => Err(Error::Usage(m)),
            None => Ok(()),
        }
    }
}

/// `--force`: replace outputs that exist.
#[derive(Args, Debug, Clone, Copy)]
pub(crate) struct ForceArgs {
    /// Replace output files that already exist (without it, an existing output is refused
    /// before any work)
    #[arg(long)]
    pub(crate) force: bool,
}

/// Checks, before any work, that `option`'s file `path` can be written
/// ([`crate::atomic::check_target`]).
pub(crate) fn check_output_file(option: &str, path: &Path, force: bool) -> Result<(), Error> {
    crate::atomic::check_target(path, force)
        .map_err(|e| Error::Usage(format!("{option} {}: {e}", path.display())))
}

/// Checks, before any work, that `option`'s directory `dir` can take the files
/// `names` ([`crate::atomic::check_dir_targets`]).
pub(crate) fn check_output_dir(
    option: &str,
    dir: &Path,
    names: &[String],
    force: bool,
) -> Result<(), Error> {
    crate::atomic::check_dir_targets(dir, names, force)
        .map_err(|e| Error::Usage(format!("{option} {}: {e}", dir.display())))
}

/// The metacarpals' dataset when given or when the default exists.
pub(crate) const DEFAULT_METACARPALS: &str = "data/atlas/measurements.csv";

/// The metacarpals' dataset `audit`, `deform` and `rig` use: `given`, or the default where it exists.
pub(crate) fn metacarpals_or_default(given: Option<&Path>) -> Option<PathBuf> {
    match given {
        Some(path) => Some(path.to_path_buf()),
        None => Some(PathBuf::from(DEFAULT_METACARPALS)).filter(|p| p.is_file()),
    }
}
