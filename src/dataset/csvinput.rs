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

use super::error::{DataError, Problem};
use std::path::Path;

/// Most characters of an offending value quoted back in an error message.
const QUOTE_MAX: usize = 40;

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

/// The problem of a record whose field count differs from the header's: most
/// often a quote left open (the field then runs on over commas and line ends),
/// a number written with an unquoted decimal comma (`346,65`, read as two fields:
/// [`decimal_commas`]), else fields missing or extra.
fn field_count_problem<C: Columns>(rec: &Record<'_>, header: &Header<C>) -> Problem {
    let width = header.names.len();
    let runaway = (0..rec.len()).any(|i| rec.get(i).is_some_and(|f| f.contains([',', '\n', '\r'])));
    let field = |i: usize| rec.get(i).unwrap_or("");
    let commas = decimal_commas(rec, header);
    let hint = if runaway {
        "a quoted field is not closed, so it runs on over commas or line ends; close the quote (\") or remove it".to_string()
    } else if !commas.is_empty() {
        let each: Vec<String> = commas
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                format!(
                    "{} {} looks like a number with a decimal comma",
                    header.names[i - k],
                    quote(&format!("{},{}", field(i), field(i + 1)))
                )
            })
            .collect();
        let fixed: Vec<String> = commas
            .iter()
            .map(|&i| format!("{}.{}", field(i), field(i + 1)))
            .collect();
        format!(
            "{}: unquoted, the comma splits it in two fields; write it with a point ({})",
            each.join(", "),
            fixed.join(", ")
        )
    } else if rec.len() > width {
        "remove the extra fields, or quote a value that contains a comma".to_string()
    } else {
        "add the missing fields (an empty value still needs its comma)".to_string()
    };
    Problem::line(
        rec.line,
        format!(
            "has {} fields but the header has {width}; {hint}",
            rec.len()
        ),
    )
}

/// Where a record with k more fields than the header holds k numbers written with an
/// unquoted decimal comma: the positions i of the fields (i, i + 1) that join into one
/// (a whole number, then digits only: `346` and `65` from `346,65`). Such a reading
/// counts only when it is the one way to join k pairs (none overlapping) so that every
/// joined number lands in a numeric column ([`Columns::numeric`]) and every numeric
/// column then holds a number or nothing; otherwise (several ways, or none) the record
/// is not said to hold a decimal comma. Empty for none. Cost: O(C(p, k)) for p
/// candidate pairs, at most 3 joins tried.
fn decimal_commas<C: Columns>(rec: &Record<'_>, header: &Header<C>) -> Vec<usize> {
    let width = header.names.len();
    let extra = rec.len().saturating_sub(width);
    if extra == 0 || extra > 3 {
        return Vec::new();
    }
    let field = |i: usize| rec.get(i).unwrap_or("");
    let digits = |f: &str| !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit());
    let whole = |f: &str| digits(f.strip_prefix('-').unwrap_or(f));
    let candidates: Vec<usize> = (0..rec.len().saturating_sub(1))
        .filter(|&i| whole(field(i)) && digits(field(i + 1)))
        .collect();
    let numeric: Vec<bool> = header
        .names
        .iter()
        .map(|n| C::ALL.iter().any(|c| c.name() == n && c.numeric()))
        .collect();
    // The record's fields with the pairs at `joins` (ascending) joined.
    let reads = |joins: &[usize]| -> bool {
        let mut out: Vec<String> = Vec::with_capacity(width);
        let mut i = 0;
        while i < rec.len() {
            if joins.contains(&i) {
                if !numeric.get(out.len()).copied().unwrap_or(false) {
                    return false;
                }
                out.push(format!("{}.{}", field(i), field(i + 1)));
                i += 2;
            } else {
                out.push(field(i).to_string());
                i += 1;
            }
        }
        out.len() == width
            && out
                .iter()
                .zip(&numeric)
                .all(|(v, &num)| !num || v.is_empty() || v.parse::<f64>().is_ok())
    };
    let mut found: Vec<Vec<usize>> = Vec::new();
    let mut pick: Vec<usize> = Vec::new();
    fn choose(
        candidates: &[usize],
        k: usize,
        pick: &mut Vec<usize>,
        found: &mut Vec<Vec<usize>>,
        reads: &dyn Fn(&[usize]) -> bool,
    ) {
        if found.len() > 1 {
            return;
        }
        if pick.len() == k {
            if reads(pick) {
                found.push(pick.clone());
            }
            return;
        }
        for (n, &c) in candidates.iter().enumerate() {
            if pick.last().is_some_and(|&p| c < p + 2) {
                continue;
            }
            pick.push(c);
            choose(&candidates[n + 1..], k, pick, found, reads);
            pick.pop();
        }
    }
    choose(&candidates, extra, &mut pick, &mut found, &reads);
    match found.as_slice() {
        [one] => one.clone(),
        _ => Vec::new(),
    }
}

