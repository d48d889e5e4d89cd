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
    std::fs::read(path).map_err(|e| io_problem(&label, &e))
}

/// Opens an input file for streaming, turning failures (missing file, a
/// directory, no permission) into a [`DataError`] that names the file.
pub fn open_input(path: &Path) -> Result<std::fs::File, DataError> {
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

/// The problem of a record whose field count differs from the header's: most
/// often a quote left open (the field then runs on over commas and line ends),
/// else fields missing or extra.
pub fn field_count_problem(rec: &Record<'_>, width: usize) -> Problem {
    let runaway = (0..rec.len()).any(|i| rec.get(i).is_some_and(|f| f.contains([',', '\n', '\r'])));
    let hint = if runaway {
        "a quoted field is not closed, so it runs on over commas or line ends; close the quote (\") or remove it"
    } else if rec.len() > width {
        "remove the extra fields, or quote a value that contains a comma"
    } else {
        "add the missing fields (an empty value still needs its comma)"
    };
    Problem::line(
        rec.line,
        format!(
            "has {} fields but the header has {width}; {hint}",
            rec.len()
        ),
    )
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

/// The byte stream under a [`CsvScan`]: hashes every byte read (SHA-256, the
/// byte-order mark included), drops a UTF-8 byte-order mark, and remembers where
/// the line ends are that the CSV reader has not been asked about yet, so line
/// numbers are exact without holding the file in memory.
pub struct Source<R> {
    inner: std::io::BufReader<R>,
    hasher: sha2::Sha256,
    /// Offset (after the byte-order mark) of the next byte to read.
    offset: u64,
    /// Offsets of CR and LF bytes not yet passed by the line counter, with `true` for LF.
    eol: std::collections::VecDeque<(u64, bool)>,
    /// Whether any byte other than white space was seen.
    content: bool,
}

impl<R: std::io::Read> std::io::Read for Source<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        sha2::Digest::update(&mut self.hasher, &buf[..n]);
        for (i, &b) in buf[..n].iter().enumerate() {
            match b {
                b'\n' | b'\r' => self.eol.push_back((self.offset + i as u64, b == b'\n')),
                b if !b.is_ascii_whitespace() => self.content = true,
                _ => {}
            }
        }
        self.offset += n as u64;
        Ok(n)
    }
}

/// A configured CSV reader over one file, read as a stream.
pub struct CsvScan<R: std::io::Read> {
    reader: csv::Reader<Source<R>>,
    record: csv::ByteRecord,
    /// Byte offset and 1-based line number reached so far, for line counting:
    /// the `csv` crate's own line numbers drift over blank lines and CRLF.
    cursor: (u64, u64),
}

impl<R: std::io::Read> CsvScan<R> {
    /// Prepares `input` for reading; a UTF-16 file is an error here. Memory: the
    /// reader's buffers and the line ends read ahead, not the file.
    pub fn new(label: &str, input: R) -> Result<Self, DataError> {
        let mut inner = std::io::BufReader::with_capacity(64 * 1024, input);
        let mut hasher = <sha2::Sha256 as sha2::Digest>::new();
        let head = std::io::BufRead::fill_buf(&mut inner)
            .map_err(|e| DataError::whole_file(label, format!("could not be read ({e})")))?;
        if head.starts_with(b"\xFF\xFE") || head.starts_with(b"\xFE\xFF") {
            return Err(DataError::whole_file(
                label,
                "is UTF-16 text; save it as UTF-8 (e.g. 'CSV UTF-8' in a spreadsheet)",
            ));
        }
        if head.starts_with(b"\xEF\xBB\xBF") {
            sha2::Digest::update(&mut hasher, &head[..3]);
            std::io::BufRead::consume(&mut inner, 3);
        }
        let source = Source {
            inner,
            hasher,
            offset: 0,
            eol: std::collections::VecDeque::new(),
            content: false,
        };
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(source);
        Ok(CsvScan {
            reader,
            record: csv::ByteRecord::new(),
            cursor: (0, 1),
        })
    }

    /// Reads what is left and returns the file's SHA-256 (lower-case hex), and
    /// whether it held anything but white space.
    pub fn finish(self) -> std::io::Result<(String, bool)> {
        let mut source = self.reader.into_inner();
        std::io::copy(&mut source, &mut std::io::sink())?;
        let digest = sha2::Digest::finalize(source.hasher);
        let hex = digest.iter().map(|b| format!("{b:02x}")).collect();
        Ok((hex, source.content))
    }

    /// Line on which the record just read starts. The reader's position points
    /// at the line end or blank lines before the record; skip them, then count
    /// the line ends since the last record: LF, CRLF (counted at its LF), or a
    /// lone CR (old Mac files). Line ends passed are forgotten. O(1) amortised.
    fn line_of_record(&mut self) -> u64 {
        let eol = &mut self.reader.get_mut().eol;
        let mut start = self
            .record
            .position()
            .map_or(0, |p| p.byte())
            .max(self.cursor.0);
        let mut newlines = 0;
        // Line ends before the cursor were counted already (or belong to quoted fields).
        while eol.front().is_some_and(|&(o, _)| o < self.cursor.0) {
            eol.pop_front();
        }
        while let Some(&(o, lf)) = eol.front() {
            if o > start {
                break;
            }
            // o == start: the record starts on a line end (a blank line); skip it.
            if o == start {
                start += 1;
            }
            let crlf = !lf
                && eol
                    .get(1)
                    .is_some_and(|&(next, next_lf)| next == o + 1 && next_lf);
            if lf || !crlf {
                newlines += 1;
            }
            eol.pop_front();
        }
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
