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

/// What `add` did.
#[derive(Debug)]
pub(crate) struct AddOutcome {
    pub added: usize,
    pub xrays_before: usize,
    pub xrays_after: usize,
    /// Rows added though flagged (with `accept_flagged`), one flag per row.
    pub flags: Vec<Flag>,
    /// Warnings to show, each starting with the file and line it is about
    /// (`new.csv:24: ...`, or the file alone for rows without a line of their own).
    pub warnings: Vec<String>,
    /// What the reader should know of the new rows: the tip that rows giving none took
    /// from the dataset, fingers whose new rows could not be checked fully (too few
    /// current X-rays, or none in the new rows' unit).
    pub notes: Vec<String>,
    /// Header columns the dataset gained (the new rows fill them).
    pub added_columns: Vec<&'static str>,
}

impl AddOutcome {
    /// The warnings and notes of an addition, one line each, for standard
    /// error: `warning: ...`, `note: ...`, and the columns the header gained.
    pub(crate) fn messages(&self) -> Vec<String> {
        let mut lines = Vec::new();
        for w in &self.warnings {
            lines.push(format!("warning: {w}"));
        }
        for n in &self.notes {
            lines.push(format!("note: {n}"));
        }
        if !self.added_columns.is_empty() {
            lines.push(format!(
                "note: the dataset's header gained the column{} {} (empty on its existing rows)",
                if self.added_columns.len() == 1 {
                    ""
                } else {
                    "s"
                },
                self.added_columns.join(", ")
            ));
        }
        lines
    }
}

/// "1 row", "50 rows".
pub(crate) fn rows_text(n: usize) -> String {
    format!("{n} row{}", if n == 1 { "" } else { "s" })
}

/// ", 1 of them recorded as flagged", or nothing.
pub(crate) fn flagged_text(n: usize) -> String {
    match n {
        0 => String::new(),
        1 => ", 1 of them recorded as flagged".to_string(),
        n => format!(", {n} of them recorded as flagged"),
    }
}

/// The current UTC time, RFC 3339, for history records.
pub(crate) fn now() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