/// Quotes a value for an error message, shortened when long.
pub(crate) fn quote(value: &str) -> String {
    if value.chars().count() <= QUOTE_MAX {
        format!("'{value}'")
    } else {
        let head: String = value.chars().take(QUOTE_MAX).collect();
        format!("'{head}...' ({} characters)", value.chars().count())
    }
}

/// One data record: its line and its fields (`None` where the field was not
/// valid text; that problem is already reported).
struct Record<'s> {
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
struct CsvScan<R: std::io::Read> {
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
    fn finish_sha(self, problems: &mut Vec<Problem>) -> String {
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

/// The columns of one kind of table: a fieldless enum, one variant per column,
/// which the table's code reads cells by.
pub(crate) trait Columns: Copy + 'static {
    /// Every column in the canonical order (required ones first); `ALL[c.index()] == c`.
    const ALL: &'static [Self];
    /// What is said about a file with nothing but white space in it.
    const EMPTY: &'static str;
    /// What is said about a file with content but no header record (e.g. only
    /// commas); `None` for "has no header line; start it with" the required columns.
    const NO_HEADER: Option<&'static str> = None;
    /// What is said about a file with a header and no record; `None` when that is fine.
    const NO_ROWS: Option<&'static str>;

    /// The column's name in a header (lower case; headers are read case-insensitively).
    fn name(self) -> &'static str;
    /// True when every file must have the column (its cells may still be empty).
    fn required(self) -> bool;
    /// True when the column holds numbers (so a number split at an unquoted decimal
    /// comma can be recognised in it).
    fn numeric(self) -> bool {
        false
    }
    /// The column's position in [`Columns::ALL`].
    fn index(self) -> usize;
}

/// A header line read against a table's columns.
pub(crate) struct Header<C> {
    /// Line of the header in the file.
    pub line: u64,
    /// Names as written in the header (lower-cased, trimmed), in file order.
    pub names: Vec<String>,
    /// Field position of each of `C::ALL` (`None` when the header lacks it).
    positions: Vec<Option<usize>>,
    columns: std::marker::PhantomData<C>,
}

impl<C: Columns> Header<C> {
    /// Reads the header record. Required columns must be present, optional ones
    /// may be; any other column, a duplicate or an empty name is a problem.
    fn parse(record: &Record<'_>, problems: &mut Vec<Problem>) -> Header<C> {
        debug_assert!(C::ALL.iter().enumerate().all(|(i, c)| c.index() == i));
        let known = || {
            C::ALL
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(",")
        };
        let mut positions = vec![None; C::ALL.len()];
        let mut names = Vec::with_capacity(record.len());
        for i in 0..record.len() {
            let name = record.get(i).unwrap_or("").to_ascii_lowercase();
            let column = i + 1;
            match C::ALL.iter().position(|c| c.name() == name) {
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
                        known()
                    ),
                }),
                None => problems.push(Problem {
                    line: Some(record.line),
                    column: Some(column),
                    field: None,
                    message: format!(
                        "unknown column {}; the known columns are {}",
                        quote(&name),
                        known()
                    ),
                }),
            }
            names.push(name);
        }
        for (c, position) in C::ALL.iter().zip(&positions) {
            if c.required() && position.is_none() {
                problems.push(Problem::line(
                    record.line,
                    format!(
                        "header lacks the required column '{}'; the header must name {}",
                        c.name(),
                        required_names::<C>()
                    ),
                ));
            }
        }
        Header {
            line: record.line,
            names,
            positions,
            columns: std::marker::PhantomData,
        }
    }

    /// The 1-based column of `c` in the file, 0 when the file lacks it.
    pub(crate) fn column(&self, c: C) -> usize {
        self.positions[c.index()].map_or(0, |p| p + 1)
    }
}

