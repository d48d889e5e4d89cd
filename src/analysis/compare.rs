//! Two cohorts compared on one quantity: difference of means, effect size, external coverage.
//!
//! Pure: slices of values in (one per X-ray, e.g. the J~2 of every index finger of cohort
//! A and of cohort B), structs out. Every difference is B - A. [`compare`] gathers:
//!
//! - n, mean and SD of each cohort;
//! - the difference of means with a Welch t interval ([`welch`]) and a bootstrap interval
//!   that resamples each cohort on its own ([`bootstrap_differences`]; quantities measured
//!   on the same X-rays share its resamples, [`compare_all`]);
//! - Hedges' g with its interval ([`hedges_g`]);
//! - external coverage ([`external_coverage`]): the share of B's values inside A's
//!   prediction interval for one new X-ray, and of A's inside B's. This is what a user of
//!   A's intervals would experience on B's hands.
//!
//! [`soft_tissue_offset`] turns a difference of the last segment into the fingertip offset
//! that would explain it.
//!
//! [`cohorts`] compares two whole datasets finger by finger and quantity by quantity.

use super::{Block, Interval, Quantity, Settings, blocks, group_by, same_xrays};
use crate::dataset::{Dataset, Finger, TipCounts, TipKind, is_pixel_unit};
use crate::stats::bootstrap::{self, Sorted};
use crate::stats::describe;
use schemars::JsonSchema;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// Tags in the top byte of the random keys of [`bootstrap_differences`] (cohort A, cohort
/// B), apart from every other stream of the crate.
const COMPARE_TAG: u64 = 0x43 << 56;
const COMPARE_B_TAG: u64 = 0x44 << 56;

/// Degrees of freedom above which the t quantile of [`welch`] comes from
/// [`describe::t_quantile`] (integer df, its 1/df expansion) instead of `statrs`.
const WELCH_STATRS_MAX_DF: f64 = 1_000.0;

/// n, mean and SD of one cohort's values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Cohort {
    pub n: usize,
    pub mean: f64,
    /// Sample SD (n - 1); `None` for n = 1.
    pub sd: Option<f64>,
}

impl Cohort {
    /// Summarises values; `None` when there are none or any is not finite. O(n).
    pub fn of(xs: &[f64]) -> Option<Cohort> {
        if xs.iter().any(|x| !x.is_finite()) {
            return None;
        }
        Some(Cohort {
            n: xs.len(),
            mean: describe::mean(xs)?,
            sd: describe::sd(xs),
        })
    }
}

/// The Welch t interval of a difference of means.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Welch {
    /// Standard error of the difference: sqrt(s_A^2/n_A + s_B^2/n_B).
    pub se: f64,
    /// Welch-Satterthwaite degrees of freedom.
    pub df: f64,
    pub interval: Interval,
}

/// Hedges' g, the bias-corrected standardised difference of means, with its interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct HedgesG {
    pub g: f64,
    /// Large-sample standard error of g (Hedges and Olkin 1985).
    pub se: f64,
    pub interval: Interval,
}

/// How many of one cohort's values fall inside the other's prediction interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct ExternalCoverage {
    /// The reference cohort's prediction interval for one new X-ray.
    pub interval: Interval,
    /// Values inside it (ends included).
    pub inside: usize,
    /// Values tested.
    pub of: usize,
    /// inside / of.
    pub share: f64,
}

/// Everything [`compare`] finds about one quantity.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Comparison {
    pub a: Cohort,
    pub b: Cohort,
    /// mean_B - mean_A.
    pub difference: f64,
    pub confidence: f64,
    pub welch: Option<Welch>,
    /// Percentile interval of the bootstrap differences ([`bootstrap_differences`]).
    pub bootstrap: Interval,
    /// Bootstrap resamples drawn.
    pub resamples: usize,
    pub hedges_g: Option<HedgesG>,
    /// B's values inside A's prediction interval.
    pub b_in_a: Option<ExternalCoverage>,
    /// A's values inside B's prediction interval.
    pub a_in_b: Option<ExternalCoverage>,
    /// Why a statistic is missing, when one is.
    pub notes: Vec<String>,
}

/// Compares cohorts A and B on one quantity: [`compare_all`] with one column.
/// Cost: O(R (n_A + n_B)) for R = `settings.resamples`.
pub fn compare(a: &[f64], b: &[f64], settings: &Settings, key: u64) -> Option<Comparison> {
    compare_all(&[a], &[b], settings, key)?.pop()
}

