//! Command-line interface: parses arguments and hands work to the library.

use crate::analysis::Quantity;
use crate::analysis::claims::{self, CheckSummary};
use crate::analysis::coverage::{self, CoverageSettings};
use crate::analysis::groups::{GroupBy, analyse_groups};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::claims::Claims;
use crate::dataset::{Dataset, Finger};
use crate::error::{EXIT_DATA, EXIT_FAILURE, Error};
use crate::report;
use crate::workflow;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Default measurement file.
pub const DEFAULT_DATA: &str = "data/measurements.csv";
/// Default claims file.
pub const DEFAULT_CLAIMS: &str = "data/paper_claims.csv";
/// Default directory of reference rigs for the report.
pub const DEFAULT_RIGS: &str = "data/rigs";

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
    /// No progress bar on standard error
    #[arg(long, short, global = true)]
    pub quiet: bool,
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
        #[command(flatten)]
        groups: GroupArgs,
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
    /// Render the HTML and Markdown report with SVG plots, and stats.json
    #[command(
        after_help = "Writes DIR/index.html (self-contained), DIR/report.md, DIR/plots/*.svg and DIR/stats.json.\n\
                            Files are replaced atomically; a failed run leaves the previous report as it was.\n\n\
                            Examples:\n  phalanx report\n  phalanx report --out /tmp/site --model-length 87.5 --format html\n  phalanx report --templates my_templates/"
    )]
    Report(ReportArgs),
    /// Add new X-rays to the dataset (validated, locked, atomic) and record a snapshot
    #[command(
        after_help = "New rows pass every check of the dataset and may not repeat an (xray, finger) already there; \
                            on any problem nothing is added. A value outside the current prediction interval is flagged \
                            as a likely measurement or typing error: a warning, or a refusal with --strict.\n\n\
                            Examples:\n  phalanx add new_xrays.csv\n  phalanx add --xray 2a --finger index --lengths 352.1,201.4,178.0 --sex female --age 34\n  phalanx add --strict --xray 2a --finger thumb --lengths 270.1,233.9"
    )]
    Add(AddArgs),
    /// Where to put the joints of a model finger of a given length (from its root joint)
    #[command(
        after_help = "Positions are measured from the finger's root joint (MCP): PIP at J~1 x L, DIP at (J~1 + J~2) x L, \
                            the tip at L; the thumb's IP joint at J~1 x L. Lengths are in your model's units.\n\n\
                            Examples:\n  phalanx place --finger index --length 1000\n  phalanx place --hand thumb=5.1,index=7.9,middle=8.6,ring=8.1,little=6.4\n  phalanx place --finger ring --length 81.5 --format json"
    )]
    Place {
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        boot: BootArgs,
        /// The finger (with --length)
        #[arg(long, value_parser = parse_finger, requires = "length", conflicts_with = "hand")]
        finger: Option<Finger>,
        /// The model finger's total length, root joint to tip (with --finger)
        #[arg(long, value_parser = parse_length, requires = "finger", allow_negative_numbers = true)]
        length: Option<f64>,
        /// Several fingers at once: FINGER=LENGTH,... (e.g. thumb=5.1,index=7.9)
        #[arg(long, value_name = "FINGER=L,...", value_parser = parse_hand)]
        hand: Option<Hand>,
        /// Output format
        #[arg(long, value_enum, default_value_t = TextFormat::Table)]
        format: TextFormat,
    },
    /// Judge a rigged hand (glTF 2.0) against the X-ray statistics; --fix writes a corrected copy
    #[command(
        after_help = "Finds the finger chains of either hand by their names (Mixamo mixamorig:RightHandIndex1..4, \
                            Rigify f_index.01.R / DEF-f_index.01.R / thumb.01.R, VRM rightIndexProximal or its humanoid table, \
                            Unreal index_01_r, WebXR index-finger-phalanx-proximal; case and separators ignored; --map for others) \
                            and measures joint-to-joint distances in the node (bind) pose. Each inner joint is reported inside the \
                            X-ray range, inside the prediction interval, or outside by how many mm and in which direction. \
                            Rigs without tip nodes are judged on J2/J1 only.\n\n\
                            --fix OUT.glb writes a copy with the middle joints at the mean positions along each finger (root and \
                            tip fixed) and the inverse bind matrices updated so the mesh's rest shape is unchanged; the input is \
                            never modified.\n\n\
                            --map FILE: CSV with the header node,side,finger,joint (joint MCP, PIP, DIP, IP or tip).\n\n\
                            Examples:\n  phalanx audit hand.glb\n  phalanx audit hand.glb --fix hand-fixed.glb\n  phalanx audit avatar.vrm --format json\n  phalanx audit rig.gltf --map my-names.csv"
    )]
    Audit {
        /// The rig: a .glb, .gltf or .vrm (glTF 2.0) file
        #[arg(value_name = "RIG")]
        rig: PathBuf,
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        boot: BootArgs,
        /// Custom joint names: CSV with node,side,finger,joint
        #[arg(long, value_name = "FILE")]
        map: Option<PathBuf>,
        /// Write a corrected copy of the rig here (.glb, or .gltf with the buffer embedded)
        #[arg(long, value_name = "OUT")]
        fix: Option<PathBuf>,
        /// Exit with status 1 when a finger is outside the prediction interval
        #[arg(long)]
        strict: bool,
        /// Output format
        #[arg(long, value_enum, default_value_t = TextFormat::Table)]
        format: TextFormat,
    },
    /// Write a synthetic dataset (for benchmarks and tests; never mix it into real data)
    #[command(
        after_help = "The model (hand scale, per-finger totals and proportions from the paper's Table 1, \
                            correlated segments) is documented in src/synth.rs and the README.\n\n\
                            Examples:\n  phalanx synth --xrays 10000 --seed 1 --out /tmp/hands.csv\n  phalanx synth --xrays 20 --no-metadata"
    )]
    Synth {
        /// Number of X-rays (hands); each has the five fingers
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
        xrays: u64,
        /// Seed of the generator
        #[arg(long, value_name = "S", default_value_t = analysis::DEFAULT_SEED)]
        seed: u64,
        /// Output file (written atomically); standard output when absent
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// Leave sex, age and side empty
        #[arg(long)]
        no_metadata: bool,
    },
    /// Record a snapshot of the current statistics in the history (after editing the data by hand)
    #[command(
        after_help = "Examples:\n  phalanx snapshot\n  phalanx snapshot --data lab/hands.csv"
    )]
    Snapshot {
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        history: HistoryArgs,
        #[command(flatten)]
        boot: BootArgs,
    },
    /// Show how the statistics moved, snapshot by snapshot
    #[command(
        after_help = "Examples:\n  phalanx history\n  phalanx history --finger index --quantity rel_j1\n  phalanx history --format json"
    )]
    History {
        #[command(flatten)]
        data: DataArgs,
        #[command(flatten)]
        history: HistoryArgs,
        /// Only this finger (thumb, index, middle, ring, little, or an alias)
        #[arg(long, value_parser = parse_finger)]
        finger: Option<Finger>,
        /// Only this quantity (rel_j1, rel_j2, rel_j3, total)
        #[arg(long, value_parser = parse_quantity)]
        quantity: Option<Quantity>,
        /// Output format
        #[arg(long, value_enum, default_value_t = TextFormat::Table)]
        format: TextFormat,
    },
}

