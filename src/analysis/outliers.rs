//! Outlier flags for new X-rays: a calibrated rule per row, and a typo rule.
//!
//! A new row of a finger with k segments (k = 3, the thumb 2) has k relative
//! values J~j = Jj / J (eq. 2) and k lengths. It is flagged when either rule fires:
//!
//! **Prediction rule (calibrated).** From the n current X-rays of the finger,
//! with mean m_j and SD s_j of J~j, the value x_j is outside
//!
//! ```text
//! m_j +/- t_{n-1, 1 - alpha/(2k)} * s_j * sqrt(1 + 1/n),   alpha = ROW_ALPHA = 0.01
//! ```
//!
//! for some j. Derivation: if the J~j of genuine X-rays are normal, a new
//! independent value satisfies (x_j - m_j) / (s_j sqrt(1 + 1/n)) ~ t_{n-1}
//! exactly, at every n >= 2, so each interval misses a genuine value with
//! probability alpha/k. By the union (Bonferroni) bound the probability that
//! any of the k misses is at most k * alpha/k = alpha = 1% per genuine row,
//! whatever the correlation of the J~j (they sum to 1 and are strongly
//! correlated, so the real rate is lower; for the thumb J~2 = 1 - J~1 and the
//! two intervals are one event, so its rate is alpha/2). The intervals are
//! therefore wider than the report's 95% prediction intervals: at n = 5 with
//! k = 3 the factor is t_{4, 0.99833} = 6.25 instead of t_{4, 0.975} = 2.78.
//! Relative values of normal lengths are only close to normal; the
//! simulation in this module's tests (and the README's table) measures the
//! rate with lengths drawn from multivariate normal models fitted to the
//! paper's index finger and thumb: it stays below 1% from n = 3 to 10,000.
//!
//! **Typo rule.** A length at least sqrt(10) = 3.16 times, or at most
//! 1/sqrt(10) times, the median of that length over the current X-rays
//! (`TYPO_RATIO`). sqrt(10) is the geometric midpoint between a genuine length
//! (ratio near 1) and a tenfold typo or misplaced decimal point (ratio near 10
//! or 0.1): any genuine length within a factor of 3.16 of the median that is
//! typed 10 times too large or too small is caught, and a genuine length is
//! flagged only if it is itself 3.16 times away from the median: in the
//! paper's data every length lies within 1.2 times its median (0.90 to 1.19;
//! segment CVs 3-9%, so 3.16 times is more than 20 SDs away; the simulation
//! counts its false alarms with the rest and asserts that it has none). The median does not move when
//! an earlier typo has entered the data (it ignores up to half the rows), while
//! that typo inflates s_j and so widens the prediction intervals: this rule
//! still catches the second typo. It also names the length to fix.
//!
//! **Typos under the prediction rule.** A tenfold error in one length moves
//! the relative values far beyond the adjusted intervals: on the paper's data
//! (n = 5) every x10 and x0.1 error in any length of any finger puts some J~j
//! at least 2.5 half-widths away from m_j (tests `every_tenfold_typo_*`),
//! so each typo is caught by both rules.
//!
//! **Degenerate data, said, never silent.** When every current X-ray has the
//! same J~j (s_j = 0, up to rounding), the interval is that single value: a new
//! value that differs by more than 1e-9 (relative) is flagged, and the message
//! says that every current X-ray has that value. With n = 1 no spread can be
//! estimated and no interval exists: only the typo rule applies, and
//! [`limits`] says so. Lengths are positive (the loader checks), so the median
//! is positive.
//!
//! **Units.** Relative values have no unit, so the prediction rule uses every current
//! X-ray whatever its unit; the typo rule compares a length only with the lengths of
//! the current X-rays in the same unit (`unit` column; rows that name none count as one
//! unit). With none in that unit it does not apply, and [`unit_limits`] says so.
//!
//! **Swapped J1 and J3.** A flagged row of a three-segment finger whose J3 is longer
//! than its J1 and that both rules would pass with the two exchanged is said to have
//! them swapped (measured from the tip), instead of a bare "likely error".
//!
//! One [`Flag`] per row: the quantities outside, each with its interval, and
//! the lengths that look like typos, in one message.
//! Cost per row: O(k); building the reference of a finger: O(n log n).

