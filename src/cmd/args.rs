//! Option groups and value parsers shared by several commands.
//!
//! Every option value is checked here, where it is parsed: what reaches the
//! library is valid.

use crate::analysis::groups::{self, GroupBy};
use crate::analysis::{self, Settings};
use crate::dataset::Finger;
use crate::error::Error;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

/// Default measurement file.
pub(crate) const DEFAULT_DATA: &str = "data/measurements.csv";
/// Default claims file.
pub(crate) const DEFAULT_CLAIMS: &str = "data/paper_claims.csv";

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
    /// Bootstrap resamples (exact enumeration is used when it needs fewer)
    #[arg(long, value_name = "B", default_value_t = analysis::DEFAULT_RESAMPLES, value_parser = parse_resamples)]
    pub(crate) resamples: usize,
    /// Seed of the random streams (ChaCha8)
    #[arg(long, value_name = "S", default_value_t = analysis::DEFAULT_SEED)]
    pub(crate) seed: u64,
    /// Confidence level of every interval, strictly between 0 and 1
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
    /// Age band edges for --group-by age, ascending
    #[arg(long, value_name = "EDGES", value_delimiter = ',', default_values_t = groups::DEFAULT_AGE_BINS, allow_negative_numbers = true)]
    pub(crate) age_bins: Vec<f64>,
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
                groups::validate_age_bins(&self.age_bins).map_err(Error::Usage)?;
                Some(GroupBy::Age(self.age_bins.clone()))
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

/// A finite positive length.
pub(crate) fn parse_length(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(l) if l.is_finite() && l > 0.0 => Ok(l),
        _ => Err(format!("'{text}' is not a positive length; give e.g. 1000")),
    }
}

fn parse_confidence(text: &str) -> Result<f64, String> {
    let c: f64 = text
        .parse()
        .map_err(|_| format!("'{text}' is not a number; give e.g. 0.95"))?;
    if c > 0.0 && c < 1.0 {
        Ok(c)
    } else {
        Err(format!(
            "{c} is not strictly between 0 and 1; give e.g. 0.95"
        ))
    }
}

fn parse_resamples(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(b) if (1..=100_000_000).contains(&b) => Ok(b),
        _ => Err(format!(
            "'{text}' is not a whole number from 1 to 100000000; the default is 10000"
        )),
    }
}
