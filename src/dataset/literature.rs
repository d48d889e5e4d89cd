//! Published summary tables: a cohort known only by the mean (and SD) of each segment.
//!
//! Some sources print no per-hand values, only a table of means: Buryanov and Kotiuk
//! (2010), Table I, gives the mean +/- SD in mm of each phalanx, each metacarpal and the
//! fingertip's soft tissue of 66 adult hands. Such a table is a file of rows
//! `finger,segment,mean,sd,n,unit` ([`SummaryTable::load`]); `sd` and `n` may be empty
//! when a source prints no spread, and then no interval can be given.
//!
//! Segments: `proximal`, `middle`, `distal` (the phalanges; the thumb has no middle
//! phalanx), `tip_soft_tissue` (the fingertip's soft tissue beyond the distal phalanx) and
//! `metacarpal`. Every row names the same unit. Every problem of the file is reported
//! together with its line and column.
//!
//! [`Source::load`] tells such a table from a measurement file by its header, so every
//! command that takes a cohort can take either.

use super::csvinput::{self, Cells, Columns, quote};
use super::{DataError, Dataset, Finger, looks_like_formula};
use schemars::JsonSchema;
use serde::Serialize;
use std::collections::HashMap;
use std::path::Path;

/// A segment of a finger as a summary table names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Segment {
    /// The proximal phalanx (J1).
    Proximal,
    /// The middle phalanx (J2; not for the thumb).
    Middle,
    /// The distal phalanx, to the end of the bone (J3, the thumb's J2).
    Distal,
    /// The fingertip's soft tissue beyond the distal phalanx.
    TipSoftTissue,
    /// The metacarpal (CMC to MCP).
    Metacarpal,
}

impl Segment {
    /// Every segment, in the table's usual order.
    pub const ALL: [Segment; 5] = [
        Segment::Proximal,
        Segment::Middle,
        Segment::Distal,
        Segment::TipSoftTissue,
        Segment::Metacarpal,
    ];

    /// The name in a table: `proximal`, ..., `tip_soft_tissue`, `metacarpal`.
    pub fn name(self) -> &'static str {
        match self {
            Segment::Proximal => "proximal",
            Segment::Middle => "middle",
            Segment::Distal => "distal",
            Segment::TipSoftTissue => "tip_soft_tissue",
            Segment::Metacarpal => "metacarpal",
        }
    }

    /// Parses a segment's name, case-insensitively.
    pub fn parse(text: &str) -> Option<Segment> {
        let t = text.trim().to_ascii_lowercase();
        Segment::ALL.into_iter().find(|s| s.name() == t)
    }

    /// The phalanges of a finger, root to tip: J1, J2[, J3] as bones.
    pub fn phalanges(finger: Finger) -> &'static [Segment] {
        match finger {
            Finger::Thumb => &[Segment::Proximal, Segment::Distal],
            _ => &[Segment::Proximal, Segment::Middle, Segment::Distal],
        }
    }
}

/// The mean (and spread) of one segment of one finger.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TableRow {
    /// Line in the file (1-based).
    pub line: u64,
    pub finger: Finger,
    pub segment: Segment,
    /// Mean length, in the table's unit.
    pub mean: f64,
    /// Sample SD of the lengths; `None` when the source gives none.
    pub sd: Option<f64>,
    /// Hands measured; `None` when the source gives no number.
    pub n: Option<u64>,
}

/// A validated summary table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SummaryTable {
    /// The path as given by the user.
    pub path: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
    /// The one unit of every row (e.g. `mm`).
    pub unit: String,
    /// Rows in file order.
    pub rows: Vec<TableRow>,
}

impl SummaryTable {
    /// Reads and validates a summary table. Cost: O(bytes).
    pub fn load(path: &Path) -> Result<SummaryTable, DataError> {
        let file = csvinput::open_input(path)?;
        SummaryTable::from_reader(&path.display().to_string(), file)
    }

    /// Validates a summary table's bytes; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<SummaryTable, DataError> {
        SummaryTable::from_reader(label, bytes)
    }

    fn from_reader(
        label: &str,
        input: impl std::io::Read + Send,
    ) -> Result<SummaryTable, DataError> {
        let mut rows: Vec<TableRow> = Vec::new();
        let mut seen: HashMap<(Finger, Segment), u64> = HashMap::new();
        let mut unit: Option<(String, u64)> = None;
        let (_, sha256) = csvinput::read_table(label, input, |cells| {
            let Some((row, row_unit)) = parse_row(cells) else {
                return;
            };
            if let Some(first) = seen.get(&(row.finger, row.segment)) {
                cells.bad(
                    TableColumn::Segment,
                    format!(
                        "duplicate row: the {} {} is already given on line {first}; remove one of them",
                        row.finger.name(),
                        row.segment.name()
                    ),
                );
                return;
            }
            match &unit {
                Some((u, first)) if *u != row_unit => {
                    cells.bad(
                        TableColumn::Unit,
                        format!(
                            "is {}, but line {first} gives {}: a table has one unit; convert the rows to one unit",
                            quote(&row_unit),
                            quote(u)
                        ),
                    );
                    return;
                }
                Some(_) => {}
                None => unit = Some((row_unit, row.line)),
            }
            seen.insert((row.finger, row.segment), row.line);
            rows.push(row);
        })?;
        Ok(SummaryTable {
            path: label.to_string(),
            sha256,
            // read_table refuses a file without rows, so a unit was seen.
            unit: unit.map(|(u, _)| u).unwrap_or_default(),
            rows,
        })
    }

    /// The row of one segment of one finger.
    pub fn get(&self, finger: Finger, segment: Segment) -> Option<&TableRow> {
        self.rows
            .iter()
            .find(|r| r.finger == finger && r.segment == segment)
    }

    /// The fingers the table gives every phalanx of, thumb first.
    pub fn fingers(&self) -> Vec<Finger> {
        Finger::ALL
            .into_iter()
            .filter(|&f| {
                Segment::phalanges(f)
                    .iter()
                    .all(|&s| self.get(f, s).is_some())
            })
            .collect()
    }

    /// The largest n of any row, the table's sample size as far as it says.
    pub fn n(&self) -> Option<u64> {
        self.rows.iter().filter_map(|r| r.n).max()
    }
}