/// Compares cohorts A and B on several quantities measured on the same X-rays: column k
/// of `a` and of `b` holds quantity k, and every column of a cohort lists its X-rays in
/// one order (e.g. J~1, J~2, J~3 of a finger, or every quantity of every finger when each
/// X-ray has all fingers). The quantities share one bootstrap ([`bootstrap_differences`]).
/// `key` separates the bootstrap streams of different calls under one seed (below 2^56).
///
/// `None` when there are no columns, the columns of a cohort differ in length, a cohort
/// is empty, or a value is not finite. Cost: O(R (n_A + n_B) q) for R = `settings.resamples`
/// and q quantities.
pub fn compare_all(
    a: &[&[f64]],
    b: &[&[f64]],
    settings: &Settings,
    key: u64,
) -> Option<Vec<Comparison>> {
    if a.is_empty() || a.len() != b.len() {
        return None;
    }
    let c = settings.confidence;
    let boot = bootstrap_differences(a, b, settings.resamples, settings.seed, key, c)?;
    a.iter()
        .zip(b)
        .zip(boot)
        .map(|((a, b), bootstrap)| {
            let (ca, cb) = (Cohort::of(a)?, Cohort::of(b)?);
            let mut notes = Vec::new();
            for (name, x) in [("A", &ca), ("B", &cb)] {
                match x.sd {
                    None => notes.push(format!(
                        "cohort {name} has one X-ray: no spread, so no t interval, effect size or prediction interval"
                    )),
                    Some(0.0) => notes.push(format!("cohort {name}'s values are all equal")),
                    Some(_) => {}
                }
            }
            let welch = welch(&ca, &cb, c);
            if welch.is_none() && ca.sd.is_some() && cb.sd.is_some() {
                notes.push("neither cohort varies: no Welch interval".into());
            }
            Some(Comparison {
                a: ca,
                b: cb,
                difference: cb.mean - ca.mean,
                confidence: c,
                welch,
                bootstrap,
                resamples: settings.resamples,
                hedges_g: hedges_g(&ca, &cb, c),
                b_in_a: external_coverage(a, b, c),
                a_in_b: external_coverage(b, a, c),
                notes,
            })
        })
        .collect()
}

/// Welch's t interval of mean_B - mean_A (Welch 1947):
/// SE = sqrt(v_A + v_B) with v = s^2 / n; Welch-Satterthwaite
/// df = (v_A + v_B)^2 / (v_A^2 / (n_A - 1) + v_B^2 / (n_B - 1));
/// interval = difference -/+ t_{(1+c)/2, df} SE, the t quantile at fractional df from
/// `statrs` (above 1,000 df from [`describe::t_quantile`] at floor(df), which differs by
/// under 1e-6). `None` when a cohort has n < 2 or both have zero spread.
pub fn welch(a: &Cohort, b: &Cohort, confidence: f64) -> Option<Welch> {
    let (sa, sb) = (a.sd?, b.sd?);
    let (va, vb) = (sa * sa / a.n as f64, sb * sb / b.n as f64);
    let se = (va + vb).sqrt();
    if !(se > 0.0 && se.is_finite()) {
        return None;
    }
    let df = (va + vb).powi(2) / (va * va / (a.n - 1) as f64 + vb * vb / (b.n - 1) as f64);
    let p = 1.0 - (1.0 - confidence) / 2.0;
    let t = if df <= WELCH_STATRS_MAX_DF {
        StudentsT::new(0.0, 1.0, df).ok()?.inverse_cdf(p)
    } else {
        describe::t_quantile(confidence, df.floor() as usize)?
    };
    let d = b.mean - a.mean;
    t.is_finite().then(|| Welch {
        se,
        df,
        interval: Interval::new(d - t * se, d + t * se),
    })
}

