//! Statistics of finger-segment proportions: the paper's and beyond.
//!
//! For each finger and X-ray: the total J = sum J_k (eq. 1) and the relative
//! values J~k = J_k / J (eq. 2). For each quantity over the X-rays: the paper's
//! mean (eq. 5), min and max (eq. 7) and range (eq. 9), then SD, SE, median, CV,
//! Student-t, bootstrap percentile and BCa intervals of the mean, and a
//! prediction interval for one new X-ray. Knows nothing of files or rendering.

pub mod audit;
pub mod bootstrap;
pub mod claims;
pub mod compare;
pub mod coverage;
pub mod describe;
pub mod groups;
pub mod placement;
pub mod population;
pub mod rng;
pub mod tracking;

use crate::dataset::{Dataset, Finger, Row};
use bootstrap::{Plan, Sorted};
use serde::{Serialize, Serializer};
use std::collections::HashMap;
use std::sync::Arc;

/// The default seed: the paper's publication date, 2013-01-01, as a number.
pub const DEFAULT_SEED: u64 = 20_130_101;
/// Default number of bootstrap resamples.
pub const DEFAULT_RESAMPLES: usize = 10_000;
/// Default confidence level of every interval.
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// Settings of an analysis.
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

/// A closed interval `[low, high]`; serialised as a two-element array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub low: f64,
    pub high: f64,
}

impl Interval {
    pub fn new(low: f64, high: f64) -> Interval {
        Interval { low, high }
    }

    /// A zero-width interval at `x`.
    pub fn point(x: f64) -> Interval {
        Interval { low: x, high: x }
    }

    /// high - low.
    pub fn width(&self) -> f64 {
        self.high - self.low
    }

    /// True when `low <= x <= high`.
    pub fn contains(&self, x: f64) -> bool {
        self.low <= x && x <= self.high
    }

    /// The interval multiplied by a non-negative factor.
    pub fn scaled(&self, k: f64) -> Interval {
        Interval::new(self.low * k, self.high * k)
    }
}

impl Serialize for Interval {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        [self.low, self.high].serialize(s)
    }
}

/// A quantity measured once per X-ray of a finger.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Quantity {
    /// J~1 = J1 / J.
    RelJ1,
    /// J~2 = J2 / J.
    RelJ2,
    /// J~3 = J3 / J (not for the thumb).
    RelJ3,
    /// J2 / J1, the ratio of adjacent segments (needs no fingertip).
    RatioJ2J1,
    /// J3 / J2 (not for the thumb).
    RatioJ3J2,
    /// J, the total length in data units.
    Total,
}

impl Quantity {
    /// Every quantity, in output order.
    pub const ALL: [Quantity; 6] = [
        Quantity::RelJ1,
        Quantity::RelJ2,
        Quantity::RelJ3,
        Quantity::RatioJ2J1,
        Quantity::RatioJ3J2,
        Quantity::Total,
    ];

    /// The quantities of a finger.
    pub fn of(finger: Finger) -> &'static [Quantity] {
        match finger {
            Finger::Thumb => &[
                Quantity::RelJ1,
                Quantity::RelJ2,
                Quantity::RatioJ2J1,
                Quantity::Total,
            ],
            _ => &Quantity::ALL,
        }
    }

    /// Machine name (`rel_j1`, ..., `total`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::RelJ1 => "rel_j1",
            Quantity::RelJ2 => "rel_j2",
            Quantity::RelJ3 => "rel_j3",
            Quantity::RatioJ2J1 => "ratio_j2_j1",
            Quantity::RatioJ3J2 => "ratio_j3_j2",
            Quantity::Total => "total",
        }
    }

    /// Parses a machine name.
    pub fn parse(text: &str) -> Option<Quantity> {
        Quantity::ALL
            .into_iter()
            .find(|q| q.name() == text.trim().to_ascii_lowercase())
    }

    /// Name for people, in the paper's notation.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::RelJ1 => "J~1 = J1/J",
            Quantity::RelJ2 => "J~2 = J2/J",
            Quantity::RelJ3 => "J~3 = J3/J",
            Quantity::RatioJ2J1 => "J2/J1",
            Quantity::RatioJ3J2 => "J3/J2",
            Quantity::Total => "J (total length)",
        }
    }

    /// The symbol alone: "J~1", "J2/J1", "J (total length)".
    pub fn symbol(self) -> &'static str {
        self.label().split(" = ").next().unwrap_or(self.name())
    }

    /// True for the relative values J~k (fractions of the total length).
    pub fn is_relative(self) -> bool {
        matches!(self, Quantity::RelJ1 | Quantity::RelJ2 | Quantity::RelJ3)
    }

    /// True for every quantity without a unit (relative values and ratios).
    pub fn is_unitless(self) -> bool {
        self != Quantity::Total
    }

    /// The value of this quantity for one X-ray's derived values.
    pub fn of_xray(self, x: &XrayValues) -> f64 {
        match self {
            Quantity::RelJ1 => x.relative[0],
            Quantity::RelJ2 => x.relative[1],
            Quantity::RelJ3 => x.relative[2],
            Quantity::RatioJ2J1 => x.lengths[1] / x.lengths[0],
            Quantity::RatioJ3J2 => x.lengths[2] / x.lengths[1],
            Quantity::Total => x.total,
        }
    }
}

