//! The paper's stated numbers (`data/paper_claims.csv`): ingest and validation.
//!
//! One row per number the paper prints:
//! `id,location,refers_to,finger,xray,quantity,statistic,model_length,stated,erratum,note`.
//! The printed precision is read off `stated` itself (`0.0319` has 4 decimals).

use super::csvinput::{CsvScan, Header, quote, read_input};
use super::{DataError, Dataset, Finger, Problem};
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// Columns of a claims file; all are required, `xray`, `model_length`, `erratum`
/// and `note` may be empty.
pub const CLAIM_COLUMNS: [&str; 11] = [
    "id",
    "location",
    "refers_to",
    "finger",
    "xray",
    "quantity",
    "statistic",
    "model_length",
    "stated",
    "erratum",
    "note",
];

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
    /// 1-based column of each of [`CLAIM_COLUMNS`] in the file.
    pub columns: Vec<usize>,
}

/// Decimal places a number is printed to: `0.0319` -> 4, `31.9` -> 1,
/// `4.846e-1` -> 4 (mantissa decimals minus the exponent), never below 0.
pub fn printed_decimals(text: &str) -> usize {
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
        let mut problems = Vec::new();
        let mut scan = CsvScan::new(label, bytes)?;
        let Some(header_rec) = scan.next_record(&mut problems) else {
            let content = scan.finish().map(|(_, c)| c).unwrap_or(true);
            return Err(DataError::whole_file(
                label,
                if content {
                    format!(
                        "has no header line; start it with {}",
                        CLAIM_COLUMNS.join(",")
                    )
                } else {
                    "is empty; it needs a header line and one row per claim".to_string()
                },
            ));
        };
        let header = Header::parse(&header_rec, &CLAIM_COLUMNS, &[], &mut problems);
        let header_ok = problems.is_empty();
        let mut claims = Vec::new();
        let mut ids: HashMap<String, u64> = HashMap::new();
        let mut records = 0;
        while let Some(rec) = scan.next_record(&mut problems) {
            records += 1;
            if !header_ok {
                continue;
            }
            if rec.len() != header.names.len() {
                problems.push(super::csvinput::field_count_problem(
                    &rec,
                    header.names.len(),
                ));
                continue;
            }
            let before = problems.len();
            let line = rec.line;
            let get = |k: usize| header.positions[k].and_then(|p| rec.get(p));
            let col = |k: usize| header.positions[k].map_or(0, |p| p + 1);
            let mut bad = |k: usize, msg: String| {
                problems.push(Problem::field(line, col(k), CLAIM_COLUMNS[k], msg));
            };
            let id = get(0).unwrap_or("").to_string();
            if id.is_empty() {
                bad(0, "is empty; give every claim a unique id".into());
            } else if let Some(first) = ids.get(&id) {
                bad(
                    0,
                    format!(
                        "{} is already used on line {first}; ids must be unique",
                        quote(&id)
                    ),
                );
            } else {
                ids.insert(id.clone(), line);
            }
            let finger = get(3).and_then(|t| {
                let f = Finger::parse(t);
                if f.is_none() {
                    bad(
                        3,
                        format!(
                            "unknown finger {}; use one of {}",
                            quote(t),
                            Finger::ACCEPTED
                        ),
                    );
                }
                f
            });
            let subject = get(5).and_then(|t| {
                let s = Subject::parse(t);
                if s.is_none() {
                    bad(
                        5,
                        format!(
                            "unknown quantity {}; use j1, j2, j3, rel_j1, rel_j2, rel_j3 or total",
                            quote(t)
                        ),
                    );
                }
                s
            });
            let statistic = get(6).and_then(|t| {
                let s = Statistic::parse(t);
                if s.is_none() {
                    bad(
                        6,
                        format!(
                            "unknown statistic {}; use value, mean, min, max, range or n",
                            quote(t)
                        ),
                    );
                }
                s
            });
            let xray = get(4).filter(|t| !t.is_empty()).map(str::to_string);
            if statistic == Some(Statistic::Value) && xray.is_none() {
                bad(
                    4,
                    "is empty, but a 'value' claim is about one X-ray; name it".into(),
                );
            }
            if let (Some(f), Some(s)) = (finger, subject)
                && s.segment().is_some_and(|k| k >= f.segments())
            {
                bad(
                    5,
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
                bad(
                    6,
                    "raw lengths (j1..j3) can only be stated as 'value' claims".into(),
                );
            }
            let model_length = match get(7) {
                Some("") | None => None,
                Some(t) => match t.parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => Some(v),
                    _ => {
                        bad(
                            7,
                            format!(
                                "{} is not a positive number; give the model's total length or leave it empty",
                                quote(t)
                            ),
                        );
                        None
                    }
                },
            };
            let stated_text = get(8).unwrap_or("").to_string();
            let stated = match stated_text.parse::<f64>() {
                Ok(v) if v.is_finite() => Some(v),
                _ => {
                    bad(
                        8,
                        format!(
                            "{} is not a number; copy the number as printed in the paper",
                            quote(&stated_text)
                        ),
                    );
                    None
                }
            };
            let decimals = printed_decimals(&stated_text);
            let erratum = match get(9).unwrap_or("").to_ascii_lowercase().as_str() {
                "" | "no" => None,
                "yes" => Some(get(10).unwrap_or("").to_string()),
                other => {
                    bad(9, format!("{} must be 'yes' or empty", quote(other)));
                    None
                }
            };
            if problems.len() > before {
                continue;
            }
            if let (Some(finger), Some(subject), Some(statistic), Some(stated)) =
                (finger, subject, statistic, stated)
            {
                claims.push(Claim {
                    line,
                    id,
                    location: get(1).unwrap_or("").to_string(),
                    refers_to: get(2).unwrap_or("").to_string(),
                    finger,
                    xray,
                    subject,
                    statistic,
                    model_length,
                    stated,
                    stated_text,
                    decimals,
                    erratum,
                    note: get(10).unwrap_or("").to_string(),
                });
            }
        }
        if records == 0 && problems.is_empty() {
            problems.push(Problem::file("has a header but no claims"));
        }
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        if problems.is_empty() {
            Ok(Claims {
                path: label.to_string(),
                claims,
                columns: header
                    .positions
                    .iter()
                    .map(|p| p.map_or(0, |p| p + 1))
                    .collect(),
            })
        } else {
            Err(DataError {
                file: label.to_string(),
                problems,
            })
        }
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
                    self.columns.get(3).copied().unwrap_or(0),
                    "finger",
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
                    self.columns.get(4).copied().unwrap_or(0),
                    "xray",
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