/// Hedges' g of B against A with its large-sample interval.
///
/// Pooled SD s_p = sqrt(((n_A - 1) s_A^2 + (n_B - 1) s_B^2) / (n_A + n_B - 2));
/// Cohen's d = (mean_B - mean_A) / s_p; g = J d with the small-sample correction
/// J = 1 - 3 / (4 (n_A + n_B) - 9) (Hedges 1981). Standard error from the large-sample
/// variance of Hedges and Olkin (1985, *Statistical Methods for Meta-Analysis*, ch. 5):
/// SE = sqrt((n_A + n_B) / (n_A n_B) + g^2 / (2 (n_A + n_B))); interval g -/+ z_{(1+c)/2} SE.
/// `None` when a cohort has n < 2 or the pooled SD is 0.
pub fn hedges_g(a: &Cohort, b: &Cohort, confidence: f64) -> Option<HedgesG> {
    let (sa, sb) = (a.sd?, b.sd?);
    let (na, nb) = (a.n as f64, b.n as f64);
    let sp = (((na - 1.0) * sa * sa + (nb - 1.0) * sb * sb) / (na + nb - 2.0)).sqrt();
    if !(sp > 0.0 && sp.is_finite()) {
        return None;
    }
    let j = 1.0 - 3.0 / (4.0 * (na + nb) - 9.0);
    let g = j * (b.mean - a.mean) / sp;
    let se = ((na + nb) / (na * nb) + g * g / (2.0 * (na + nb))).sqrt();
    let z = describe::normal_quantile(1.0 - (1.0 - confidence) / 2.0);
    Some(HedgesG {
        g,
        se,
        interval: Interval::new(g - z * se, g + z * se),
    })
}

/// The share of `others` inside the prediction interval for one new X-ray of `reference`
/// ([`describe::prediction_interval`], the interval the analysis reports: mean -/+
/// t_{(1+c)/2, n-1} s sqrt(1 + 1/n)), ends included. `None` when `reference` has n < 2 or
/// `others` is empty. O(n).
pub fn external_coverage(
    reference: &[f64],
    others: &[f64],
    confidence: f64,
) -> Option<ExternalCoverage> {
    let r = Cohort::of(reference)?;
    let interval = describe::prediction_interval(r.mean, r.sd?, r.n, confidence)?;
    if others.is_empty() {
        return None;
    }
    let inside = others.iter().filter(|&&x| interval.contains(x)).count();
    Some(ExternalCoverage {
        interval,
        inside,
        of: others.len(),
        share: inside as f64 / others.len() as f64,
    })
}

/// Percentile bootstrap interval of mean_B - mean_A, each cohort resampled on its own:
/// [`bootstrap_differences`] with one column.
pub fn bootstrap_difference(
    a: &[f64],
    b: &[f64],
    resamples: usize,
    seed: u64,
    key: u64,
    confidence: f64,
) -> Option<Interval> {
    bootstrap_differences(&[a], &[b], resamples, seed, key, confidence)?.pop()
}

/// Percentile bootstrap intervals of mean_B - mean_A for several quantities measured on
/// the same X-rays (columns as in [`compare_all`]), each cohort resampled on its own.
///
/// The unit resampled is the X-ray: resample j draws n_A X-rays of A and, independently,
/// n_B X-rays of B, with replacement, and every quantity takes the difference of its
/// means over those X-rays. Each cohort's resamples come from the statistics' bootstrap
/// kernel ([`bootstrap::resample_means_random`], chunks of [`bootstrap::CHUNK`] resamples
/// on their own ChaCha8 streams), A's under key (seed, tag A ^ `key`) and B's under
/// (seed, tag B ^ `key`). The draws do not depend on the number of columns, so a quantity
/// gets the same interval alone or with others, on every machine and thread count. Each
/// interval is the (1-c)/2 and (1+c)/2 quantiles of its R differences
/// ([`bootstrap::percentile_interval`]).
///
/// `None` for no columns, columns of a cohort of different lengths, an empty cohort, a
/// cohort of 2^32 X-rays or more, or no resamples. Cost: O(R (n_A + n_B) q) time,
/// O(R q) memory.
pub fn bootstrap_differences(
    a: &[&[f64]],
    b: &[&[f64]],
    resamples: usize,
    seed: u64,
    key: u64,
    confidence: f64,
) -> Option<Vec<Interval>> {
    let q = a.len();
    let usable = |cols: &[&[f64]]| {
        let n = cols.first().map_or(0, |c| c.len());
        n > 0 && u32::try_from(n).is_ok() && cols.iter().all(|c| c.len() == n)
    };
    if q == 0 || b.len() != q || resamples == 0 || !usable(a) || !usable(b) {
        return None;
    }
    let da = bootstrap::resample_means_random(a, resamples, seed, COMPARE_TAG ^ key);
    let db = bootstrap::resample_means_random(b, resamples, seed, COMPARE_B_TAG ^ key);
    let weights = vec![1.0 / resamples as f64; resamples];
    Some(
        da.means
            .iter()
            .zip(&db.means)
            .map(|(ma, mb)| {
                let diffs: Vec<f64> = mb.iter().zip(ma).map(|(y, x)| y - x).collect();
                bootstrap::percentile_interval(&Sorted::new(&diffs, &weights), confidence)
            })
            .collect(),
    )
}