use super::{Analysis, Interval, Quantity};
use crate::dataset::{Finger, Row};
use crate::format::{num, trimmed};
use crate::stats::describe;
use serde::Serialize;
use std::sync::Arc;

/// Family-wise false-alarm rate of the prediction rule per genuine row.
pub(crate) const ROW_ALPHA: f64 = 0.01;

/// A length this many times its median, or 1/this times, looks like a typo: sqrt(10).
pub(crate) const TYPO_RATIO: f64 = 3.162_277_660_168_379_5;

/// Relative tolerance under which two relative values count as equal (zero spread).
const SAME: f64 = 1e-9;

/// The relative value J~j of segment j (0-based).
fn relative(j: usize) -> Quantity {
    [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3][j.min(2)]
}

/// What the current X-rays of one finger say a genuine new row looks like.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Reference {
    /// Current X-rays.
    pub n: usize,
    /// Level of each relative value's prediction interval: 1 - ROW_ALPHA / k.
    pub level: f64,
    /// Per segment: the mean of J~j and its interval (`None` for n < 2).
    pub relative: Vec<(f64, Option<Interval>)>,
    /// Per segment: true when every current X-ray has the same J~j.
    pub constant: Vec<bool>,
    /// Per segment: the median length (of the X-rays in the new row's unit, see
    /// [`Reference::with_medians_of`]); empty when no current X-ray is in that unit,
    /// and the typo rule then does not apply.
    pub medians: Vec<f64>,
    /// True when the medians are of the X-rays in one unit only (others left out).
    pub one_unit: bool,
}

/// One relative value outside its interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Outside {
    /// Segment, 0-based.
    pub segment: usize,
    pub value: f64,
    pub interval: Interval,
    /// True when the interval is a single value (zero spread).
    pub constant: bool,
}

/// One length that looks like a typo.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Typo {
    /// Segment, 0-based.
    pub segment: usize,
    pub value: f64,
    pub median: f64,
    /// value / median.
    pub ratio: f64,
}

/// What the rules found in one row.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Findings {
    pub outside: Vec<Outside>,
    pub typos: Vec<Typo>,
}

impl Findings {
    /// True when neither rule fired.
    pub(crate) fn is_empty(&self) -> bool {
        self.outside.is_empty() && self.typos.is_empty()
    }
}

impl Reference {
    /// The reference of the current X-rays, each given by its segment lengths
    /// (all of the same count k >= 2, every length positive). `None` for no rows.
    /// Cost: O(k n log n).
    pub(crate) fn new(rows: &[&[f64]]) -> Option<Reference> {
        let k = rows.first()?.len();
        if k < 2 || rows.iter().any(|r| r.len() != k) {
            return None;
        }
        let n = rows.len();
        let level = 1.0 - ROW_ALPHA / k as f64;
        let mut relative = Vec::with_capacity(k);
        let mut constant = Vec::with_capacity(k);
        let mut medians = Vec::with_capacity(k);
        for j in 0..k {
            let rel: Vec<f64> = rows.iter().map(|r| r[j] / r.iter().sum::<f64>()).collect();
            let mean = describe::mean(&rel)?;
            let (lo, hi) = describe::min_max(&rel)?;
            let same = n >= 2 && hi - lo <= SAME * mean.abs();
            let interval = if same {
                Some(Interval::point(mean))
            } else {
                describe::sd(&rel).and_then(|s| describe::prediction_interval(mean, s, n, level))
            };
            relative.push((mean, interval));
            constant.push(same);
            let lengths: Vec<f64> = rows.iter().map(|r| r[j]).collect();
            medians.push(describe::median(&lengths)?);
        }
        Some(Reference {
            n,
            level,
            relative,
            constant,
            medians,
            one_unit: false,
        })
    }

