//! Errors in input files: every problem of a file, each with its place and a fix.

use std::fmt;

/// One problem found in an input file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// 1-based line number, when the problem sits on a line.
    pub line: Option<u64>,
    /// 1-based column (field) number, when the problem sits in a field.
    pub column: Option<usize>,
    /// The column's header name, when known.
    pub field: Option<String>,
    /// What is wrong and what to do about it.
    pub message: String,
}

impl Problem {
    /// A problem of the whole file (no line).
    pub(crate) fn file(message: impl Into<String>) -> Self {
        Problem {
            line: None,
            column: None,
            field: None,
            message: message.into(),
        }
    }

    /// A problem of one line, not tied to a field.
    pub(crate) fn line(line: u64, message: impl Into<String>) -> Self {
        Problem {
            line: Some(line),
            column: None,
            field: None,
            message: message.into(),
        }
    }

    /// A problem of one field.
    pub(crate) fn field(line: u64, column: usize, field: &str, message: impl Into<String>) -> Self {
        Problem {
            line: Some(line),
            column: Some(column),
            field: Some(field.to_string()),
            message: message.into(),
        }
    }
}

/// All problems found in one input file. Displayed one per line as
/// `FILE:LINE:COLUMN: FIELD: message`, like a compiler.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DataError {
    /// The file as the user named it.
    pub file: String,
    /// Every problem found, in file order.
    pub problems: Vec<Problem>,
}

impl DataError {
    /// A single whole-file problem.
    pub(crate) fn whole_file(file: &str, message: impl Into<String>) -> Self {
        DataError {
            file: file.to_string(),
            problems: vec![Problem::file(message)],
        }
    }
}

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.problems.len();
        write!(
            f,
            "{} problem{} in {}:",
            n,
            if n == 1 { "" } else { "s" },
            self.file
        )?;
        for p in &self.problems {
            write!(f, "\n  {}", self.file)?;
            if let Some(line) = p.line {
                write!(f, ":{line}")?;
                if let Some(col) = p.column {
                    write!(f, ":{col}")?;
                }
            }
            f.write_str(": ")?;
            if let Some(field) = &p.field {
                write!(f, "{field}: ")?;
            }
            f.write_str(&p.message)?;
        }
        Ok(())
    }
}

impl std::error::Error for DataError {}

/// Most characters of an offending value quoted back in an error message.
const QUOTE_MAX: usize = 40;

/// Quotes a value for an error message, shortened when long.
pub(crate) fn quote(value: &str) -> String {
    if value.chars().count() <= QUOTE_MAX {
        format!("'{value}'")
    } else {
        let head: String = value.chars().take(QUOTE_MAX).collect();
        format!("'{head}...' ({} characters)", value.chars().count())
    }
}