/// The fingertip offset that would explain a difference of the last segment.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct TipOffset {
    /// d / J_A: the offset as a share of A's finger length as measured (tip at the skin).
    pub share_of_a: f64,
    /// d / (J_A - d): the offset as a share of the finger's length to the bone tip.
    pub share_of_bone: f64,
    /// d in A's length units: `share_of_a` times A's mean total.
    pub in_a_units: f64,
    /// d in B's length units: `share_of_bone` times B's mean total (B's tips at the bone).
    pub in_b_units: f64,
}

/// The soft-tissue offset d of the fingertip that would turn B's mean relative last
/// segment (J~3, the thumb's J~2) into A's, if A's tips were at the skin and B's at the bone.
///
/// Take a finger of bone length J (MCP to the bone tip) whose last segment is J_last, so
/// that its relative last segment is r_B = J_last / J, as B measures it. Moving the tip out
/// by d along the finger adds d to both: J~last' = (J_last + d) / (J + d). Setting this
/// equal to A's r_A: (r_B J + d) / (J + d) = r_A, so d (1 - r_A) = J (r_A - r_B) and
///
/// - d / J = (r_A - r_B) / (1 - r_A) (a share of the bone length, `share_of_bone`);
/// - d / (J + d) = (r_A - r_B) / (1 - r_B) (a share of the length as A measures it,
///   tip at the skin, `share_of_a`).
///
/// In A's units d = share_of_a x A's mean total (A's totals include d); at B's scale
/// d = share_of_bone x B's mean total. Means stand in for each hand, so the offset is that
/// of an average finger. A negative offset means A's last segment is the shorter: no
/// soft tissue explains that. `None` unless 0 < r < 1 for both and the totals are
/// positive and finite.
pub fn soft_tissue_offset(
    rel_last_a: f64,
    rel_last_b: f64,
    total_a: f64,
    total_b: f64,
) -> Option<TipOffset> {
    let unit = |r: f64| r > 0.0 && r < 1.0;
    let positive = |t: f64| t > 0.0 && t.is_finite();
    if !(unit(rel_last_a) && unit(rel_last_b) && positive(total_a) && positive(total_b)) {
        return None;
    }
    let share_of_a = (rel_last_a - rel_last_b) / (1.0 - rel_last_b);
    let share_of_bone = (rel_last_a - rel_last_b) / (1.0 - rel_last_a);
    Some(TipOffset {
        share_of_a,
        share_of_bone,
        in_a_units: share_of_a * total_a,
        in_b_units: share_of_bone * total_b,
    })
}

#[cfg(test)]
mod tests;

/// What a comparison says about one of its datasets.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct CohortInfo {
    /// The path as given.
    pub path: String,
    pub sha256: String,
    pub xrays: usize,
    pub rows: usize,
    /// The unit the rows name, if any.
    pub unit: Option<String>,
    /// Where the rows put their fingertips.
    pub tips: TipCounts,
    /// The sides the rows record (`left`, `right`), sorted, once each.
    pub sides: Vec<String>,
    /// The youngest and oldest age the rows record.
    pub ages: Option<(f64, f64)>,
    /// The cohort's description beside its file, set by the caller.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub about: Option<crate::dataset::CohortNotes>,
}

impl CohortInfo {
    pub(crate) fn of(data: &Dataset) -> CohortInfo {
        let mut sides: Vec<String> = data
            .rows
            .iter()
            .filter_map(|r| r.meta.side.as_deref().map(str::to_string))
            .collect();
        sides.sort();
        sides.dedup();
        let ages =
            data.rows
                .iter()
                .filter_map(|r| r.meta.age)
                .fold(None, |acc: Option<(f64, f64)>, a| {
                    Some(acc.map_or((a, a), |(lo, hi)| (lo.min(a), hi.max(a))))
                });
        CohortInfo {
            path: data.path.clone(),
            sha256: data.sha256.clone(),
            xrays: data.xray_count(),
            rows: data.rows.len(),
            unit: data.unit().map(str::to_string),
            tips: data.tips(),
            sides,
            ages,
            about: None,
        }
    }
}