    /// The same reference with the typo rule's medians taken from `rows` only (the
    /// current X-rays in the new row's unit); none leaves the typo rule out. O(k n log n).
    pub(crate) fn with_medians_of(mut self, rows: &[&[f64]]) -> Reference {
        let k = self.relative.len();
        self.one_unit = rows.len() < self.n;
        self.medians = if rows.is_empty() || rows.iter().any(|r| r.len() != k) {
            Vec::new()
        } else {
            (0..k)
                .filter_map(|j| {
                    let lengths: Vec<f64> = rows.iter().map(|r| r[j]).collect();
                    describe::median(&lengths)
                })
                .collect()
        };
        self
    }

    /// Applies both rules to a new row's segment lengths (k of them). O(k).
    pub(crate) fn check(&self, lengths: &[f64]) -> Findings {
        let total: f64 = lengths.iter().sum();
        let mut found = Findings::default();
        for (j, &len) in lengths.iter().enumerate().take(self.relative.len()) {
            let x = len / total;
            if let Some((mean, Some(pi))) = self.relative.get(j).copied() {
                let inside = if self.constant[j] {
                    (x - mean).abs() <= SAME * mean.abs()
                } else {
                    pi.contains(x)
                };
                if !inside {
                    found.outside.push(Outside {
                        segment: j,
                        value: x,
                        interval: pi,
                        constant: self.constant[j],
                    });
                }
            }
            let Some(&median) = self.medians.get(j) else {
                continue;
            };
            let ratio = len / median;
            if !(ratio < TYPO_RATIO && ratio > 1.0 / TYPO_RATIO) {
                found.typos.push(Typo {
                    segment: j,
                    value: len,
                    median,
                    ratio,
                });
            }
        }
        found
    }
}

/// A relative value outside its interval, as reported.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct OutsideValue {
    /// `rel_j1`, ...
    pub quantity: String,
    pub value: f64,
    /// The interval the value is outside of (a single value for zero spread).
    pub interval: [f64; 2],
}

/// A length that looks like a typo, as reported.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct TypoLength {
    /// `j1`, `j2` or `j3`.
    pub length: String,
    pub value: f64,
    /// The median of this length over the current X-rays.
    pub median: f64,
    /// value / median.
    pub ratio: f64,
}

/// A new row that the current data says is likely wrong: one per row.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct Flag {
    pub xray: String,
    pub finger: String,
    /// Current X-rays of the finger.
    pub n: usize,
    /// Level of each prediction interval (1 - 0.01/k).
    pub level: f64,
    pub outside: Vec<OutsideValue>,
    pub typos: Vec<TypoLength>,
    /// True when the row fits with J1 and J3 exchanged (measured from the tip).
    pub swapped: bool,
    /// What the rules found, with the likely fix (the reason without the row's name).
    pub finding: String,
    /// Everything above in one sentence: the row, what was found, the likely fix.
    pub reason: String,
}

/// The reference of one finger of an analysis: relative values from all its X-rays,
/// the typo rule's medians from all of them too. `None` when the data lacks the finger.
pub(crate) fn reference(a: &Analysis, finger: Finger) -> Option<Reference> {
    let fa = a.finger(finger)?;
    let rows: Vec<&[f64]> = fa.xrays.iter().map(|x| x.lengths.as_slice()).collect();
    Reference::new(&rows)
}

/// The reference of one finger for new rows in `unit`: relative values from all its
/// X-rays, the typo rule's medians from those in `unit` only (none: no typo rule). A row
/// that names no unit is compared with every X-ray (`add` gives such rows the dataset's
/// unit first, and refuses them when the dataset names several).
fn reference_in(a: &Analysis, finger: Finger, unit: Option<&str>) -> Option<Reference> {
    if unit.is_none() {
        return reference(a, finger);
    }
    let fa = a.finger(finger)?;
    let same: Vec<&[f64]> = fa
        .xrays
        .iter()
        .filter(|x| x.unit.as_deref() == unit)
        .map(|x| x.lengths.as_slice())
        .collect();
    Some(reference(a, finger)?.with_medians_of(&same))
}

