//! The paper's stated numbers (`data/paper_claims.csv`): ingest and validation.
//!
//! One row per number the paper prints:
//! `id,location,refers_to,finger,xray,quantity,statistic,model_length,stated,erratum,note`.
//! The printed precision is read off `stated` itself (`0.0319` has 4 decimals).

use super::csvinput::{Cells, Columns, quote, read_input, read_table};
use super::{DataError, Dataset, Finger, Problem};
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// The columns of a claims file; all are required, `xray`, `model_length`,
/// `erratum` and `note` may be empty.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Column {
    Id,
    Location,
    RefersTo,
    Finger,
    Xray,
    Quantity,
    Statistic,
    ModelLength,
    Stated,
    Erratum,
    Note,
}

impl Columns for Column {
    const ALL: &'static [Column] = &[
        Column::Id,
        Column::Location,
        Column::RefersTo,
        Column::Finger,
        Column::Xray,
        Column::Quantity,
        Column::Statistic,
        Column::ModelLength,
        Column::Stated,
        Column::Erratum,
        Column::Note,
    ];
    const EMPTY: &'static str = "is empty; it needs a header line and one row per claim";
    const NO_ROWS: Option<&'static str> = Some("has a header but no claims");

    fn name(self) -> &'static str {
        match self {
            Column::Id => "id",
            Column::Location => "location",
            Column::RefersTo => "refers_to",
            Column::Finger => "finger",
            Column::Xray => "xray",
            Column::Quantity => "quantity",
            Column::Statistic => "statistic",
            Column::ModelLength => "model_length",
            Column::Stated => "stated",
            Column::Erratum => "erratum",
            Column::Note => "note",
        }
    }

    fn required(self) -> bool {
        true
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// What a claim's number is about, for one finger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subject {
    /// A raw segment length J1, J2 or J3 (0-based index), as quoted in the text.
    Length(usize),
    /// A relative value J~k (0-based segment index).
    Relative(usize),
    /// The total length J.
    Total,
}

impl Subject {
    fn parse(text: &str) -> Option<Subject> {
        Some(match text.to_ascii_lowercase().as_str() {
            "j1" => Subject::Length(0),
            "j2" => Subject::Length(1),
            "j3" => Subject::Length(2),
            "rel_j1" => Subject::Relative(0),
            "rel_j2" => Subject::Relative(1),
            "rel_j3" => Subject::Relative(2),
            "total" => Subject::Total,
            _ => return None,
        })
    }

    /// Machine name, as written in the file.
    pub fn name(self) -> &'static str {
        match self {
            Subject::Length(k) => ["j1", "j2", "j3"][k],
            Subject::Relative(k) => ["rel_j1", "rel_j2", "rel_j3"][k],
            Subject::Total => "total",
        }
    }

    /// The segment this subject needs, if any.
    fn segment(self) -> Option<usize> {
        match self {
            Subject::Length(k) | Subject::Relative(k) => Some(k),
            Subject::Total => None,
        }
    }
}

/// Which statistic a claim states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// The value of one X-ray.
    Value,
    /// Eq. (5).
    Mean,
    /// Eq. (7).
    Min,
    /// Eq. (7).
    Max,
    /// Eq. (9).
    Range,
    /// The number of X-rays.
    N,
}

impl Statistic {
    fn parse(text: &str) -> Option<Statistic> {
        Some(match text.to_ascii_lowercase().as_str() {
            "value" => Statistic::Value,
            "mean" => Statistic::Mean,
            "min" => Statistic::Min,
            "max" => Statistic::Max,
            "range" => Statistic::Range,
            "n" => Statistic::N,
            _ => return None,
        })
    }

    /// Machine name, as written in the file.
    pub fn name(self) -> &'static str {
        match self {
            Statistic::Value => "value",
            Statistic::Mean => "mean",
            Statistic::Min => "min",
            Statistic::Max => "max",
            Statistic::Range => "range",
            Statistic::N => "n",
        }
    }
}

/// One number the paper states.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    pub line: u64,
    pub id: String,
    /// Where in the paper (e.g. "eq. (6)").
    pub location: String,
    /// What the number refers to, in words.
    pub refers_to: String,
    pub finger: Finger,
    /// The X-ray, for `value` claims.
    pub xray: Option<String>,
    pub subject: Subject,
    pub statistic: Statistic,
    /// For the worked examples: the model's total length the statistic is multiplied by.
    pub model_length: Option<f64>,
    pub stated: f64,
    /// `stated` as printed.
    pub stated_text: String,
    /// Decimals printed.
    pub decimals: usize,
    /// A known erratum: the explanation recorded in the file.
    pub erratum: Option<String>,
    pub note: String,
}

