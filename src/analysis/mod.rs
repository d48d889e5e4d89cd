//! Statistics of finger-segment proportions: the paper's and beyond.
//!
//! For each finger and X-ray: the total J = sum J_k (eq. 1) and the relative
//! values J~k = J_k / J (eq. 2). For each quantity over the X-rays: the paper's
//! mean (eq. 5), min and max (eq. 7) and range (eq. 9), then SD, SE, median, CV,
//! Student-t, bootstrap percentile and BCa intervals of the mean, and a
//! prediction interval for one new X-ray. Knows nothing of files or rendering.
//!
//! Where the metacarpal is measured, mc/J and J1/mc join the quantities of the X-rays
//! that have it. Lengths in per-image pixels ([`is_pixel_unit`]) are not comparable
//! across X-rays, so their total J is not averaged: such an analysis has no `total`.
//! Neither is a finger's J whose X-rays give their lengths in different units (mm and
//! image units, say): the relative values and ratios, which have no unit, pool across
//! units; the total is left out ([`totals_comparable`]) and the reports say why.

pub(crate) mod budget;
pub mod claims;
pub mod compare;
pub mod coverage;
pub mod groups;
pub mod literature;
pub(crate) mod outliers;
pub mod placement;
pub(crate) mod plausible;
pub mod population;
pub mod region;
pub(crate) mod tracking;

/// The interval type of [`crate::stats`] and the quantities of [`crate::dataset`],
/// also here for the analysis's callers.
pub use crate::dataset::Quantity;
pub use crate::stats::Interval;

use crate::dataset::tip::LineRuns;
use crate::dataset::{Dataset, Finger, Row, TipCounts, is_pixel_unit};
use crate::stats::Intervals;
use crate::stats::bootstrap::{self, Plan, Sorted};
use crate::stats::describe;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use schemars::JsonSchema;
use serde::Serialize;
use std::sync::Arc;

/// The default seed: the paper's publication date, 2013-01-01, as a number.
pub const DEFAULT_SEED: u64 = 20_130_101;
/// Default number of bootstrap resamples.
pub const DEFAULT_RESAMPLES: usize = 10_000;
/// Default confidence level of every interval.
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// Settings of an analysis.
///
/// Build them with [`Settings::new`], which refuses values the analysis cannot
/// use; a literal must pass [`Settings::validate`] before it is analysed with
/// (a confidence outside (0, 1) has no t quantile).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Settings {
    /// Bootstrap resamples asked for (fewer are used when exact enumeration is cheaper).
    pub resamples: usize,
    pub seed: u64,
    /// Confidence level of every interval, in (0, 1).
    pub confidence: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            resamples: DEFAULT_RESAMPLES,
            seed: DEFAULT_SEED,
            confidence: DEFAULT_CONFIDENCE,
        }
    }
}

impl Settings {
    /// Checked settings: a confidence strictly between 0 and 1, at least one resample.
    pub fn new(resamples: usize, seed: u64, confidence: f64) -> Result<Settings, String> {
        let settings = Settings {
            resamples,
            seed,
            confidence,
        };
        settings.validate()?;
        Ok(settings)
    }

    /// Checks the settings, explaining what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.confidence > 0.0 && self.confidence < 1.0) {
            return Err(format!(
                "confidence must lie strictly between 0 and 1 (e.g. 0.95), got {}",
                self.confidence
            ));
        }
        if self.resamples == 0 {
            return Err("resamples must be at least 1 (default 10000)".into());
        }
        Ok(())
    }
}

/// The two or three values of a finger's segments (J1, J2[, J3]), held inline: a finger's
/// X-rays are many (500,000 at 100,000 hands) and two small heap vectors each were a
/// million allocations and about 50 bytes an X-ray more. Reads as a slice (`Deref`) and
/// serialises as a JSON array of its values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segments {
    values: [f64; 3],
    len: u8,
}

impl Segments {
    /// The first (at most three) values of `values`.
    pub fn new(values: &[f64]) -> Segments {
        let mut s = Segments {
            values: [0.0; 3],
            len: values.len().min(3) as u8,
        };
        s.values[..s.len as usize].copy_from_slice(&values[..s.len as usize]);
        s
    }