/// The columns of a summary table; all six are required (`sd` and `n` may be empty).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TableColumn {
    Finger,
    Segment,
    Mean,
    Sd,
    N,
    Unit,
}

impl Columns for TableColumn {
    const ALL: &'static [TableColumn] = &[
        TableColumn::Finger,
        TableColumn::Segment,
        TableColumn::Mean,
        TableColumn::Sd,
        TableColumn::N,
        TableColumn::Unit,
    ];
    const EMPTY: &'static str =
        "is empty; a summary table needs the header finger,segment,mean,sd,n,unit and its rows";
    const NO_ROWS: Option<&'static str> =
        Some("has a header but no rows; add one row per finger and segment");

    fn name(self) -> &'static str {
        match self {
            TableColumn::Finger => "finger",
            TableColumn::Segment => "segment",
            TableColumn::Mean => "mean",
            TableColumn::Sd => "sd",
            TableColumn::N => "n",
            TableColumn::Unit => "unit",
        }
    }

    fn required(self) -> bool {
        true
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Validates one row of a summary table; its problems go to `cells`.
fn parse_row(cells: &mut Cells<'_, '_, TableColumn>) -> Option<(TableRow, String)> {
    let finger = cells.parse(TableColumn::Finger, |t| {
        Finger::parse(t).ok_or_else(|| {
            format!(
                "unknown finger {}; use one of {}",
                quote(t),
                Finger::ACCEPTED
            )
        })
    });
    let segment = cells.parse(TableColumn::Segment, |t| {
        Segment::parse(t).ok_or_else(|| {
            format!(
                "unknown segment {}; use one of proximal, middle, distal, tip_soft_tissue, metacarpal",
                quote(t)
            )
        })
    });
    if finger == Some(Finger::Thumb) && segment == Some(Segment::Middle) {
        cells.bad(
            TableColumn::Segment,
            "the thumb has no middle phalanx (its phalanges are proximal and distal); correct the finger or the segment",
        );
    }
    let mean = cells.parse(TableColumn::Mean, |t| match t.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(v) if v.is_finite() => Err(format!(
            "{} is not positive; a mean length must be greater than 0",
            quote(t)
        )),
        _ if t.is_empty() => Err("is empty; enter the mean length".into()),
        _ => Err(format!(
            "{} is not a finite number; write the mean length as a decimal number such as 15.82",
            quote(t)
        )),
    });
    let sd = cells
        .parse(TableColumn::Sd, |t| {
            if t.is_empty() {
                return Ok(None);
            }
            match t.parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 0.0 => Ok(Some(v)),
                Ok(v) if v.is_finite() => Err(format!(
                    "{} is negative; an SD is 0 or more (leave it empty when the source gives none)",
                    quote(t)
                )),
                _ => Err(format!(
                    "{} is not a finite number; write the SD as a decimal number, or leave it empty",
                    quote(t)
                )),
            }
        })
        .flatten();
    let n = cells
        .parse(TableColumn::N, |t| {
            if t.is_empty() {
                return Ok(None);
            }
            match t.parse::<u64>() {
                Ok(v) if v >= 1 => Ok(Some(v)),
                _ => Err(format!(
                    "{} is not a number of hands; write a whole number of 1 or more, or leave it empty",
                    quote(t)
                )),
            }
        })
        .flatten();
    let unit = cells.parse(TableColumn::Unit, |t| {
        if t.is_empty() {
            Err("is empty; name the unit of the lengths (e.g. mm)".to_string())
        } else if looks_like_formula(t) {
            Err(format!(
                "{} starts like a spreadsheet formula; remove the leading character",
                quote(t)
            ))
        } else {
            Ok(t.to_string())
        }
    });
    if cells.has_problems() {
        return None;
    }
    Some((
        TableRow {
            line: cells.line(),
            finger: finger?,
            segment: segment?,
            mean: mean?,
            sd,
            n,
        },
        unit?,
    ))
}

