//! One module per command: its options (a clap `Args` struct with the help
//! text), and a `run` that parses nothing further, calls the library and hands
//! the results to an exporter. Shared option groups are in [`args`], the one
//! writer to standard output in [`out`].

pub(crate) mod args;
pub(crate) mod out;

pub(crate) mod add;
pub(crate) mod audit;
pub(crate) mod check;
pub(crate) mod compare;
pub(crate) mod completions;
pub(crate) mod coverage;
pub(crate) mod history;
pub(crate) mod import;
pub(crate) mod man;
pub(crate) mod place;
pub(crate) mod report;
pub(crate) mod snapshot;
pub(crate) mod stats;
pub(crate) mod synth;

use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::error::Error;
use std::path::Path;

/// Analyses a dataset with a progress bar on a terminal for long bootstraps.
pub(crate) fn analyse_showing_progress(
    dataset: &Dataset,
    settings: &Settings,
    quiet: bool,
) -> Analysis {
    let bar = crate::report::progress::TerminalProgress::new(
        quiet,
        settings.resamples,
        dataset.rows.len(),
    );
    let a = analysis::analyse_with(dataset, settings, &bar);
    bar.finish();
    a
}

/// Loads a dataset and analyses it.
pub(crate) fn load_and_analyse(path: &Path, settings: &Settings) -> Result<Analysis, Error> {
    let data = Dataset::load(path)?;
    Ok(analysis::analyse(&data, settings))
}
