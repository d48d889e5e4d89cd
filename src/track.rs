//! The tracking workflow's file operations: adding and removing X-rays, taking snapshots.
//!
//! `add` and `remove` hold the dataset's lock from reading to replacing the file, so two
//! changes at the same time both land; the dataset is replaced atomically, so a killed
//! run leaves the old or the new file, never a torn one; on any problem nothing is
//! written. Each change appends a record to the history that says what changed
//! ([`ChangeRecord`]).
//!
//! Rows that the outlier or typo rules of [`outliers`] flag are refused unless the
//! request accepts them (`--accept-flagged`); accepted, each keeps why in its `flagged`
//! column and in the history record.
//!
//! The settings are used as given: build them with
//! [`Settings::new`](crate::analysis::Settings::new) (the command line does).

use crate::analysis::outliers::{self, Flag};
use crate::analysis::tracking;
use crate::analysis::{self, Settings};
use crate::atomic;
use crate::dataset::append::{self, DatasetLock};
use crate::dataset::history::{self, ChangeRecord, Event, FlaggedRow, Snapshot};
use crate::dataset::tip::{self, TipKind};
use crate::dataset::{DataError, Dataset, Finger, Problem, Row, csvinput};
use crate::error::Error;
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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
    /// Add rows flagged by [`outliers::flag_rows`] (recorded as flagged) instead of
    /// refusing them.
    pub accept_flagged: bool,
    /// The user's note for the history record.
    pub note: Option<String>,
    /// Pool new rows whose fingertips differ from the dataset's (bone with skin).
    pub mixed_tips: bool,
    /// Where the fingertips of every new row that gives none were measured (`--tip`);
    /// without it such a row takes the tip every row of the dataset records, and is
    /// refused when they do not all record one ([`tip::record_new`]).
    pub tip: Option<TipKind>,
    pub settings: Settings,
}

/// What `add` did; `report::track_words` says it.
#[derive(Debug)]
pub(crate) struct AddOutcome {
    pub added: usize,
    pub xrays_before: usize,
    pub xrays_after: usize,
    /// Rows added though flagged (with `accept_flagged`), one flag per row.
    pub flags: Vec<Flag>,
    /// The label of the new rows' file (`<command line>` for a row given as options).
    pub new_file: String,
    /// Whether the new row was given as options.
    pub from_options: bool,
    /// Each row added though flagged: its line in the user's file (when it has
    /// one) and why it was flagged.
    pub accepted: Vec<(Option<u64>, String)>,
    /// Each finger whose segments look swapped with the rows added: the new
    /// rows' lines of that finger in the user's file, and the warning.
    pub swapped: Vec<(Vec<u64>, String)>,
    /// The tip that new rows giving none took from the dataset: its kind, how
    /// many rows took it, and their first distinct X-ray ids (at most 11).
    pub taken_tip: Option<(TipKind, usize, Vec<String>)>,
    /// Fingers whose new rows could not be checked fully (too few current
    /// X-rays, or none in the new rows' unit), one sentence each.
    pub limits: Vec<String>,
    /// Header columns the dataset gained (the new rows fill them).
    pub added_columns: Vec<&'static str>,
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

/// The new rows read once: as a dataset, their file's typed cells (none for rows
/// made by the program), and the problems of a file's rows that do not read (the
/// dataset then holds the rows that do, so their other problems are found in the
/// same pass; see [`append::readable_rest`]).
type ReadNew<'r> = (Cow<'r, Dataset>, append::Typed, Vec<Problem>);

fn read_new(rows: &NewRows) -> Result<ReadNew<'_>, Error> {
    Ok(match rows {
        NewRows::File(p) => {
            let bytes = csvinput::read_input(p)?;
            let label = p.display().to_string();
            let (new, unread) = match Dataset::from_bytes(&label, &bytes) {
                Ok(new) => (new, Vec::new()),
                Err(e) => match append::readable_rest(&label, &bytes, &e) {
                    Some(rest) => (rest, e.problems),
                    None => return Err(e.into()),
                },
            };
            (Cow::Owned(new), append::Typed::of(&bytes), unread)
        }
        NewRows::Fields(fields) => (
            Cow::Owned(append::single_row(fields)?),
            append::Typed::of(&append::single_row_bytes(fields)?),
            Vec::new(),
        ),
        NewRows::Rows(rows) => (Cow::Borrowed(rows), append::Typed::default(), Vec::new()),
    })
}