/// A validated claims file.
#[derive(Debug, Clone)]
pub struct Claims {
    pub path: String,
    pub claims: Vec<Claim>,
    /// 1-based column of each of [`Column::ALL`] in the file.
    columns: Vec<usize>,
}

/// Decimal places a number is printed to: `0.0319` -> 4, `31.9` -> 1,
/// `4.846e-1` -> 4 (mantissa decimals minus the exponent), never below 0.
pub(crate) fn printed_decimals(text: &str) -> usize {
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(i) => (&text[..i], text[i + 1..].parse::<i64>().unwrap_or(0)),
        None => (text, 0),
    };
    let digits = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i64;
    (digits - exponent).max(0) as usize
}

impl Claims {
    /// Reads and validates a claims file.
    pub fn load(path: &Path) -> Result<Claims, DataError> {
        let bytes = read_input(path)?;
        Claims::from_bytes(&path.display().to_string(), &bytes)
    }

    /// Validates the bytes of a claims file; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<Claims, DataError> {
        let mut claims = Vec::new();
        let mut ids: HashMap<String, u64> = HashMap::new();
        let (header, _) = read_table(label, bytes, |cells| {
            if let Some(claim) = read_claim(cells, &mut ids) {
                claims.push(claim);
            }
        })?;
        Ok(Claims {
            path: label.to_string(),
            claims,
            columns: Column::ALL.iter().map(|&c| header.column(c)).collect(),
        })
    }

    /// The 1-based column of `c` in the file.
    pub(crate) fn column(&self, c: Column) -> usize {
        self.columns.get(c.index()).copied().unwrap_or(0)
    }

    /// The X-rays the claims name (e.g. the paper's 1a-1e).
    pub fn xrays(&self) -> HashSet<&str> {
        self.claims
            .iter()
            .filter_map(|c| c.xray.as_deref())
            .collect()
    }

    /// How many of the dataset's X-rays the claims name, and how many X-rays it has:
    /// `(k, n)`, with k == n > 0 when the dataset holds exactly the claims' X-rays.
    pub fn named_in(&self, data: &Dataset) -> (usize, usize) {
        let named = self.xrays();
        let xrays: HashSet<&str> = data.rows.iter().map(|r| &*r.xray).collect();
        let k = xrays.iter().filter(|x| named.contains(*x)).count();
        (k, xrays.len())
    }

    /// Checks that every claim points at a finger and X-ray the dataset has.
    pub fn check_against(&self, data: &Dataset) -> Result<(), DataError> {
        let fingers: HashSet<Finger> = data.rows.iter().map(|r| r.finger).collect();
        let rows: HashSet<(&str, Finger)> =
            data.rows.iter().map(|r| (&*r.xray, r.finger)).collect();
        let mut problems = Vec::new();
        for c in &self.claims {
            if !fingers.contains(&c.finger) {
                problems.push(Problem::field(
                    c.line,
                    self.column(Column::Finger),
                    Column::Finger.name(),
                    format!(
                        "the dataset {} has no {} rows; fix the claim or the --data path",
                        data.path, c.finger
                    ),
                ));
            } else if let Some(x) = &c.xray
                && !rows.contains(&(x.as_str(), c.finger))
            {
                problems.push(Problem::field(
                    c.line,
                    self.column(Column::Xray),
                    Column::Xray.name(),
                    format!(
                        "the dataset {} has no {} row for X-ray {}",
                        data.path,
                        c.finger,
                        quote(x)
                    ),
                ));
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(DataError {
                file: self.path.clone(),
                problems,
            })
        }
    }
}

