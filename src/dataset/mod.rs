//! Ingest and validate measurement tables (Table 1 of the paper and its successors).
//!
//! A measurement file has one row per X-ray and finger:
//! `xray,finger,j1,j2,j3[,sex,age,side,source,unit]`, with `j3` empty for the
//! thumb. [`Dataset::load`] reads a whole file and either returns every row or
//! a [`DataError`] listing every problem in the file with its line and column.

pub mod append;
pub mod claims;
pub mod csvinput;
pub mod error;
pub mod finger;
pub mod history;
pub mod landmarks;

pub use error::{DataError, Problem};
pub use finger::Finger;

use csvinput::{CsvScan, Header, Record, quote};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::path::Path;
use std::sync::Arc;

/// Largest accepted segment length (any unit): beyond it squares of sums could overflow.
pub const MAX_LENGTH: f64 = 1e100;
/// Largest accepted ratio between the longest and the shortest segment of a finger.
pub const MAX_SPREAD: f64 = 1e6;

/// Columns every measurement file must have, in the canonical order.
pub const REQUIRED_COLUMNS: [&str; 5] = ["xray", "finger", "j1", "j2", "j3"];
/// Metadata columns a measurement file may have; their values may be empty.
pub const OPTIONAL_COLUMNS: [&str; 5] = ["sex", "age", "side", "source", "unit"];

/// Descriptive metadata of one row; every field may be absent.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Meta {
    /// `female`, `male` (from `f`/`m` too) or the text given, lower-cased.
    pub sex: Option<Arc<str>>,
    /// Age in years.
    pub age: Option<f64>,
    /// `left` or `right`.
    pub side: Option<Arc<str>>,
    /// Where the measurement comes from (e.g. "Figure 1a").
    pub source: Option<Arc<str>>,
    /// Unit of the lengths (e.g. "image units").
    pub unit: Option<Arc<str>>,
}

/// One validated measurement row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Line of the row in its file (1-based).
    pub line: u64,
    /// The X-ray's id.
    pub xray: Arc<str>,
    pub finger: Finger,
    /// J1, J2, J3 (J3 is 0 for the thumb; use [`Row::segments`]).
    pub lengths: [f64; 3],
    pub meta: Meta,
}

impl Row {
    /// The measured segment lengths: `[J1, J2]` for the thumb, `[J1, J2, J3]` otherwise.
    pub fn segments(&self) -> &[f64] {
        &self.lengths[..self.finger.segments()]
    }

    /// Total length J = sum of the segments (eq. 1).
    pub fn total(&self) -> f64 {
        self.segments().iter().sum()
    }
}

/// A validated measurement table.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// The path as given by the user.
    pub path: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
    /// Column names of the header, lower-case, in file order.
    pub columns: Vec<String>,
    /// Rows in file order.
    pub rows: Vec<Row>,
}

impl Dataset {
    /// Reads and validates a measurement file. Cost: O(bytes).
    /// The file is streamed: memory holds the rows, not the file's bytes.
    pub fn load(path: &Path) -> Result<Dataset, DataError> {
        let file = csvinput::open_input(path)?;
        Dataset::from_reader(&path.display().to_string(), file)
    }

    /// Validates a measurement table read from `input`; `label` names it in errors.
    pub fn from_reader(label: &str, input: impl std::io::Read) -> Result<Dataset, DataError> {
        let (columns, rows, sha256) = parse_rows(label, input)?;
        Ok(Dataset {
            path: label.to_string(),
            sha256,
            columns,
            rows,
        })
    }

    /// Validates the bytes of a measurement file; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<Dataset, DataError> {
        Dataset::from_reader(label, bytes)
    }

    /// Number of distinct X-ray ids.
    pub fn xray_count(&self) -> usize {
        let mut ids: Vec<&str> = self.rows.iter().map(|r| &*r.xray).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }

    /// The rows of one finger, in file order.
    pub fn rows_of(&self, finger: Finger) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(move |r| r.finger == finger)
    }
}

