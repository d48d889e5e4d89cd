//! The one place that configures CSV reading for every input file.
//!
//! Accepts a UTF-8 byte-order mark, CRLF or LF line ends, quoted fields and blank
//! lines anywhere (a line of empty fields counts as blank). Refuses UTF-16 and
//! binary files up front, and reports non-UTF-8 or NUL bytes per field, so the
//! callers only ever see clean text.

use super::error::{DataError, Problem};
use std::path::Path;

/// Most characters of an offending value quoted back in an error message.
const QUOTE_MAX: usize = 40;

/// Reads a whole input file, turning I/O failures (missing file, a directory,
/// no permission) into a [`DataError`] that names the file.
pub fn read_input(path: &Path) -> Result<Vec<u8>, DataError> {
    let label = path.display().to_string();
    if path.is_dir() {
        return Err(DataError::whole_file(
            &label,
            "is a directory, not a CSV file; give the path of the file itself",
        ));
    }
    std::fs::read(path).map_err(|e| {
        let hint = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file; check the path (see --data)",
            std::io::ErrorKind::PermissionDenied => "permission denied; make the file readable",
            _ => "could not be read",
        };
        DataError::whole_file(&label, format!("{hint} ({e})"))
    })
}

/// Quotes a value for an error message, shortened when long.
pub fn quote(value: &str) -> String {
    if value.chars().count() <= QUOTE_MAX {
        format!("'{value}'")
    } else {
        let head: String = value.chars().take(QUOTE_MAX).collect();
        format!("'{head}...' ({} characters)", value.chars().count())
    }
}

/// One data record: its line and its fields (`None` where the field was not
/// valid text; that problem is already reported).
pub struct Record<'s> {
    pub line: u64,
    fields: Vec<Option<&'s str>>,
}

impl<'s> Record<'s> {
    /// Number of fields on the line.
    pub fn len(&self) -> usize {
        self.fields.len()
    }

    /// True when the record has no fields (never returned by [`CsvScan`]).
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// Field `i` trimmed, `Some("")` when absent or empty, `None` when not valid text.
    pub fn get(&self, i: usize) -> Option<&'s str> {
        match self.fields.get(i) {
            Some(f) => f.map(str::trim),
            None => Some(""),
        }
    }
}

/// A configured CSV reader over the bytes of one file.
pub struct CsvScan<'a> {
    reader: csv::Reader<&'a [u8]>,
    record: csv::ByteRecord,
    bytes: &'a [u8],
    /// Byte offset and 1-based line number reached so far, for line counting:
    /// the `csv` crate's own line numbers drift over blank lines and CRLF.
    cursor: (usize, u64),
}

impl<'a> CsvScan<'a> {
    /// Prepares `bytes` for reading; whole-file problems (empty, UTF-16) are errors here.
    pub fn new(label: &str, bytes: &'a [u8]) -> Result<Self, DataError> {
        let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        if bytes.starts_with(b"\xFF\xFE") || bytes.starts_with(b"\xFE\xFF") {
            return Err(DataError::whole_file(
                label,
                "is UTF-16 text; save it as UTF-8 (e.g. 'CSV UTF-8' in a spreadsheet)",
            ));
        }
        if bytes.iter().all(|b| b.is_ascii_whitespace()) {
            return Err(DataError::whole_file(
                label,
                "is empty; it needs a header line and at least one data row",
            ));
        }
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(bytes);
        Ok(CsvScan {
            reader,
            record: csv::ByteRecord::new(),
            bytes,
            cursor: (0, 1),
        })
    }

    /// Line on which the record just read starts. The reader's position points
    /// at the line end or blank lines before the record; skip them, then count
    /// the newlines since the last record. O(bytes) over the whole file.
    fn line_of_record(&mut self) -> u64 {
        let from = self.record.position().map_or(0, |p| p.byte() as usize);
        let mut start = from.max(self.cursor.0).min(self.bytes.len());
        while start < self.bytes.len() && matches!(self.bytes[start], b'\r' | b'\n') {
            start += 1;
        }
        // A line ends at LF, at CRLF (counted at its LF), or at a lone CR (old Mac files).
        let newlines = (self.cursor.0..start)
            .filter(|&i| match self.bytes[i] {
                b'\n' => true,
                b'\r' => self.bytes.get(i + 1) != Some(&b'\n'),
                _ => false,
            })
            .count() as u64;
        self.cursor = (start, self.cursor.1 + newlines);
        self.cursor.1
    }

