//! Appending new X-rays to a dataset file: validated, locked, atomic.
//!
//! The existing bytes are kept as they are (only a missing final line end is
//! added); new rows go after them in the file's own column order. The caller
//! holds a [`DatasetLock`] from reading to replacing the file, so concurrent
//! additions serialise instead of losing each other's rows.

use super::csvinput::{Columns, quote};
use super::{Column, DataError, Dataset, Problem, Row};
use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

/// An exclusive advisory lock on a dataset (on `<dataset>.lock` beside it,
/// since the dataset itself is replaced by rename). Released when dropped.
pub(crate) struct DatasetLock {
    _file: File,
}

impl DatasetLock {
    /// Blocks until the lock on `data` is ours. A link is followed, so every
    /// path to the same file shares one lock.
    pub(crate) fn acquire(data: &Path) -> std::io::Result<DatasetLock> {
        let data = crate::atomic::resolve(data);
        let mut name = data.as_os_str().to_owned();
        name.push(".lock");
        let path = PathBuf::from(name);
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)?;
        file.lock()?;
        Ok(DatasetLock { _file: file })
    }
}

/// The CSV (header and one row) of a row given on the command line.
pub(crate) fn single_row_bytes(fields: &[(&str, String)]) -> Result<Vec<u8>, DataError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header: Vec<&str> = fields.iter().map(|(k, _)| *k).collect();
    let values: Vec<&str> = fields.iter().map(|(_, v)| v.as_str()).collect();
    w.write_record(&header)
        .and_then(|_| w.write_record(&values))
        .map_err(|e| e.to_string())
        .and_then(|_| w.into_inner().map_err(|e| e.to_string()))
        .map_err(|e| DataError::whole_file("<command line>", e))
}

/// Parses new rows given on the command line as one CSV row; problems name the
/// option they came from instead of a line.
pub(crate) fn single_row(fields: &[(&str, String)]) -> Result<Dataset, DataError> {
    let bytes = single_row_bytes(fields)?;
    Dataset::from_bytes("<command line>", &bytes).map_err(|mut e| {
        for p in &mut e.problems {
            p.line = None;
            p.column = None;
            if let Some(f) = p.field.take() {
                p.message = format!("--{}: {}", option_of(&f), p.message);
            }
        }
        e
    })
}

/// The `add` option a column comes from.
fn option_of(column: &str) -> &str {
    match column {
        "j1" | "j2" | "j3" => "lengths",
        other => other,
    }
}

/// Formats a length so that it parses back to the same `f64`.
fn length_text(x: f64) -> String {
    crate::format::full(Some(x))
}