/// Parses one segment length, explaining what to fix when it is not a
/// positive finite number.
pub fn parse_length(text: &str) -> Result<f64, String> {
    if text.is_empty() {
        return Err("is empty; enter the measured length (a positive number)".into());
    }
    match text.parse::<f64>() {
        Ok(v) if v.is_nan() => Err(format!(
            "{} is not a number (NaN); enter the measured length",
            quote(text)
        )),
        Ok(v) if v.is_infinite() => {
            let numeric = text
                .trim_start_matches(['+', '-'])
                .starts_with(|c: char| c.is_ascii_digit() || c == '.');
            if numeric {
                Err(format!(
                    "{} is too large to represent (over 1.8e308); check the value",
                    quote(text)
                ))
            } else {
                Err(format!(
                    "{} is infinite; enter the measured length",
                    quote(text)
                ))
            }
        }
        Ok(v) if v <= 0.0 => Err(if v == 0.0 {
            format!("{} is zero; a segment length must be positive", quote(text))
        } else {
            format!(
                "{} is negative; a segment length must be positive",
                quote(text)
            )
        }),
        Ok(v) => Ok(v),
        Err(_) => {
            let comma = text.replacen(',', ".", 1);
            if text.matches(',').count() == 1 && comma.parse::<f64>().is_ok() {
                Err(format!(
                    "{} uses a decimal comma; write it with a point: {comma}",
                    quote(text)
                ))
            } else {
                Err(format!(
                    "{} is not a number; write the length as a decimal number such as 188.83",
                    quote(text)
                ))
            }
        }
    }
}

/// Interns repeated metadata strings so a large file keeps one copy of each.
#[derive(Default)]
struct Interner(HashMap<String, Arc<str>>);

impl Interner {
    fn get(&mut self, s: &str) -> Arc<str> {
        if let Some(a) = self.0.get(s) {
            return a.clone();
        }
        let a: Arc<str> = Arc::from(s);
        self.0.insert(s.to_string(), a.clone());
        a
    }

    fn opt(&mut self, s: &str) -> Option<Arc<str>> {
        (!s.is_empty()).then(|| self.get(s))
    }
}

/// Column positions in the canonical order of REQUIRED then OPTIONAL columns.
const XRAY: usize = 0;
const FINGER: usize = 1;
const J: [usize; 3] = [2, 3, 4];
const SEX: usize = 5;
const AGE: usize = 6;
const SIDE: usize = 7;
const SOURCE: usize = 8;
const UNIT: usize = 9;

fn column_name(k: usize) -> &'static str {
    if k < 5 {
        REQUIRED_COLUMNS[k]
    } else {
        OPTIONAL_COLUMNS[k - 5]
    }
}

/// Per-X-ray metadata seen so far, to catch rows of one X-ray that disagree.
struct XrayMeta {
    line: u64,
    sex: Option<Arc<str>>,
    age: Option<f64>,
    side: Option<Arc<str>>,
    unit: Option<Arc<str>>,
}

/// Parses and validates rows; returns the header's columns, the rows and the
/// file's SHA-256.
fn parse_rows(
    label: &str,
    input: impl std::io::Read,
) -> Result<(Vec<String>, Vec<Row>, String), DataError> {
    let mut problems = Vec::new();
    let mut scan = CsvScan::new(label, input)?;
    let (header_line, header) = match scan.next_record(&mut problems) {
        Some(rec) => (
            rec.line,
            Header::parse(&rec, &REQUIRED_COLUMNS, &OPTIONAL_COLUMNS, &mut problems),
        ),
        None => {
            let content = scan.finish().map(|(_, c)| c).unwrap_or(true);
            if problems.is_empty() {
                problems.push(Problem::file(if content {
                    "has no header line; start it with xray,finger,j1,j2,j3"
                } else {
                    "is empty; it needs a header line and at least one data row"
                }));
            }
            return Err(DataError {
                file: label.to_string(),
                problems,
            });
        }
    };
    let header_ok = problems.is_empty();
    let width = header.names.len();
    let mut interner = Interner::default();
    let mut seen: HashMap<(Arc<str>, Finger), u64> = HashMap::new();
    let mut xray_meta: HashMap<Arc<str>, XrayMeta> = HashMap::new();
    let mut rows = Vec::new();
    let mut records = 0usize;
    while let Some(rec) = scan.next_record(&mut problems) {
        records += 1;
        if !header_ok {
            continue; // column meanings are unknown; the header problems say why
        }
        if rec.len() != width {
            problems.push(csvinput::field_count_problem(&rec, width));
            continue;
        }
        if let Some(row) = parse_row(&rec, &header, &mut interner, &mut problems) {
            match seen.entry((row.xray.clone(), row.finger)) {
                Entry::Occupied(first) => {
                    problems.push(Problem::field(
                        row.line,
                        header.positions[XRAY].map_or(0, |p| p + 1),
                        "xray",
                        format!(
                            "duplicate row: X-ray {} already has {} row on line {}; remove one or correct the X-ray id",
                            quote(&row.xray),
                            row.finger.with_article(),
                            first.get()
                        ),
                    ));
                    continue;
                }
                Entry::Vacant(v) => {
                    v.insert(row.line);
                }
            }
            check_xray_meta(&row, &header, &mut xray_meta, &mut problems);
            rows.push(row);
        }
    }
    if records == 0 && problems.is_empty() {
        problems.push(Problem::file(
            "has a header but no data rows; add one row per X-ray and finger",
        ));
    }
    // Byte-level problems (non-UTF-8, NUL) know their column; name its field.
    for p in &mut problems {
        if let (None, Some(c), Some(l)) = (&p.field, p.column, p.line)
            && l > header_line
        {
            p.field = header.names.get(c - 1).filter(|n| !n.is_empty()).cloned();
        }
    }
    let sha256 = match scan.finish() {
        Ok((sha, _)) => sha,
        Err(e) => {
            problems.push(Problem::file(format!("could not be read to the end ({e})")));
            String::new()
        }
    };
    if problems.is_empty() {
        Ok((header.names, rows, sha256))
    } else {
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        Err(DataError {
            file: label.to_string(),
            problems,
        })
    }
}