/// Grouping of X-rays (the paper's future work: statistics by sex and age).
#[derive(Args, Debug, Clone)]
pub struct GroupArgs {
    /// Also compute every statistic per group of X-rays
    #[arg(long, value_enum, value_name = "COLUMN")]
    pub group_by: Option<GroupColumn>,
    /// Age band edges for --group-by age, ascending
    #[arg(long, value_name = "EDGES", value_delimiter = ',', default_values_t = crate::analysis::groups::DEFAULT_AGE_BINS, allow_negative_numbers = true)]
    pub age_bins: Vec<f64>,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupColumn {
    Sex,
    Age,
    Side,
}

impl GroupArgs {
    /// The grouping asked for, validated.
    pub fn group_by(&self) -> Result<Option<GroupBy>, Error> {
        Ok(match self.group_by {
            None => None,
            Some(GroupColumn::Sex) => Some(GroupBy::Sex),
            Some(GroupColumn::Side) => Some(GroupBy::Side),
            Some(GroupColumn::Age) => {
                crate::analysis::groups::validate_age_bins(&self.age_bins).map_err(Error::Usage)?;
                Some(GroupBy::Age(self.age_bins.clone()))
            }
        })
    }
}

/// The history file.
#[derive(Args, Debug, Clone)]
pub struct HistoryArgs {
    /// History file (JSON Lines); default: history.jsonl beside the dataset
    #[arg(long = "history", value_name = "PATH")]
    pub path: Option<PathBuf>,
}

impl HistoryArgs {
    /// The history file for a dataset.
    pub fn resolve(&self, data: &Path) -> PathBuf {
        self.path
            .clone()
            .unwrap_or_else(|| crate::dataset::history::default_path(data))
    }
}

/// Options of `phalanx add`.
#[derive(Args, Debug, Clone)]
pub struct AddArgs {
    /// CSV file of new rows, in the dataset's format (with a header)
    #[arg(value_name = "FILE.csv", conflicts_with_all = ["xray", "finger", "lengths"])]
    pub file: Option<PathBuf>,
    /// X-ray id of one new row
    #[arg(long, requires_all = ["finger", "lengths"])]
    pub xray: Option<String>,
    /// Finger of the new row
    #[arg(long, requires_all = ["xray", "lengths"])]
    pub finger: Option<String>,
    /// Segment lengths J1,J2[,J3] of the new row (J3 not for the thumb)
    #[arg(long, value_name = "J1,J2[,J3]", requires_all = ["xray", "finger"], allow_hyphen_values = true)]
    pub lengths: Option<String>,
    /// Sex of the hand (female, male, ...)
    #[arg(long)]
    pub sex: Option<String>,
    /// Age in years
    #[arg(long)]
    pub age: Option<String>,
    /// left or right
    #[arg(long)]
    pub side: Option<String>,
    /// Where the measurement comes from
    #[arg(long)]
    pub source: Option<String>,
    /// Unit of the lengths
    #[arg(long)]
    pub unit: Option<String>,
    /// Refuse rows flagged as likely errors instead of warning
    #[arg(long)]
    pub strict: bool,
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub history: HistoryArgs,
    #[command(flatten)]
    pub boot: BootArgs,
}

/// Model finger lengths given with `--hand`.
#[derive(Debug, Clone, PartialEq)]
pub struct Hand(pub Vec<(Finger, f64)>);

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

fn parse_finger(text: &str) -> Result<Finger, String> {
    Finger::parse(text).ok_or_else(|| format!("unknown finger '{text}'; use {}", Finger::ACCEPTED))
}

fn parse_quantity(text: &str) -> Result<Quantity, String> {
    Quantity::parse(text)
        .ok_or_else(|| format!("unknown quantity '{text}'; use rel_j1, rel_j2, rel_j3 or total"))
}

/// Options of `phalanx report`.
#[derive(Args, Debug, Clone)]
pub struct ReportArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// The claims file checked in the "Reproducing the paper" section
    #[arg(long, value_name = "PATH", default_value = DEFAULT_CLAIMS)]
    pub claims: PathBuf,
    /// Output directory
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub out: PathBuf,
    #[command(flatten)]
    pub boot: BootArgs,
    /// Total length of the model finger for the joint-placement section, in model units
    #[arg(long, value_name = "L", default_value_t = 1000.0, value_parser = parse_length, allow_negative_numbers = true)]
    pub model_length: f64,
    /// Formats to write, comma-separated
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [ReportFormat::Html, ReportFormat::Md, ReportFormat::Json])]
    pub format: Vec<ReportFormat>,
    /// Directory with report.html.tera and/or report.md.tera overriding the built-in templates
    #[arg(long, value_name = "DIR")]
    pub templates: Option<PathBuf>,
    /// Add the generation time (UTC) to the provenance; the report is then no longer reproducible byte for byte
    #[arg(long)]
    pub timestamp: bool,
    /// Simulated datasets for the coverage section
    #[arg(long, default_value_t = 4000, value_parser = clap::value_parser!(u64).range(1..))]
    pub sims: u64,
    #[command(flatten)]
    pub history: HistoryArgs,
    #[command(flatten)]
    pub groups: GroupArgs,
    /// Directory of reference rigs (*.json) for "Popular rigs against the X-rays"; absent = no section
    #[arg(long, value_name = "DIR", default_value = DEFAULT_RIGS)]
    pub rigs: PathBuf,
    /// Target half-width of the confidence interval of a relative mean, for "X-rays needed"
    #[arg(long, value_name = "W", default_value_t = 0.005, value_parser = parse_target)]
    pub target: f64,
}