/// The required columns of `C`, comma-separated, as a header starts.
fn required_names<C: Columns>() -> String {
    let names: Vec<&str> = C::ALL
        .iter()
        .filter(|c| c.required())
        .map(|c| c.name())
        .collect();
    names.join(",")
}

/// The cells of one data record, read by column, with the file's problem list.
pub(crate) struct Cells<'a, 's, C> {
    record: &'a Record<'s>,
    header: &'a Header<C>,
    problems: &'a mut Vec<Problem>,
    /// Problems found before this record's cells were read (its byte-level ones included).
    before: usize,
}

impl<'s, C: Columns> Cells<'_, 's, C> {
    /// The record's line.
    pub(crate) fn line(&self) -> u64 {
        self.record.line
    }

    /// Byte offset of the record's first byte in the file (a byte-order mark counted).
    pub(crate) fn start(&self) -> u64 {
        self.record.start
    }

    /// The 1-based column of `c` in the file, 0 when the file lacks it.
    pub fn column(&self, c: C) -> usize {
        self.header.column(c)
    }

    /// The cell of column `c`, trimmed: `Some("")` when empty or when the file
    /// lacks the column, `None` when not valid text (already reported).
    pub(crate) fn text(&self, c: C) -> Option<&'s str> {
        match self.header.positions[c.index()] {
            Some(p) => self.record.get(p),
            None => Some(""),
        }
    }

    /// The cell of column `c` read by `parse`; its error is reported at the cell.
    /// `None` when the cell is not valid text or `parse` refuses it.
    pub(crate) fn parse<T>(
        &mut self,
        c: C,
        parse: impl FnOnce(&'s str) -> Result<T, String>,
    ) -> Option<T> {
        match parse(self.text(c)?) {
            Ok(v) => Some(v),
            Err(message) => {
                self.bad(c, message);
                None
            }
        }
    }

    /// Reports a problem with the cell of column `c`.
    pub(crate) fn bad(&mut self, c: C, message: impl Into<String>) {
        let column = self.header.column(c);
        self.problems
            .push(Problem::field(self.record.line, column, c.name(), message));
    }

    /// Reports a problem with the record as a whole.
    pub(crate) fn bad_line(&mut self, message: impl Into<String>) {
        self.problems.push(Problem::line(self.record.line, message));
    }

    /// True when a problem was reported through these cells.
    pub(crate) fn has_problems(&self) -> bool {
        self.problems.len() > self.before
    }
}

