//! Statistics of finger-segment proportions: the paper's and beyond.
//!
//! For each finger and X-ray: the total J = sum J_k (eq. 1) and the relative
//! values J~k = J_k / J (eq. 2). For each quantity over the X-rays: the paper's
//! mean (eq. 5), min and max (eq. 7) and range (eq. 9), then SD, SE, median, CV,
//! Student-t, bootstrap percentile and BCa intervals of the mean, and a
//! prediction interval for one new X-ray. Knows nothing of files or rendering.

pub(crate) mod budget;
pub mod claims;
pub mod coverage;
pub mod groups;
pub(crate) mod outliers;
pub mod placement;
pub(crate) mod plausible;
pub(crate) mod tracking;

/// The interval type of [`crate::stats`] and the quantities of [`crate::dataset`],
/// also here for the analysis's callers.
pub use crate::dataset::Quantity;
pub use crate::stats::Interval;

use crate::dataset::{Dataset, Finger, Row};
use crate::stats::Intervals;
use crate::stats::bootstrap::{self, Plan, Sorted};
use crate::stats::describe;
use schemars::JsonSchema;
use serde::Serialize;
use std::collections::HashMap;
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

/// The derived values of one X-ray for one finger (eqs. 1-2).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct XrayValues {
    pub xray: Arc<str>,
    /// J1, J2[, J3] in data units.
    pub lengths: Vec<f64>,
    /// J = sum of the lengths (eq. 1).
    pub total: f64,
    /// J~k = J_k / J for every segment (eq. 2).
    pub relative: Vec<f64>,
}

impl XrayValues {
    /// The value of quantity `q` on this X-ray.
    pub fn value(&self, q: Quantity) -> f64 {
        match q {
            Quantity::RelJ1 => self.relative[0],
            Quantity::RelJ2 => self.relative[1],
            Quantity::RelJ3 => self.relative[2],
            Quantity::RatioJ2J1 => self.lengths[1] / self.lengths[0],
            Quantity::RatioJ3J2 => self.lengths[2] / self.lengths[1],
            Quantity::Total => self.total,
        }
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
        .map(|&q| xrays.iter().map(|x| x.value(q)).collect())
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
pub(crate) fn xray_values(row: &Row) -> XrayValues {
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
pub(crate) fn quantity_stats(
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
    let intervals = if n < 2 {
        notes.push("n = 1 X-ray: no spread can be estimated, so every interval is null".into());
        Intervals::NONE
    } else if zero_spread {
        notes.push(
            "every X-ray gives the same value: every interval collapses to that value".into(),
        );
        Intervals::point(mean)
    } else {
        let sorted = Sorted::new(boot, weights);
        let (intervals, why) = Intervals::of_mean(values, mean, sd.unwrap_or(0.0), &sorted, c);
        notes.extend(why.map(str::to_string));
        intervals
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