    /// The values as a slice.
    pub fn as_slice(&self) -> &[f64] {
        self
    }
}

impl<'a> IntoIterator for &'a Segments {
    type Item = &'a f64;
    type IntoIter = std::slice::Iter<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

impl std::ops::Deref for Segments {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.values[..self.len as usize]
    }
}

impl std::ops::DerefMut for Segments {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.values[..self.len as usize]
    }
}

impl Serialize for Segments {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

/// The derived values of one X-ray for one finger (eqs. 1-2).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct XrayValues {
    pub xray: Arc<str>,
    /// J1, J2[, J3] in data units.
    #[schemars(with = "Vec<f64>")]
    pub lengths: Segments,
    /// J = sum of the lengths (eq. 1).
    pub total: f64,
    /// J~k = J_k / J for every segment (eq. 2).
    #[schemars(with = "Vec<f64>")]
    pub relative: Segments,
    /// The metacarpal (CMC to MCP) in data units, when measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mc: Option<f64>,
    /// The unit of the lengths, when the row names one (not in the JSON documents, which
    /// hold the statistics; the dataset holds the units).
    #[serde(skip)]
    pub unit: Option<Arc<str>>,
}

impl XrayValues {
    /// The value of quantity `q` on this X-ray; `None` when the X-ray lacks what `q`
    /// needs (J3 of a thumb, the metacarpal where it is not measured).
    pub fn value(&self, q: Quantity) -> Option<f64> {
        let l = |k: usize| self.lengths.get(k).copied();
        Some(match q {
            Quantity::RelJ1 | Quantity::RelJ2 | Quantity::RelJ3 => {
                let k = match q {
                    Quantity::RelJ1 => 0,
                    Quantity::RelJ2 => 1,
                    _ => 2,
                };
                *self.relative.get(k)?
            }
            Quantity::RatioJ2J1 => l(1)? / l(0)?,
            Quantity::RatioJ3J2 => l(2)? / l(1)?,
            Quantity::Total => self.total,
            Quantity::RatioMcJ => self.mc? / self.total,
            Quantity::RatioJ1Mc => l(0)? / self.mc?,
        })
    }
}

/// Every statistic of one quantity over the X-rays of a finger.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct QuantityStats {
    pub name: Quantity,
    pub n: usize,
    /// Eq. (5).
    pub mean: f64,
    /// Sample SD (n - 1); null for n = 1.
    pub sd: Option<f64>,
    /// SD / sqrt(n); null for n = 1.
    pub se: Option<f64>,
    pub median: f64,
    /// Eq. (7).
    pub min: f64,
    /// Eq. (7).
    pub max: f64,
    /// Eq. (9): max - min.
    pub range: f64,
    /// SD / mean; null for n = 1.
    pub cv: Option<f64>,
    /// The t, percentile and BCa intervals of the mean and the prediction
    /// interval for one new X-ray (JSON keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`).
    #[serde(flatten)]
    pub intervals: Intervals,
    /// Why an interval is null or collapsed, when it is.
    pub notes: Vec<String>,
}

/// The analysis of one finger.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct FingerAnalysis {
    pub finger: Finger,
    /// Number of X-rays with this finger (the metacarpal's quantities may have fewer:
    /// their own `n`).
    pub n: usize,
    pub xrays: Vec<XrayValues>,
    pub quantities: Vec<QuantityStats>,
    /// How the bootstrap distribution was obtained.
    pub bootstrap: Plan,
}

impl FingerAnalysis {
    /// The statistics of one quantity, if the finger has it.
    pub fn quantity(&self, q: Quantity) -> Option<&QuantityStats> {
        self.quantities.iter().find(|s| s.name == q)
    }

    /// The prediction region of this finger's relative joint positions at
    /// `confidence` ([`region::JointRegion`], from every X-ray's lengths),
    /// its shape borrowed from `prior` (`None`: the X-rays' own); `None`
    /// with too few X-rays or a singular covariance. O(n).
    pub fn joint_region(
        &self,
        confidence: f64,
        prior: Option<region::ShapePrior>,
    ) -> Option<region::JointRegion> {
        region::JointRegion::with_prior(&self.positions()?, confidence, prior)
    }

