//! A cohort against a published summary table: ratios of the table's means, their
//! delta-method standard errors under a stated correlation, and where the fingertips are.
//!
//! A table ([`SummaryTable`]) gives each segment's mean, SD and n, not per-hand values. Each
//! quantity of a finger is then a ratio of sums of its means (J~3 = distal / (proximal +
//! middle + distal), J2/J1 = middle / proximal, mc/J, ...), whose standard error follows from
//! the delta method ([`crate::stats::delta`]) once a correlation between segments is assumed:
//! the table does not give one. [`Correlation`] states the one used, by default the mean
//! correlation of the segment lengths of each finger in a dataset with per-hand values
//! ([`correlations_from`]), and every verdict is also given at correlations 0 and 0.9
//! ([`SWEEP`]), so a reader sees whether it rests on the assumption.
//!
//! A table with `tip_soft_tissue` can give the last segment two ways: to the end of the
//! bone, or to the skin (the soft tissue added to the distal phalanx and to the finger).
//! [`tables`] compares a dataset's last segment with both ([`TipFinding`]) and says which
//! one the data rejects.
//!
//! The difference of two estimates has a Welch-type interval: SE = sqrt(SE_A^2 + SE_B^2),
//! Welch-Satterthwaite degrees of freedom from each side's n - 1 (a table's n is its
//! smallest n among the segments used). An interval that excludes 0 rejects equal means;
//! one that holds 0 does not reject them, which is not a finding that they are equal (at
//! n = 5 the interval is wide). Cost: O(rows) for the data, O(segments^2) per quantity of
//! the table.

use super::{Interval, Quantity, blocks};
use crate::dataset::{Dataset, Finger, Segment, SummaryTable, TipKind, is_pixel_unit};
use crate::stats::delta::{self, Part};
use crate::stats::describe;
use schemars::JsonSchema;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// The correlations every verdict is also given at, beside the assumed one.
pub const SWEEP: [f64; 2] = [0.0, 0.9];

/// A cohort as the comparison with a table reads it.
#[derive(Debug, Clone, Copy)]
pub enum Side<'a> {
    Data(&'a Dataset),
    Table(&'a SummaryTable),
}

/// The correlation assumed between any two segments of a finger of a table.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Correlation {
    /// Per finger: the value assumed, and how many hands it was measured on.
    pub fingers: Vec<FingerCorrelation>,
    /// The dataset it was measured on; `None` when the user gave the value.
    pub from: Option<String>,
}

/// The correlation assumed for one finger.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct FingerCorrelation {
    pub finger: Finger,
    pub rho: f64,
    /// Hands of the dataset it was measured on; `None` when given.
    pub hands: Option<usize>,
}

impl Correlation {
    /// One value for every finger, as given by the user.
    pub fn given(rho: f64) -> Correlation {
        Correlation {
            fingers: Finger::ALL
                .into_iter()
                .map(|finger| FingerCorrelation {
                    finger,
                    rho,
                    hands: None,
                })
                .collect(),
            from: None,
        }
    }

    /// The value assumed for `finger`: measured, given, or 0 when the dataset lacks the finger.
    pub fn of(&self, finger: Finger) -> f64 {
        self.fingers
            .iter()
            .find(|c| c.finger == finger)
            .map_or(0.0, |c| c.rho)
    }

    /// The correlations of a finger's verdicts: 0, the assumed one and 0.9, ascending, once each.
    pub fn sweep(&self, finger: Finger) -> Vec<f64> {
        let mut v = vec![SWEEP[0], self.of(finger), SWEEP[1]];
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        v
    }
}

/// Per finger, the mean of Pearson's correlations between every two of its segment lengths
/// (J1, J2, J3 and, where measured, the metacarpal) over the X-rays of `data`: the value a
/// table's segments are assumed to share. Lengths of one X-ray are in one scale, so a
/// per-image pixel unit is no obstacle; differences of scale between images (age, pixel
/// spacing) do raise these correlations. O(rows).
pub fn correlations_from(data: &Dataset) -> Correlation {
    let mut fingers = Vec::new();
    for f in Finger::ALL {
        let rows: Vec<_> = data.rows_of(f).collect();
        let k = f.segments();
        let mut columns: Vec<Vec<f64>> = (0..k)
            .map(|s| rows.iter().map(|r| r.lengths[s]).collect())
            .collect();
        // The metacarpal joins when every row of the finger measures it.
        if !rows.is_empty() && rows.iter().all(|r| r.mc.is_some()) {
            columns.push(rows.iter().filter_map(|r| r.mc).collect());
        }
        let mut rs = Vec::new();
        for i in 0..columns.len() {
            for j in i + 1..columns.len() {
                if let Some(r) = delta::pearson(&columns[i], &columns[j]) {
                    rs.push(r);
                }
            }
        }
        if let Some(rho) = describe::mean(&rs) {
            fingers.push(FingerCorrelation {
                finger: f,
                rho,
                hands: Some(rows.len()),
            });
        }
    }
    Correlation {
        fingers,
        from: Some(data.path.clone()),
    }
}

