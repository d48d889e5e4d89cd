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
        "flagged" => s(&row.meta.flagged),
        _ => String::new(),
    }
}

/// The bytes of the dataset with `new` appended, after checking that the new rows
/// fit it: no (X-ray, finger) already present, and no sex, age, side, unit or tip that
/// differs from what the X-ray's existing rows give (filling one they leave empty is no
/// conflict for sex, age and side). Problems name the new rows' lines in `new.path`.
///
/// Optional columns that the new rows fill and the dataset lacks (`mc`, `tip`, `unit`,
/// `flagged`, ...) are added to its header, in the format's order after its own columns,
/// with every existing row left empty there: the file is then written anew from the
/// fields as they are typed (see [`with_columns`]). Otherwise the existing bytes are kept
/// as they are (only a missing final line end is added). Returns the new bytes and the
/// dataset they hold (validated once). Numbers are written as `typed` holds them (see
/// [`Typed`]; with `Typed::default()`, in their shortest exact form). A new row that
/// leaves sex, age, side, unit or tip empty takes the value of the X-ray's existing
/// rows (one hand has one value).
pub(crate) fn appended_bytes_typed(
    current_bytes: &[u8],
    current: &Dataset,
    new: &Dataset,
    typed: &Typed,
) -> Result<(Vec<u8>, Dataset), DataError> {
    check_fits(current, new, true)?;
    let added = added_columns(current, new);
    let base = if added.is_empty() {
        current_bytes.to_vec()
    } else {
        with_columns(current_bytes, &current.path, &current.columns, &added)?
    };
    let mut columns = current.columns.clone();
    columns.extend(added.iter().map(|c| c.to_string()));
    let out = append_rows(&base, &columns, current, new, typed)?;
    // The result must load as a valid dataset; that dataset is returned with it.
    let appended = Dataset::from_bytes(&current.path, &out)?;
    Ok((out, appended))
}

/// The optional columns some new row fills that the dataset's header lacks, in the
/// format's column order.
pub(crate) fn added_columns(current: &Dataset, new: &Dataset) -> Vec<&'static str> {
    Column::ALL
        .iter()
        .filter(|c| !c.required())
        .map(|c| c.name())
        .filter(|name| !current.columns.iter().any(|c| c == name))
        .filter(|name| new.rows.iter().any(|r| !field_of(r, name).is_empty()))
        .collect()
}

/// The dataset's bytes with `added` columns at the end of its header and an empty field
/// for each in every row: the header and the fields as typed (trimmed), written anew
/// with the file's line ends and byte-order mark. O(bytes).
fn with_columns(
    bytes: &[u8],
    label: &str,
    names: &[String],
    added: &[&str],
) -> Result<Vec<u8>, DataError> {
    let columns: Vec<Option<Column>> = names
        .iter()
        .map(|n| Column::ALL.iter().copied().find(|c| c.name() == n))
        .collect();
    let mut records: Vec<Vec<String>> = Vec::new();
    super::csvinput::read_table::<Column>(label, bytes, |cells| {
        records.push(
            columns
                .iter()
                .map(|c| {
                    c.and_then(|c| cells.text(c))
                        .unwrap_or_default()
                        .to_string()
                })
                .collect(),
        );
    })?;
    let mut out = Vec::new();
    if bytes.starts_with(b"\xEF\xBB\xBF") {
        out.extend_from_slice(b"\xEF\xBB\xBF");
    }
    let mut w = writer(bytes, out);
    let header: Vec<&str> = names
        .iter()
        .map(String::as_str)
        .chain(added.iter().copied())
        .collect();
    let fail = |e: csv::Error| DataError::whole_file(label, e.to_string());
    w.write_record(&header).map_err(fail)?;
    for mut r in records {
        r.extend(added.iter().map(|_| String::new()));
        w.write_record(&r).map_err(fail)?;
    }
    w.into_inner()
        .map_err(|e| DataError::whole_file(label, e.to_string()))
}

