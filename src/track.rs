//! The tracking workflow's file operations: adding X-rays and taking snapshots.
//!
//! `add` holds the dataset's lock from reading to replacing the file, so two
//! additions at the same time both land; the dataset is replaced atomically,
//! so a killed run leaves the old or the new file, never a torn one; on any
//! problem nothing is written.
//!
//! The settings are used as given: build them with
//! [`Settings::new`](crate::analysis::Settings::new) (the command line does).

use crate::analysis::outliers::{self, Flag};
use crate::analysis::tracking;
use crate::analysis::{self, Settings};
use crate::atomic;
use crate::dataset::append::{self, DatasetLock};
use crate::dataset::history::{self, Event, Snapshot};
use crate::dataset::{DataError, Dataset, Problem, csvinput};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Where new rows come from.
pub(crate) enum NewRows {
    /// A CSV file in the dataset's format (with its own header).
    File(PathBuf),
    /// One row given as options: (column, value) pairs.
    Fields(Vec<(&'static str, String)>),
    /// Rows made by the program (e.g. imported from landmarks), already validated as
    /// a dataset; problems name their X-ray, not a line of a file nobody wrote.
    Rows(Dataset),
}

/// What `add` is asked to do.
pub(crate) struct AddRequest {
    pub data: PathBuf,
    pub history: PathBuf,
    pub rows: NewRows,
    /// Refuse rows flagged by [`outliers::flag_rows`].
    pub strict: bool,
    /// Pool new rows whose fingertips differ from the dataset's (bone with skin).
    pub mixed_tips: bool,
    pub settings: Settings,
}

/// What `add` did.
#[derive(Debug)]
pub(crate) struct AddOutcome {
    pub added: usize,
    pub xrays_before: usize,
    pub xrays_after: usize,
    /// Rows that look wrong, one flag per row (warnings unless strict).
    pub flags: Vec<Flag>,
    /// Fingers whose new rows could not be checked fully (too few current X-rays).
    pub notes: Vec<String>,
    /// Implausible data in the resulting dataset (e.g. swapped columns).
    pub implausible: Vec<String>,
}

/// The current UTC time, RFC 3339, for history records.
pub(crate) fn now() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

/// The tip rule of `add`: new rows whose fingertips are at the bone do not join rows at
/// the skin (or the reverse) unless asked (`--mixed-tips`); see
/// [`crate::dataset::tip::pooling_problem`].
fn refuse_mixed_tips(current: &Dataset, new: &Dataset, allowed: bool) -> Result<(), Error> {
    if allowed {
        return Ok(());
    }
    let files = [
        (current.path.as_str(), &current.rows[..]),
        (new.path.as_str(), &new.rows[..]),
    ];
    match crate::dataset::tip::pooling_problem(&files, "--mixed-tips") {
        Some(m) => Err(Error::Usage(format!("nothing added: {m}"))),
        None => Ok(()),
    }
}

/// Adds new rows to a dataset, then appends a snapshot to its history.
pub(crate) fn add(req: &AddRequest) -> Result<AddOutcome, Error> {
    let loaded;
    let (new, typed) = match &req.rows {
        NewRows::File(p) => {
            loaded = Dataset::load(p)?;
            (&loaded, append::Typed::of(&csvinput::read_input(p)?))
        }
        NewRows::Fields(fields) => {
            loaded = append::single_row(fields)?;
            (
                &loaded,
                append::Typed::of(&append::single_row_bytes(fields)?),
            )
        }
        NewRows::Rows(rows) => (rows, append::Typed::default()),
    };
    csvinput::open_input(&req.data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(&req.data).map_err(Error::write(&req.data))?;
    let current_bytes = csvinput::read_input(&req.data)?;
    let label = req.data.display().to_string();
    let current = Dataset::from_bytes(&label, &current_bytes)?;
    refuse_mixed_tips(&current, new, req.mixed_tips)?;
    let n = current.xray_count() + new.xray_count();
    analysis::budget::check_bootstrap(n, req.settings.resamples).map_err(Error::Usage)?;
    let from_options = !matches!(req.rows, NewRows::File(_));
    let (bytes, after) = append::appended_bytes_typed(&current_bytes, &current, new, &typed)
        .map_err(|mut e| {
            if from_options {
                e.problems.iter_mut().for_each(|p| p.line = None);
            }
            e
        })?;
    let before = analysis::analyse(&current, &req.settings);
    let flags = outliers::flag_rows(&before, &new.rows);
    let mut notes: Vec<String> = Vec::new();
    for r in &new.rows {
        if let Some(note) = outliers::limits(&before, r.finger)
            && !notes.contains(&note)
        {
            notes.push(note);
        }
    }
    if req.strict && !flags.is_empty() {
        return Err(refusal(new, &flags, from_options).into());
    }
    let a = analysis::analyse(&after, &req.settings);
    let snapshot = tracking::snapshot(&a, now(), Event::Add);
    // Stage both files in full before replacing either: a history that cannot be
    // written stops the add with the dataset untouched. Between the two renames
    // a crash can only lose the snapshot ('phalanx snapshot' records it again).
    let history_bytes =
        history::appended_bytes(&req.history, &snapshot).map_err(Error::write(&req.history))?;
    let staged_data = atomic::stage(&req.data, &bytes).map_err(Error::write(&req.data))?;
    let staged_history =
        atomic::stage(&req.history, &history_bytes).map_err(Error::write(&req.history))?;
    atomic::commit(staged_data, &req.data).map_err(Error::write(&req.data))?;
    atomic::commit(staged_history, &req.history).map_err(Error::write(&req.history))?;
    Ok(AddOutcome {
        added: new.rows.len(),
        xrays_before: current.xray_count(),
        xrays_after: after.xray_count(),
        flags,
        notes,
        implausible: analysis::plausible::warnings(&a),
    })
}

/// The error of `add --strict`: one problem per flagged value, at the new row's
/// line (no line for a row given as options).
fn refusal(new: &Dataset, flags: &[Flag], from_options: bool) -> DataError {
    let problems = new
        .rows
        .iter()
        .flat_map(|r| {
            flags
                .iter()
                .filter(move |f| f.xray == *r.xray && f.finger == r.finger.name())
                .map(move |f| Problem::line(r.line, format!("refused (--strict): {}", f.reason)))
        })
        .map(|mut p| {
            if from_options {
                p.line = None;
            }
            p
        })
        .collect();
    DataError {
        file: new.path.clone(),
        problems,
    }
}

/// Appends a snapshot of the dataset's current statistics to its history
/// (for data edited by hand). Holds the dataset's lock while it reads.
pub(crate) fn snapshot(
    data: &Path,
    history_path: &Path,
    settings: &Settings,
) -> Result<Snapshot, Error> {
    csvinput::open_input(data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(data).map_err(Error::write(data))?;
    let dataset = Dataset::load(data)?;
    analysis::budget::check_bootstrap(dataset.xray_count(), settings.resamples)
        .map_err(Error::Usage)?;
    let a = analysis::analyse(&dataset, settings);
    let snap = tracking::snapshot(&a, now(), Event::Snapshot);
    history::append(history_path, &snap).map_err(Error::write(history_path))?;
    Ok(snap)
}