/// Adds new rows to a dataset, then appends a snapshot to its history.
pub(crate) fn add(req: &AddRequest) -> Result<AddOutcome, Error> {
    let (new, typed, unread) = read_new(&req.rows)?;
    let from_file = matches!(req.rows, NewRows::File(_));
    let line_of = |r: &Row| from_file.then_some(r.line);
    // Rows given as options have no line of their own: problems name none.
    let unlined = |mut e: DataError| {
        if !from_file {
            e.problems.iter_mut().for_each(|p| p.line = None);
        }
        e
    };
    csvinput::open_input(&req.data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(&req.data).map_err(Error::write(&req.data))?;
    let current_bytes = csvinput::read_input(&req.data)?;
    let current = Dataset::from_bytes(&req.data.display().to_string(), &current_bytes)?;
    let tipped = tip::record_new(&current, &new, req.tip, from_file);
    // Rows that do not read, conflicting metadata and missing tips are refused before
    // anything else is said about the rows, every problem of the file at once, with
    // the rows that the typo and outlier rules flag among the others.
    let mut problems = unread;
    problems.extend(tipped.problems);
    if let Err(e) = append::check_fits(&current, &tipped.rows, from_file) {
        problems.extend(e.problems);
    }
    if !problems.is_empty() {
        if !req.accept_flagged {
            problems.extend(flags_among(
                &current,
                &tipped.rows,
                &problems,
                req,
                from_file,
            ));
        }
        problems.sort_by_key(|p| (p.line.is_none(), p.line));
        let file = tipped.rows.path.clone();
        return Err(unlined(DataError { file, problems }).into());
    }
    refuse_mixed_tips(&current, &tipped.rows, req.mixed_tips)?;
    let n = current.xray_count() + tipped.rows.xray_count();
    analysis::budget::check_bootstrap(n, req.settings.resamples).map_err(Error::Usage)?;
    let mut new = append::with_defaults(&tipped.rows, &current);
    let before = analysis::analyse(&current, &req.settings);
    let flags = outliers::flag_rows(&before, &new.rows);
    if !flags.is_empty() && !req.accept_flagged {
        return Err(refusal(&new, &flags, from_file).into());
    }
    let mut limits: Vec<String> = Vec::new();
    for r in &new.rows {
        if let Some(note) = outliers::limits(&before, r.finger)
            && !limits.contains(&note)
        {
            limits.push(note);
        }
    }
    limits.extend(outliers::unit_limits(&before, &new.rows));
    // Accepted flags are recorded in the rows themselves.
    for r in &mut new.rows {
        if let Some(f) = flag_of(&flags, r) {
            r.meta.flagged = Some(Arc::from(f.finding.as_str()));
        }
    }
    let (bytes, after) =
        append::appended_bytes_typed(&current_bytes, &current, &new, &typed).map_err(unlined)?;
    let a = analysis::analyse(&after, &req.settings);
    let accepted = new
        .rows
        .iter()
        .filter_map(|r| Some((line_of(r), flag_of(&flags, r)?.reason.clone())))
        .collect();
    let swapped = a
        .fingers
        .iter()
        .filter_map(|f| {
            let w = analysis::plausible::swapped_segments(f)?;
            let rows = new.rows.iter().filter(|r| r.finger == f.finger);
            Some((rows.filter_map(line_of).collect(), w))
        })
        .collect();
    let mut snapshot = tracking::snapshot(&a, now(), Event::Add);
    snapshot.change = Some(change_record(&req.rows, &new, &flags));
    snapshot.note.clone_from(&req.note);
    commit(&req.data, &bytes, &req.history, &snapshot)?;
    Ok(AddOutcome {
        added: new.rows.len(),
        xrays_before: current.xray_count(),
        xrays_after: after.xray_count(),
        new_file: new.path.clone(),
        from_options: matches!(req.rows, NewRows::Fields(_)),
        accepted,
        swapped,
        taken_tip: tipped
            .from_dataset
            .map(|(kind, rows)| (kind, rows.len(), first_ids(&new, &rows))),
        limits,
        added_columns: append::added_columns(&current, &new),
        flags,
    })
}

/// The history's record of an addition: the new rows' file (none for rows
/// given as options), X-rays, and the rows added though flagged.
fn change_record(source: &NewRows, new: &Dataset, flags: &[Flag]) -> ChangeRecord {
    ChangeRecord {
        file: match source {
            NewRows::Fields(_) => None,
            _ => Some(new.path.clone()),
        },
        xrays: xray_ids(&new.rows),
        rows: new.rows.len(),
        flagged: new
            .rows
            .iter()
            .filter_map(|r| {
                let f = flag_of(flags, r)?;
                Some(FlaggedRow {
                    xray: r.xray.to_string(),
                    finger: r.finger,
                    reason: f.finding.clone(),
                })
            })
            .collect(),
    }
}

/// The first distinct X-ray ids (at most 11) of the rows at `rows` of `new`.
fn first_ids(new: &Dataset, rows: &[usize]) -> Vec<String> {
    let mut seen = std::collections::HashSet::new();
    rows.iter()
        .filter_map(|&i| new.rows.get(i))
        .map(|r| &*r.xray)
        .filter(|x| seen.insert(*x))
        .take(11)
        .map(str::to_string)
        .collect()
}

/// The flag of a new row, if the rules flagged it.
fn flag_of<'f>(flags: &'f [Flag], r: &Row) -> Option<&'f Flag> {
    flags
        .iter()
        .find(|f| f.xray == *r.xray && f.finger == r.finger.name())
}