/// One cohort's estimate of one quantity.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Estimate {
    /// The mean over X-rays (a dataset), or the ratio of the table's means.
    pub mean: f64,
    /// Standard error: SD / sqrt(n), or the delta method's.
    pub se: Option<f64>,
    /// Degrees of freedom of the t quantile: n - 1.
    pub df: Option<f64>,
    /// X-rays or hands.
    pub n: Option<usize>,
    /// SD of one hand's value (for a table, to first order under the correlation).
    pub sd: Option<f64>,
    /// The t interval of the mean.
    pub ci: Option<Interval>,
    /// The prediction interval for one new hand.
    pub pi: Option<Interval>,
    /// Why there is no interval, when there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

impl Estimate {
    /// The estimate from one value per X-ray.
    pub fn of_values(xs: &[f64], confidence: f64) -> Option<Estimate> {
        let mean = describe::mean(xs)?;
        let n = xs.len();
        let sd = describe::sd(xs);
        let se = sd.map(|s| s / (n as f64).sqrt());
        Some(Estimate {
            mean,
            se,
            df: (n > 1).then(|| (n - 1) as f64),
            n: Some(n),
            sd,
            ci: sd.and_then(|s| describe::t_interval(mean, s, n, confidence)),
            pi: sd.and_then(|s| describe::prediction_interval(mean, s, n, confidence)),
            why: (n < 2).then(|| "one X-ray: no spread, so no interval".to_string()),
        })
    }
}

/// The segments of quantity `q` of `finger`, with the fingertip at `tip`, as parts of a
/// ratio of sums of the table's means (at correlation `rho`, for the SE). Err says what
/// the table lacks.
fn table_parts(
    table: &SummaryTable,
    finger: Finger,
    q: Quantity,
    tip: TipKind,
) -> Result<Vec<(Segment, Part)>, String> {
    let ph = Segment::phalanges(finger);
    let last = *ph.last().unwrap_or(&Segment::Distal);
    let skin = tip == TipKind::Skin;
    // Which segments form the numerator and the denominator.
    let mut total: Vec<Segment> = ph.to_vec();
    if skin {
        total.push(Segment::TipSoftTissue);
    }
    let last_part: Vec<Segment> = if skin {
        vec![last, Segment::TipSoftTissue]
    } else {
        vec![last]
    };
    let (num, den): (Vec<Segment>, Vec<Segment>) = match q {
        Quantity::RelJ1 => (vec![ph[0]], total.clone()),
        Quantity::RelJ2 if finger == Finger::Thumb => (last_part.clone(), total.clone()),
        Quantity::RelJ2 => (vec![ph[1]], total.clone()),
        Quantity::RelJ3 if finger == Finger::Thumb => {
            return Err("the thumb has no J3".into());
        }
        Quantity::RelJ3 => (last_part.clone(), total.clone()),
        Quantity::RatioJ2J1 if finger == Finger::Thumb => (last_part.clone(), vec![ph[0]]),
        Quantity::RatioJ2J1 => (vec![ph[1]], vec![ph[0]]),
        Quantity::RatioJ3J2 if finger == Finger::Thumb => {
            return Err("the thumb has no J3".into());
        }
        Quantity::RatioJ3J2 => (last_part.clone(), vec![ph[1]]),
        Quantity::Total => (total.clone(), vec![]),
        Quantity::RatioMcJ => (vec![Segment::Metacarpal], total.clone()),
        Quantity::RatioJ1Mc => (vec![ph[0]], vec![Segment::Metacarpal]),
    };
    let mut used: Vec<Segment> = num.iter().chain(&den).copied().collect();
    used.sort();
    used.dedup();
    used.into_iter()
        .map(|s| {
            let row = table
                .get(finger, s)
                .ok_or_else(|| format!("the table gives no {} {}", finger.name(), s.name()))?;
            Ok((
                s,
                Part {
                    mean: row.mean,
                    sd: row.sd,
                    n: row.n.map(|n| n as f64),
                    num: f64::from(u8::from(num.contains(&s))),
                    den: f64::from(u8::from(den.contains(&s))),
                },
            ))
        })
        .collect()
}

