//! The bytes of a CSV file to records: a UTF-8 byte-order mark dropped, UTF-16 refused up
//! front, every byte hashed (SHA-256), exact line numbers over blank lines, CRLF and lone
//! CR, and each field checked for UTF-8 and NUL bytes; and the batches of records the
//! reading thread of [`super::read_table`] hands on. Memory: the reader's buffers, not the
//! file. Cost: O(bytes).

use crate::dataset::error::{DataError, Problem};

/// One data record: its line and its fields (`None` where the field was not
/// valid text; that problem is already reported).
pub(super) struct Record<'s> {
    pub line: u64,
    /// Byte offset of the record's first byte in the file (a byte-order mark counted).
    pub start: u64,
    fields: Vec<Option<&'s str>>,
}

impl<'s> Record<'s> {
    /// Number of fields on the line.
    pub(crate) fn len(&self) -> usize {
        self.fields.len()
    }

    /// Field `i` trimmed, `Some("")` when absent or empty, `None` when not valid text.
    pub(crate) fn get(&self, i: usize) -> Option<&'s str> {
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
struct Source<R> {
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
pub(super) struct CsvScan<R: std::io::Read> {
    reader: csv::Reader<Source<R>>,
    record: csv::ByteRecord,
    /// Byte offset and 1-based line number reached so far, for line counting:
    /// the `csv` crate's own line numbers drift over blank lines and CRLF.
    cursor: (u64, u64),
    /// Length of the byte-order mark dropped before the CSV reader (0 or 3).
    bom: u64,
}

impl<R: std::io::Read> CsvScan<R> {
    /// Prepares `input` for reading; a UTF-16 file is an error here. Memory: the
    /// reader's buffers and the line ends read ahead, not the file.
    pub(crate) fn new(label: &str, input: R) -> Result<Self, DataError> {
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
        let bom = head.starts_with(b"\xEF\xBB\xBF");
        if bom {
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
            bom: if bom { 3 } else { 0 },
        })
    }

    /// Reads what is left and returns the file's SHA-256 (lower-case hex), and
    /// whether it held anything but white space.
    pub(crate) fn finish(self) -> std::io::Result<(String, bool)> {
        let mut source = self.reader.into_inner();
        std::io::copy(&mut source, &mut std::io::sink())?;
        let digest = sha2::Digest::finalize(source.hasher);
        let hex = digest.iter().map(|b| format!("{b:02x}")).collect();
        Ok((hex, source.content))
    }

    /// [`CsvScan::finish`]'s SHA-256, or an empty string and a problem saying the
    /// file could not be read to the end.
    pub(super) fn finish_sha(self, problems: &mut Vec<Problem>) -> String {
        match self.finish() {
            Ok((sha, _)) => sha,
            Err(e) => {
                problems.push(Problem::file(format!("could not be read to the end ({e})")));
                String::new()
            }
        }
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
    pub(crate) fn next_record(&mut self, problems: &mut Vec<Problem>) -> Option<Record<'_>> {
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
        let start = self.cursor.0 + self.bom;
        Some(Record {
            line,
            start,
            fields,
        })
    }
}

/// Records read ahead by [`super::read_table`]'s reading thread, handed to the table's code
/// [`Batch::RECORDS`] at a time: their fields' text side by side in one string, and the
/// problems [`CsvScan::next_record`] found in each (its bytes: not UTF-8, a NUL).
#[derive(Default)]
pub(super) struct Batch {
    text: String,
    /// Per record: line, first byte, end of its fields in `fields`, end of its problems.
    pub(super) records: Vec<(u64, u64, usize, usize)>,
    /// Per field: its range in `text`, or `None` where it is not valid text.
    fields: Vec<Option<(usize, usize)>>,
    problems: Vec<Problem>,
}

impl Batch {
    /// Records per batch: large enough that handing one over costs nothing beside
    /// reading it, small enough to stay in cache.
    pub(super) const RECORDS: usize = 1024;

    pub(super) fn push(&mut self, record: &Record<'_>, problems: &mut Vec<Problem>) {
        for f in &record.fields {
            self.fields.push(f.map(|t| {
                let from = self.text.len();
                self.text.push_str(t);
                (from, self.text.len())
            }));
        }
        self.problems.append(problems);
        self.records.push((
            record.line,
            record.start,
            self.fields.len(),
            self.problems.len(),
        ));
    }

    /// Each record in file order, with the problems found in its bytes.
    pub(super) fn each(mut self, mut visit: impl FnMut(Record<'_>, &mut Vec<Problem>)) {
        let mut problems = std::mem::take(&mut self.problems).into_iter();
        let (mut field, mut problem) = (0, 0);
        for &(line, start, fields_end, problems_end) in &self.records {
            let fields = self.fields[field..fields_end]
                .iter()
                .map(|f| f.map(|(a, b)| &self.text[a..b]))
                .collect();
            field = fields_end;
            let mut own: Vec<Problem> = problems.by_ref().take(problems_end - problem).collect();
            problem = problems_end;
            visit(
                Record {
                    line,
                    start,
                    fields,
                },
                &mut own,
            );
        }
    }
}
