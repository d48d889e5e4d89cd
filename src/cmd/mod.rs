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
pub(crate) mod deform;
pub(crate) mod history;
pub(crate) mod import;
pub(crate) mod man;
pub(crate) mod place;
pub(crate) mod remove;
pub(crate) mod report;
pub(crate) mod rig;
pub(crate) mod schema;
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
) -> Result<Analysis, Error> {
    within_budget(dataset, settings)?;
    let bar = crate::report::progress::TerminalProgress::new(
        quiet,
        settings.resamples,
        dataset.rows.len(),
    );
    let a = analysis::analyse_with(dataset, settings, &bar);
    bar.finish();
    Ok(a)
}

/// The groups of `by` (none when not grouping), with a note on standard error
/// instead of one "unknown" group when the column has no value at all.
pub(crate) fn groups_of(
    dataset: &Dataset,
    by: Option<&analysis::groups::GroupBy>,
    settings: &Settings,
) -> Option<analysis::groups::Groups> {
    let by = by?;
    if let Some(note) = analysis::groups::nothing_to_group(dataset, by) {
        eprintln!("note: {note}");
        return None;
    }
    Some(analysis::groups::analyse_groups(dataset, by, settings))
}

/// Prints the warnings about implausible data (e.g. swapped columns) on standard error.
pub(crate) fn warn_implausible(a: &Analysis) {
    for w in analysis::plausible::warnings(a) {
        eprintln!("warning: {w}");
    }
}

/// Refuses a bootstrap too large to serve (see [`analysis::budget`]).
pub(crate) fn within_budget(dataset: &Dataset, settings: &Settings) -> Result<(), Error> {
    analysis::budget::check_bootstrap(dataset.xray_count(), settings.resamples)
        .map_err(Error::Usage)
}

/// Loads a dataset and analyses it.
pub(crate) fn load_and_analyse(path: &Path, settings: &Settings) -> Result<Analysis, Error> {
    let data = Dataset::load(path)?;
    within_budget(&data, settings)?;
    Ok(analysis::analyse(&data, settings))
}

/// The fingertip's soft tissue measured per finger in the published table
/// [`SOFT_TISSUE_TABLE`](crate::rig::judge::SOFT_TISSUE_TABLE), read at run time;
/// unknown when the file is not found here (an audit that needs it then says so).
pub(crate) fn soft_tissue_table() -> Result<crate::rig::judge::SoftTissue, Error> {
    crate::rig::session::soft_tissue_from(Path::new(crate::rig::judge::SOFT_TISSUE_TABLE))
}

/// The warnings and notes of an addition, one line each, for standard error.
pub(crate) fn added_messages(outcome: &crate::track::AddOutcome, dataset: &Path) -> Vec<String> {
    crate::report::track_words::added_messages(&crate::report::track_words::Added {
        new_file: &outcome.new_file,
        from_options: outcome.from_options,
        dataset: &dataset.display().to_string(),
        accepted: &outcome.accepted,
        swapped: &outcome.swapped,
        taken_tip: outcome.taken_tip.as_ref(),
        limits: &outcome.limits,
        added_columns: &outcome.added_columns,
    })
}