/// The table's ratio of means for quantity `q` of `finger`, with the fingertip at `tip`,
/// its delta-method SE and per-hand SD under correlation `rho`, and the t interval of the
/// ratio of means and the prediction interval for one hand (df = n - 1 with n the smallest
/// n of the segments used). Err says what the table lacks.
pub fn table_estimate(
    table: &SummaryTable,
    finger: Finger,
    q: Quantity,
    tip: TipKind,
    rho: f64,
    confidence: f64,
) -> Result<Estimate, String> {
    let parts = table_parts(table, finger, q, tip)?;
    let plain: Vec<Part> = parts.iter().map(|(_, p)| *p).collect();
    let r = delta::ratio_of_sums(&plain, rho).ok_or_else(|| {
        format!(
            "the table's {} {} cannot be formed",
            finger.name(),
            q.symbol()
        )
    })?;
    let n = parts
        .iter()
        .map(|(_, p)| p.n)
        .collect::<Option<Vec<f64>>>()
        .and_then(|ns| ns.into_iter().reduce(f64::min))
        .map(|n| n as usize);
    let missing: Vec<&str> = parts
        .iter()
        .filter(|(_, p)| p.sd.is_none() || p.n.is_none())
        .map(|(s, _)| s.name())
        .collect();
    let df = n.filter(|&n| n > 1).map(|n| (n - 1) as f64);
    let t = df.and_then(|df| t_quantile(confidence, df));
    let ci = match (r.se, t) {
        (Some(se), Some(t)) => Some(Interval::new(r.value - t * se, r.value + t * se)),
        _ => None,
    };
    let pi = match (r.sd, t, n) {
        (Some(sd), Some(t), Some(n)) => {
            let h = t * sd * (1.0 + 1.0 / n as f64).sqrt();
            Some(Interval::new(r.value - h, r.value + h))
        }
        _ => None,
    };
    let why = if !missing.is_empty() {
        Some(format!(
            "the table gives no SD or no n for the {} {}, so no interval",
            finger.name(),
            missing.join(", ")
        ))
    } else if df.is_none() {
        Some("the table's n is 1, so no interval".to_string())
    } else {
        None
    };
    Ok(Estimate {
        mean: r.value,
        se: r.se,
        df,
        n,
        sd: r.sd,
        ci,
        pi,
        why,
    })
}

/// The t quantile at (possibly fractional) df, as Welch's interval uses it.
fn t_quantile(confidence: f64, df: f64) -> Option<f64> {
    let p = 1.0 - (1.0 - confidence) / 2.0;
    if df > 1_000.0 {
        return describe::t_quantile(confidence, df.floor() as usize);
    }
    let t = StudentsT::new(0.0, 1.0, df).ok()?.inverse_cdf(p);
    t.is_finite().then_some(t)
}

/// The difference B - A of two estimates at one correlation, with its interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Difference {
    /// The correlation assumed for the table's side(s).
    pub rho: f64,
    /// mean_B - mean_A.
    pub difference: f64,
    /// sqrt(SE_A^2 + SE_B^2).
    pub se: Option<f64>,
    /// Welch-Satterthwaite degrees of freedom.
    pub df: Option<f64>,
    pub interval: Option<Interval>,
    /// The interval holds 0: equal means are not rejected (false: the interval excludes 0,
    /// the two differ). Not rejected is not shown equal. `None`: no interval.
    pub not_rejected: Option<bool>,
}

/// B - A with a Welch-type interval: SE = sqrt(SE_A^2 + SE_B^2),
/// df = (v_A + v_B)^2 / (v_A^2 / df_A + v_B^2 / df_B), interval difference -/+ t SE.
pub fn difference(a: &Estimate, b: &Estimate, rho: f64, confidence: f64) -> Difference {
    let d = b.mean - a.mean;
    let parts = match (a.se, a.df, b.se, b.df) {
        (Some(sa), Some(da), Some(sb), Some(db)) => Some((sa * sa, da, sb * sb, db)),
        _ => None,
    };
    let (se, df, interval) = match parts {
        Some((va, da, vb, db)) if va + vb > 0.0 => {
            let se = (va + vb).sqrt();
            let df = (va + vb).powi(2) / (va * va / da + vb * vb / db);
            let iv = t_quantile(confidence, df).map(|t| Interval::new(d - t * se, d + t * se));
            (Some(se), Some(df), iv)
        }
        _ => (None, None, None),
    };
    Difference {
        rho,
        difference: d,
        se,
        df,
        interval,
        not_rejected: interval.map(|i| i.contains(0.0)),
    }
}

/// One quantity of one finger: both estimates at the assumed correlation, the difference,
/// and the difference at every correlation of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TableQuantity {
    pub quantity: Quantity,
    pub a: Estimate,
    pub b: Estimate,
    /// B - A at the assumed correlation.
    pub difference: Difference,
    /// B - A at 0, the assumed correlation and 0.9.
    pub sweep: Vec<Difference>,
}