/// A CSV writer onto `out` with the line ends of `like` (CRLF when it has them).
fn writer(like: &[u8], out: Vec<u8>) -> csv::Writer<Vec<u8>> {
    csv::WriterBuilder::new()
        .terminator(if like.windows(2).any(|p| p == b"\r\n") {
            csv::Terminator::CRLF
        } else {
            csv::Terminator::Any(b'\n')
        })
        .from_writer(out)
}

/// New rows with what they leave empty filled in: sex, age, side, unit and tip from the
/// X-ray's existing rows (one hand has one value), and a unit no row of the X-ray gives
/// from the dataset's, when every row of it names the same one. So rows typed without a
/// unit are written in the dataset's unit, and are checked and averaged as such.
pub(crate) fn with_defaults(new: &Dataset, current: &Dataset) -> Dataset {
    let hands = current.hands();
    let unit = current.unit().map(std::sync::Arc::<str>::from);
    let mut out = new.clone();
    for r in &mut out.rows {
        if let Some(hand) = hands.get(&*r.xray) {
            let m = &mut r.meta;
            m.sex = m.sex.take().or_else(|| hand.sex.clone());
            m.age = m.age.or(hand.age);
            m.side = m.side.take().or_else(|| hand.side.clone());
            m.unit = m.unit.take().or_else(|| hand.unit.clone());
            m.tip = m.tip.or(hand.tip);
        }
        if r.meta.unit.is_none() {
            r.meta.unit.clone_from(&unit);
        }
    }
    out
}

/// The metadata a new row must agree with: one hand has one value.
const HAND_FIELDS: [&str; 5] = ["sex", "age", "side", "unit", "tip"];

/// Checks that new rows fit the current dataset (see [`appended_bytes_typed`]): every
/// problem, at the new rows' lines in `new.path` (`lined`: the rows are lines of a file
/// the user wrote; a summary names them only then).
pub(crate) fn check_fits(current: &Dataset, new: &Dataset, lined: bool) -> Result<(), DataError> {
    let problems = check_new_rows(current, new, lined);
    if problems.is_empty() {
        Ok(())
    } else {
        Err(DataError {
            file: new.path.clone(),
            problems,
        })
    }
}

/// The problems of new rows against the current dataset (see [`appended_bytes_typed`]).
fn check_new_rows(current: &Dataset, new: &Dataset, lined: bool) -> Vec<Problem> {
    let mut problems = Vec::new();
    let existing: HashMap<(&str, super::Finger), &Row> = current
        .rows
        .iter()
        .map(|r| ((&*r.xray, r.finger), r))
        .collect();
    let mut by_xray: HashMap<&str, Vec<&Row>> = HashMap::new();
    for r in &current.rows {
        by_xray.entry(&r.xray).or_default().push(r);
    }
    let named: Vec<&str> = current.units().into_iter().filter_map(|(u, _)| u).collect();
    let mut present: Vec<(&Row, &&Row)> = Vec::new();
    for r in &new.rows {
        if r.meta.unit.is_none() && named.len() > 1 && !by_xray.contains_key(&*r.xray) {
            let list: Vec<String> = named.iter().map(|u| quote(u)).collect();
            problems.push(Problem::line(
                r.line,
                format!(
                    "names no unit, but the rows of {} are in {} units ({}), so the new lengths' unit cannot be taken from them; give it (--unit, or the unit column)",
                    current.path,
                    named.len(),
                    list.join(", ")
                ),
            ));
        }
        if let Some(old) = existing.get(&(&*r.xray, r.finger)) {
            present.push((r, old));
        }
        if let Some(old) = by_xray.get(&*r.xray) {
            metadata_conflicts(r, old, &current.path, &mut problems);
        }
    }
    problems.extend(already_present(&present, &current.path, lined));
    problems
}