/// The distinct X-ray ids of rows, in order of first appearance.
fn xray_ids(rows: &[Row]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows {
        if !out.iter().any(|x| *x == *r.xray) {
            out.push(r.xray.to_string());
        }
    }
    out
}

/// Stages the dataset and the history in full before replacing either: a history that
/// cannot be written stops the change with the dataset untouched. Between the two
/// renames a crash can only lose the record ('phalanx snapshot' records it again).
fn commit(
    data: &Path,
    bytes: &[u8],
    history_path: &Path,
    snapshot: &Snapshot,
) -> Result<(), Error> {
    let history_bytes =
        history::appended_bytes(history_path, snapshot).map_err(Error::write(history_path))?;
    let staged_data = atomic::stage(data, bytes).map_err(Error::write(data))?;
    let staged_history =
        atomic::stage(history_path, &history_bytes).map_err(Error::write(history_path))?;
    atomic::commit(staged_data, data).map_err(Error::write(data))?;
    atomic::commit(staged_history, history_path).map_err(Error::write(history_path))?;
    Ok(())
}

/// The flagged rows among new rows that have other `problems`: the rows without a
/// problem of their own line that the rules flag (one problem each, at its line), so
/// one pass names every problem of the file. None when the dataset cannot be analysed
/// with the request's settings.
fn flags_among(
    current: &Dataset,
    new: &Dataset,
    problems: &[Problem],
    req: &AddRequest,
    from_file: bool,
) -> Vec<Problem> {
    let budget = analysis::budget::check_bootstrap(current.xray_count(), req.settings.resamples);
    if budget.is_err() || current.rows.is_empty() {
        return Vec::new();
    }
    let mut clean = append::with_defaults(new, current);
    clean
        .rows
        .retain(|r| !problems.iter().any(|p| p.line == Some(r.line)));
    let before = analysis::analyse(current, &req.settings);
    let flags = outliers::flag_rows(&before, &clean.rows);
    let mut out = flag_problems(&clean, &flags, from_file);
    if !out.is_empty() {
        out.push(Problem::file(
            "nothing was added. Correct the rows above and add again; a flagged row that is right as measured goes in with --accept-flagged (then recorded as flagged)",
        ));
    }
    out
}