impl Serialize for Quantity {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// The derived values of one X-ray for one finger (eqs. 1-2).
#[derive(Debug, Clone, Serialize)]
pub struct XrayValues {
    pub xray: Arc<str>,
    /// J1, J2[, J3] in data units.
    pub lengths: Vec<f64>,
    /// J = sum of the lengths (eq. 1).
    pub total: f64,
    /// J~k = J_k / J for every segment (eq. 2).
    pub relative: Vec<f64>,
}

/// Every statistic of one quantity over the X-rays of a finger.
#[derive(Debug, Clone, Serialize)]
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
    pub ci_t: Option<Interval>,
    pub ci_percentile: Option<Interval>,
    pub ci_bca: Option<Interval>,
    /// Prediction interval for one new X-ray.
    pub pi: Option<Interval>,
    /// Why an interval is null or collapsed, when it is.
    pub notes: Vec<String>,
}

/// The analysis of one finger.
#[derive(Debug, Clone, Serialize)]
pub struct FingerAnalysis {
    pub finger: Finger,
    /// Number of X-rays with this finger.
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
}

/// What an analysis was computed from: enough to cite the dataset, not its rows.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
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
}

impl Analysis {
    /// The analysis of one finger, if the data has it.
    pub fn finger(&self, f: Finger) -> Option<&FingerAnalysis> {
        self.fingers.iter().find(|a| a.finger == f)
    }
}

/// The values of every quantity of a finger, one column per quantity.
fn columns(finger: Finger, xrays: &[XrayValues]) -> Vec<Vec<f64>> {
    Quantity::of(finger)
        .iter()
        .map(|q| xrays.iter().map(|x| q.of_xray(x)).collect())
        .collect()
}

/// Analyses a dataset. Fingers whose X-rays are the same share every bootstrap
/// resample (the X-ray is the unit resampled). Cost: O(B n q) for B resamples.
pub fn analyse(data: &Dataset, settings: &Settings) -> Analysis {
    analyse_with(data, settings, &bootstrap::NoProgress)
}