    /// The next non-blank record, or `None` at the end. Problems with the
    /// record's bytes are pushed to `problems`.
    pub fn next_record(&mut self, problems: &mut Vec<Problem>) -> Option<Record<'_>> {
        loop {
            match self.reader.read_byte_record(&mut self.record) {
                Ok(false) => return None,
                Ok(true) => {}
                Err(e) => {
                    let line = e.position().map(|p| p.line()).unwrap_or(0);
                    problems.push(Problem::line(
                        line,
                        format!("unreadable CSV ({e}); check quotes and separators"),
                    ));
                    return None;
                }
            }
            let blank = self
                .record
                .iter()
                .all(|f| f.iter().all(|b| b.is_ascii_whitespace()));
            if !blank {
                break;
            }
        }
        let line = self.line_of_record();
        let mut fields = Vec::with_capacity(self.record.len());
        for (i, raw) in self.record.iter().enumerate() {
            let column = i + 1;
            match std::str::from_utf8(raw) {
                Err(e) => {
                    problems.push(Problem {
                        line: Some(line),
                        column: Some(column),
                        field: None,
                        message: format!(
                            "is not UTF-8 text (bad byte 0x{:02X} at byte {} of the field); save the file as UTF-8",
                            raw[e.valid_up_to()],
                            e.valid_up_to() + 1
                        ),
                    });
                    fields.push(None);
                }
                Ok(text) if text.contains('\0') => {
                    problems.push(Problem {
                        line: Some(line),
                        column: Some(column),
                        field: None,
                        message: "contains a NUL byte; is this a binary or UTF-16 file? save it as UTF-8 text".into(),
                    });
                    fields.push(None);
                }
                Ok(text) => fields.push(Some(text)),
            }
        }
        Some(Record { line, fields })
    }
}

/// Maps a header line to column positions for a set of known column names.
pub struct Header {
    /// Position of each wanted column (`None` when the header lacks it).
    pub positions: Vec<Option<usize>>,
    /// Names as written in the header (lower-cased, trimmed), by position.
    pub names: Vec<String>,
}

impl Header {
    /// Reads the header record. `required` columns must be present; `optional`
    /// ones may be; any other column, a duplicate or an empty name is a problem.
    /// Positions are returned for `required` then `optional`, in that order.
    pub fn parse(
        record: &Record<'_>,
        required: &[&str],
        optional: &[&str],
        problems: &mut Vec<Problem>,
    ) -> Header {
        let known: Vec<&str> = required.iter().chain(optional).copied().collect();
        let mut positions = vec![None; known.len()];
        let mut names = Vec::with_capacity(record.len());
        for i in 0..record.len() {
            let name = record.get(i).unwrap_or("").to_ascii_lowercase();
            let column = i + 1;
            match known.iter().position(|k| *k == name) {
                Some(k) if positions[k].is_some() => problems.push(Problem::field(
                    record.line,
                    column,
                    &name,
                    "column appears twice in the header; remove one of them",
                )),
                Some(k) => positions[k] = Some(i),
                None if name.is_empty() => problems.push(Problem {
                    line: Some(record.line),
                    column: Some(column),
                    field: None,
                    message: format!(
                        "header has an empty column name; name it (known columns: {})",
                        known.join(",")
                    ),
                }),
                None => problems.push(Problem {
                    line: Some(record.line),
                    column: Some(column),
                    field: None,
                    message: format!(
                        "unknown column {}; the known columns are {}",
                        quote(&name),
                        known.join(",")
                    ),
                }),
            }
            names.push(name);
        }
        for (k, name) in required.iter().enumerate() {
            if positions[k].is_none() {
                problems.push(Problem::line(
                    record.line,
                    format!(
                        "header lacks the required column '{name}'; the header must name {}",
                        required.join(",")
                    ),
                ));
            }
        }
        Header { positions, names }
    }
}
