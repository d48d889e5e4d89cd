//! Ingest and validate measurement tables (Table 1 of the paper and its successors).
//!
//! A measurement file has one row per X-ray and finger:
//! `xray,finger,j1,j2,j3[,mc,sex,age,side,source,unit,tip,flagged]`, with `j3` empty for
//! the thumb. [`Dataset::load`] reads a whole file and either returns every row or
//! a [`DataError`] listing every problem in the file with its line and column.
//!
//! The optional `mc` is the metacarpal's length (CMC to MCP) in the row's unit, and
//! `tip` says where the fingertips are (`bone`, `skin`, or empty: unknown). The unit is
//! per row (the rows of one X-ray share it): relative values and ratios have no unit and
//! pool across units, while lengths in different units are never averaged together (the
//! analysis leaves the total out, with a note). `flagged` holds why `phalanx add
//! --accept-flagged` let in a row its outlier or typo rules flagged (empty: not flagged).
//!
//! One hand has one sex, age and side: rows of one X-ray may leave them empty (unknown),
//! but two rows that give different values conflict. [`Dataset::hand`] gives the hand's
//! values.

pub(crate) mod append;
pub mod claims;
pub mod cohort;
pub(crate) mod csvinput;
pub(crate) mod error;
pub(crate) mod finger;
pub mod history;
pub(crate) mod landmarks;
pub mod literature;
mod named;
pub(crate) mod quantity;
pub mod tip;
pub(crate) mod tip_rows;
#[cfg(test)]
pub(crate) mod vendored;

pub use cohort::CohortNotes;
pub use error::{DataError, Problem};
pub use finger::Finger;
pub use literature::{Segment, Source, SummaryTable, TableRow};
pub use quantity::Quantity;
pub use tip::{TipCounts, TipKind};

use csvinput::{Cells, Columns, quote};
use rustc_hash::FxHashMap;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Largest accepted segment length (any unit): beyond it squares of sums could overflow.
pub(crate) const MAX_LENGTH: f64 = 1e100;
/// Largest accepted ratio between the longest and the shortest segment of a finger.
pub(crate) const MAX_SPREAD: f64 = 1e6;

/// The columns of a measurement file: `xray`, `finger`, `j1`, `j2` and `j3` are
/// required; the metacarpal `mc` and the metadata `sex`, `age`, `side`, `source`,
/// `unit` and `tip` optional (and may be empty).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Column {
    Xray,
    Finger,
    J1,
    J2,
    J3,
    Mc,
    Sex,
    Age,
    Side,
    Source,
    Unit,
    Tip,
    Flagged,
}

impl Column {
    /// The segment columns J1, J2, J3.
    const SEGMENTS: [Column; 3] = [Column::J1, Column::J2, Column::J3];
}

impl Columns for Column {
    const ALL: &'static [Column] = &[
        Column::Xray,
        Column::Finger,
        Column::J1,
        Column::J2,
        Column::J3,
        Column::Mc,
        Column::Sex,
        Column::Age,
        Column::Side,
        Column::Source,
        Column::Unit,
        Column::Tip,
        Column::Flagged,
    ];
    const EMPTY: &'static str = "is empty; it needs a header line and at least one data row";
    const NO_ROWS: Option<&'static str> =
        Some("has a header but no data rows; add one row per X-ray and finger");

    fn name(self) -> &'static str {
        match self {
            Column::Xray => "xray",
            Column::Finger => "finger",
            Column::J1 => "j1",
            Column::J2 => "j2",
            Column::J3 => "j3",
            Column::Mc => "mc",
            Column::Sex => "sex",
            Column::Age => "age",
            Column::Side => "side",
            Column::Source => "source",
            Column::Unit => "unit",
            Column::Tip => "tip",
            Column::Flagged => "flagged",
        }
    }

    fn required(self) -> bool {
        matches!(
            self,
            Column::Xray | Column::Finger | Column::J1 | Column::J2 | Column::J3
        )
    }

    fn numeric(self) -> bool {
        matches!(
            self,
            Column::J1 | Column::J2 | Column::J3 | Column::Mc | Column::Age
        )
    }

    fn index(self) -> usize {
        self as usize
    }
}

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
    /// Where the fingertips are; `None` when unknown.
    pub tip: Option<TipKind>,
    /// Why the row was flagged as a likely error when it was added anyway
    /// (`phalanx add --accept-flagged`); `None` for a row nobody flagged.
    pub flagged: Option<Arc<str>>,
}