/// Where a message about one new row points: `FILE:LINE` for a row of a file the user
/// wrote, the file alone for rows given as options or made by the program.
fn place(new: &Dataset, line: Option<u64>) -> String {
    match line {
        Some(l) => format!("{}:{l}", new.path),
        None => new.path.clone(),
    }
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
    let from_file = matches!(req.rows, NewRows::File(_));
    let line_of = |r: &Row| from_file.then_some(r.line);
    csvinput::open_input(&req.data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(&req.data).map_err(Error::write(&req.data))?;
    let current_bytes = csvinput::read_input(&req.data)?;
    let label = req.data.display().to_string();
    let current = Dataset::from_bytes(&label, &current_bytes)?;
    let tipped = tip::record_new(&current, new, req.tip, from_file);
    let new = &tipped.rows;
    // Conflicting metadata and missing tips are refused before anything else is said
    // about the rows, every problem at once.
    let mut problems = tipped.problems;
    if let Err(e) = append::check_fits(&current, new) {
        problems.extend(e.problems);
    }
    if !problems.is_empty() {
        problems.sort_by_key(|p| (p.line.is_none(), p.line));
        if !from_file {
            problems.iter_mut().for_each(|p| p.line = None);
        }
        return Err(DataError {
            file: new.path.clone(),
            problems,
        }
        .into());
    }
    refuse_mixed_tips(&current, new, req.mixed_tips)?;
    let n = current.xray_count() + new.xray_count();
    analysis::budget::check_bootstrap(n, req.settings.resamples).map_err(Error::Usage)?;
    let filled = append::with_defaults(new, &current);
    let new = &filled;
    let before = analysis::analyse(&current, &req.settings);
    let flags = outliers::flag_rows(&before, &new.rows);
    if !flags.is_empty() && !req.accept_flagged {
        return Err(refusal(new, &flags, from_file).into());
    }
    let mut notes: Vec<String> = Vec::new();
    if let Some((kind, rows)) = &tipped.from_dataset {
        notes.push(taken_tip_note(&req.rows, new, &current, *kind, rows));
    }
    for r in &new.rows {
        if let Some(note) = outliers::limits(&before, r.finger)
            && !notes.contains(&note)
        {
            notes.push(note);
        }
    }
    notes.extend(outliers::unit_limits(&before, &new.rows));
    // Accepted flags are recorded in the rows themselves.
    let marked;
    let new = if flags.is_empty() {
        new
    } else {
        let mut m = new.clone();
        for r in &mut m.rows {
            if let Some(f) = flag_of(&flags, r) {
                r.meta.flagged = Some(Arc::from(f.finding.as_str()));
            }
        }
        marked = m;
        &marked
    };
    let (bytes, after) = append::appended_bytes_typed(&current_bytes, &current, new, &typed)
        .map_err(|mut e| {
            if !from_file {
                e.problems.iter_mut().for_each(|p| p.line = None);
            }
            e
        })?;
    let added_columns = append::added_columns(&current, new);
    let a = analysis::analyse(&after, &req.settings);
    let mut warnings: Vec<String> = new
        .rows
        .iter()
        .filter_map(|r| {
            let f = flag_of(&flags, r)?;
            Some(format!(
                "{}: added though flagged (--accept-flagged): {}",
                place(new, line_of(r)),
                f.reason
            ))
        })
        .collect();
    for f in &a.fingers {
        if let Some(w) = analysis::plausible::swapped_segments(f) {
            let lines: Vec<String> = new
                .rows
                .iter()
                .filter(|r| r.finger == f.finger)
                .filter_map(|r| line_of(r).map(|l| l.to_string()))
                .collect();
            let at = if lines.is_empty() {
                new.path.clone()
            } else {
                format!("{}:{}", new.path, lines.join(","))
            };
            warnings.push(format!("{at}: {w}"));
        }
    }
    let mut snapshot = tracking::snapshot(&a, now(), Event::Add);
    snapshot.change = Some(ChangeRecord {
        file: match &req.rows {
            NewRows::Fields(_) => None,
            _ => Some(new.path.clone()),
        },
        xrays: xray_ids(&new.rows),
        rows: new.rows.len(),
        flagged: new
            .rows
            .iter()
            .filter_map(|r| {
                let f = flag_of(&flags, r)?;
                Some(FlaggedRow {
                    xray: r.xray.to_string(),
                    finger: r.finger,
                    reason: f.finding.clone(),
                })
            })
            .collect(),
    });
    snapshot.note.clone_from(&req.note);
    commit(&req.data, &bytes, &req.history, &snapshot)?;
    Ok(AddOutcome {
        added: new.rows.len(),
        xrays_before: current.xray_count(),
        xrays_after: after.xray_count(),
        flags,
        warnings,
        notes,
        added_columns,
    })
}

/// What `add` says of new rows that gave no tip and took the one every row of the dataset
/// records: "50 rows of new.csv give no tip: recorded at the skin, as every row of
/// data/measurements.csv is; give --tip bone if these were measured to the bone (take them
/// out first: phalanx remove --xray n1,n2)".
fn taken_tip_note(
    source: &NewRows,
    new: &Dataset,
    current: &Dataset,
    kind: TipKind,
    rows: &[usize],
) -> String {
    let other = match kind {
        TipKind::Bone => TipKind::Skin,
        TipKind::Skin => TipKind::Bone,
    };
    let n = rows.len();
    let mut seen = std::collections::HashSet::new();
    let ids: Vec<&str> = rows
        .iter()
        .filter_map(|&i| new.rows.get(i))
        .map(|r| &*r.xray)
        .filter(|x| seen.insert(*x))
        .take(11)
        .collect();
    // Ids a shell and the option parser take as they are.
    let plain = |x: &&str| {
        x.starts_with(|c: char| c.is_ascii_alphanumeric())
            && x.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
    };
    let (subject, these, them) = match source {
        NewRows::Fields(_) => ("the new row gives".to_string(), "it was", "it"),
        _ => (
            format!(
                "{} of {} give{}",
                crate::format::count(n, "row", "rows"),
                new.path,
                if n == 1 { "s" } else { "" }
            ),
            if n == 1 { "it was" } else { "these were" },
            if n == 1 { "it" } else { "them" },
        ),
    };
    let remove = if ids.len() <= 10 && ids.iter().all(plain) {
        format!("phalanx remove --xray {}", ids.join(","))
    } else {
        "phalanx remove --xray with their ids".to_string()
    };
    format!(
        "{subject} no tip: recorded at the {}, as every row of {} is; give --tip {} if {these} \
         measured to the {} (take {them} out first: {remove})",
        kind.name(),
        current.path,
        other.name(),
        other.name()
    )
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

/// The error of an `add` whose rows the rules flag: one problem per flagged row, at its
/// line in the user's file, then what to do.
fn refusal(new: &Dataset, flags: &[Flag], from_file: bool) -> DataError {
    let mut problems: Vec<Problem> = new
        .rows
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
        .collect();
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
}

/// Appends a snapshot of the dataset's current statistics to its history (for data
/// edited by hand), unless nothing changed since the last record: the same file
/// (SHA-256) and the same settings. Holds the dataset's lock while it reads.
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
        return Ok(SnapshotOutcome::Unchanged {
            record: snaps.len(),
            last: last.clone(),
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