    /// Every X-ray's relative joint positions u ([`region::positions`]);
    /// `None` when one X-ray's lengths give none. O(n).
    pub fn positions(&self) -> Option<Vec<region::Position>> {
        self.xrays
            .iter()
            .map(|x| region::Position::of(&x.lengths))
            .collect()
    }
}

/// What an analysis was computed from: enough to cite the dataset, not its rows.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct DatasetInfo {
    /// The path as given.
    pub path: String,
    /// SHA-256 of the file, lower-case hex.
    pub sha256: String,
    /// Distinct X-rays.
    pub xrays: usize,
    /// Measurement rows (X-ray x finger).
    pub rows: usize,
}

impl DatasetInfo {
    /// Summarises a dataset.
    pub fn of(data: &Dataset) -> DatasetInfo {
        DatasetInfo {
            path: data.path.clone(),
            sha256: data.sha256.clone(),
            xrays: data.xray_count(),
            rows: data.rows.len(),
        }
    }
}

/// The analysis of a whole dataset.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub dataset: DatasetInfo,
    pub settings: Settings,
    /// Fingers present in the data, thumb first.
    pub fingers: Vec<FingerAnalysis>,
    /// The one unit every row names, if they all name the same ([`Dataset::unit`]).
    pub unit: Option<String>,
    /// Every unit the rows give (`None`: not named) with its number of rows, in order
    /// of first appearance; more than one when the dataset mixes units.
    pub units: Vec<(Option<String>, usize)>,
    /// Where the rows put their fingertips.
    pub tips: TipCounts,
    /// The lines of the rows that record no tip ([`Dataset::untipped`]).
    pub untipped: LineRuns,
    /// Rows added though flagged as likely errors (`add --accept-flagged`), file order.
    pub flagged: Vec<FlaggedRow>,
}

/// A row of the data that `add` flagged as a likely error and was told to add anyway.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct FlaggedRow {
    #[schemars(with = "String")]
    pub xray: Arc<str>,
    pub finger: Finger,
    /// Line of the row in the dataset.
    pub line: u64,
    /// Why it was flagged (the dataset's `flagged` column).
    pub reason: String,
}

/// Why intervals at small n are wide: the t quantile at the smallest finger
/// count against the normal quantile, at the analysis's confidence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WidthReason {
    /// The smallest number of X-rays of a finger.
    pub n: usize,
    /// The two-sided t quantile with n - 1 degrees of freedom (`None` below n = 2).
    pub t: Option<f64>,
    /// The two-sided normal quantile.
    pub z: f64,
}

impl Analysis {
    /// The prior shapes of the joint regions from this analysis as the prior
    /// cohort ([`region::ShapePriors`]): each finger's correlation of u,
    /// weighted as `hands` hands. O(X-rays).
    pub fn shape_priors(&self, hands: f64) -> region::ShapePriors {
        let fingers: Vec<(Finger, Vec<region::Position>)> = self
            .fingers
            .iter()
            .filter_map(|f| f.positions().map(|u| (f.finger, u)))
            .collect();
        region::ShapePriors::of_hands(&self.dataset.path, &fingers, hands)
    }

    /// The t and normal quantiles that say why the intervals are as wide as
    /// they are at this data's n ([`WidthReason`]). O(fingers).
    pub fn width_reason(&self) -> WidthReason {
        let n = self.fingers.iter().map(|f| f.n).min().unwrap_or(0);
        let c = self.settings.confidence;
        WidthReason {
            n,
            t: crate::stats::describe::t_quantile(c, n.saturating_sub(1)),
            z: crate::stats::describe::normal_quantile(1.0 - (1.0 - c) / 2.0),
        }
    }

    /// True when the rows give their lengths in more than one unit: relative values
    /// and ratios pool across them, lengths and totals are not averaged across them.
    pub fn mixed_units(&self) -> bool {
        self.units.len() > 1
    }