/// The problems of new rows whose (X-ray, finger) the dataset at `path` already has
/// (`(new row, existing row)` pairs): one per row for a single one, else one summary
/// that names the X-rays, their fingers and both files' lines compactly (the new rows'
/// lines only when `lined`).
fn already_present(present: &[(&Row, &&Row)], path: &str, lined: bool) -> Vec<Problem> {
    const NEVER: &str =
        "existing rows are never replaced. Use another X-ray id, or edit the dataset by hand";
    match present {
        [] => Vec::new(),
        [(r, old)] => vec![Problem::line(
            r.line,
            format!(
                "X-ray {} already has {} row in {path} (line {}); {NEVER}",
                quote(&r.xray),
                r.finger.with_article(),
                old.line
            ),
        )],
        _ => {
            let new_lines: Vec<u64> = present.iter().map(|(r, _)| r.line).collect();
            let old_lines: Vec<u64> = present.iter().map(|(_, o)| o.line).collect();
            let own = if lined {
                format!(" ({} of this file)", lines_text(&new_lines))
            } else {
                String::new()
            };
            vec![Problem::file(format!(
                "{} rows already present in {path} (its {}): {}{own}; {NEVER}",
                present.len(),
                lines_text(&old_lines),
                xrays_and_fingers(present),
            ))]
        }
    }
}

/// "X-rays L01-L10, all fingers", or "X-rays 2a (thumb, index), 3b (ring)" when
/// some of the X-rays' fingers are not among `present`.
fn xrays_and_fingers(present: &[(&Row, &&Row)]) -> String {
    let mut by_xray: Vec<(&str, Vec<super::Finger>)> = Vec::new();
    for (r, _) in present {
        match by_xray.iter_mut().find(|(x, _)| *x == &*r.xray) {
            Some((_, f)) => f.push(r.finger),
            None => by_xray.push((&r.xray, vec![r.finger])),
        }
    }
    let every = by_xray
        .iter()
        .all(|(_, f)| super::Finger::ALL.iter().all(|a| f.contains(a)));
    let noun = if by_xray.len() == 1 {
        "X-ray"
    } else {
        "X-rays"
    };
    if every {
        let ids: Vec<&str> = by_xray.iter().map(|(x, _)| *x).collect();
        return format!("{noun} {}, all fingers", id_ranges(&ids));
    }
    let parts: Vec<String> = by_xray
        .iter()
        .map(|(x, f)| {
            let names: Vec<&str> = f.iter().map(|f| f.name()).collect();
            format!("{x} ({})", names.join(", "))
        })
        .collect();
    format!("{noun} {}", parts.join(", "))
}

/// Line numbers in compact form: "line 7", "lines 2-51", "lines 2-4, 9".
pub(crate) fn lines_text(lines: &[u64]) -> String {
    let mut sorted = lines.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut runs: Vec<(u64, u64)> = Vec::new();
    for l in sorted {
        match runs.last_mut() {
            Some((_, hi)) if *hi + 1 == l => *hi = l,
            _ => runs.push((l, l)),
        }
    }
    let parts: Vec<String> = runs
        .iter()
        .map(|&(lo, hi)| {
            if lo == hi {
                lo.to_string()
            } else {
                format!("{lo}-{hi}")
            }
        })
        .collect();
    let noun = if lines.len() == 1 { "line" } else { "lines" };
    format!("{noun} {}", parts.join(", "))
}

/// X-ray ids with runs of consecutive numbers joined: "L01-L10", "2a, 3, 5-7".
/// A run shares its text before the number and the number's width.
pub(crate) fn id_ranges(ids: &[&str]) -> String {
    let split = |id: &str| -> Option<(String, u64, usize)> {
        let digits = id.chars().rev().take_while(char::is_ascii_digit).count();
        let (head, tail) = id.split_at(id.len() - digits);
        Some((head.to_string(), tail.parse().ok()?, digits))
    };
    let mut runs: Vec<(String, String, usize)> = Vec::new(); // (first, last, length)
    let mut prev: Option<(String, u64, usize)> = None;
    for id in ids {
        let this = split(id);
        let follows = matches!((&prev, &this), (Some((h, n, w)), Some((h2, n2, w2)))
            if h == h2 && w == w2 && n + 1 == *n2);
        match runs.last_mut() {
            Some(run) if follows => {
                run.1 = id.to_string();
                run.2 += 1;
            }
            _ => runs.push((id.to_string(), id.to_string(), 1)),
        }
        prev = this;
    }
    let parts: Vec<String> = runs
        .into_iter()
        .map(|(first, last, n)| match n {
            1 => first,
            2 => format!("{first}, {last}"),
            _ => format!("{first}-{last}"),
        })
        .collect();
    parts.join(", ")
}