/// Validates one record; pushes its problems and returns the row when it has none.
fn parse_row(
    rec: &Record<'_>,
    header: &Header,
    interner: &mut Interner,
    problems: &mut Vec<Problem>,
) -> Option<Row> {
    let before = problems.len();
    let line = rec.line;
    // Field k of the canonical order: `Some(text)` (maybe empty) or `None` when unreadable.
    let field = |k: usize| -> Option<&str> {
        match header.positions[k] {
            Some(p) => rec.get(p),
            None => Some(""),
        }
    };
    let col = |k: usize| header.positions[k].map_or(0, |p| p + 1);
    let mut bad = |k: usize, msg: String| {
        problems.push(Problem::field(line, col(k), column_name(k), msg));
    };

    let xray = field(XRAY);
    if xray == Some("") {
        bad(
            XRAY,
            "is empty; give every row the id of its X-ray (e.g. 'Figure 1a')".into(),
        );
    }
    // Text that a spreadsheet would run as a formula never enters the dataset, so
    // no CSV phalanx writes from it (e.g. on 'add') can carry one.
    for k in [XRAY, SEX, SIDE, SOURCE, UNIT] {
        if let Some(t) = field(k).filter(|t| looks_like_formula(t)) {
            bad(
                k,
                format!(
                    "{} starts like a spreadsheet formula; remove the leading '{}'",
                    quote(t),
                    t.chars().next().unwrap_or('=')
                ),
            );
        }
    }
    let finger_text = field(FINGER);
    let finger = match finger_text {
        Some("") => {
            bad(
                FINGER,
                format!("is empty; name the finger: {}", Finger::ACCEPTED),
            );
            None
        }
        Some(t) => {
            let f = Finger::parse(t);
            if f.is_none() {
                bad(
                    FINGER,
                    format!(
                        "unknown finger {}; use one of {}",
                        quote(t),
                        Finger::ACCEPTED
                    ),
                );
            }
            f
        }
        None => None,
    };
    let mut lengths = [0.0f64; 3];
    for (s, &k) in J.iter().enumerate() {
        let Some(text) = field(k) else { continue };
        if s == 2 {
            match finger {
                Some(Finger::Thumb) => {
                    if !text.is_empty() {
                        bad(
                            k,
                            format!(
                                "the thumb has only J1 and J2, but j3 is {}; leave j3 empty for the thumb",
                                quote(text)
                            ),
                        );
                    }
                    continue;
                }
                None => {
                    if text.is_empty() {
                        continue; // cannot tell whether j3 is needed
                    }
                }
                Some(f) if text.is_empty() => {
                    bad(
                        k,
                        format!("is empty, but the {f} finger has three segments; enter J3"),
                    );
                    continue;
                }
                Some(_) => {}
            }
        }
        match parse_length(text) {
            Ok(v) => lengths[s] = v,
            Err(msg) => bad(k, msg),
        }
    }
    let mut meta = Meta::default();
    if let Some(t) = field(SEX) {
        meta.sex = interner.opt(&normalise_sex(t));
    }
    if let Some(t) = field(AGE).filter(|t| !t.is_empty()) {
        match t.parse::<f64>() {
            Ok(a) if a.is_finite() && (0.0..=150.0).contains(&a) => meta.age = Some(a),
            _ => bad(
                AGE,
                format!(
                    "{} is not an age; give years from 0 to 150, or leave it empty",
                    quote(t)
                ),
            ),
        }
    }
    if let Some(t) = field(SIDE).filter(|t| !t.is_empty()) {
        match t.to_ascii_lowercase().as_str() {
            "left" | "l" => meta.side = Some(interner.get("left")),
            "right" | "r" => meta.side = Some(interner.get("right")),
            _ => bad(
                SIDE,
                format!(
                    "{} is not a side; use left or right, or leave it empty",
                    quote(t)
                ),
            ),
        }
    }
    if let Some(t) = field(SOURCE) {
        meta.source = interner.opt(t);
    }
    if let Some(t) = field(UNIT) {
        meta.unit = interner.opt(t);
    }
    if problems.len() > before {
        return None;
    }
    let finger = finger?;
    let row = Row {
        line,
        xray: interner.get(xray?),
        finger,
        lengths,
        meta,
    };
    if !row.total().is_finite() {
        problems.push(Problem::line(
            line,
            "the lengths add up to more than the largest representable number; check the values",
        ));
        return None;
    }
    // Bounds that keep every statistic finite (squares, ratios) and catch unit slips.
    let segs = row.segments();
    let (lo, hi) = segs.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
        (lo.min(l), hi.max(l))
    });
    if hi > MAX_LENGTH {
        problems.push(Problem::line(
            line,
            format!("a length of {hi:e} is implausibly large (over {MAX_LENGTH:e}); check the value and its unit"),
        ));
        return None;
    }
    if hi / lo > MAX_SPREAD {
        problems.push(Problem::line(
            line,
            format!(
                "the lengths differ more than {MAX_SPREAD:e}-fold ({lo:e} to {hi:e}); the segments of one finger are of similar size: check the values"
            ),
        ));
        return None;
    }
    Some(row)
}