fn parse_target(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!(
            "'{text}' is not a positive half-width; give e.g. 0.005"
        )),
    }
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportFormat {
    Html,
    Md,
    Json,
}

fn parse_length(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(l) if l.is_finite() && l > 0.0 => Ok(l),
        _ => Err(format!("'{text}' is not a positive length; give e.g. 1000")),
    }
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
    #[arg(long, value_name = "C", default_value_t = analysis::DEFAULT_CONFIDENCE, value_parser = parse_confidence, allow_negative_numbers = true)]
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
    let quiet = cli.quiet;
    match cli.command {
        Command::Stats {
            data,
            boot,
            groups,
            format,
        } => {
            let settings = boot.settings();
            settings.validate().map_err(Error::Usage)?;
            let by = groups.group_by()?;
            let dataset = Dataset::load(&data.data)?;
            let a = analyse_showing_progress(&dataset, &settings, quiet);
            let groups = by.map_or_else(Vec::new, |by| analyse_groups(&dataset, &by, &settings));
            drop(dataset);
            let bytes = match format {
                StatsFormat::Table => report::text::stats_with_groups(&a, &groups).into_bytes(),
                StatsFormat::Json => {
                    // Streamed: the document of a large dataset is not held in memory.
                    return match report::json::write_stats(std::io::stdout().lock(), &a, &groups) {
                        Err(e) if is_broken_pipe(&e) => Ok(0),
                        other => other.map(|()| 0),
                    };
                }
                StatsFormat::Csv => report::csv_out::stats(&a, &groups)?,
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
                max_n: None,
            };
            let rows = coverage::of_analysis(&a, &s);
            let bytes = match format {
                TextFormat::Table => report::text::coverage(&rows, &s).into_bytes(),
                TextFormat::Json => report::json::coverage(&a.dataset, &s, &rows)?,
            };
            print(&bytes)?;
            Ok(0)
        }
        Command::Report(args) => {
            report_command(&args, quiet)?;
            Ok(0)
        }
        Command::Add(args) => add_command(&args),
        Command::Synth {
            xrays,
            seed,
            out,
            no_metadata,
        } => {
            let bytes = crate::synth::generate(&crate::synth::SynthOptions {
                xrays: xrays as usize,
                seed,
                metadata: !no_metadata,
            });
            match out {
                Some(path) => crate::atomic::replace(&path, &bytes).map_err(Error::write(&path))?,
                None => print(&bytes)?,
            }
            Ok(0)
        }
        Command::Place {
            data,
            boot,
            finger,
            length,
            hand,
            format,
        } => {
            let wanted = match (finger, length, hand) {
                (Some(f), Some(l), None) => vec![(f, l)],
                (None, None, Some(h)) => h.0,
                _ => {
                    return Err(Error::Usage(
                        "give --finger and --length, or --hand FINGER=L,... (see phalanx place --help)".into(),
                    ));
                }
            };
            let a = load_and_analyse(&data.data, &boot.settings())?;
            let mut placements = Vec::new();
            for (f, l) in wanted {
                placements.push(analysis::placement::place(&a, f, l).ok_or_else(|| {
                    Error::Usage(format!(
                        "{} has no {f} rows to place it from",
                        a.dataset.path
                    ))
                })?);
            }
            let bytes = match format {
                TextFormat::Table => {
                    report::text::placement(&placements, a.settings.confidence).into_bytes()
                }
                TextFormat::Json => report::json::placement(&a, &placements)?,
            };
            print(&bytes)?;
            Ok(0)
        }
        Command::Audit {
            rig,
            data,
            boot,
            map,
            fix,
            strict,
            format,
        } => {
            let out = workflow::audit(&workflow::AuditRequest {
                rig: &rig,
                map: map.as_deref(),
                fix: fix.as_deref(),
                data: &data.data,
                settings: boot.settings(),
                json: format == TextFormat::Json,
            })?;
            print(&out.output)?;
            if !quiet {
                for m in &out.messages {
                    eprintln!("{m}");
                }
            }
            Ok(if strict && out.outside > 0 {
                EXIT_FAILURE
            } else {
                0
            })
        }
        Command::Snapshot {
            data,
            history,
            boot,
        } => {
            let path = history.resolve(&data.data);
            let snap = workflow::snapshot(&data.data, &path, &boot.settings())?;
            print(
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
        Command::History {
            data,
            history,
            finger,
            quantity,
            format,
        } => {
            let path = history.resolve(&data.data);
            let snaps = crate::dataset::history::read(&path)?;
            let bytes = match format {
                TextFormat::Table => {
                    report::text::history(&path, &snaps, finger, quantity).into_bytes()
                }
                TextFormat::Json => report::json::history(&snaps, finger, quantity)?,
            };
            print(&bytes)?;
            Ok(0)
        }
    }
}

/// `phalanx add`: new rows from a file or from options.
fn add_command(args: &AddArgs) -> Result<i32, Error> {
    let rows = match (&args.file, &args.xray, &args.finger, &args.lengths) {
        (Some(f), ..) => workflow::NewRows::File(f.clone()),
        (None, Some(x), Some(f), Some(l)) => {
            let mut parts: Vec<String> = l.split(',').map(|p| p.trim().to_string()).collect();
            if parts.len() < 2 || parts.len() > 3 {
                return Err(Error::Usage(format!(
                    "--lengths '{l}': give 2 (thumb) or 3 (other fingers) comma-separated lengths, e.g. 352.1,201.4,178.0"
                )));
            }
            parts.resize(3, String::new());
            let opt = |v: &Option<String>| v.clone().unwrap_or_default();
            let mut fields = vec![
                ("xray", x.clone()),
                ("finger", f.clone()),
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
                if v.is_some() {
                    fields.push((name, opt(v)));
                }
            }
            workflow::NewRows::Fields(fields)
        }
        _ => {
            return Err(Error::Usage(
                "give a CSV file of new rows, or --xray, --finger and --lengths for one row (see phalanx add --help)".into(),
            ));
        }
    };
    let history = args.history.resolve(&args.data.data);
    let outcome = workflow::add(&workflow::AddRequest {
        data: args.data.data.clone(),
        history: history.clone(),
        rows,
        strict: args.strict,
        settings: args.boot.settings(),
    })?;
    for f in &outcome.flags {
        eprintln!("warning: {}", f.reason);
    }
    print(
        format!(
            "added {} row{} to {}: {} -> {} X-rays; snapshot appended to {}\n",
            outcome.added,
            if outcome.added == 1 { "" } else { "s" },
            args.data.data.display(),
            outcome.xrays_before,
            outcome.xrays_after,
            history.display()
        )
        .as_bytes(),
    )?;
    Ok(0)
}

/// `phalanx report`: analyse, check, simulate, render everything in memory, then write.
fn report_command(args: &ReportArgs, quiet: bool) -> Result<(), Error> {
    let settings = args.boot.settings();
    settings.validate().map_err(Error::Usage)?;
    let templates = match &args.templates {
        Some(dir) => report::render::Templates::from_dir(dir)?,
        None => report::render::Templates::builtin()?,
    };
    let by = args.groups.group_by()?;
    let dataset = Dataset::load(&args.data.data)?;
    let groups = by.map_or_else(Vec::new, |by| analyse_groups(&dataset, &by, &settings));
    let history_path = args.history.resolve(&args.data.data);
    let history = crate::dataset::history::read(&history_path)?;
    let claims = Claims::load(&args.claims)?;
    // Claims about rows this dataset lacks (another lab's data, say) cannot be
    // checked: the report says so instead of failing.
    let (results, claims_note) = match claims.check_against(&dataset) {
        Ok(()) => (claims::check(&claims, &dataset), None),
        Err(e) => (
            Vec::new(),
            Some(format!(
                "The claims were not checked: they refer to rows this dataset does not have ({} problem(s), the first: {}).",
                e.problems.len(),
                e.problems
                    .first()
                    .map_or(String::new(), |p| p.message.clone())
            )),
        ),
    };
    let references = crate::rig::reference::load_dir(&args.rigs)?;
    let a = analyse_showing_progress(&dataset, &settings, quiet);
    drop(dataset);
    let rigs: Vec<report::view::ReferenceAudit> = references
        .into_iter()
        .map(|rig| {
            let audit = crate::rig::AuditedRig::of(&rig.name, &rig.chains, &[], &a);
            report::view::ReferenceAudit { rig, audit }
        })
        .collect();
    let cov_settings = CoverageSettings {
        sims: args.sims as usize,
        resamples: settings.resamples,
        seed: settings.seed,
        confidence: settings.confidence,
        max_n: Some(coverage::REPORT_MAX_N),
    };
    let cov = coverage::of_analysis(&a, &cov_settings);
    let placements = analysis::placement::place_all(&a, args.model_length);
    let timestamp = args
        .timestamp
        .then(|| humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string());
    let inputs = report::view::ReportInputs {
        analysis: &a,
        claims_file: &claims.path,
        claims: &results,
        claims_note: claims_note.as_deref(),
        coverage_settings: &cov_settings,
        coverage: &cov,
        placements: &placements,
        model_length: args.model_length,
        timestamp,
        history_file: &history_path.display().to_string(),
        history: &history,
        target: args.target,
        groups: &groups,
        rigs: &rigs,
    };
    let formats = report::Formats {
        html: args.format.contains(&ReportFormat::Html),
        markdown: args.format.contains(&ReportFormat::Md),
        json: args.format.contains(&ReportFormat::Json),
    };
    let files = report::render(&inputs, formats, &templates)?;
    report::writer::write_all(&args.out, &files)?;
    let names: Vec<String> = files.iter().map(|f| f.path.display().to_string()).collect();
    eprintln!(
        "phalanx: wrote {} files to {}: {}",
        files.len(),
        args.out.display(),
        names.join(", ")
    );
    Ok(())
}

/// Analyses a dataset with a progress bar on a terminal for long bootstraps.
fn analyse_showing_progress(dataset: &Dataset, settings: &Settings, quiet: bool) -> Analysis {
    let bar =
        report::progress::TerminalProgress::new(quiet, settings.resamples, dataset.rows.len());
    let a = analysis::analyse_with(dataset, settings, &bar);
    bar.finish();
    a
}

/// Loads a dataset and analyses it.
pub fn load_and_analyse(path: &Path, settings: &Settings) -> Result<Analysis, Error> {
    settings.validate().map_err(Error::Usage)?;
    let data = Dataset::load(path)?;
    Ok(analysis::analyse(&data, settings))
}

/// True when an error comes from writing to a closed pipe (e.g. `| head`).
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut cur: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = cur {
        if err
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            || err
                .downcast_ref::<serde_json::Error>()
                .and_then(serde_json::Error::io_error_kind)
                == Some(std::io::ErrorKind::BrokenPipe)
        {
            return true;
        }
        cur = err.source();
    }
    false
}

/// Writes to standard output; a closed pipe (e.g. `| head`) is not an error.
fn print(bytes: &[u8]) -> Result<(), Error> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::write(Path::new("<stdout>"))(e)),
        Ok(()) => Ok(()),
    }
}