/// One quantity of one finger compared.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct QuantityComparison {
    pub quantity: Quantity,
    #[serde(flatten)]
    pub comparison: Comparison,
}

/// Which cohort's fingertips a [`LastSegment`] offset puts at the skin, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TipBasis {
    /// The recorded tips: one cohort's at the bone, the other's at the skin or not recorded.
    Recorded,
    /// Neither cohort's tips tell them apart: the cohort with the longer last segment is
    /// taken as the one measured to the skin.
    LongerLastSegment,
}

/// The last segment of a finger (J~3, the thumb's J~2) and the soft tissue that would
/// explain its difference.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LastSegment {
    pub quantity: Quantity,
    /// mean_B - mean_A of the relative last segment.
    pub difference: f64,
    /// `a` or `b`: the cohort taken as measured to the skin.
    pub skin: &'static str,
    pub basis: TipBasis,
    /// The offset, with A and B as in [`soft_tissue_offset`] when `skin` is `a` (else
    /// swapped: `share_of_a` is then the share of B's length).
    pub offset: TipOffset,
}

/// Both cohorts compared on one finger.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct FingerComparison {
    pub finger: Finger,
    /// X-rays of each cohort with this finger.
    pub n_a: usize,
    pub n_b: usize,
    pub quantities: Vec<QuantityComparison>,
    /// The fingertip offset that would explain the last segment's difference.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub last_segment: Option<LastSegment>,
}

impl FingerComparison {
    /// The comparison of one quantity, if both cohorts have it.
    pub fn quantity(&self, q: Quantity) -> Option<&Comparison> {
        self.quantities
            .iter()
            .find(|c| c.quantity == q)
            .map(|c| &c.comparison)
    }
}

/// Two datasets compared finger by finger: what [`cohorts`] returns.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cohorts {
    pub a: CohortInfo,
    pub b: CohortInfo,
    pub settings: Settings,
    /// Fingers both cohorts have, thumb first.
    pub fingers: Vec<FingerComparison>,
    /// What was not compared and why.
    pub notes: Vec<String>,
}

impl Cohorts {
    /// Over every finger and relative quantity, how many of B's values lie inside A's
    /// prediction interval for one new X-ray, and of how many tested (`(0, 0)`: none).
    pub fn b_inside_a(&self) -> (usize, usize) {
        self.fingers
            .iter()
            .flat_map(|f| &f.quantities)
            .filter(|q| q.quantity.is_relative())
            .filter_map(|q| q.comparison.b_in_a)
            .fold((0, 0), |(inside, of), e| (inside + e.inside, of + e.of))
    }
}

/// Compares datasets A and B: for every finger both have, every quantity both measure
/// ([`compare_all`]; differences B - A), and the soft tissue that would explain the
/// difference of the last segment ([`soft_tissue_offset`]).
///
/// The total length J is compared only when both datasets name the same unit and it is not
/// per-image pixels; the metacarpal's quantities only when both measure it. Fingers whose
/// X-rays are the same in each cohort (e.g. five fingers per hand) share one bootstrap,
/// keyed by the leading finger. Cost: O(R (n_A + n_B) q) for R resamples and q quantities
/// (no bootstrap of either dataset's own statistics is needed).
pub fn cohorts(a: &Dataset, b: &Dataset, settings: &Settings) -> Cohorts {
    let (info_a, info_b) = (CohortInfo::of(a), CohortInfo::of(b));
    let mut notes = Vec::new();
    let same_unit = match (&info_a.unit, &info_b.unit) {
        (Some(x), Some(y)) => x == y && !is_pixel_unit(x),
        _ => false,
    };
    if !same_unit {
        notes.push(total_note(&info_a.unit, &info_b.unit));
    }
    let pairs = paired_blocks(&blocks(a), &blocks(b), same_unit, &mut notes);
    let results = compare_pairs(&pairs, settings);
    let mut fingers = by_finger(&pairs, results);
    for f in &mut fingers {
        f.last_segment = last_segment(f, &info_a.tips, &info_b.tips, &pairs);
    }
    Cohorts {
        a: info_a,
        b: info_b,
        settings: *settings,
        fingers,
        notes,
    }
}