/// True for text a spreadsheet would evaluate: starting with `=`, `+` or `@`
/// (a leading `-` is allowed: ids such as "-1" are plausible).
pub fn looks_like_formula(text: &str) -> bool {
    text.starts_with(['=', '+', '@'])
}

fn normalise_sex(text: &str) -> String {
    let t = text.to_lowercase();
    match t.as_str() {
        "f" | "female" | "woman" => "female".into(),
        "m" | "male" | "man" => "male".into(),
        _ => t,
    }
}

/// Rows of one X-ray describe one hand: their sex, age, side and unit must agree.
fn check_xray_meta(
    row: &Row,
    header: &Header,
    seen: &mut HashMap<Arc<str>, XrayMeta>,
    problems: &mut Vec<Problem>,
) {
    let entry = seen.entry(row.xray.clone()).or_insert_with(|| XrayMeta {
        line: row.line,
        sex: row.meta.sex.clone(),
        age: row.meta.age,
        side: row.meta.side.clone(),
        unit: row.meta.unit.clone(),
    });
    let mut conflict = |k: usize, ours: String, theirs: String| {
        problems.push(Problem::field(
            row.line,
            header.positions[k].map_or(0, |p| p + 1),
            column_name(k),
            format!(
                "is {ours}, but line {} gives {theirs} for the same X-ray {}; one hand has one value",
                entry.line,
                quote(&row.xray)
            ),
        ));
    };
    let show = |v: &Option<Arc<str>>| v.as_deref().map_or("empty".to_string(), quote);
    if row.meta.sex != entry.sex {
        conflict(SEX, show(&row.meta.sex), show(&entry.sex));
    }
    if row.meta.age != entry.age {
        let f = |a: Option<f64>| a.map_or("empty".to_string(), |a| a.to_string());
        conflict(AGE, f(row.meta.age), f(entry.age));
    }
    if row.meta.side != entry.side {
        conflict(SIDE, show(&row.meta.side), show(&entry.side));
    }
    if row.meta.unit != entry.unit {
        conflict(UNIT, show(&row.meta.unit), show(&entry.unit));
    }
}

#[cfg(test)]
mod tests;
