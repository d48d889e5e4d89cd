//! Command-line interface: the global options, the commands and the dispatch.
//! Each command's options and steps are in its module under `cmd/`.

use crate::cmd;
use crate::error::{EXIT_DATA, Error};
use clap::{CommandFactory, Parser, Subcommand};

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
pub(crate) struct Cli {
    /// No progress bar on standard error
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// Show every table column, however wide (otherwise tables fit the terminal, or 100 columns when not one)
    #[arg(long, global = true)]
    pub wide: bool,
    #[command(subcommand)]
    pub command: Command,
}

// Each command wraps its module's options (and help text).
#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    Stats(cmd::stats::Args),
    Check(cmd::check::Args),
    Compare(cmd::compare::Args),
    Coverage(cmd::coverage::Args),
    Report(cmd::report::Args),
    Add(cmd::add::Args),
    Remove(cmd::remove::Args),
    Import(cmd::import::Args),
    Place(cmd::place::Args),
    Audit(cmd::audit::Args),
    Deform(cmd::deform::Args),
    Rig(cmd::rig::Args),
    Synth(cmd::synth::Args),
    Snapshot(cmd::snapshot::Args),
    History(cmd::history::Args),
    Completions(cmd::completions::Args),
    Man(cmd::man::Args),
    // Writes docs/schema/ (for contributors; hidden from help and completions).
    #[command(hide = true)]
    Schema(cmd::schema::Args),
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
pub(crate) fn run(cli: Cli) -> Result<i32, Error> {
    let quiet = cli.quiet;
    let width = cmd::out::width(cli.wide);
    let result = match cli.command {
        Command::Stats(args) => cmd::stats::run(&args, quiet, width),
        Command::Check(args) => cmd::check::run(&args, width),
        Command::Compare(args) => cmd::compare::run(&args, width),
        Command::Coverage(args) => cmd::coverage::run(&args, width),
        Command::Report(args) => cmd::report::run(&args, quiet),
        Command::Add(args) => cmd::add::run(&args),
        Command::Remove(args) => cmd::remove::run(&args),
        Command::Import(args) => cmd::import::run(&args),
        Command::Place(args) => cmd::place::run(&args, width),
        Command::Audit(args) => cmd::audit::run(&args, quiet, width),
        Command::Deform(args) => cmd::deform::run(&args, width),
        Command::Rig(args) => cmd::rig::run(&args, quiet, width),
        Command::Synth(args) => cmd::synth::run(&args),
        Command::Snapshot(args) => cmd::snapshot::run(&args),
        Command::History(args) => cmd::history::run(&args, width),
        Command::Completions(args) => cmd::completions::run(&args, Cli::command()),
        Command::Man(args) => cmd::man::run(&args, Cli::command()),
        Command::Schema(args) => cmd::schema::run(&args),
    };
    result.map_err(cmd::args::outside_checkout)
}
