//! The one CSV table reader: measurements, claims and rig name maps all come through here.
//!
//! Accepts a UTF-8 byte-order mark, CRLF or LF line ends, quoted fields and blank
//! lines anywhere (a line of empty fields counts as blank). Refuses UTF-16 and
//! binary files up front, and reports non-UTF-8 or NUL bytes per field, so the
//! tables only ever see clean text.
//!
//! A table declares its columns ([`Columns`]: name, required or not) and reads
//! each record's cells by column through [`Cells`], with its own parser per
//! cell; [`read_table`] does the rest once for every table: the header (missing,
//! unknown, duplicate or empty column names), field counts, and collecting every
//! problem of the file as FILE:LINE:COLUMN: FIELD: what to fix.

mod columns;
mod problems;
mod scan;

pub(crate) use super::error::quote;
use super::error::{DataError, Problem};
pub(crate) use columns::{Cells, Columns, Header};
use problems::{field_count_problem, name_fields, no_header_problem, read_header};
use scan::{Batch, CsvScan, Record};
use std::path::Path;

/// Reads a whole input file, turning I/O failures (missing file, a directory,
/// no permission) into a [`DataError`] that names the file.
pub(crate) fn read_input(path: &Path) -> Result<Vec<u8>, DataError> {
    let label = path.display().to_string();
    if path.is_dir() {
        return Err(DataError::whole_file(
            &label,
            "is a directory, not a CSV file; give the path of the file itself",
        ));
    }
    std::fs::read(path).map_err(|e| io_problem(&label, &e))
}

/// Opens an input file for streaming, turning failures (missing file, a
/// directory, no permission) into a [`DataError`] that names the file.
pub(crate) fn open_input(path: &Path) -> Result<std::fs::File, DataError> {
    let label = path.display().to_string();
    if path.is_dir() {
        return Err(DataError::whole_file(
            &label,
            "is a directory, not a CSV file; give the path of the file itself",
        ));
    }
    std::fs::File::open(path).map_err(|e| io_problem(&label, &e))
}

fn io_problem(label: &str, e: &std::io::Error) -> DataError {
    let hint = match e.kind() {
        std::io::ErrorKind::NotFound => "no such file; check the path",
        std::io::ErrorKind::PermissionDenied => "permission denied; make the file readable",
        _ => "could not be read",
    };
    DataError::whole_file(label, format!("{hint} ({e})"))
}

/// One record of a headerless table ([`read_headerless`]): its line and its fields.
pub struct Fields<'a, 's> {
    record: &'a Record<'s>,
}

impl<'s> Fields<'_, 's> {
    /// The record's line (1-based; blank lines and line ends inside quotes counted).
    pub fn line(&self) -> u64 {
        self.record.line
    }

    /// Number of fields on the line.
    pub fn len(&self) -> usize {
        self.record.len()
    }

    /// Field `i` (0-based) trimmed: `Some("")` when absent or empty, `None` when not
    /// valid text (that problem is already reported, with its line and column).
    pub fn get(&self, i: usize) -> Option<&'s str> {
        self.record.get(i)
    }
}

/// Reads a CSV table without a header line (e.g. the Digital Hand Atlas's landmarks),
/// handing each non-blank record to `row` with the file's problem list. The byte-level
/// checks are those of [`read_table`]: a UTF-8 byte-order mark is dropped, a UTF-16 file is
/// refused up front (the error), and each field that is not UTF-8 or holds a NUL byte is
/// reported at its line and column (and handed on as `None`). The caller checks field
/// counts and values. Returns the file's SHA-256 (lower-case hex) and the number of
/// records read. Memory: one record at a time. Cost: O(bytes).
pub fn read_headerless(
    label: &str,
    input: impl std::io::Read,
    problems: &mut Vec<Problem>,
    mut row: impl FnMut(&Fields<'_, '_>, &mut Vec<Problem>),
) -> Result<(String, usize), DataError> {
    let mut scan = CsvScan::new(label, input)?;
    let mut records = 0usize;
    while let Some(record) = scan.next_record(problems) {
        records += 1;
        row(&Fields { record: &record }, problems);
    }
    let sha256 = scan.finish_sha(problems);
    Ok((sha256, records))
}