/// Validates one claim; reports its problems and returns it when it has none.
/// `ids` holds the ids seen so far, with their lines.
fn read_claim(cells: &mut Cells<'_, '_, Column>, ids: &mut HashMap<String, u64>) -> Option<Claim> {
    let id = read_id(cells, ids);
    let finger = cells.parse(Column::Finger, parse_finger);
    let subject = cells.parse(Column::Quantity, parse_subject);
    let statistic = cells.parse(Column::Statistic, parse_statistic);
    let xray = cells
        .text(Column::Xray)
        .filter(|t| !t.is_empty())
        .map(str::to_string);
    check_combination(cells, finger, subject, statistic, xray.is_some());
    let model_length = cells
        .parse(Column::ModelLength, parse_model_length)
        .flatten();
    let stated_text = cells.text(Column::Stated).unwrap_or("").to_string();
    let stated = match stated_text.parse::<f64>() {
        Ok(v) if v.is_finite() => Some(v),
        _ => {
            cells.bad(
                Column::Stated,
                format!(
                    "{} is not a number; copy the number as printed in the paper",
                    quote(&stated_text)
                ),
            );
            None
        }
    };
    let note = cells.text(Column::Note).unwrap_or("").to_string();
    let erratum = match cells
        .text(Column::Erratum)
        .unwrap_or("")
        .to_ascii_lowercase()
        .as_str()
    {
        "" | "no" => None,
        "yes" => Some(note.clone()),
        other => {
            cells.bad(
                Column::Erratum,
                format!("{} must be 'yes' or empty", quote(other)),
            );
            None
        }
    };
    if cells.has_problems() {
        return None;
    }
    Some(Claim {
        line: cells.line(),
        id,
        location: cells.text(Column::Location).unwrap_or("").to_string(),
        refers_to: cells.text(Column::RefersTo).unwrap_or("").to_string(),
        finger: finger?,
        xray,
        subject: subject?,
        statistic: statistic?,
        model_length,
        decimals: printed_decimals(&stated_text),
        stated: stated?,
        stated_text,
        erratum,
        note,
    })
}

/// The claim's id, which must be given and unique.
fn read_id(cells: &mut Cells<'_, '_, Column>, ids: &mut HashMap<String, u64>) -> String {
    let id = cells.text(Column::Id).unwrap_or("").to_string();
    if id.is_empty() {
        cells.bad(Column::Id, "is empty; give every claim a unique id");
    } else if let Some(first) = ids.get(&id) {
        cells.bad(
            Column::Id,
            format!(
                "{} is already used on line {first}; ids must be unique",
                quote(&id)
            ),
        );
    } else {
        ids.insert(id.clone(), cells.line());
    }
    id
}

/// A finger's name (or one of its aliases).
fn parse_finger(text: &str) -> Result<Finger, String> {
    Finger::parse(text).ok_or_else(|| {
        format!(
            "unknown finger {}; use one of {}",
            quote(text),
            Finger::ACCEPTED
        )
    })
}

/// What the number is about (see [`Subject::name`]).
fn parse_subject(text: &str) -> Result<Subject, String> {
    Subject::parse(text).ok_or_else(|| {
        format!(
            "unknown quantity {}; use j1, j2, j3, rel_j1, rel_j2, rel_j3 or total",
            quote(text)
        )
    })
}

/// Which statistic the number is (see [`Statistic::name`]).
fn parse_statistic(text: &str) -> Result<Statistic, String> {
    Statistic::parse(text).ok_or_else(|| {
        format!(
            "unknown statistic {}; use value, mean, min, max, range or n",
            quote(text)
        )
    })
}

/// Checks that the finger, quantity, statistic and X-ray of a claim fit together.
fn check_combination(
    cells: &mut Cells<'_, '_, Column>,
    finger: Option<Finger>,
    subject: Option<Subject>,
    statistic: Option<Statistic>,
    has_xray: bool,
) {
    if statistic == Some(Statistic::Value) && !has_xray {
        cells.bad(
            Column::Xray,
            "is empty, but a 'value' claim is about one X-ray; name it",
        );
    }
    if let (Some(f), Some(s)) = (finger, subject)
        && s.segment().is_some_and(|k| k >= f.segments())
    {
        cells.bad(
            Column::Quantity,
            format!(
                "the {f} has no {}; it has {} segments",
                s.name(),
                f.segments()
            ),
        );
    }
    if matches!(subject, Some(Subject::Length(_)))
        && statistic.is_some_and(|s| s != Statistic::Value)
    {
        cells.bad(
            Column::Statistic,
            "raw lengths (j1..j3) can only be stated as 'value' claims",
        );
    }
}

/// The model's total length of a worked example: a positive number, or `None` when empty.
fn parse_model_length(text: &str) -> Result<Option<f64>, String> {
    if text.is_empty() {
        return Ok(None);
    }
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(v)),
        _ => Err(format!(
            "{} is not a positive number; give the model's total length or leave it empty",
            quote(text)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::printed_decimals;

    #[test]
    fn decimals_as_printed() {
        assert_eq!(printed_decimals("0.0319"), 4);
        assert_eq!(printed_decimals("31.9"), 1);
        assert_eq!(printed_decimals("5"), 0);
        assert_eq!(printed_decimals("4.846e-1"), 4);
        assert_eq!(printed_decimals("4.846E2"), 1);
        assert_eq!(printed_decimals("5e3"), 0);
    }
}