    /// The analysis of one finger, if the data has it.
    pub fn finger(&self, f: Finger) -> Option<&FingerAnalysis> {
        self.fingers.iter().find(|a| a.finger == f)
    }

    /// True when the lengths are per-image pixels ([`is_pixel_unit`]): the total J and
    /// the metacarpal are then not comparable across X-rays and J is not averaged.
    pub fn pixel_lengths(&self) -> bool {
        self.unit.as_deref().is_some_and(is_pixel_unit)
    }
}

/// True when the total length J of these X-rays may be averaged: every one gives its
/// lengths in the same unit (or none names one), and that unit is not per-image pixels.
pub(crate) fn totals_comparable(xrays: &[XrayValues]) -> bool {
    let one_unit = xrays.windows(2).all(|w| w[0].unit == w[1].unit);
    let pixels = xrays
        .first()
        .and_then(|x| x.unit.as_deref())
        .is_some_and(is_pixel_unit);
    one_unit && !pixels
}

/// The quantities of a finger measured on all its X-rays: [`Quantity::of`], without
/// the total when its lengths are pixels or in more than one unit
/// ([`totals_comparable`]), and with the metacarpal's when every X-ray has it.
fn quantities(finger: Finger, xrays: &[XrayValues]) -> Vec<Quantity> {
    let total = totals_comparable(xrays);
    let mut qs: Vec<Quantity> = Quantity::of(finger)
        .iter()
        .copied()
        .filter(|&q| total || q != Quantity::Total)
        .collect();
    if xrays.iter().all(|x| x.mc.is_some()) {
        qs.extend(Quantity::METACARPAL);
    }
    qs
}

/// One bootstrap unit: quantities of a finger over a list of its X-rays.
#[derive(Debug, Clone)]
pub(crate) struct Block {
    pub(crate) finger: Finger,
    pub(crate) quantities: Vec<Quantity>,
    pub(crate) xrays: Vec<XrayValues>,
    /// Whether these are the finger's X-rays (else a subset for the metacarpal).
    pub(crate) main: bool,
}

/// The blocks of a dataset, fingers thumb first: each finger's X-rays (in order of first
/// appearance in the file, so fingers of the same X-rays line up) with the quantities
/// measured on all of them, then, when only some of them measure the metacarpal, those
/// with the metacarpal's quantities. O(rows log rows).
pub(crate) fn blocks(data: &Dataset) -> Vec<Block> {
    let mut order: FxHashMap<&str, usize> = FxHashMap::default();
    for r in &data.rows {
        let next = order.len();
        order.entry(&r.xray).or_insert(next);
    }
    // The fingers' blocks are independent: built side by side (rayon), kept in finger order.
    let per_finger: Vec<Vec<Block>> = Finger::ALL
        .par_iter()
        .map(|&f| finger_blocks(data, f, &order))
        .collect();
    per_finger.into_iter().flatten().collect()
}

/// The main block of finger `f` (its rows in the X-rays' first-appearance `order`) and,
/// when only some of its X-rays have the metacarpal, the block of those. O(rows).
fn finger_blocks(data: &Dataset, f: Finger, order: &FxHashMap<&str, usize>) -> Vec<Block> {
    let mut rows: Vec<&Row> = data.rows_of(f).collect();
    if rows.is_empty() {
        return Vec::new();
    }
    // One lookup per row, not one per comparison (a finger has one row per X-ray).
    rows.sort_by_cached_key(|r| order[&*r.xray]);
    let xrays: Vec<XrayValues> = rows.iter().map(|r| xray_values(r)).collect();
    let quantities = quantities(f, &xrays);
    let partial: Vec<XrayValues> = xrays.iter().filter(|x| x.mc.is_some()).cloned().collect();
    let subset = !partial.is_empty() && partial.len() < xrays.len();
    let mut blocks = vec![Block {
        finger: f,
        quantities,
        xrays,
        main: true,
    }];
    if subset {
        blocks.push(Block {
            finger: f,
            quantities: Quantity::METACARPAL.to_vec(),
            xrays: partial,
            main: false,
        });
    }
    blocks
}