/// The rows of a new-rows file that parse, when the file's only problems sit on
/// rows (`bad`): those rows' records are blanked (their line ends kept, so every
/// other row keeps its line) and the rest is read again. `None` when the file's
/// problems are not all on rows, or the rest does not read either. O(bytes).
pub(crate) fn readable_rest(label: &str, bytes: &[u8], bad: &DataError) -> Option<Dataset> {
    let lines: Vec<u64> = bad.problems.iter().map(|p| p.line).collect::<Option<_>>()?;
    let mut starts: Vec<(u64, usize)> = Vec::new();
    super::csvinput::read_table::<Column>(label, bytes, |cells| {
        starts.push((cells.line(), cells.start() as usize));
    })
    .ok()?;
    let mut out = Vec::with_capacity(bytes.len());
    out.extend_from_slice(&bytes[..starts.first().map_or(bytes.len(), |s| s.1)]);
    for (i, &(line, start)) in starts.iter().enumerate() {
        let end = starts.get(i + 1).map_or(bytes.len(), |s| s.1);
        let record = &bytes[start..end];
        if lines.contains(&line) {
            out.extend(record.iter().filter(|&&b| b == b'\n' || b == b'\r'));
        } else {
            out.extend_from_slice(record);
        }
    }
    Dataset::from_bytes(label, &out).ok()
}

/// A new row's metadata that differs from what the same X-ray's existing rows `old` (in
/// file `path`) give: one hand has one value. For sex, age and side only a value given on
/// both sides can differ (an empty one is unknown, and filling it is no conflict); unit
/// and tip are the same on every row of a hand, so a new value differs from an empty one.
fn metadata_conflicts(r: &Row, old: &[&Row], path: &str, problems: &mut Vec<Problem>) {
    for name in HAND_FIELDS {
        let ours = field_of(r, name);
        if ours.is_empty() {
            continue; // an empty field takes the X-ray's value (see append_rows)
        }
        let given = old.iter().find(|o| !field_of(o, name).is_empty());
        let (theirs, line) = match given {
            Some(o) => (field_of(o, name), o.line),
            None if matches!(name, "unit" | "tip") => (String::new(), old[0].line),
            None => continue,
        };
        if ours == theirs {
            continue;
        }
        if name == "tip" && theirs.is_empty() {
            problems.push(Problem::line(
                r.line,
                format!(
                    "tip is {} but {path} line {line} records no tip for the same X-ray {}; one \
                     hand has one tip, and every row added records one: record it on the X-ray's \
                     rows of {path} first (edit line {line}), then add this row",
                    quote(&ours),
                    quote(&r.xray),
                ),
            ));
            continue;
        }
        let theirs = if theirs.is_empty() {
            "empty".into()
        } else {
            quote(&theirs)
        };
        problems.push(Problem::line(
            r.line,
            format!(
                "{name} is {} but {} line {line} gives {theirs} for the same X-ray {}; one hand has one value. \
                 Leave {name} out (omit --{name}, or leave the field empty) and the row takes {theirs}, \
                 or, if {theirs} is wrong, edit line {line} of {} first",
                quote(&ours),
                path,
                quote(&r.xray),
                path,
            ),
        ));
    }
}