impl TableQuantity {
    /// True when the verdict (differs or not rejected) is the same at every correlation of
    /// the sweep.
    pub fn verdict_holds(&self) -> bool {
        self.sweep
            .iter()
            .all(|d| d.not_rejected == self.difference.not_rejected)
    }
}

/// Which of the table's last segments, to the bone and to the skin, the data does not
/// reject (the interval of the difference holds 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Fit {
    /// The last segment to the bone is rejected, to the skin not rejected.
    Skin,
    /// The last segment to the skin is rejected, to the bone not rejected.
    Bone,
    /// Neither is rejected: the data cannot tell.
    Both,
    /// Both are rejected.
    Neither,
}

impl Fit {
    /// From whether the bone and the skin are not rejected.
    fn of(bone: Option<bool>, skin: Option<bool>) -> Option<Fit> {
        Some(match (bone?, skin?) {
            (false, true) => Fit::Skin,
            (true, false) => Fit::Bone,
            (true, true) => Fit::Both,
            (false, false) => Fit::Neither,
        })
    }

    /// The tip the fit points to (the one not rejected while the other is), when it points
    /// to one.
    pub fn tip(self) -> Option<TipKind> {
        match self {
            Fit::Skin => Some(TipKind::Skin),
            Fit::Bone => Some(TipKind::Bone),
            _ => None,
        }
    }
}

/// A dataset's last segment (J~3, the thumb's J~2) against the table's to the bone and to the
/// skin.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TipFinding {
    pub finger: Finger,
    pub quantity: Quantity,
    /// The dataset's mean and t interval.
    pub data: Estimate,
    /// The table's ratio of means to the end of the bone.
    pub bone: Estimate,
    /// The table's ratio of means to the skin (soft tissue included).
    pub skin: Estimate,
    /// The table's soft tissue as a share of its finger to the skin: s / (J + s).
    pub soft_share: f64,
    /// Table - data at the assumed correlation, bone and skin.
    pub bone_difference: Difference,
    pub skin_difference: Difference,
    /// Which tip the data does not reject at the assumed correlation.
    pub fit: Option<Fit>,
    /// The fit at each correlation of the sweep (0, assumed, 0.9).
    pub sweep: Vec<(f64, Option<Fit>)>,
}

/// Every finger's tip finding, and what they say together.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TipVerdict {
    /// `a` or `b`: the side with per-hand values.
    pub data: &'static str,
    pub fingers: Vec<TipFinding>,
    /// The fit of every finger, when all agree at every correlation of the sweep.
    pub overall: Option<Fit>,
    /// The tips the data's rows record (one kind for all rows), if any.
    pub recorded: Option<TipKind>,
}

impl TipVerdict {
    /// True when every finger points to the same tip at every correlation, and the rows
    /// record that tip. Consistent with the record, not a confirmation of it: the record
    /// may rest on this very comparison (the paper's does).
    pub fn matches_record(&self) -> bool {
        matches!((self.overall.and_then(Fit::tip), self.recorded), (Some(f), Some(r)) if f == r)
    }

    /// The finding whose interval of the difference to the tip not rejected comes nearest
    /// to excluding 0 (the smallest distance from 0 to an end of the interval, at the
    /// assumed correlation): the weakest "not rejected". `None` without such a tip.
    pub fn nearest_to_rejection(&self) -> Option<(&TipFinding, Interval)> {
        let tip = self.overall.and_then(Fit::tip)?;
        self.fingers
            .iter()
            .filter_map(|t| {
                let d = match tip {
                    TipKind::Skin => &t.skin_difference,
                    TipKind::Bone => &t.bone_difference,
                };
                d.interval.map(|i| (t, i))
            })
            .min_by(|(_, x), (_, y)| {
                let gap = |i: &Interval| i.low.abs().min(i.high.abs());
                gap(x).total_cmp(&gap(y))
            })
    }
}

/// What [`tables`] says about one side.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct SideInfo {
    pub path: String,
    pub sha256: String,
    /// `data` (per-hand values) or `table` (a published summary table).
    pub kind: &'static str,
    /// X-rays (data) or the table's largest n (hands).
    pub n: Option<usize>,
    pub unit: Option<String>,
    /// Where the data's rows record their tips (data only).
    pub tips: Option<crate::dataset::TipCounts>,
    /// The sides and the age range the data's rows record (data only).
    pub sides: Vec<String>,
    pub ages: Option<(f64, f64)>,
    /// Where the table's last segments end in the comparison (table only).
    pub table_tip: Option<TipKind>,
    /// The cohort's description beside its file, set by the caller.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub about: Option<crate::dataset::CohortNotes>,
}