impl Meta {
    /// Fills this hand's empty sex, age, side, unit and tip from another row of it
    /// (source and flag are the row's own and are not copied).
    fn fill_from(&mut self, row: &Meta) {
        if self.sex.is_none() {
            self.sex.clone_from(&row.sex);
        }
        self.age = self.age.or(row.age);
        if self.side.is_none() {
            self.side.clone_from(&row.side);
        }
        if self.unit.is_none() {
            self.unit.clone_from(&row.unit);
        }
        self.tip = self.tip.or(row.tip);
    }
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
    /// The metacarpal, CMC to MCP, in the row's unit, when measured.
    pub mc: Option<f64>,
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
    pub fn from_reader(
        label: &str,
        input: impl std::io::Read + Send,
    ) -> Result<Dataset, DataError> {
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

    /// The one unit every row names, or `None` when no row names a unit or the rows
    /// name different ones (or some name none): see [`Dataset::units`].
    pub fn unit(&self) -> Option<&str> {
        match self.units().as_slice() {
            [(Some(u), _)] => Some(u),
            _ => None,
        }
    }

    /// Every unit the rows give (`None`: not named), with its number of rows, in order
    /// of first appearance. O(rows x units).
    pub fn units(&self) -> Vec<(Option<&str>, usize)> {
        let mut out: Vec<(Option<&str>, usize)> = Vec::new();
        for r in &self.rows {
            let u = r.meta.unit.as_deref();
            match out.iter_mut().find(|(v, _)| *v == u) {
                Some((_, n)) => *n += 1,
                None => out.push((u, 1)),
            }
        }
        out
    }

    /// The hand of one X-ray: the sex, age, side, unit and tip its rows give (rows may
    /// leave sex, age and side empty; [`Dataset::load`] refuses rows of one X-ray that
    /// give different values). `Meta::default()` for an X-ray the dataset lacks. O(rows).
    pub fn hand(&self, xray: &str) -> Meta {
        let mut meta = Meta::default();
        for r in self.rows.iter().filter(|r| &*r.xray == xray) {
            meta.fill_from(&r.meta);
        }
        meta
    }

    /// The hands of every X-ray ([`Dataset::hand`]) at once, by X-ray id. O(rows).
    pub fn hands(&self) -> HashMap<&str, Meta> {
        let mut out: HashMap<&str, Meta> = HashMap::new();
        for r in &self.rows {
            out.entry(&r.xray).or_default().fill_from(&r.meta);
        }
        out
    }

    /// The rows flagged as likely errors that were added anyway (`flagged` column), in
    /// file order.
    pub fn flagged(&self) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(|r| r.meta.flagged.is_some())
    }

    /// Where the rows put their fingertips.
    pub fn tips(&self) -> TipCounts {
        TipCounts::of(self.rows.iter().map(|r| r.meta.tip))
    }

    /// The lines of the rows that record no tip, the first 6 runs of them. O(rows).
    pub fn untipped(&self) -> tip::LineRuns {
        tip::LineRuns::of(
            self.rows
                .iter()
                .filter(|r| r.meta.tip.is_none())
                .map(|r| r.line),
            6,
        )
    }
}

/// True for a unit of per-image pixels (`px`, `pixel`, `pixels`, any case), the unit
/// `phalanx import` writes without a pixel spacing. Such lengths (the total J, the
/// metacarpal) are not comparable across images of different scale; only ratios are.
pub fn is_pixel_unit(unit: &str) -> bool {
    matches!(
        unit.trim().to_ascii_lowercase().as_str(),
        "px" | "pixel" | "pixels"
    )
}