/// Flags every new row that either rule finds unusual, one [`Flag`] per row,
/// in the order of `rows`. Rows of a finger the data lacks are not flagged
/// (see [`limits`]); the typo rule compares lengths within one unit ([`unit_limits`]).
/// Cost: O(n log n) per finger and unit plus O(k) per row.
pub(crate) fn flag_rows(a: &Analysis, rows: &[Row]) -> Vec<Flag> {
    let mut references: Vec<(Finger, Option<Arc<str>>, Option<Reference>)> = Vec::new();
    rows.iter()
        .filter_map(|row| {
            let unit = row.meta.unit.clone();
            let i = match references
                .iter()
                .position(|(f, u, _)| *f == row.finger && *u == unit)
            {
                Some(i) => i,
                None => {
                    let r = reference_in(a, row.finger, unit.as_deref());
                    references.push((row.finger, unit, r));
                    references.len() - 1
                }
            };
            let r = references[i].2.as_ref()?;
            let found = r.check(row.segments());
            (!found.is_empty()).then(|| flag(row, r, &found))
        })
        .collect()
}

/// Why the typo rule cannot check some new rows, if it cannot: no current X-ray of their
/// finger gives lengths in their unit (their relative values are still checked). One
/// note per unit, naming the fingers, in order of first appearance.
pub(crate) fn unit_limits(a: &Analysis, rows: &[Row]) -> Vec<String> {
    let mut by_unit: Vec<(Option<&str>, Vec<Finger>)> = Vec::new();
    for r in rows {
        let unit = r.meta.unit.as_deref();
        let Some(fa) = a.finger(r.finger).filter(|_| unit.is_some()) else {
            continue;
        };
        if fa.xrays.iter().any(|x| x.unit.as_deref() == unit) {
            continue;
        }
        match by_unit.iter_mut().find(|(u, _)| *u == unit) {
            Some((_, fs)) if !fs.contains(&r.finger) => fs.push(r.finger),
            Some(_) => {}
            None => by_unit.push((unit, vec![r.finger])),
        }
    }
    by_unit
        .into_iter()
        .map(|(unit, fingers)| {
            let named = format!("'{}'", unit.unwrap_or_default());
            let names: Vec<&str> = fingers.iter().map(|f| f.name()).collect();
            let names = match names.split_last() {
                Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
                _ => names.join(""),
            };
            format!(
                "no current X-ray gives {names} lengths in {named}, so the new rows in {named} are checked on their relative values only (the tenfold-typo rule compares lengths of one unit)"
            )
        })
        .collect()
}

/// Why rows of a finger cannot be checked fully, if they cannot: fewer than 2
/// current X-rays give no prediction interval (only the typo rule applies),
/// none give no check at all.
pub(crate) fn limits(a: &Analysis, finger: Finger) -> Option<String> {
    let n = a.finger(finger).map_or(0, |f| f.n);
    match n {
        0 => Some(format!(
            "the dataset has no {finger} rows yet: new {finger} rows cannot be checked for errors"
        )),
        1 => Some(format!(
            "the dataset has 1 {finger} X-ray: no prediction interval exists yet, so new {finger} rows are only checked for tenfold typos (against the lengths of that X-ray)"
        )),
        _ => None,
    }
}