/// Pairs of blocks (A's, B's) of each finger both cohorts have, each cut to the quantities
/// both measure (J only when `same_unit`); notes the fingers and metacarpal quantities only
/// one cohort has.
fn paired_blocks(
    blocks_a: &[Block],
    blocks_b: &[Block],
    same_unit: bool,
    notes: &mut Vec<String>,
) -> Vec<(Block, Block)> {
    let mut pairs: Vec<(Block, Block)> = Vec::new();
    let mut mc_missing: Vec<&str> = Vec::new();
    for f in Finger::ALL {
        let of = |bs: &[Block]| {
            bs.iter()
                .filter(|b| b.finger == f)
                .cloned()
                .collect::<Vec<_>>()
        };
        let (fa, fb) = (of(blocks_a), of(blocks_b));
        if fa.is_empty() || fb.is_empty() {
            if !(fa.is_empty() && fb.is_empty()) {
                notes.push(format!(
                    "{}: only cohort {} has it, so it is not compared",
                    f.name(),
                    if fa.is_empty() { "B" } else { "A" }
                ));
            }
            continue;
        }
        let has_mc = |bs: &[Block]| bs.iter().any(|b| b.quantities.iter().any(|q| q.needs_mc()));
        if has_mc(&fa) != has_mc(&fb) {
            mc_missing.push(f.name());
        }
        for x in &fa {
            for y in &fb {
                if let Some(pair) = shared_quantities(x, y, same_unit) {
                    pairs.push(pair);
                }
            }
        }
    }
    if !mc_missing.is_empty() {
        notes.push(format!(
            "mc/J and J1/mc ({}): only one cohort measures the metacarpal, so they are not compared",
            mc_missing.join(", ")
        ));
    }
    pairs
}

/// Blocks `x` and `y` cut to the quantities both measure (J only when `same_unit`); `None`
/// when they share none.
fn shared_quantities(x: &Block, y: &Block, same_unit: bool) -> Option<(Block, Block)> {
    let quantities: Vec<Quantity> = x
        .quantities
        .iter()
        .copied()
        .filter(|q| y.quantities.contains(q))
        .filter(|&q| q != Quantity::Total || same_unit)
        .collect();
    if quantities.is_empty() {
        return None;
    }
    Some((
        Block {
            quantities: quantities.clone(),
            ..x.clone()
        },
        Block {
            quantities,
            ..y.clone()
        },
    ))
}

/// The comparisons of every pair's quantities ([`compare_all`]); pairs whose X-rays are the
/// same in A and in B share one bootstrap. A group [`compare_all`] cannot compare is left empty.
fn compare_pairs(pairs: &[(Block, Block)], settings: &Settings) -> Vec<Vec<QuantityComparison>> {
    let groups = group_by(pairs, |p, q| {
        same_xrays(&p.0.xrays, &q.0.xrays) && same_xrays(&p.1.xrays, &q.1.xrays)
    });
    let mut results: Vec<Vec<QuantityComparison>> = vec![Vec::new(); pairs.len()];
    for g in &groups {
        let cols_a: Vec<Vec<Vec<f64>>> = g.iter().map(|&i| pairs[i].0.columns()).collect();
        let cols_b: Vec<Vec<Vec<f64>>> = g.iter().map(|&i| pairs[i].1.columns()).collect();
        let flat_a: Vec<&[f64]> = cols_a.iter().flatten().map(Vec::as_slice).collect();
        let flat_b: Vec<&[f64]> = cols_b.iter().flatten().map(Vec::as_slice).collect();
        let key = pairs[g[0]].0.key();
        let Some(mut all) = compare_all(&flat_a, &flat_b, settings, key) else {
            continue;
        };
        for &i in g.iter().rev() {
            let q = &pairs[i].0.quantities;
            let tail = all.split_off(all.len() - q.len());
            results[i] = q
                .iter()
                .zip(tail)
                .map(|(&quantity, comparison)| QuantityComparison {
                    quantity,
                    comparison,
                })
                .collect();
        }
    }
    results
}

/// The pairs' comparisons gathered per finger, in the pairs' order (last segments not yet set).
fn by_finger(
    pairs: &[(Block, Block)],
    results: Vec<Vec<QuantityComparison>>,
) -> Vec<FingerComparison> {
    let mut fingers: Vec<FingerComparison> = Vec::new();
    for ((x, y), r) in pairs.iter().zip(results) {
        match fingers.iter_mut().find(|f| f.finger == x.finger) {
            Some(f) => f.quantities.extend(r),
            None => fingers.push(FingerComparison {
                finger: x.finger,
                n_a: x.xrays.len(),
                n_b: y.xrays.len(),
                quantities: r,
                last_segment: None,
            }),
        }
    }
    fingers
}