/// What a first line that is not a header of `C` looks like, and what to do,
/// as one problem: a file of another separator (one field holding semicolons
/// or tabs: Excel's "CSV" in locales with a decimal comma, a TSV export), or
/// a file without a header line (no field names a column of `C`, and one
/// looks like data: a number, a finger, a side or a joint). `None` when the
/// line is a header with mistakes in it, which are reported column by column.
fn sniff<C: Columns>(record: &Record<'_>) -> Option<Problem> {
    let fields: Vec<&str> = (0..record.len())
        .map(|i| record.get(i).unwrap_or(""))
        .collect();
    let line = fields.join(",");
    let save = "save it as 'CSV UTF-8 (Comma delimited)'";
    if let [only] = fields.as_slice() {
        let semicolons = only.matches(';').count();
        let tabs = only.matches('\t').count();
        let message = if semicolons > 0 && semicolons >= tabs {
            format!(
                "the file looks semicolon-separated ({}), as Excel saves CSV in many locales; phalanx reads \
                 comma-separated files: {save}, or replace each ';' with ',' and any decimal comma with a point \
                 (339,96 -> 339.96)",
                quote(only)
            )
        } else if tabs > 0 {
            format!(
                "the file looks tab-separated ({}), as a TSV export or cells pasted from a spreadsheet; phalanx \
                 reads comma-separated files: {save}, or replace each tab with ','",
                quote(&only.replace('\t', "\\t"))
            )
        } else {
            return None;
        };
        return Some(Problem::line(record.line, message));
    }
    let names_a_column = fields
        .iter()
        .any(|f| C::ALL.iter().any(|c| c.name().eq_ignore_ascii_case(f)));
    let data_like = |f: &&str| {
        f.parse::<f64>().is_ok()
            || super::Finger::parse(f).is_some()
            || ["left", "right", "mcp", "pip", "dip", "ip", "tip"]
                .iter()
                .any(|v| v.eq_ignore_ascii_case(f))
    };
    if names_a_column || !fields.iter().any(data_like) {
        return None;
    }
    let optional: Vec<&str> = C::ALL
        .iter()
        .filter(|c| !c.required())
        .map(|c| c.name())
        .collect();
    let optional = if optional.is_empty() {
        String::new()
    } else {
        format!(" (and any of the optional columns {})", optional.join(","))
    };
    Some(Problem::line(
        record.line,
        format!(
            "the file has no header line: its first line, {}, is data; add the header line {}{optional} above it",
            quote(&line),
            required_names::<C>()
        ),
    ))
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

/// Records read ahead by [`read_table`]'s reading thread, handed to the table's code
/// [`Batch::RECORDS`] at a time: their fields' text side by side in one string, and the
/// problems [`CsvScan::next_record`] found in each (its bytes: not UTF-8, a NUL).
#[derive(Default)]
struct Batch {
    text: String,
    /// Per record: line, first byte, end of its fields in `fields`, end of its problems.
    records: Vec<(u64, u64, usize, usize)>,
    /// Per field: its range in `text`, or `None` where it is not valid text.
    fields: Vec<Option<(usize, usize)>>,
    problems: Vec<Problem>,
}

impl Batch {
    /// Records per batch: large enough that handing one over costs nothing beside
    /// reading it, small enough to stay in cache.
    const RECORDS: usize = 1024;

    fn push(&mut self, record: &Record<'_>, problems: &mut Vec<Problem>) {
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
    fn each(mut self, mut visit: impl FnMut(Record<'_>, &mut Vec<Problem>)) {
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
        row(&mut Cells {
            record: &record,
            header,
            problems,
            before,
        });
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

/// The problem of a file without a header record: empty (`content` false, only white
/// space), or the table's own message, or which columns to start it with.
fn no_header_problem<C: Columns>(content: bool) -> Problem {
    Problem::file(match (content, C::NO_HEADER) {
        (false, _) => C::EMPTY.to_string(),
        (true, Some(message)) => message.to_string(),
        (true, None) => format!(
            "has no header line; start it with {}",
            required_names::<C>()
        ),
    })
}

/// The header of `record`; when it has problems and the record shows what kind of file
/// this is ([`sniff`]), one message saying so replaces one per header column.
fn read_header<C: Columns>(record: &Record<'_>, problems: &mut Vec<Problem>) -> Header<C> {
    let before_header = problems.len();
    let header = Header::<C>::parse(record, problems);
    if problems.len() > before_header
        && let Some(shape) = sniff::<C>(record)
    {
        problems.truncate(before_header);
        problems.push(shape);
    }
    header
}

/// Byte-level problems (non-UTF-8, NUL) after the header know their column; names its field.
fn name_fields<C: Columns>(problems: &mut [Problem], header: &Header<C>) {
    for p in problems {
        if let (None, Some(c), Some(l)) = (&p.field, p.column, p.line)
            && l > header.line
        {
            p.field = header.names.get(c - 1).filter(|n| !n.is_empty()).cloned();
        }
    }
}