/// The flag of one row, with its message.
fn flag(row: &Row, r: &Reference, found: &Findings) -> Flag {
    let mut parts = outside_parts(r, &found.outside);
    parts.extend(found.typos.iter().map(|t| typo_part(t, r.one_unit)));
    let segs = row.segments();
    let swapped =
        segs.len() == 3 && segs[2] > segs[0] && r.check(&[segs[2], segs[1], segs[0]]).is_empty();
    let finding = format!(
        "{}{}",
        parts.join("; "),
        if swapped {
            format!(
                ": j1 and j3 look swapped (J3 = {} is longer than J1 = {}, but the proximal phalanx is the longest; measured from the tip?), and exchanged they fit",
                segs[2], segs[0]
            )
        } else {
            hint(&found.typos)
        }
    );
    Flag {
        xray: row.xray.to_string(),
        finger: row.finger.name().to_string(),
        n: r.n,
        level: r.level,
        outside: found
            .outside
            .iter()
            .map(|o| OutsideValue {
                quantity: relative(o.segment).name().to_string(),
                value: o.value,
                interval: [o.interval.low, o.interval.high],
            })
            .collect(),
        typos: found
            .typos
            .iter()
            .map(|t| TypoLength {
                length: format!("j{}", t.segment + 1),
                value: t.value,
                median: t.median,
                ratio: t.ratio,
            })
            .collect(),
        swapped,
        reason: format!("{} X-ray '{}': {finding}", row.finger, row.xray),
        finding,
    }
}

/// Decimals of a relative value in a flag's message.
const VALUE_DECIMALS: usize = 4;

/// The message parts for the relative values outside their intervals: the
/// varying ones together with the level that bounds the false alarms, then one
/// part per value that differs from a constant (zero-spread) quantity.
fn outside_parts(r: &Reference, outside: &[Outside]) -> Vec<String> {
    let d = VALUE_DECIMALS;
    let (constant, varying): (Vec<&Outside>, Vec<&Outside>) =
        outside.iter().partition(|o| o.constant);
    let mut parts = Vec::new();
    if !varying.is_empty() {
        let list: Vec<String> = varying
            .iter()
            .map(|o| {
                format!(
                    "{} = {} is outside [{}, {}]",
                    relative(o.segment).symbol(),
                    num(o.value, d),
                    num(o.interval.low, d),
                    num(o.interval.high, d)
                )
            })
            .collect();
        parts.push(format!(
            "{} ({}% prediction interval{} of the current {} X-rays, so that a genuine row is flagged at most {}% of the time)",
            list.join(", "),
            percent(r.level),
            if varying.len() == 1 { "" } else { "s" },
            r.n,
            percent(ROW_ALPHA)
        ));
    }
    parts.extend(constant.into_iter().map(|o| {
        format!(
            "{} = {} differs from {}, the value of every current X-ray (zero spread: any other value is flagged)",
            relative(o.segment).symbol(),
            num(o.value, d),
            num(o.interval.low, d)
        )
    }));
    parts
}

/// The message part of one length that looks mistyped; `one_unit` when the median is of
/// the current X-rays in the row's unit only.
fn typo_part(t: &Typo, one_unit: bool) -> String {
    format!(
        "j{} = {} is {} times the median j{} of the current X-rays{} ({})",
        t.segment + 1,
        t.value,
        ratio_text(t.ratio),
        t.segment + 1,
        if one_unit { " in its unit" } else { "" },
        t.median
    )
}

/// The likely fix that ends a flag's message.
fn hint(typos: &[Typo]) -> String {
    match typos {
        [t] => {
            let power = t.ratio.log10().abs().round().max(1.0) as i32;
            format!(
                ": j{} looks {} times too {} (a misplaced decimal point?)",
                t.segment + 1,
                10u64.pow(power.unsigned_abs().min(18)),
                if t.ratio > 1.0 { "large" } else { "small" }
            )
        }
        [] => ": a likely measurement or typing error".to_string(),
        _ => ": several lengths look mistyped (a misplaced decimal point, or another unit?)"
            .to_string(),
    }
}

/// A level as a percentage with at most 2 decimals and no trailing zeros:
/// 0.996667 -> "99.67", 0.01 -> "1".
fn percent(p: f64) -> String {
    trimmed(p * 100.0, 2)
}

/// A ratio for people: "10.0" or "0.10".
fn ratio_text(r: f64) -> String {
    num(r, if r >= 1.0 { 1 } else { 2 })
}

#[cfg(test)]
mod tests;