/// Why the total length J is not compared.
fn total_note(a: &Option<String>, b: &Option<String>) -> String {
    let show = |u: &Option<String>| {
        u.as_deref()
            .map_or("no unit".to_string(), |u| format!("'{u}'"))
    };
    match (a, b) {
        (Some(x), Some(y)) if x == y => format!(
            "J (total length): both cohorts are in per-image pixels ('{x}'), not comparable across images, so it is not compared"
        ),
        _ => format!(
            "J (total length): the cohorts' units differ or are not named (A {}, B {}), so lengths are not compared; relative values and ratios are unitless",
            show(a),
            show(b)
        ),
    }
}

/// The last segment's comparison and the soft-tissue offset that would explain it
/// (see [`TipBasis`] for which cohort is taken as measured to the skin).
fn last_segment(
    f: &FingerComparison,
    tips_a: &TipCounts,
    tips_b: &TipCounts,
    pairs: &[(Block, Block)],
) -> Option<LastSegment> {
    let quantity = if f.finger == Finger::Thumb {
        Quantity::RelJ2
    } else {
        Quantity::RelJ3
    };
    let c = f.quantity(quantity)?;
    let (ta, tb) = (tips_a.single(), tips_b.single());
    let (skin_is_a, basis) = match (ta, tb) {
        (Some(TipKind::Bone), t) if t != Some(TipKind::Bone) => (false, TipBasis::Recorded),
        (t, Some(TipKind::Bone)) if t != Some(TipKind::Bone) => (true, TipBasis::Recorded),
        _ => (c.difference <= 0.0, TipBasis::LongerLastSegment),
    };
    // Mean totals of the finger in each cohort (its main block), in their own units.
    let total = |pick: fn(&(Block, Block)) -> &Block| {
        let b = pairs
            .iter()
            .map(pick)
            .find(|b| b.finger == f.finger && b.main)?;
        describe::mean(&b.xrays.iter().map(|x| x.total).collect::<Vec<_>>())
    };
    let (total_a, total_b) = (total(|p| &p.0)?, total(|p| &p.1)?);
    let offset = if skin_is_a {
        soft_tissue_offset(c.a.mean, c.b.mean, total_a, total_b)?
    } else {
        soft_tissue_offset(c.b.mean, c.a.mean, total_b, total_a)?
    };
    Some(LastSegment {
        quantity,
        difference: c.difference,
        skin: if skin_is_a { "a" } else { "b" },
        basis,
        offset,
    })
}

/// An X-ray that both cohorts hold: B's X-ray `b` has exactly the rows (fingers and
/// lengths, bit for bit) of A's X-ray `a`; the ids may differ.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SharedXray {
    pub a: String,
    pub b: String,
}

/// One X-ray's rows as compared: (finger index, lengths' bits), sorted.
type HandRows = Vec<(usize, [u64; 3])>;

/// The X-rays of `b` that are X-rays of `a` (the same rows, by id or by values alone),
/// in B's order: cohorts that share hands are not independent, so their comparison's
/// intervals mean nothing. O(rows).
pub fn shared_xrays(a: &Dataset, b: &Dataset) -> Vec<SharedXray> {
    let hands = |d: &Dataset| {
        let mut out: Vec<(String, HandRows)> = Vec::new();
        let mut at: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
        for r in &d.rows {
            let i = *at.entry(&r.xray).or_insert_with(|| {
                out.push((r.xray.to_string(), Vec::new()));
                out.len() - 1
            });
            out[i]
                .1
                .push((r.finger.index(), r.lengths.map(f64::to_bits)));
        }
        for (_, rows) in &mut out {
            rows.sort_unstable();
        }
        out
    };
    let in_a = hands(a);
    let mut by_rows: std::collections::HashMap<&[(usize, [u64; 3])], Vec<&str>> =
        std::collections::HashMap::new();
    for (id, rows) in &in_a {
        by_rows.entry(rows).or_default().push(id);
    }
    hands(b)
        .into_iter()
        .filter_map(|(id, rows)| {
            let ids = by_rows.get(rows.as_slice())?;
            // The same id when A has it with these rows, else A's first such X-ray.
            let a = ids.iter().find(|x| **x == id).unwrap_or(&ids[0]);
            Some(SharedXray {
                a: a.to_string(),
                b: id,
            })
        })
        .collect()
}