/// Reads a table of columns `C` from `input` (`label` names it in errors),
/// handing each data record to `row`, which reads its cells and reports what
/// is wrong with them. Returns the header and the file's SHA-256, or every
/// problem of the file sorted by line and column.
///
/// Records are not handed on when the header has a problem (their meaning is
/// unknown) or when their field count differs from the header's; they are
/// still read, so byte-level problems of the whole file are reported.
///
/// The bytes are read, hashed and split into records on a second thread while `row`
/// reads the records before them (a pipeline of [`Batch`]es: half the time of a large
/// file on two cores); the problems come in the order one thread would find them.
/// Memory: a few batches of records. Cost: O(bytes).
pub(crate) fn read_table<C: Columns>(
    label: &str,
    input: impl std::io::Read + Send,
    mut row: impl FnMut(&mut Cells<'_, '_, C>),
) -> Result<(Header<C>, String), DataError> {
    let mut scan = CsvScan::new(label, input)?;
    let mut problems = Vec::new();
    let mut header: Option<Header<C>> = None;
    let mut header_ok = false;
    let mut records = 0usize;
    let mut handle = |record: Record<'_>, own: &mut Vec<Problem>, problems: &mut Vec<Problem>| {
        // A field that is not text is the row's own problem: the row is not read further
        // (its other cells are, so their problems are reported too).
        let before = problems.len();
        problems.append(own);
        let Some(header) = &header else {
            let h = read_header::<C>(&record, problems);
            header_ok = problems.is_empty();
            header = Some(h);
            return;
        };
        records += 1;
        if !header_ok {
            return; // column meanings are unknown; the header problems say why
        }
        if record.len() != header.names.len() {
            problems.push(field_count_problem(&record, header));
            return;
        }
        row(&mut Cells::new(&record, header, problems, before));
    };
    let (mut trailing, end) = std::thread::scope(|s| {
        let (send, receive) = std::sync::mpsc::sync_channel::<Batch>(4);
        let reader = s.spawn(move || {
            let mut own = Vec::new();
            let mut batch = Batch::default();
            while let Some(record) = scan.next_record(&mut own) {
                batch.push(&record, &mut own);
                if batch.records.len() == Batch::RECORDS
                    && send.send(std::mem::take(&mut batch)).is_err()
                {
                    break;
                }
            }
            if !batch.records.is_empty() {
                // A closed channel means the receiving side is gone (it panicked).
                let _ = send.send(batch);
            }
            // `own` now holds what ended the reading (unreadable CSV), if anything.
            (own, scan.finish())
        });
        for batch in receive {
            batch.each(|record, own| handle(record, own, &mut problems));
        }
        match reader.join() {
            Ok(done) => done,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    });
    problems.append(&mut trailing);
    let Some(header) = header else {
        let content = end.as_ref().map(|(_, c)| *c).unwrap_or(true);
        if problems.is_empty() {
            problems.push(no_header_problem::<C>(content));
        }
        return Err(DataError {
            file: label.to_string(),
            problems,
        });
    };
    if records == 0
        && problems.is_empty()
        && let Some(message) = C::NO_ROWS
    {
        problems.push(Problem::file(message));
    }
    name_fields(&mut problems, &header);
    let sha256 = match end {
        Ok((sha, _)) => sha,
        Err(e) => {
            problems.push(Problem::file(format!("could not be read to the end ({e})")));
            String::new()
        }
    };
    if problems.is_empty() {
        Ok((header, sha256))
    } else {
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        Err(DataError {
            file: label.to_string(),
            problems,
        })
    }
}