/// Indices of `blocks` grouped by equal X-ray sequences (by `same`), in order of first
/// appearance: blocks of a group share one bootstrap.
pub(crate) fn group_by<T>(items: &[T], same: impl Fn(&T, &T) -> bool) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, b) in items.iter().enumerate() {
        match groups.iter_mut().find(|g| same(&items[g[0]], b)) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// True when two lists of X-ray values are of the same X-rays in the same order.
pub(crate) fn same_xrays(a: &[XrayValues], b: &[XrayValues]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.xray == y.xray)
}

impl Block {
    /// The values of every quantity, one column per quantity.
    pub(crate) fn columns(&self) -> Vec<Vec<f64>> {
        self.quantities
            .iter()
            .map(|&q| self.xrays.iter().filter_map(|x| x.value(q)).collect())
            .collect()
    }

    /// The random key of the block's bootstrap when it leads its group: the finger's
    /// index for the finger's own X-rays (as before the metacarpal), 8 + the index for
    /// a metacarpal subset.
    pub(crate) fn key(&self) -> u64 {
        self.finger.index() as u64 + if self.main { 0 } else { 8 }
    }
}

/// Analyses a dataset. Fingers whose X-rays are the same share every bootstrap
/// resample (the X-ray is the unit resampled). Cost: O(B n q) for B resamples.
pub fn analyse(data: &Dataset, settings: &Settings) -> Analysis {
    analyse_with(data, settings, &bootstrap::NoProgress)
}

/// [`analyse`] without the bootstrap: every statistic but the percentile and BCa
/// intervals, which are left empty (`None`). For the rig's judgement, which reads the
/// means, spreads, prediction intervals and X-ray values alone (an audit of a rig
/// against the 910-X-ray atlas spent most of its time on a bootstrap it never read).
/// Cost: O(n q).
pub fn analyse_without_bootstrap(data: &Dataset, settings: &Settings) -> Analysis {
    analyse_inner(data, settings, &bootstrap::NoProgress, false)
}

/// [`analyse`] reporting bootstrap progress (in resamples, over all groups) to `progress`.
pub fn analyse_with(
    data: &Dataset,
    settings: &Settings,
    progress: &dyn bootstrap::Progress,
) -> Analysis {
    analyse_inner(data, settings, progress, true)
}

/// [`analyse_with`], with the bootstrap intervals only when `boot`.
fn analyse_inner(
    data: &Dataset,
    settings: &Settings,
    progress: &dyn bootstrap::Progress,
    boot: bool,
) -> Analysis {
    let unit = data.unit().map(str::to_string);
    let blocks = blocks(data);
    let groups = group_by(&blocks, |a, b| same_xrays(&a.xrays, &b.xrays));
    let random_groups = groups
        .iter()
        .filter(|g| {
            let n = blocks[g[0]].xrays.len();
            boot && matches!(Plan::choose(n, settings.resamples), Plan::Random { .. })
        })
        .count();
    progress.start((random_groups * settings.resamples) as u64);
    let mut stats: Vec<Vec<QuantityStats>> = vec![Vec::new(); blocks.len()];
    let mut plans: Vec<Option<Plan>> = vec![None; blocks.len()];
    for group in &groups {
        let cols: Vec<Vec<Vec<f64>>> = group.iter().map(|&i| blocks[i].columns()).collect();
        let flat: Vec<&[f64]> = cols.iter().flatten().map(Vec::as_slice).collect();
        let key = blocks[group[0]].key();
        let dist = boot.then(|| {
            bootstrap::resample_means_with(&flat, settings.resamples, settings.seed, key, progress)
        });
        // Without the bootstrap, the plan it would follow, with no resample drawn.
        let plan = dist.as_ref().map_or_else(
            || Plan::choose(flat.first().map_or(0, |c| c.len()), settings.resamples),
            |d| d.plan,
        );
        let mut offset = 0;
        for (&i, bcols) in group.iter().zip(&cols) {
            let b = &blocks[i];
            // Each quantity's statistics (a median's sort, the bootstrap means' sort) are
            // independent of the others': computed side by side, collected in order.
            stats[i] = b
                .quantities
                .par_iter()
                .zip(bcols.par_iter())
                .enumerate()
                .map(|(k, (&q, col))| {
                    let boot = dist
                        .as_ref()
                        .map(|d| (d.means[offset + k].as_slice(), &d.weights[..]));
                    let mut s = quantity_stats(q, col, boot, settings);
                    if !b.main {
                        s.notes.push(format!(
                            "from the {} of {} X-rays whose metacarpal is measured",
                            b.xrays.len(),
                            data.rows_of(b.finger).count()
                        ));
                    }
                    s
                })
                .collect();
            plans[i] = Some(plan);
            offset += bcols.len();
        }
    }
    let mut fingers: Vec<FingerAnalysis> = Vec::new();
    for ((b, s), plan) in blocks.into_iter().zip(stats).zip(plans) {
        if b.main {
            fingers.push(FingerAnalysis {
                finger: b.finger,
                n: b.xrays.len(),
                xrays: b.xrays,
                quantities: s,
                bootstrap: plan.unwrap_or(Plan::Exact { distinct: 0 }),
            });
        } else if let Some(f) = fingers.last_mut() {
            f.quantities.extend(s);
        }
    }
    Analysis {
        dataset: DatasetInfo::of(data),
        settings: *settings,
        fingers,
        unit,
        units: data
            .units()
            .into_iter()
            .map(|(u, n)| (u.map(str::to_string), n))
            .collect(),
        tips: data.tips(),
        untipped: data.untipped(),
        flagged: data
            .flagged()
            .map(|r| FlaggedRow {
                xray: r.xray.clone(),
                finger: r.finger,
                line: r.line,
                reason: r.meta.flagged.as_deref().unwrap_or_default().to_string(),
            })
            .collect(),
    }
}