/// Parses one segment length, explaining what to fix when it is not a
/// positive finite number.
pub(crate) fn parse_length(text: &str) -> Result<f64, String> {
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
struct Interner(FxHashMap<String, Arc<str>>);

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

/// Per-X-ray metadata seen so far, to catch rows of one X-ray that disagree: the first
/// row's line, unit and tip (every row must give the same, empty included), and the first
/// sex, age and side given, each with its line (a row may leave them empty).
struct XrayMeta {
    line: u64,
    /// The line of the X-ray's row of each finger (by [`Finger::index`]), 0 while none.
    fingers: [u64; 5],
    sex: Option<(Arc<str>, u64)>,
    age: Option<(f64, u64)>,
    side: Option<(Arc<str>, u64)>,
    unit: Option<Arc<str>>,
    tip: Option<TipKind>,
}

/// Parses and validates rows; returns the header's columns, the rows and the
/// file's SHA-256.
fn parse_rows(
    label: &str,
    input: impl std::io::Read + Send,
) -> Result<(Vec<String>, Vec<Row>, String), DataError> {
    let mut interner = Interner::default();
    let mut xray_meta: FxHashMap<Arc<str>, XrayMeta> = FxHashMap::default();
    let mut rows = Vec::new();
    let read = csvinput::read_table(label, input, |cells| {
        let Some(row) = parse_row(cells, &mut interner) else {
            return;
        };
        // One lookup per row serves the duplicate check and the hand's metadata.
        let entry = xray_meta
            .entry(row.xray.clone())
            .or_insert_with(|| XrayMeta {
                line: row.line,
                fingers: [0; 5],
                sex: None,
                age: None,
                side: None,
                unit: row.meta.unit.clone(),
                tip: row.meta.tip,
            });
        let first = &mut entry.fingers[row.finger.index()];
        if *first != 0 {
            cells.bad(
                Column::Xray,
                format!(
                    "duplicate row: X-ray {} already has {} row on line {}; remove one or correct the X-ray id",
                    quote(&row.xray),
                    row.finger.with_article(),
                    first
                ),
            );
            return;
        }
        *first = row.line;
        check_xray_meta(&row, cells, entry);
        rows.push(row);
    });
    let (header, sha256) = read?;
    Ok((header.names, rows, sha256))
}

/// Validates one record; reports its problems and returns the row when it has none.
fn parse_row(cells: &mut Cells<'_, '_, Column>, interner: &mut Interner) -> Option<Row> {
    let xray = cells.text(Column::Xray);
    if xray == Some("") {
        cells.bad(
            Column::Xray,
            "is empty; give every row the id of its X-ray (e.g. 'Figure 1a')",
        );
    }
    check_formulas(cells);
    let finger = cells.parse(Column::Finger, parse_finger);
    let lengths = read_lengths(cells, finger);
    let mc = cells
        .parse(Column::Mc, |t| {
            if t.is_empty() {
                Ok(None)
            } else {
                parse_length(t).map(Some)
            }
        })
        .flatten();
    let meta = read_meta(cells, interner);
    if cells.has_problems() {
        return None;
    }
    let row = Row {
        line: cells.line(),
        xray: interner.get(xray?),
        finger: finger?,
        lengths,
        mc,
        meta,
    };
    match check_bounds(&row) {
        Ok(()) => Some(row),
        Err(message) => {
            cells.bad_line(message);
            None
        }
    }
}

/// Text that a spreadsheet would run as a formula never enters the dataset, so
/// no CSV phalanx writes from it (e.g. on 'add') can carry one.
fn check_formulas(cells: &mut Cells<'_, '_, Column>) {
    for c in [
        Column::Xray,
        Column::Sex,
        Column::Side,
        Column::Source,
        Column::Unit,
        Column::Flagged,
    ] {
        if let Some(t) = cells.text(c).filter(|t| looks_like_formula(t)) {
            cells.bad(
                c,
                format!(
                    "{} starts like a spreadsheet formula; remove the leading '{}'",
                    quote(t),
                    t.chars().next().unwrap_or('=')
                ),
            );
        }
    }
}

/// Reads a finger's name (or one of its aliases).
fn parse_finger(text: &str) -> Result<Finger, String> {
    if text.is_empty() {
        return Err(format!("is empty; name the finger: {}", Finger::ACCEPTED));
    }
    Finger::parse(text).ok_or_else(|| {
        format!(
            "unknown finger {}; use one of {}",
            quote(text),
            Finger::ACCEPTED
        )
    })
}

/// Reads J1, J2 and J3 (0 where absent: J3 of the thumb, or a refused value).
/// Whether J3 must be given depends on the finger; with the finger unknown, an
/// empty J3 is not reported.
fn read_lengths(cells: &mut Cells<'_, '_, Column>, finger: Option<Finger>) -> [f64; 3] {
    let mut lengths = [0.0f64; 3];
    for (s, c) in Column::SEGMENTS.into_iter().enumerate() {
        let Some(text) = cells.text(c) else { continue };
        if c == Column::J3 {
            match finger {
                Some(Finger::Thumb) => {
                    if !text.is_empty() {
                        cells.bad(
                            c,
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
                    cells.bad(
                        c,
                        format!("is empty, but the {f} finger has three segments; enter J3"),
                    );
                    continue;
                }
                Some(_) => {}
            }
        }
        match parse_length(text) {
            Ok(v) => lengths[s] = v,
            Err(message) => cells.bad(c, message),
        }
    }
    lengths
}

/// Reads the optional metadata, interning repeated text.
fn read_meta(cells: &mut Cells<'_, '_, Column>, interner: &mut Interner) -> Meta {
    let mut meta = Meta::default();
    if let Some(t) = cells.text(Column::Sex) {
        meta.sex = interner.opt(&normalise_sex(t));
    }
    meta.age = cells.parse(Column::Age, parse_age).flatten();
    meta.side = cells
        .parse(Column::Side, parse_side)
        .flatten()
        .map(|s| interner.get(s));
    if let Some(t) = cells.text(Column::Source) {
        meta.source = interner.opt(t);
    }
    if let Some(t) = cells.text(Column::Unit) {
        meta.unit = interner.opt(t);
    }
    meta.tip = cells.parse(Column::Tip, parse_tip).flatten();
    if let Some(t) = cells.text(Column::Flagged) {
        meta.flagged = interner.opt(t);
    }
    meta
}

/// `bone` or `skin` (any case); `None` when empty.
fn parse_tip(text: &str) -> Result<Option<TipKind>, String> {
    if text.is_empty() {
        return Ok(None);
    }
    TipKind::parse(text).map(Some).ok_or_else(|| {
        format!(
            "{} is not a fingertip kind; use bone (landmark at the end of the distal phalanx) or skin (at the skin's outline), or leave it empty",
            quote(text)
        )
    })
}

/// An age in years from 0 to 150; `None` when empty.
fn parse_age(text: &str) -> Result<Option<f64>, String> {
    if text.is_empty() {
        return Ok(None);
    }
    match text.parse::<f64>() {
        Ok(a) if a.is_finite() && (0.0..=150.0).contains(&a) => Ok(Some(a)),
        _ => Err(format!(
            "{} is not an age; give years from 0 to 150, or leave it empty",
            quote(text)
        )),
    }
}

/// `left` or `right` (from `l`/`r` too, any case); `None` when empty.
fn parse_side(text: &str) -> Result<Option<&'static str>, String> {
    match text.to_ascii_lowercase().as_str() {
        "" => Ok(None),
        "left" | "l" => Ok(Some("left")),
        "right" | "r" => Ok(Some("right")),
        _ => Err(format!(
            "{} is not a side; use left or right, or leave it empty",
            quote(text)
        )),
    }
}

/// Bounds that keep every statistic finite (sums, squares, ratios) and catch
/// unit slips; the error says what to check.
fn check_bounds(row: &Row) -> Result<(), String> {
    if !row.total().is_finite() {
        return Err(
            "the lengths add up to more than the largest representable number; check the values"
                .into(),
        );
    }
    let segs = row.segments();
    let (lo, hi) = segs.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
        (lo.min(l), hi.max(l))
    });
    let hi = hi.max(row.mc.unwrap_or(0.0));
    if hi > MAX_LENGTH {
        return Err(format!(
            "a length of {hi:e} is implausibly large (over {MAX_LENGTH:e}); check the value and its unit"
        ));
    }
    if hi / lo > MAX_SPREAD {
        return Err(format!(
            "the lengths differ more than {MAX_SPREAD:e}-fold ({lo:e} to {hi:e}); the segments of one finger are of similar size: check the values"
        ));
    }
    Ok(())
}