/// A cohort as a command reads it: per-hand measurements, or a published summary table.
#[derive(Debug, Clone)]
pub enum Source {
    Data(Dataset),
    Table(SummaryTable),
}

impl Source {
    /// Reads `path` as a summary table when its header names a `segment` column, else as
    /// a measurement file; either way every problem of the file is reported.
    pub fn load(path: &Path) -> Result<Source, DataError> {
        let bytes = csvinput::read_input(path)?;
        let label = path.display().to_string();
        if is_summary_table(&bytes) {
            SummaryTable::from_bytes(&label, &bytes).map(Source::Table)
        } else {
            Dataset::from_bytes(&label, &bytes).map(Source::Data)
        }
    }

    /// The path as given.
    pub fn path(&self) -> &str {
        match self {
            Source::Data(d) => &d.path,
            Source::Table(t) => &t.path,
        }
    }
}

/// True when the first non-blank line is a header naming the column `segment`: a summary
/// table's header (a measurement file has no such column).
pub fn is_summary_table(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    let text = text.trim_start_matches('\u{feff}');
    text.lines()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|header| {
            header
                .split(',')
                .any(|c| c.trim().trim_matches('"').eq_ignore_ascii_case("segment"))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "finger,segment,mean,sd,n,unit\n";

    #[test]
    fn the_vendored_table_reads() {
        let t = SummaryTable::load(Path::new("data/literature/buryanov-kotiuk-2010.csv")).unwrap();
        assert_eq!(t.rows.len(), 24);
        assert_eq!(t.unit, "mm");
        assert_eq!(t.n(), Some(66));
        assert_eq!(t.fingers().len(), 5);
        let r = t.get(Finger::Little, Segment::Proximal).unwrap();
        // The PDF's figure (a copy elsewhere misprints 32.57).
        assert_eq!((r.mean, r.sd, r.n), (32.74, Some(2.77), Some(66)));
        assert!(t.get(Finger::Thumb, Segment::Middle).is_none());
    }

    #[test]
    fn every_problem_of_a_bad_table_with_its_line_and_column() {
        let text = format!(
            "{HEADER}toe,distal,1,1,5,mm\nindex,nail,1,1,5,mm\nthumb,middle,20,1,5,mm\n\
             index,distal,0,1,5,mm\nindex,proximal,-3,1,5,mm\nring,distal,17,-2,5,mm\n\
             ring,distal,17,2,5,mm\nring,middle,25,2,5,cm\nlittle,distal,15,1,2.5,mm\n"
        );
        let e = SummaryTable::from_bytes("bad.csv", text.as_bytes()).unwrap_err();
        let got: Vec<(Option<u64>, Option<usize>, &str)> = e
            .problems
            .iter()
            .map(|p| (p.line, p.column, p.message.as_str()))
            .collect();
        let at = |line: u64, col: usize, needle: &str| {
            assert!(
                got.iter()
                    .any(|(l, c, m)| *l == Some(line) && *c == Some(col) && m.contains(needle)),
                "no problem at {line}:{col} with {needle:?} in {got:#?}"
            );
        };
        at(2, 1, "unknown finger 'toe'");
        at(3, 2, "unknown segment 'nail'");
        at(4, 2, "the thumb has no middle phalanx");
        at(5, 3, "'0' is not positive");
        at(6, 3, "'-3' is not positive");
        at(7, 4, "'-2' is negative");
        // Line 7 was refused, so line 8's ring distal is the first, not a duplicate.
        at(9, 6, "is 'cm', but line 8 gives 'mm'");
        at(10, 5, "'2.5' is not a number of hands");
        assert_eq!(e.problems.len(), 8, "{e}");
        let shown = e.to_string();
        assert!(shown.starts_with("8 problems in bad.csv:"), "{shown}");
        assert!(
            shown.contains("bad.csv:2:1: finger: unknown finger"),
            "{shown}"
        );
    }

    #[test]
    fn duplicates_name_the_first_line() {
        let text = format!("{HEADER}index,distal,15,1,5,mm\nindex,distal,16,1,5,mm\n");
        let e = SummaryTable::from_bytes("d.csv", text.as_bytes()).unwrap_err();
        assert_eq!(e.problems.len(), 1);
        assert_eq!(
            (e.problems[0].line, e.problems[0].column),
            (Some(3), Some(2))
        );
        assert!(e.problems[0].message.contains("already given on line 2"));
    }

    #[test]
    fn empty_sd_and_n_are_allowed() {
        let text = format!("{HEADER}index,distal,15.82,,,mm\n");
        let t = SummaryTable::from_bytes("t.csv", text.as_bytes()).unwrap();
        assert_eq!((t.rows[0].sd, t.rows[0].n), (None, None));
    }

    #[test]
    fn a_table_is_told_from_a_measurement_file_by_its_header() {
        assert!(is_summary_table(HEADER.as_bytes()));
        assert!(is_summary_table(b"\xef\xbb\xbf\n\"Finger\",Segment,mean\n"));
        assert!(!is_summary_table(b"xray,finger,j1,j2,j3\n"));
        assert!(!is_summary_table(b""));
    }
}