/// Eqs. (1)-(2) for one row.
pub(crate) fn xray_values(row: &Row) -> XrayValues {
    let lengths = Segments::new(row.segments());
    let total = row.total();
    let mut relative = lengths;
    relative.iter_mut().for_each(|l| *l /= total);
    XrayValues {
        xray: row.xray.clone(),
        lengths,
        total,
        relative,
        mc: row.mc,
        unit: row.meta.unit.clone(),
    }
}

/// Every statistic of one quantity, given its values and its bootstrap distribution.
///
/// Degenerate cases: with n = 1 every interval and SD-based statistic is null
/// (no spread can be estimated); with zero spread every interval collapses to
/// the common value. Each case leaves a note.
pub(crate) fn quantity_stats(
    name: Quantity,
    values: &[f64],
    boot: Option<(&[f64], &[f64])>,
    settings: &Settings,
) -> QuantityStats {
    let n = values.len();
    let c = settings.confidence;
    let mean = describe::mean(values).unwrap_or(0.0);
    let (min, max) = describe::min_max(values).unwrap_or((mean, mean));
    let median = describe::median(values).unwrap_or(mean);
    // Values equal up to rounding (e.g. 4/10 and 2/5) count as zero spread.
    let zero_spread = n >= 2 && (max - min) <= 1e-12 * mean.abs();
    let sd = if zero_spread {
        Some(0.0)
    } else {
        describe::sd(values)
    };
    let se = sd.map(|s| s / (n as f64).sqrt());
    let cv = sd.map(|s| s / mean);
    let mut notes = Vec::new();
    let intervals = if n < 2 {
        notes.push("n = 1 X-ray: no spread can be estimated, so every interval is null".into());
        Intervals::NONE
    } else if zero_spread {
        notes.push(
            "every X-ray gives the same value: every interval collapses to that value".into(),
        );
        Intervals::point(mean)
    } else if let Some((boot, weights)) = boot {
        let sorted = Sorted::new(boot, weights);
        let (intervals, why) = Intervals::of_mean(values, mean, sd.unwrap_or(0.0), &sorted, c);
        notes.extend(why.map(str::to_string));
        intervals
    } else {
        Intervals::parametric(mean, sd.unwrap_or(0.0), n, c)
    };
    QuantityStats {
        name,
        n,
        mean,
        sd,
        se,
        median,
        min,
        max,
        range: max - min,
        cv,
        intervals,
        notes,
    }
}

#[cfg(test)]
mod tests;
