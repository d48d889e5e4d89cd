//! Command-line interface: parses arguments and hands work to the library.

use crate::analysis::claims::{self, CheckSummary};
use crate::analysis::coverage::{self, CoverageSettings};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::dataset::claims::Claims;
use crate::error::{EXIT_DATA, EXIT_FAILURE, Error};
use crate::report;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Default measurement file.
pub const DEFAULT_DATA: &str = "data/measurements.csv";
/// Default claims file.
pub const DEFAULT_CLAIMS: &str = "data/paper_claims.csv";

#[derive(Parser, Debug)]
#[command(
    name = "phalanx",
    version,
    about = "Finger-joint statistics from hand X-ray measurements, for placing the joints of rigged hands",
    long_about = "Finger-joint statistics from hand X-ray measurements, for placing the joints of rigged hands.\n\n\
                  Reproduces Chaudhry et al., 'Statistical Analysis of Joint Determination for Skeleton \
                  Driven Animation of Human Hands', checks every number it states, and adds standard \
                  deviations, bootstrap and t intervals and prediction intervals.",
    after_help = "Exit status: 0 success, 1 failure (or 'check' found a new mismatch), 2 bad input data or options.\n\n\
                  Examples:\n  phalanx stats\n  phalanx check\n  phalanx report"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Statistics of every finger: the paper's (mean, min, max, range) and beyond
    #[command(
        after_help = "Examples:\n  phalanx stats\n  phalanx stats --format json > stats.json\n  phalanx stats --format csv --resamples 20000 --seed 7 --confidence 0.9"
    )]
    Stats {
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        boot: BootArgs,
        /// Output format
        #[arg(long, value_enum, default_value_t = StatsFormat::Table)]
        format: StatsFormat,
    },
    /// Recompute every number the paper states and explain each disagreement
    #[command(
        after_help = "Exits 0 when every claim matches or is a recorded erratum, 1 when a new mismatch appears.\n\n\
                            Examples:\n  phalanx check\n  phalanx check --claims my_claims.csv --format json"
    )]
    Check {
        #[command(flatten)]
        data: DataArgs,
        /// The claims file (one row per number the paper states)
        #[arg(long, value_name = "PATH", default_value = DEFAULT_CLAIMS)]
        claims: PathBuf,
        /// Output format
        #[arg(long, value_enum, default_value_t = TextFormat::Table)]
        format: TextFormat,
    },
    /// Estimate by simulation how often each interval method really covers at the data's n
    #[command(
        after_help = "Examples:\n  phalanx coverage\n  phalanx coverage --sims 20000 --format json"
    )]
    Coverage {
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        boot: BootArgs,
        /// Simulated datasets per sample size
        #[arg(long, default_value_t = 4000, value_parser = clap::value_parser!(u64).range(1..))]
        sims: u64,
        /// Output format
        #[arg(long, value_enum, default_value_t = TextFormat::Table)]
        format: TextFormat,
    },
}

/// The dataset to read.
#[derive(Args, Debug, Clone)]
pub struct DataArgs {
    /// Measurement CSV (columns xray,finger,j1,j2,j3[,sex,age,side,source,unit])
    #[arg(long, value_name = "PATH", default_value = DEFAULT_DATA)]
    pub data: PathBuf,
}

/// Bootstrap and interval settings.
#[derive(Args, Debug, Clone, Copy)]
pub struct BootArgs {
    /// Bootstrap resamples (exact enumeration is used when it needs fewer)
    #[arg(long, value_name = "B", default_value_t = analysis::DEFAULT_RESAMPLES, value_parser = parse_resamples)]
    pub resamples: usize,
    /// Seed of the random streams (ChaCha8)
    #[arg(long, value_name = "S", default_value_t = analysis::DEFAULT_SEED)]
    pub seed: u64,
    /// Confidence level of every interval, strictly between 0 and 1
    #[arg(long, value_name = "C", default_value_t = analysis::DEFAULT_CONFIDENCE, value_parser = parse_confidence)]
    pub confidence: f64,
}

impl BootArgs {
    /// The analysis settings.
    pub fn settings(&self) -> Settings {
        Settings {
            resamples: self.resamples,
            seed: self.seed,
            confidence: self.confidence,
        }
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

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatsFormat {
    Table,
    Json,
    Csv,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextFormat {
    Table,
    Json,
}

/// Runs phalanx with the process arguments; returns the exit status.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { EXIT_DATA } else { 0 };
            let _ = e.print();
            return code;
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("{}", crate::error::report(&e));
            e.exit_code()
        }
    }
}

/// Runs one parsed command; returns the exit status on success.
pub fn run(cli: Cli) -> Result<i32, Error> {
    match cli.command {
        Command::Stats { data, boot, format } => {
            let a = load_and_analyse(&data.data, &boot.settings())?;
            let bytes = match format {
                StatsFormat::Table => report::text::stats(&a).into_bytes(),
                StatsFormat::Json => report::json::stats(&a)?,
                StatsFormat::Csv => report::csv_out::stats(&a)?,
            };
            print(&bytes)?;
            Ok(0)
        }
        Command::Check {
            data,
            claims,
            format,
        } => {
            let dataset = Dataset::load(&data.data)?;
            let claims = Claims::load(&claims)?;
            claims.check_against(&dataset)?;
            let results = claims::check(&claims, &dataset);
            let info = analysis::DatasetInfo::of(&dataset);
            let bytes = match format {
                TextFormat::Table => report::text::check(&results).into_bytes(),
                TextFormat::Json => report::json::check(&info, &claims.path, &results)?,
            };
            print(&bytes)?;
            let s = CheckSummary::of(&results);
            if s.mismatches > 0 {
                eprintln!(
                    "phalanx: {} claim(s) disagree with the data and are not recorded as errata",
                    s.mismatches
                );
                return Ok(EXIT_FAILURE);
            }
            Ok(0)
        }
        Command::Coverage {
            data,
            boot,
            sims,
            format,
        } => {
            let a = load_and_analyse(&data.data, &boot.settings())?;
            let s = CoverageSettings {
                sims: sims as usize,
                resamples: boot.resamples,
                seed: boot.seed,
                confidence: boot.confidence,
            };
            let rows = coverage::of_analysis(&a, &s);
            let bytes = match format {
                TextFormat::Table => report::text::coverage(&rows, s.confidence).into_bytes(),
                TextFormat::Json => report::json::coverage(&a.dataset, &s, &rows)?,
            };
            print(&bytes)?;
            Ok(0)
        }
    }
}

/// Loads a dataset and analyses it.
pub fn load_and_analyse(path: &Path, settings: &Settings) -> Result<Analysis, Error> {
    settings.validate().map_err(Error::Usage)?;
    let data = Dataset::load(path)?;
    Ok(analysis::analyse(&data, settings))
}

/// Writes to standard output; a closed pipe (e.g. `| head`) is not an error.
fn print(bytes: &[u8]) -> Result<(), Error> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::Write {
            path: PathBuf::from("<stdout>"),
            source: e,
        }),
        Ok(()) => Ok(()),
    }
}