/// One finger of the comparison.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TableFinger {
    pub finger: Finger,
    /// The correlation assumed for the table's segments of this finger.
    pub rho: f64,
    pub quantities: Vec<TableQuantity>,
}

/// Two cohorts compared where at least one is a summary table: what [`tables`] returns.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct TableCohorts {
    pub a: SideInfo,
    pub b: SideInfo,
    pub confidence: f64,
    pub correlation: Correlation,
    pub fingers: Vec<TableFinger>,
    /// The fingertip finding, when one side is data and the other a table with soft tissue.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tips: Option<TipVerdict>,
    /// The quantities compared that no interval can test, and where one side's point values
    /// of them fall against the other side's t intervals ([`Untestable::of`]).
    pub untestable: Untestable,
    /// What was not compared and why.
    pub notes: Vec<String>,
}

/// The quantities of a comparison whose difference has no interval (a side gives no SD or
/// no n for a segment they need), and of those, how many point values of the side without
/// an interval lie outside the other side's t interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub struct Untestable {
    /// Quantities compared whose difference has no interval.
    pub quantities: usize,
    /// `a` or `b`: the side whose t intervals the other's point values are held against,
    /// when one side has intervals where the other has none.
    pub intervals_of: Option<&'static str>,
    /// Of the untestable quantities, those with that side's interval ...
    pub checked: usize,
    /// ... and how many of them put the other side's point value outside it.
    pub outside: usize,
}

impl Untestable {
    /// Counts over `fingers`: a quantity is untestable when its difference has no
    /// interval; its point value (the side without an interval) is checked against the
    /// t interval of the side with one. O(quantities).
    pub fn of(fingers: &[TableFinger]) -> Untestable {
        let mut u = Untestable {
            quantities: 0,
            intervals_of: None,
            checked: 0,
            outside: 0,
        };
        for q in fingers.iter().flat_map(|f| &f.quantities) {
            if q.difference.interval.is_some() {
                continue;
            }
            u.quantities += 1;
            let (side, ci, value) = match (q.a.ci, q.b.ci) {
                (Some(ci), None) => ("a", ci, q.b.mean),
                (None, Some(ci)) => ("b", ci, q.a.mean),
                _ => continue,
            };
            // One side is named; a table whose rows are partly without SD could switch
            // sides only if both were tables, and then neither has a t interval.
            u.intervals_of.get_or_insert(side);
            u.checked += 1;
            if !ci.contains(value) {
                u.outside += 1;
            }
        }
        u
    }
}

/// A finger and, per quantity, its value on each X-ray.
type FingerValues = (Finger, Vec<(Quantity, Vec<f64>)>);

/// Each finger's values of quantity q on a dataset (from its main block).
fn data_values(data: &Dataset) -> Vec<FingerValues> {
    let mut out: Vec<FingerValues> = Vec::new();
    for b in blocks(data) {
        let values: Vec<(Quantity, Vec<f64>)> = b
            .quantities
            .iter()
            .map(|&q| (q, b.xrays.iter().filter_map(|x| x.value(q)).collect()))
            .collect();
        match out.iter_mut().find(|(f, _)| *f == b.finger) {
            Some((_, v)) => v.extend(values.into_iter().filter(|(q, _)| q.needs_mc())),
            None => out.push((b.finger, values)),
        }
    }
    out
}

/// Where a table's last segments end when compared with `other`: at the skin when the
/// other side is data whose rows all record skin tips and the table gives the soft tissue
/// of every finger; at the bone otherwise.
fn table_tip(table: &SummaryTable, other: &Side<'_>) -> TipKind {
    let soft = table
        .fingers()
        .iter()
        .all(|&f| table.get(f, Segment::TipSoftTissue).is_some());
    match other {
        Side::Data(d) if soft && d.tips().single() == Some(TipKind::Skin) => TipKind::Skin,
        _ => TipKind::Bone,
    }
}

fn side_info(side: &Side<'_>, tip: Option<TipKind>) -> SideInfo {
    match side {
        Side::Data(d) => {
            let info = super::compare::CohortInfo::of(d);
            SideInfo {
                path: info.path,
                sha256: info.sha256,
                kind: "data",
                n: Some(info.xrays),
                unit: info.unit,
                tips: Some(info.tips),
                sides: info.sides,
                ages: info.ages,
                table_tip: None,
                about: None,
            }
        }
        Side::Table(t) => SideInfo {
            path: t.path.clone(),
            sha256: t.sha256.clone(),
            kind: "table",
            n: t.n().map(|n| n as usize),
            unit: Some(t.unit.clone()),
            tips: None,
            sides: Vec::new(),
            ages: None,
            table_tip: tip,
            about: None,
        },
    }
}