/// The fields of new rows as the user typed them: line -> column -> trimmed
/// text, read with the loader's own table reader (so the lines are the rows' lines).
#[derive(Debug, Default)]
pub(crate) struct Typed(HashMap<u64, HashMap<&'static str, String>>);

impl Typed {
    /// Reads the typed fields of a measurement CSV; unreadable input gives none
    /// (the loader reports it).
    pub(crate) fn of(bytes: &[u8]) -> Typed {
        let mut out = HashMap::new();
        let _ = super::csvinput::read_table::<Column>("", bytes, |cells| {
            let fields = Column::ALL
                .iter()
                .filter_map(|&c| Some((c.name(), cells.text(c)?.to_string())))
                .filter(|(_, text)| !text.is_empty())
                .collect();
            out.insert(cells.line(), fields);
        });
        Typed(out)
    }

    /// The text typed for a number, when it reads as exactly `value` (so
    /// `275.00` stays `275.00`); `None` otherwise.
    fn number(&self, line: u64, column: &str, value: f64) -> Option<String> {
        let text = self.0.get(&line)?.get(column)?;
        (text.parse::<f64>().ok()? == value).then(|| text.clone())
    }
}

/// One field of a row, by column name, numbers as typed where known.
fn typed_field_of(row: &Row, column: &str, typed: &Typed) -> String {
    let number = match column {
        "j1" => Some(row.lengths[0]),
        "j2" => Some(row.lengths[1]),
        "j3" if row.finger.segments() == 3 => Some(row.lengths[2]),
        "age" => row.meta.age,
        _ => None,
    };
    number
        .and_then(|v| typed.number(row.line, column, v))
        .unwrap_or_else(|| field_of(row, column))
}

/// One field of a row, by column name.
fn field_of(row: &Row, column: &str) -> String {
    let s = |v: &Option<std::sync::Arc<str>>| v.as_deref().unwrap_or("").to_string();
    match column {
        "xray" => row.xray.to_string(),
        "finger" => row.finger.name().to_string(),
        "j1" => length_text(row.lengths[0]),
        "j2" => length_text(row.lengths[1]),
        "j3" if row.finger.segments() == 3 => length_text(row.lengths[2]),
        "mc" => crate::format::full(row.mc),
        "sex" => s(&row.meta.sex),
        "age" => crate::format::full(row.meta.age),
        "side" => s(&row.meta.side),
        "source" => s(&row.meta.source),
        "unit" => s(&row.meta.unit),
        "tip" => row.meta.tip.map_or(String::new(), |t| t.name().to_string()),
        _ => String::new(),
    }
}

/// The bytes of the dataset with `new` appended, after checking that the new rows
/// fit it: no (X-ray, finger) already present, the same sex/age/side/unit/tip as
/// existing rows of the same X-ray, the dataset's unit (when both name one), and no
/// metadata (or metacarpal) for a column the file lacks.
/// Problems name the new rows' lines in `new.path`. Returns the new bytes and
/// the dataset they hold (validated once). Numbers are written as `typed` holds
/// them (see [`Typed`]; with `Typed::default()`, in their shortest exact form).
/// A new row that leaves sex, age, side or unit empty takes the value of the
/// X-ray's existing rows (one hand has one value).
pub(crate) fn appended_bytes_typed(
    current_bytes: &[u8],
    current: &Dataset,
    new: &Dataset,
    typed: &Typed,
) -> Result<(Vec<u8>, Dataset), DataError> {
    let problems = check_new_rows(current, new);
    if !problems.is_empty() {
        return Err(DataError {
            file: new.path.clone(),
            problems,
        });
    }
    let out = append_rows(current_bytes, current, new, typed)?;
    // The result must load as a valid dataset; that dataset is returned with it.
    let appended = Dataset::from_bytes(&current.path, &out)?;
    Ok((out, appended))
}

/// The problems of new rows against the current dataset (see [`appended_bytes_typed`]).
fn check_new_rows(current: &Dataset, new: &Dataset) -> Vec<Problem> {
    let mut problems = Vec::new();
    let existing: HashMap<(&str, super::Finger), &Row> = current
        .rows
        .iter()
        .map(|r| ((&*r.xray, r.finger), r))
        .collect();
    let mut by_xray: HashMap<&str, &Row> = HashMap::new();
    for r in &current.rows {
        by_xray.entry(&r.xray).or_insert(r);
    }
    let unit = current
        .rows
        .iter()
        .find_map(|r| r.meta.unit.as_deref().map(|u| (u, r.line)));
    for r in &new.rows {
        if let (Some((unit, line)), Some(ours)) = (unit, r.meta.unit.as_deref())
            && ours != unit
        {
            problems.push(Problem::line(
                r.line,
                format!(
                    "unit is {} but the rows of {} are in {} (line {line}); lengths in different units cannot be averaged: convert the new lengths to {}, or give them the dataset's unit",
                    quote(ours),
                    current.path,
                    quote(unit),
                    quote(unit)
                ),
            ));
        }
        if let Some(old) = existing.get(&(&*r.xray, r.finger)) {
            problems.push(Problem::line(
                r.line,
                format!(
                    "X-ray {} already has {} row in {} (line {}); existing rows are never replaced. Use another X-ray id, or edit the dataset by hand",
                    quote(&r.xray),
                    r.finger.with_article(),
                    current.path,
                    old.line
                ),
            ));
        }
        if let Some(old) = by_xray.get(&*r.xray) {
            metadata_conflicts(r, old, &current.path, &mut problems);
        }
        missing_columns(r, current, &mut problems);
    }
    problems
}

/// A new row's metadata (sex, age, side, unit, tip) that differs from the same X-ray's
/// existing row `old` (in file `path`): one hand has one value.
fn metadata_conflicts(r: &Row, old: &Row, path: &str, problems: &mut Vec<Problem>) {
    for name in ["sex", "age", "side", "unit", "tip"] {
        let (ours, theirs) = (field_of(r, name), field_of(old, name));
        // An empty field takes the X-ray's value (see append_rows).
        if !ours.is_empty() && ours != theirs {
            let theirs = if theirs.is_empty() {
                "empty".into()
            } else {
                quote(&theirs)
            };
            problems.push(Problem::line(
                r.line,
                format!(
                    "{name} is {} but {} line {} gives {theirs} for the same X-ray {}; one hand has one value. \
                     Leave {name} out (omit --{name}, or leave the field empty) and the row takes {theirs}, \
                     or, if {theirs} is wrong, edit line {} of {} first",
                    quote(&ours),
                    path,
                    old.line,
                    quote(&r.xray),
                    old.line,
                    path,
                ),
            ));
        }
    }
}

/// An optional field the new row gives that the current dataset has no column for.
fn missing_columns(r: &Row, current: &Dataset, problems: &mut Vec<Problem>) {
    for col in Column::ALL
        .iter()
        .filter(|c| !c.required())
        .map(|c| c.name())
    {
        if !current.columns.iter().any(|c| c == col) && !field_of(r, col).is_empty() {
            problems.push(Problem::line(
                r.line,
                format!(
                    "gives a {col}, but {} has no '{col}' column; add the column to its header first or leave {col} empty",
                    current.path
                ),
            ));
        }
    }
}

/// The current bytes with the new rows written after them, in the file's own
/// column order and line ends.
fn append_rows(
    current_bytes: &[u8],
    current: &Dataset,
    new: &Dataset,
    typed: &Typed,
) -> Result<Vec<u8>, DataError> {
    let mut by_xray: HashMap<&str, &Row> = HashMap::new();
    for r in &current.rows {
        by_xray.entry(&r.xray).or_insert(r);
    }
    let mut out = current_bytes.to_vec();
    if !out.is_empty() && !out.ends_with(b"\n") {
        out.extend_from_slice(if current_bytes.contains(&b'\r') {
            b"\r\n"
        } else {
            b"\n"
        });
    }
    let mut w = csv::WriterBuilder::new()
        .terminator(if current_bytes.windows(2).any(|p| p == b"\r\n") {
            csv::Terminator::CRLF
        } else {
            csv::Terminator::Any(b'\n')
        })
        .from_writer(Vec::new());
    for r in &new.rows {
        let rec: Vec<String> = current
            .columns
            .iter()
            .map(|c| {
                let ours = typed_field_of(r, c, typed);
                match by_xray.get(&*r.xray) {
                    Some(old)
                        if ours.is_empty()
                            && ["sex", "age", "side", "unit"].contains(&c.as_str()) =>
                    {
                        field_of(old, c)
                    }
                    _ => ours,
                }
            })
            .collect();
        w.write_record(&rec)
            .map_err(|e| DataError::whole_file(&new.path, e.to_string()))?;
    }
    let tail = w
        .into_inner()
        .map_err(|e| DataError::whole_file(&new.path, e.to_string()))?;
    out.extend_from_slice(&tail);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ds(label: &str, text: &str) -> Dataset {
        Dataset::from_bytes(label, text.as_bytes()).unwrap()
    }

    const OLD: &str = "xray,finger,j1,j2,j3,sex\na,index,4,3,3,f\na,thumb,4,3,,f\n";

    #[test]
    fn appends_in_the_file_column_order_keeping_old_bytes() {
        let cur = ds("d.csv", OLD);
        let new = ds("n.csv", "finger,xray,j2,j1,j3,sex\nring,b,2.5,5.25,2,m\n");
        let (out, appended) =
            appended_bytes_typed(OLD.as_bytes(), &cur, &new, &Typed::default()).unwrap();
        assert_eq!(appended.rows.len(), 3);
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with(OLD));
        assert_eq!(&text[OLD.len()..], "b,ring,5.25,2.5,2,male\n");
    }

    #[test]
    fn adds_a_missing_final_line_end_and_keeps_crlf() {
        let old = "xray,finger,j1,j2,j3\r\na,index,4,3,3";
        let cur = ds("d.csv", old);
        let new = ds("n.csv", "xray,finger,j1,j2,j3\nb,index,1,2,3\n");
        let out = String::from_utf8(
            appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default())
                .unwrap()
                .0,
        )
        .unwrap();
        assert_eq!(out, format!("{old}\r\nb,index,1,2,3\r\n"));
    }

    #[test]
    fn refuses_duplicates_conflicts_and_unknown_columns_naming_the_new_line() {
        let cur = ds("d.csv", OLD);
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,sex,age\na,index,1,2,3,f,\nc,ring,1,2,3,,40\n",
        );
        let e = appended_bytes_typed(OLD.as_bytes(), &cur, &new, &Typed::default()).unwrap_err();
        assert_eq!(e.file, "n.csv");
        let lines: Vec<u64> = e.problems.iter().filter_map(|p| p.line).collect();
        assert_eq!(lines, vec![2, 3], "{e}");
        assert!(
            e.problems[0]
                .message
                .contains("already has an index row in d.csv (line 2)")
        );
        assert!(e.problems[1].message.contains("no 'age' column"));
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,sex\nb,ring,1,2,3,f\na,ring,1,2,3,m\n",
        );
        let e = appended_bytes_typed(OLD.as_bytes(), &cur, &new, &Typed::default()).unwrap_err();
        assert_eq!(e.problems.len(), 1, "{e}");
        assert_eq!(e.problems[0].line, Some(3));
        assert!(
            e.problems[0]
                .message
                .contains("sex is 'male' but d.csv line 2 gives 'female'")
        );
    }

    #[test]
    fn a_unit_other_than_the_datasets_is_refused() {
        let old = "xray,finger,j1,j2,j3,unit\na,index,4,3,3,image units\n";
        let cur = ds("d.csv", old);
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,unit\nb,index,4,3,3,mm\nc,index,4,3,3,\n",
        );
        let e = appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default()).unwrap_err();
        assert_eq!(e.problems.len(), 1, "{e}");
        assert_eq!(e.problems[0].line, Some(2));
        assert!(
            e.problems[0]
                .message
                .contains("unit is 'mm' but the rows of d.csv are in 'image units' (line 2)"),
            "{e}"
        );
        // The metacarpal and the tip are appended where the file has their columns.
        let old = "xray,finger,j1,j2,j3,mc,unit,tip\na,index,4,3,3,9,px,bone\n";
        let cur = ds("d.csv", old);
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,mc,unit,tip\nb,index,4,3,3,8.5,px,bone\n",
        );
        let (out, _) = appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default()).unwrap();
        assert!(
            String::from_utf8(out)
                .unwrap()
                .ends_with("b,index,4,3,3,8.5,px,bone\n")
        );
        let e = appended_bytes_typed(OLD.as_bytes(), &ds("d.csv", OLD), &new, &Typed::default())
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("gives a mc, but d.csv has no 'mc' column"),
            "{e}"
        );
    }

    #[test]
    fn single_row_errors_name_the_option() {
        let e = single_row(&[
            ("xray", "z".into()),
            ("finger", "index".into()),
            ("j1", "1".into()),
            ("j2", "abc".into()),
            ("j3", "3".into()),
        ])
        .unwrap_err();
        assert_eq!(e.problems.len(), 1);
        assert_eq!(e.problems[0].line, None);
        assert!(
            e.problems[0]
                .message
                .starts_with("--lengths: 'abc' is not a number"),
            "{e}"
        );
        let ok = single_row(&[
            ("xray", "z".into()),
            ("finger", "thumb".into()),
            ("j1", "1".into()),
            ("j2", "2".into()),
            ("j3", String::new()),
        ])
        .unwrap();
        assert_eq!(ok.rows[0].segments(), &[1.0, 2.0]);
    }

    #[test]
    fn the_lock_is_exclusive() {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("d.csv");
        let held = DatasetLock::acquire(&data).unwrap();
        // The lock file sits beside the dataset.
        let lock_file = dir.path().join("d.csv.lock");
        let f = OpenOptions::new().write(true).open(&lock_file).unwrap();
        assert!(f.try_lock().is_err(), "a second lock was granted");
        drop(held);
        assert!(f.try_lock().is_ok());
    }
}
