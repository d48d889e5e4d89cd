//! A table's columns ([`Columns`]), its header line read against them ([`Header`]), and a
//! data record's cells read by column ([`Cells`]).

use super::scan::Record;
use crate::dataset::error::{Problem, quote};

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
    pub(super) fn parse(record: &Record<'_>, problems: &mut Vec<Problem>) -> Header<C> {
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
pub(super) fn required_names<C: Columns>() -> String {
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

impl<'a, 's, C: Columns> Cells<'a, 's, C> {
    /// The cells of `record` under `header`; `before` is the number of problems found
    /// before its cells are read.
    pub(super) fn new(
        record: &'a Record<'s>,
        header: &'a Header<C>,
        problems: &'a mut Vec<Problem>,
        before: usize,
    ) -> Self {
        Cells {
            record,
            header,
            problems,
            before,
        }
    }

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