/// The quantities and estimates one side gives for a finger, at correlation `rho`.
fn estimates(
    side: &Side<'_>,
    values: &[FingerValues],
    finger: Finger,
    tip: TipKind,
    rho: f64,
    confidence: f64,
) -> Vec<(Quantity, Result<Estimate, String>)> {
    match side {
        Side::Data(_) => values
            .iter()
            .find(|(f, _)| *f == finger)
            .map(|(_, qs)| {
                qs.iter()
                    .map(|(q, xs)| {
                        let e = Estimate::of_values(xs, confidence)
                            .ok_or_else(|| "no values".to_string());
                        (*q, e)
                    })
                    .collect()
            })
            .unwrap_or_default(),
        Side::Table(t) => Quantity::ALL
            .into_iter()
            .filter(|q| Quantity::of(finger).contains(q) || q.needs_mc())
            .map(|q| (q, table_estimate(t, finger, q, tip, rho, confidence)))
            .filter(|(_, e)| e.is_ok() || finger != Finger::Thumb)
            .collect(),
    }
}

/// Compares cohorts A and B, at least one a summary table: for every finger and quantity
/// both give, the two estimates and B - A at the assumed correlation and at [`SWEEP`]; and,
/// when one side is data and the other a table with the fingertip's soft tissue, where the
/// data's fingertips are ([`TipFinding`]). Total lengths are compared only in one unit that
/// is not per-image pixels.
pub fn tables(
    a: Side<'_>,
    b: Side<'_>,
    correlation: &Correlation,
    confidence: f64,
) -> TableCohorts {
    let tip_a = match a {
        Side::Table(t) => table_tip(t, &b),
        Side::Data(_) => TipKind::Bone,
    };
    let tip_b = match b {
        Side::Table(t) => table_tip(t, &a),
        Side::Data(_) => TipKind::Bone,
    };
    let info_a = side_info(&a, matches!(a, Side::Table(_)).then_some(tip_a));
    let info_b = side_info(&b, matches!(b, Side::Table(_)).then_some(tip_b));
    let same_unit = match (&info_a.unit, &info_b.unit) {
        (Some(x), Some(y)) => x == y && !is_pixel_unit(x),
        _ => false,
    };
    let mut notes = Vec::new();
    if !same_unit {
        notes.push(format!(
            "J (total length): the cohorts' units differ or are not named (A {}, B {}), so lengths are not compared; relative values and ratios are unitless",
            info_a.unit.as_deref().map_or("no unit".into(), |u| format!("'{u}'")),
            info_b.unit.as_deref().map_or("no unit".into(), |u| format!("'{u}'")),
        ));
    }
    let va = match a {
        Side::Data(d) => data_values(d),
        Side::Table(_) => Vec::new(),
    };
    let vb = match b {
        Side::Data(d) => data_values(d),
        Side::Table(_) => Vec::new(),
    };
    let mut fingers = Vec::new();
    let mut lacking: Vec<String> = Vec::new();
    for f in Finger::ALL {
        let rho = correlation.of(f);
        let ea = estimates(&a, &va, f, tip_a, rho, confidence);
        let eb = estimates(&b, &vb, f, tip_b, rho, confidence);
        if ea.is_empty() || eb.is_empty() {
            if !(ea.is_empty() && eb.is_empty()) {
                notes.push(format!(
                    "{}: only cohort {} has it, so it is not compared",
                    f.name(),
                    if ea.is_empty() { "B" } else { "A" }
                ));
            }
            continue;
        }
        let mut quantities = Vec::new();
        for (q, x) in &ea {
            if *q == Quantity::Total && !same_unit {
                continue;
            }
            let Some((_, y)) = eb.iter().find(|(p, _)| p == q) else {
                continue;
            };
            let (x, y) = match (x, y) {
                (Ok(x), Ok(y)) => (x.clone(), y.clone()),
                (Err(e), _) | (_, Err(e)) => {
                    if !lacking.contains(e) {
                        lacking.push(e.clone());
                    }
                    continue;
                }
            };
            let sweep = correlation
                .sweep(f)
                .into_iter()
                .map(|r| {
                    let at = |s: &Side<'_>, e: &Estimate, tip| match s {
                        Side::Table(t) => table_estimate(t, f, *q, tip, r, confidence)
                            .unwrap_or_else(|_| e.clone()),
                        Side::Data(_) => e.clone(),
                    };
                    difference(&at(&a, &x, tip_a), &at(&b, &y, tip_b), r, confidence)
                })
                .collect();
            quantities.push(TableQuantity {
                quantity: *q,
                difference: difference(&x, &y, rho, confidence),
                a: x,
                b: y,
                sweep,
            });
        }
        if !quantities.is_empty() {
            fingers.push(TableFinger {
                finger: f,
                rho,
                quantities,
            });
        }
    }
    for l in lacking {
        notes.push(format!(
            "{l}, so the quantities that need it are not compared"
        ));
    }
    let tips = match (a, b) {
        (Side::Data(d), Side::Table(t)) => tip_verdict(d, &va, t, "a", correlation, confidence),
        (Side::Table(t), Side::Data(d)) => tip_verdict(d, &vb, t, "b", correlation, confidence),
        _ => None,
    };
    TableCohorts {
        a: info_a,
        b: info_b,
        confidence,
        correlation: correlation.clone(),
        untestable: Untestable::of(&fingers),
        fingers,
        tips,
        notes,
    }
}