/// True for text a spreadsheet would evaluate: starting with `=`, `+` or `@`
/// (a leading `-` is allowed: ids such as "-1" are plausible).
pub(crate) fn looks_like_formula(text: &str) -> bool {
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

/// Rows of one X-ray describe one hand. Sex, age and side may be left empty on some of
/// its rows (unknown there, so filling one in conflicts with nothing), but two rows that
/// give different values conflict; unit and tip must be the same on every row, empty
/// included (lengths of one hand are measured one way).
fn check_xray_meta(row: &Row, cells: &mut Cells<'_, '_, Column>, entry: &mut XrayMeta) {
    let line = row.line;
    // The X-ray quoted only when a conflict is reported (not once per row).
    let xray = &row.xray;
    let mut conflict = |c: Column, ours: String, theirs: String, at: u64| {
        cells.bad(
            c,
            format!(
                "is {ours}, but line {at} gives {theirs} for the same X-ray {}; one hand has one value",
                quote(xray)
            ),
        );
    };
    let show = |v: &Option<Arc<str>>| v.as_deref().map_or("empty".to_string(), quote);
    match (&row.meta.sex, &entry.sex) {
        (Some(ours), Some((theirs, at))) if ours != theirs => {
            conflict(Column::Sex, quote(ours), quote(theirs), *at);
        }
        (Some(ours), None) => entry.sex = Some((ours.clone(), line)),
        _ => {}
    }
    match (row.meta.age, entry.age) {
        (Some(ours), Some((theirs, at))) if ours != theirs => {
            conflict(Column::Age, ours.to_string(), theirs.to_string(), at);
        }
        (Some(ours), None) => entry.age = Some((ours, line)),
        _ => {}
    }
    match (&row.meta.side, &entry.side) {
        (Some(ours), Some((theirs, at))) if ours != theirs => {
            conflict(Column::Side, quote(ours), quote(theirs), *at);
        }
        (Some(ours), None) => entry.side = Some((ours.clone(), line)),
        _ => {}
    }
    if row.meta.unit != entry.unit {
        conflict(
            Column::Unit,
            show(&row.meta.unit),
            show(&entry.unit),
            entry.line,
        );
    }
    if row.meta.tip != entry.tip {
        let t = |t: Option<TipKind>| t.map_or("empty".to_string(), |t| quote(t.name()));
        conflict(Column::Tip, t(row.meta.tip), t(entry.tip), entry.line);
    }
}

#[cfg(test)]
mod tests;