/// One problem per row of `new` that the rules flag, at its line in the user's file.
fn flag_problems(new: &Dataset, flags: &[Flag], from_file: bool) -> Vec<Problem> {
    new.rows
        .iter()
        .filter_map(|r| {
            let f = flag_of(flags, r)?;
            let message = format!("flagged as a likely error: {}", f.reason);
            Some(if from_file {
                Problem::line(r.line, message)
            } else {
                Problem::file(message)
            })
        })
        .collect()
}

/// The error of an `add` whose rows the rules flag: one problem per flagged row, at its
/// line in the user's file, then what to do.
fn refusal(new: &Dataset, flags: &[Flag], from_file: bool) -> DataError {
    let mut problems = flag_problems(new, flags, from_file);
    problems.push(Problem::file(format!(
        "nothing was added. Correct the {} and add again, or, if {} right as measured, add with --accept-flagged: {} then recorded as flagged in the dataset's 'flagged' column and in the history, and listed by 'phalanx stats' and the report",
        if flags.len() == 1 { "row" } else { "rows" },
        if flags.len() == 1 { "it is" } else { "they are" },
        if flags.len() == 1 { "it is" } else { "they are" },
    )));
    DataError {
        file: new.path.clone(),
        problems,
    }
}

/// What `remove` is asked to do.
pub(crate) struct RemoveRequest {
    pub data: PathBuf,
    pub history: PathBuf,
    /// The X-rays whose rows go.
    pub xrays: Vec<String>,
    /// Only this finger of them (all their rows when `None`).
    pub finger: Option<Finger>,
    /// The user's note for the history record.
    pub note: Option<String>,
    pub settings: Settings,
}

/// What `remove` did.
#[derive(Debug)]
pub(crate) struct RemoveOutcome {
    /// The rows removed (as they were in the dataset, with their lines).
    pub removed: Vec<Row>,
    pub xrays_before: usize,
    pub xrays_after: usize,
}

/// Takes the rows of some X-rays (of one finger, or all) out of a dataset, under its
/// lock, and appends a record of the removal to its history. Every other byte of the
/// file is kept, so removing what an `add` appended (without new header columns)
/// restores the file, and its statistics, bit for bit. An X-ray without such rows is
/// refused, with the X-rays the dataset has; removing every row is refused too (a
/// dataset needs one).
pub(crate) fn remove(req: &RemoveRequest) -> Result<RemoveOutcome, Error> {
    csvinput::open_input(&req.data)?;
    let _lock = DatasetLock::acquire(&req.data).map_err(Error::write(&req.data))?;
    let current_bytes = csvinput::read_input(&req.data)?;
    let label = req.data.display().to_string();
    let current = Dataset::from_bytes(&label, &current_bytes)?;
    let selected = |r: &Row| {
        req.xrays.iter().any(|x| *x == *r.xray) && req.finger.is_none_or(|f| f == r.finger)
    };
    let mut problems = Vec::new();
    for x in &req.xrays {
        if !current.rows.iter().any(|r| *x == *r.xray && selected(r)) {
            let what = req
                .finger
                .map_or("no rows".to_string(), |f| format!("no {f} row"));
            let has = current.rows.iter().filter(|r| *x == *r.xray).count();
            problems.push(Problem::file(if has > 0 {
                format!(
                    "X-ray {} has {what} (it has {has} row{} of other fingers); nothing was removed",
                    csvinput::quote(x),
                    if has == 1 { "" } else { "s" }
                )
            } else {
                format!(
                    "has no X-ray {}; nothing was removed. Its X-rays are {}",
                    csvinput::quote(x),
                    some_ids(&current)
                )
            }));
        }
    }
    let removed: Vec<Row> = current
        .rows
        .iter()
        .filter(|r| selected(r))
        .cloned()
        .collect();
    if problems.is_empty() && removed.len() == current.rows.len() {
        problems.push(Problem::file(
            "removing these rows would leave no row; a dataset needs at least one, so nothing was removed",
        ));
    }
    if !problems.is_empty() {
        return Err(DataError {
            file: label,
            problems,
        }
        .into());
    }
    let lines: Vec<u64> = removed.iter().map(|r| r.line).collect();
    let bytes = append::removed_bytes(&current_bytes, &label, &lines)?;
    let after = Dataset::from_bytes(&label, &bytes)?;
    analysis::budget::check_bootstrap(after.xray_count(), req.settings.resamples)
        .map_err(Error::Usage)?;
    let a = analysis::analyse(&after, &req.settings);
    let mut snapshot = tracking::snapshot(&a, now(), Event::Remove);
    snapshot.change = Some(ChangeRecord {
        file: None,
        xrays: xray_ids(&removed),
        rows: removed.len(),
        flagged: removed
            .iter()
            .filter_map(|r| {
                Some(FlaggedRow {
                    xray: r.xray.to_string(),
                    finger: r.finger,
                    reason: r.meta.flagged.as_deref()?.to_string(),
                })
            })
            .collect(),
    });
    snapshot.note.clone_from(&req.note);
    commit(&req.data, &bytes, &req.history, &snapshot)?;
    Ok(RemoveOutcome {
        removed,
        xrays_before: current.xray_count(),
        xrays_after: after.xray_count(),
    })
}