/// The dataset's last segment against the table's to the bone and to the skin, every finger
/// both give; `None` when the table gives no soft tissue.
fn tip_verdict(
    data: &Dataset,
    values: &[FingerValues],
    table: &SummaryTable,
    side: &'static str,
    correlation: &Correlation,
    confidence: f64,
) -> Option<TipVerdict> {
    let mut fingers = Vec::new();
    for (f, qs) in values {
        let f = *f;
        let q = if f == Finger::Thumb {
            Quantity::RelJ2
        } else {
            Quantity::RelJ3
        };
        let Some((_, xs)) = qs.iter().find(|(p, _)| *p == q) else {
            continue;
        };
        let Some(est) = Estimate::of_values(xs, confidence) else {
            continue;
        };
        let at = |tip, rho| table_estimate(table, f, q, tip, rho, confidence).ok();
        let rho = correlation.of(f);
        let (Some(bone), Some(skin)) = (at(TipKind::Bone, rho), at(TipKind::Skin, rho)) else {
            continue;
        };
        let fit_at = |r: f64| {
            let b = difference(&est, &at(TipKind::Bone, r)?, r, confidence);
            let s = difference(&est, &at(TipKind::Skin, r)?, r, confidence);
            Fit::of(b.not_rejected, s.not_rejected)
        };
        let bone_difference = difference(&est, &bone, rho, confidence);
        let skin_difference = difference(&est, &skin, rho, confidence);
        let soft = table.get(f, Segment::TipSoftTissue)?.mean;
        let finger_bone: f64 = Segment::phalanges(f)
            .iter()
            .filter_map(|&s| table.get(f, s).map(|r| r.mean))
            .sum();
        fingers.push(TipFinding {
            finger: f,
            quantity: q,
            fit: Fit::of(bone_difference.not_rejected, skin_difference.not_rejected),
            sweep: correlation
                .sweep(f)
                .into_iter()
                .map(|r| (r, fit_at(r)))
                .collect(),
            data: est,
            bone,
            skin,
            soft_share: soft / (finger_bone + soft),
            bone_difference,
            skin_difference,
        });
    }
    if fingers.is_empty() {
        return None;
    }
    let first = fingers[0].fit;
    let overall = first.filter(|_| {
        fingers
            .iter()
            .all(|t| t.fit == first && t.sweep.iter().all(|(_, s)| *s == first))
    });
    Some(TipVerdict {
        data: side,
        fingers,
        overall,
        recorded: data.tips().single(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn bk() -> SummaryTable {
        SummaryTable::load(Path::new("data/literature/buryanov-kotiuk-2010.csv")).unwrap()
    }

    #[test]
    fn ratios_of_the_tables_means_by_hand() {
        // index: 15.82 / (39.78 + 22.38 + 15.82); with the soft tissue 3.84 added to the
        // distal phalanx and to the finger: 19.66 / 81.82 (the table: 0.2029, 0.2403).
        let t = bk();
        let e = |tip| table_estimate(&t, Finger::Index, Quantity::RelJ3, tip, 0.0, 0.95).unwrap();
        assert!((e(TipKind::Bone).mean - 15.82 / 77.98).abs() < 1e-15);
        assert!((e(TipKind::Skin).mean - 19.66 / 81.82).abs() < 1e-15);
        // thumb J~2: 21.67 / 53.24 and 27.34 / 58.91; J2/J1 and mc/J.
        let th = |q, tip| {
            table_estimate(&t, Finger::Thumb, q, tip, 0.0, 0.95)
                .unwrap()
                .mean
        };
        assert!((th(Quantity::RelJ2, TipKind::Bone) - 21.67 / 53.24).abs() < 1e-15);
        assert!((th(Quantity::RelJ2, TipKind::Skin) - 27.34 / 58.91).abs() < 1e-15);
        assert!((th(Quantity::RatioJ2J1, TipKind::Bone) - 21.67 / 31.57).abs() < 1e-15);
        assert!((th(Quantity::RatioMcJ, TipKind::Bone) - 46.22 / 53.24).abs() < 1e-15);
        assert!(
            table_estimate(&t, Finger::Thumb, Quantity::RelJ3, TipKind::Bone, 0.0, 0.95).is_err()
        );
    }

    #[test]
    fn a_table_without_spread_has_no_interval_and_says_why() {
        let text = "finger,segment,mean,sd,n,unit\nindex,proximal,39.78,,,mm\nindex,middle,22.38,2.51,66,mm\nindex,distal,15.82,2.26,66,mm\n";
        let t = SummaryTable::from_bytes("t.csv", text.as_bytes()).unwrap();
        let e =
            table_estimate(&t, Finger::Index, Quantity::RelJ3, TipKind::Bone, 0.5, 0.95).unwrap();
        assert!((e.mean - 15.82 / 77.98).abs() < 1e-15);
        assert_eq!((e.se, e.ci), (None, None));
        assert!(
            e.why
                .unwrap()
                .contains("no SD or no n for the index proximal")
        );
        // J3/J2 does not need the proximal phalanx, so it has its interval.
        let r = table_estimate(
            &t,
            Finger::Index,
            Quantity::RatioJ3J2,
            TipKind::Bone,
            0.5,
            0.95,
        )
        .unwrap();
        assert!(r.ci.is_some() && r.why.is_none());
    }

    #[test]
    fn higher_correlation_narrows_a_share_of_the_finger() {
        let t = bk();
        let se = |rho| {
            table_estimate(
                &t,
                Finger::Middle,
                Quantity::RelJ3,
                TipKind::Bone,
                rho,
                0.95,
            )
            .unwrap()
            .se
            .unwrap()
        };
        assert!(se(0.9) < se(0.5) && se(0.5) < se(0.0));
    }

    #[test]
    fn the_atlas_correlations_are_stated_per_finger() {
        let Some(atlas) = crate::dataset::vendored::atlas() else {
            return;
        };
        let c = correlations_from(&atlas);
        assert_eq!(c.fingers.len(), 5);
        for f in &c.fingers {
            assert_eq!(f.hands, Some(910));
            assert!(f.rho > 0.6 && f.rho < 0.95, "{f:?}");
        }
        assert_eq!(c.sweep(Finger::Index).len(), 3);
        assert_eq!(Correlation::given(0.9).sweep(Finger::Index), vec![0.0, 0.9]);
    }

    /// The paper's fingertips are taken at the skin: on every finger its last segment rejects
    /// B&K's bone alone and does not reject bone plus soft tissue, at every correlation from
    /// 0 to 0.9, and data/measurements.csv records `skin`, its source naming B&K's table and
    /// this test. If the data or the table change so that this no longer holds, the
    /// recorded tip (and its source note) must be revisited.
    #[test]
    fn the_papers_tips_are_at_the_skin_and_the_data_says_so() {
        let paper = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        let t = bk();
        let c = tables(
            Side::Data(&paper),
            Side::Table(&t),
            &Correlation::given(0.5),
            0.95,
        );
        let v = c.tips.expect("B&K gives the soft tissue");
        assert_eq!(v.fingers.len(), 5);
        for f in &v.fingers {
            assert_eq!(f.fit, Some(Fit::Skin), "{:?}", f.finger);
            assert!(f.sweep.iter().all(|(_, s)| *s == Some(Fit::Skin)), "{f:?}");
        }
        assert_eq!(v.overall, Some(Fit::Skin));
        assert_eq!(v.recorded, Some(TipKind::Skin));
        assert!(v.matches_record());
        // The weakest "not rejected": the ring's interval of B&K's skin - the paper, whose
        // upper end is +0.00012 (tests/independent/literature_reference.txt, at the atlas's
        // correlation 0.8688, under the assumed 0.5 here a little wider).
        let (t, i) = v.nearest_to_rejection().unwrap();
        assert_eq!(t.finger, Finger::Ring);
        assert!(i.low < 0.0 && i.high > 0.0 && i.high < 0.001, "{i:?}");
        assert_eq!(c.untestable.quantities, 0);
        for r in &paper.rows {
            let s = r.meta.source.as_deref().unwrap_or("");
            assert!(
                s.contains("; tip at the skin: bone tips rejected against Buryanov & Kotiuk 2010 Table I (Welch test of the last segment's share, every correlation 0-0.9), skin tips not rejected; not stated by the paper"),
                "line {}: {s}",
                r.line
            );
        }
    }
}