/// `base` (the dataset's bytes, with any added columns) with the new rows written after
/// it, in the order of `columns` and with its line ends.
fn append_rows(
    base: &[u8],
    columns: &[String],
    current: &Dataset,
    new: &Dataset,
    typed: &Typed,
) -> Result<Vec<u8>, DataError> {
    let hands = current.hands();
    let mut out = base.to_vec();
    if !out.is_empty() && !out.ends_with(b"\n") {
        out.extend_from_slice(if base.contains(&b'\r') {
            b"\r\n"
        } else {
            b"\n"
        });
    }
    let mut w = writer(base, Vec::new());
    for r in &new.rows {
        let rec: Vec<String> = columns
            .iter()
            .map(|c| {
                let ours = typed_field_of(r, c, typed);
                match hands.get(&*r.xray) {
                    Some(hand) if ours.is_empty() && HAND_FIELDS.contains(&c.as_str()) => {
                        meta_field(hand, c)
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

/// One metadata field of a hand (see [`Dataset::hand`]), by column name.
fn meta_field(m: &super::Meta, column: &str) -> String {
    let s = |v: &Option<std::sync::Arc<str>>| v.as_deref().unwrap_or("").to_string();
    match column {
        "sex" => s(&m.sex),
        "age" => crate::format::full(m.age),
        "side" => s(&m.side),
        "unit" => s(&m.unit),
        "tip" => m.tip.map_or(String::new(), |t| t.name().to_string()),
        _ => String::new(),
    }
}

/// The dataset's bytes without the rows at `lines` (their records and the line ends and
/// blank lines after them; every other byte is kept). `lines` must be rows of `bytes`,
/// which must load as a dataset. O(bytes).
pub(crate) fn removed_bytes(
    bytes: &[u8],
    label: &str,
    lines: &[u64],
) -> Result<Vec<u8>, DataError> {
    let mut starts: Vec<(u64, usize)> = Vec::new();
    super::csvinput::read_table::<Column>(label, bytes, |cells| {
        starts.push((cells.line(), cells.start() as usize));
    })?;
    let mut out = Vec::with_capacity(bytes.len());
    let first = starts.first().map_or(bytes.len(), |s| s.1);
    out.extend_from_slice(&bytes[..first]);
    for (i, &(line, start)) in starts.iter().enumerate() {
        let end = starts.get(i + 1).map_or(bytes.len(), |s| s.1);
        if !lines.contains(&line) {
            out.extend_from_slice(&bytes[start..end]);
        }
    }
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
    fn refuses_duplicates_and_conflicts_naming_the_new_line() {
        let cur = ds("d.csv", OLD);
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,sex,age\na,index,1,2,3,f,\nc,ring,1,2,3,,40\n",
        );
        let e = appended_bytes_typed(OLD.as_bytes(), &cur, &new, &Typed::default()).unwrap_err();
        assert_eq!(e.file, "n.csv");
        let lines: Vec<u64> = e.problems.iter().filter_map(|p| p.line).collect();
        assert_eq!(lines, vec![2], "{e}");
        assert!(
            e.problems[0]
                .message
                .contains("already has an index row in d.csv (line 2)")
        );
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
    fn a_column_the_dataset_lacks_is_added_to_its_header() {
        // c gives an age: the header gains 'age', every old row an empty field there (its
        // other fields as typed).
        let cur = ds("d.csv", OLD);
        let new = ds("n.csv", "xray,finger,j1,j2,j3,age\nc,ring,1,2,3,40\n");
        assert_eq!(added_columns(&cur, &new), ["age"]);
        let (out, d) = appended_bytes_typed(OLD.as_bytes(), &cur, &new, &Typed::default()).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "xray,finger,j1,j2,j3,sex,age\na,index,4,3,3,f,\na,thumb,4,3,,f,\nc,ring,1,2,3,,40\n"
        );
        assert_eq!(d.columns.last().map(String::as_str), Some("age"));
        // A column only named, never filled, is not added.
        let new = ds("n.csv", "xray,finger,j1,j2,j3,mc\nc,ring,1,2,3,\n");
        assert!(added_columns(&cur, &new).is_empty());
        // CRLF and a byte-order mark survive the rewrite; quoted fields stay quoted.
        let old = "\u{feff}xray,finger,j1,j2,j3,source\r\na,index,4,3,3,\"Fig. 1, left\"\r\n";
        let cur = ds("d.csv", old);
        let new = ds("n.csv", "xray,finger,j1,j2,j3,unit\nb,index,4,3,3,mm\n");
        let (out, _) = appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default()).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "\u{feff}xray,finger,j1,j2,j3,source,unit\r\na,index,4,3,3,\"Fig. 1, left\",\r\nb,index,4,3,3,,mm\r\n"
        );
    }

    #[test]
    fn rows_in_another_unit_are_appended_and_one_hand_keeps_one_unit() {
        let old = "xray,finger,j1,j2,j3,unit\na,index,4,3,3,image units\n";
        let cur = ds("d.csv", old);
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,unit\nb,index,4,3,3,mm\nc,index,4,3,3,\n",
        );
        let (out, d) = appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default()).unwrap();
        assert!(
            String::from_utf8(out)
                .unwrap()
                .ends_with("b,index,4,3,3,mm\nc,index,4,3,3,\n")
        );
        assert_eq!(
            d.units(),
            [(Some("image units"), 1), (Some("mm"), 1), (None, 1)]
        );
        // The same X-ray in another unit than its rows: refused.
        let new = ds("n.csv", "xray,finger,j1,j2,j3,unit\na,ring,4,3,3,mm\n");
        let e = appended_bytes_typed(old.as_bytes(), &cur, &new, &Typed::default()).unwrap_err();
        assert!(
            e.to_string().contains(
                "unit is 'mm' but d.csv line 2 gives 'image units' for the same X-ray 'a'"
            ),
            "{e}"
        );
        // A row without a unit takes the dataset's (one named unit), its X-ray's first.
        let filled = with_defaults(&ds("n.csv", "xray,finger,j1,j2,j3\nz,index,4,3,3\n"), &cur);
        assert_eq!(filled.rows[0].meta.unit.as_deref(), Some("image units"));
        // With two units named, it must say which.
        let two = ds(
            "d.csv",
            "xray,finger,j1,j2,j3,unit\na,index,4,3,3,px\nb,index,4,3,3,mm\n",
        );
        let e = check_fits(
            &two,
            &ds("n.csv", "xray,finger,j1,j2,j3\nz,index,4,3,3\n"),
            true,
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("names no unit, but the rows of d.csv are in 2 units ('px', 'mm')"),
            "{e}"
        );
        assert!(
            check_fits(
                &two,
                &ds("n.csv", "xray,finger,j1,j2,j3\na,ring,4,3,3\n"),
                true
            )
            .is_ok()
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
    }

    #[test]
    fn removing_rows_keeps_every_other_byte() {
        let old = "xray,finger,j1,j2,j3\r\na,index,4,3,3\r\n\r\nb,index,5,3,3\r\nc,index,6,3,3";
        let out = |lines: &[u64]| {
            String::from_utf8(removed_bytes(old.as_bytes(), "d.csv", lines).unwrap()).unwrap()
        };
        assert_eq!(out(&[]), old);
        assert_eq!(
            out(&[2]),
            "xray,finger,j1,j2,j3\r\nb,index,5,3,3\r\nc,index,6,3,3"
        );
        assert_eq!(
            out(&[4]),
            "xray,finger,j1,j2,j3\r\na,index,4,3,3\r\n\r\nc,index,6,3,3"
        );
        assert_eq!(
            out(&[5]),
            "xray,finger,j1,j2,j3\r\na,index,4,3,3\r\n\r\nb,index,5,3,3\r\n"
        );
        // A byte-order mark stays; a quoted field over two lines goes with its row.
        let bom =
            "\u{feff}xray,finger,j1,j2,j3,source\na,index,4,3,3,\"two\nlines\"\nb,index,5,3,3,x\n";
        let got = String::from_utf8(removed_bytes(bom.as_bytes(), "d.csv", &[2]).unwrap()).unwrap();
        assert_eq!(
            got,
            "\u{feff}xray,finger,j1,j2,j3,source\nb,index,5,3,3,x\n"
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