/// [`analyse`] reporting bootstrap progress (in resamples, over all groups) to `progress`.
pub fn analyse_with(
    data: &Dataset,
    settings: &Settings,
    progress: &dyn bootstrap::Progress,
) -> Analysis {
    // X-rays in order of first appearance, so fingers of the same X-rays line up.
    let mut order: HashMap<&str, usize> = HashMap::new();
    for r in &data.rows {
        let next = order.len();
        order.entry(&r.xray).or_insert(next);
    }
    let mut per_finger: Vec<(Finger, Vec<XrayValues>)> = Vec::new();
    for f in Finger::ALL {
        let mut rows: Vec<&Row> = data.rows_of(f).collect();
        if rows.is_empty() {
            continue;
        }
        rows.sort_by_key(|r| order[&*r.xray]);
        let xrays = rows.iter().map(|r| xray_values(r)).collect();
        per_finger.push((f, xrays));
    }
    // Group fingers by their X-ray sequence; each group shares one bootstrap.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, (_, xs)) in per_finger.iter().enumerate() {
        let same = |g: &Vec<usize>| {
            let ys = &per_finger[g[0]].1;
            ys.len() == xs.len() && ys.iter().zip(xs).all(|(a, b)| a.xray == b.xray)
        };
        match groups.iter_mut().find(|g| same(g)) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    let random_groups = groups
        .iter()
        .filter(|g| {
            let n = per_finger[g[0]].1.len();
            matches!(Plan::choose(n, settings.resamples), Plan::Random { .. })
        })
        .count();
    progress.start((random_groups * settings.resamples) as u64);
    let mut results: Vec<Option<FingerAnalysis>> = vec![None; per_finger.len()];
    let mut per_finger: Vec<(Finger, Option<Vec<XrayValues>>)> =
        per_finger.into_iter().map(|(f, x)| (f, Some(x))).collect();
    for group in &groups {
        let cols: Vec<Vec<Vec<f64>>> = group
            .iter()
            .map(|&i| columns(per_finger[i].0, per_finger[i].1.as_deref().unwrap_or(&[])))
            .collect();
        let flat: Vec<&[f64]> = cols.iter().flatten().map(Vec::as_slice).collect();
        let key = per_finger[group[0]].0.index() as u64;
        let dist =
            bootstrap::resample_means_with(&flat, settings.resamples, settings.seed, key, progress);
        let mut offset = 0;
        for (&i, fcols) in group.iter().zip(&cols) {
            let finger = per_finger[i].0;
            let xrays = per_finger[i].1.take().unwrap_or_default();
            let quantities = Quantity::of(finger)
                .iter()
                .zip(fcols)
                .enumerate()
                .map(|(k, (&q, col))| {
                    quantity_stats(q, col, &dist.means[offset + k], &dist.weights, settings)
                })
                .collect();
            offset += fcols.len();
            results[i] = Some(FingerAnalysis {
                finger,
                n: xrays.len(),
                xrays,
                quantities,
                bootstrap: dist.plan,
            });
        }
    }
    Analysis {
        dataset: DatasetInfo::of(data),
        settings: *settings,
        fingers: results.into_iter().flatten().collect(),
    }
}

/// Eqs. (1)-(2) for one row.
pub fn xray_values(row: &Row) -> XrayValues {
    let lengths = row.segments().to_vec();
    let total = row.total();
    let relative = lengths.iter().map(|l| l / total).collect();
    XrayValues {
        xray: row.xray.clone(),
        lengths,
        total,
        relative,
    }
}

/// Every statistic of one quantity, given its values and its bootstrap distribution.
///
/// Degenerate cases: with n = 1 every interval and SD-based statistic is null
/// (no spread can be estimated); with zero spread every interval collapses to
/// the common value. Each case leaves a note.
pub fn quantity_stats(
    name: Quantity,
    values: &[f64],
    boot: &[f64],
    weights: &[f64],
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
    let (ci_t, ci_percentile, ci_bca, pi);
    if n < 2 {
        notes.push("n = 1: no spread can be estimated, so every interval is null".into());
        (ci_t, ci_percentile, ci_bca, pi) = (None, None, None, None);
    } else if zero_spread {
        notes.push(
            "every X-ray gives the same value: every interval collapses to that value".into(),
        );
        let p = Some(Interval::point(mean));
        (ci_t, ci_percentile, ci_bca, pi) = (p, p, p, p);
    } else {
        let s = sd.unwrap_or(0.0);
        ci_t = describe::t_interval(mean, s, n, c);
        pi = describe::prediction_interval(mean, s, n, c);
        let sorted = Sorted::new(boot, weights);
        ci_percentile = Some(bootstrap::percentile_interval(&sorted, c));
        ci_bca = match bootstrap::bca_interval(&sorted, values, mean, c) {
            Ok(i) => Some(i),
            Err(reason) => {
                notes.push(reason.to_string());
                None
            }
        };
    }
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
        ci_t,
        ci_percentile,
        ci_bca,
        pi,
        notes,
    }
}

#[cfg(test)]
mod tests;