/// The first X-ray ids of a dataset, for a message: at most 10, then how many more.
fn some_ids(d: &Dataset) -> String {
    let ids = xray_ids(&d.rows);
    let shown: Vec<String> = ids.iter().take(10).map(|x| csvinput::quote(x)).collect();
    if ids.len() > shown.len() {
        format!("{} and {} more", shown.join(", "), ids.len() - shown.len())
    } else {
        shown.join(", ")
    }
}

/// What `snapshot` did.
#[derive(Debug)]
pub(crate) enum SnapshotOutcome {
    /// A record was appended.
    Written(Snapshot),
    /// The data and settings are those of the history's last record (number `record`,
    /// 1-based): nothing was written.
    Unchanged { record: usize, last: Snapshot },
    /// The data and settings are those of record `same` (1-based), and a note was
    /// given: a milestone was appended, a copy of that record's statistics (the same
    /// SHA-256) with the note and the time.
    Milestone { same: usize, snap: Snapshot },
}

/// Appends a snapshot of the dataset's current statistics to its history (for data
/// edited by hand), unless nothing changed since the last record: the same file
/// (SHA-256) and the same settings. With a note, an unchanged dataset gets a milestone
/// (the last record's statistics again, with the note) instead of nothing. Holds the
/// dataset's lock while it reads.
pub(crate) fn snapshot(
    data: &Path,
    history_path: &Path,
    settings: &Settings,
    note: Option<String>,
) -> Result<SnapshotOutcome, Error> {
    csvinput::open_input(data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(data).map_err(Error::write(data))?;
    let dataset = Dataset::load(data)?;
    let snaps = history::read(history_path)?;
    if let Some(last) = snaps.last()
        && last.sha256 == dataset.sha256
        && last.settings.resamples == settings.resamples
        && last.settings.seed == settings.seed
        && last.settings.confidence == settings.confidence
    {
        if note.is_none() {
            return Ok(SnapshotOutcome::Unchanged {
                record: snaps.len(),
                last: last.clone(),
            });
        }
        let mut snap = last.clone();
        snap.time = now();
        snap.event = Event::Snapshot;
        snap.change = None;
        snap.note = note;
        history::append(history_path, &snap).map_err(Error::write(history_path))?;
        return Ok(SnapshotOutcome::Milestone {
            same: snaps.len(),
            snap,
        });
    }
    analysis::budget::check_bootstrap(dataset.xray_count(), settings.resamples)
        .map_err(Error::Usage)?;
    let a = analysis::analyse(&dataset, settings);
    let mut snap = tracking::snapshot(&a, now(), Event::Snapshot);
    snap.note = note;
    history::append(history_path, &snap).map_err(Error::write(history_path))?;
    Ok(SnapshotOutcome::Written(snap))
}
