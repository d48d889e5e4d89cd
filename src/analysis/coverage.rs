//! How often each interval method really covers, at the dataset's sample size.
//!
//! Simulation from a normal model N(mean, sd^2) fitted to a quantity: draw n
//! values, build every interval, and count how often the confidence intervals
//! contain the model's mean and the prediction interval contains one further
//! draw. All four methods are location-scale equivariant (an affine change of
//! the data moves every interval the same way), so the coverage depends on n
//! alone, not on the fitted mean and SD: quantities of equal n share one
//! simulation (common random numbers), and their coverages are equal.

use crate::stats::bootstrap::{self, Sorted};
use crate::stats::{Interval, Intervals, describe, rng};
use rayon::prelude::*;
use schemars::JsonSchema;
use serde::Serialize;

/// Key of the random streams of the normal model's draws: `COVERAGE_KEY ^ n` for
/// samples of size n (its top byte is 0, apart from every tagged key below).
const COVERAGE_KEY: u64 = 0xC0_7E_4A_6E;
/// Tag of the random bootstrap of each simulated sample ([`stream_key`]). It was
/// `COVERAGE_KEY + 1 + sim`, which met `COVERAGE_KEY ^ n` (sim 15 and n = 16).
const BOOTSTRAP_TAG: u64 = 0x52;

/// The random key of stream family `tag` for sample size `n` and simulation `sim`:
/// tag in bits 56-63, n in bits 32-55, sim in bits 0-31, so no two families, sizes or
/// simulations share a stream (n and sim are below 2^24 and 2^32 where used).
pub(super) fn stream_key(tag: u64, n: usize, sim: u64) -> u64 {
    (tag << 56) | ((n as u64 & 0xFF_FFFF) << 32) | (sim & 0xFFFF_FFFF)
}

/// Settings of a coverage simulation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct CoverageSettings {
    /// Simulated datasets.
    pub sims: usize,
    /// Bootstrap resamples per simulated dataset (exact enumeration when cheaper).
    pub resamples: usize,
    pub seed: u64,
    pub confidence: f64,
    /// Largest sample size simulated; larger ones are skipped with a note
    /// (the cost grows as sims x resamples x n). `None`: no limit.
    pub max_n: Option<usize>,
}

/// The report's limit on simulated sample sizes: beyond a few hundred X-rays the
/// t and bootstrap intervals are close to nominal, and simulating them costs minutes.
pub const REPORT_MAX_N: usize = 200;

/// The estimated coverage of one interval method.
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
pub struct MethodCoverage {
    /// `t`, `percentile`, `bca` or `prediction`.
    pub method: &'static str,
    /// What the interval is meant to contain.
    pub target: &'static str,
    pub nominal: f64,
    /// Fraction of the simulations whose interval contained the target.
    pub coverage: f64,
    /// Monte-Carlo standard error of `coverage`: sqrt(p (1 - p) / sims).
    pub mc_se: f64,
    /// Simulations in which the method gave no interval (counted as misses).
    pub undefined: usize,
}

/// Coverage of every method at one sample size.
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
pub struct Coverage {
    pub n: usize,
    pub sims: usize,
    /// How each simulated bootstrap was done.
    pub bootstrap: bootstrap::Plan,
    pub methods: Vec<MethodCoverage>,
}

/// Simulates the coverage of every interval method for samples of size `n`
/// from N(mean, sd^2). `None` for n < 2 or sd not positive. Cost: O(sims * B * n).
pub fn simulate(n: usize, mean: f64, sd: f64, s: &CoverageSettings) -> Option<Coverage> {
    if n < 2 || sd.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || s.sims == 0 {
        return None;
    }
    let plan = bootstrap::Plan::choose(n, s.resamples);
    // Small n: the exact resamples depend on n only; enumerate them once.
    let enumeration = match plan {
        bootstrap::Plan::Exact { distinct } => Some(bootstrap::Enumeration::new(n, distinct)),
        bootstrap::Plan::Random { .. } => None,
    };
    // hits[method] per simulation: t, percentile, bca, prediction; None = undefined.
    let outcomes: Vec<[Option<bool>; 4]> = (0..s.sims)
        .into_par_iter()
        .map_init(
            || vec![0.0f64; n],
            |xs, sim| {
                let mut r = rng::stream(s.seed, COVERAGE_KEY ^ n as u64, sim as u64);
                xs.iter_mut()
                    .for_each(|x| *x = mean + sd * rng::standard_normal(&mut r));
                let new = mean + sd * rng::standard_normal(&mut r);
                let boot_key = stream_key(BOOTSTRAP_TAG, n, sim as u64);
                one_sample(xs, new, mean, s, boot_key, enumeration.as_ref())
            },
        )
        .collect();
    Some(Coverage {
        n,
        sims: s.sims,
        bootstrap: plan,
        methods: tally(&outcomes, ["mean", "one new X-ray"], s),
    })
}

/// The coverage of each method from the outcomes of every simulation (t, percentile,
/// BCa, prediction; `None` = no interval, counted as a miss): the share of hits and its
/// Monte-Carlo standard error sqrt(p (1 - p) / sims). `targets` names what the
/// confidence intervals and the prediction interval aim at.
pub(super) fn tally(
    outcomes: &[[Option<bool>; 4]],
    targets: [&'static str; 2],
    s: &CoverageSettings,
) -> Vec<MethodCoverage> {
    let [mean, further] = targets;
    let names = [
        ("t", mean),
        ("percentile", mean),
        ("bca", mean),
        ("prediction", further),
    ];
    let sims = outcomes.len();
    names
        .iter()
        .enumerate()
        .map(|(m, &(method, target))| {
            let hits = outcomes.iter().filter(|o| o[m] == Some(true)).count();
            let undefined = outcomes.iter().filter(|o| o[m].is_none()).count();
            let p = hits as f64 / sims as f64;
            MethodCoverage {
                method,
                target,
                nominal: s.confidence,
                coverage: p,
                mc_se: (p * (1.0 - p) / sims as f64).sqrt(),
                undefined,
            }
        })
        .collect()
}

/// The simulated coverage for one quantity of one finger.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct QuantityCoverage {
    pub finger: crate::dataset::Finger,
    pub quantity: super::Quantity,
    pub n: usize,
    /// `None` when coverage cannot be simulated (n < 2 or zero spread); see `note`.
    pub coverage: Option<Coverage>,
    pub note: Option<String>,
}

/// Simulates coverage for every quantity of an analysis. Quantities of equal n
/// share one simulation (coverage depends on n alone; see the module docs).
pub fn of_analysis(a: &super::Analysis, s: &CoverageSettings) -> Vec<QuantityCoverage> {
    let mut by_n: std::collections::BTreeMap<usize, Option<Coverage>> = Default::default();
    let mut out = Vec::new();
    for f in &a.fingers {
        for q in &f.quantities {
            let sd = q.sd.unwrap_or(0.0);
            let (coverage, note) = if q.n < 2 {
                (None, Some("n = 1: no model can be fitted".to_string()))
            } else if sd.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                (
                    None,
                    Some("zero spread: every interval collapses".to_string()),
                )
            } else if let Some(max) = s.max_n.filter(|&m| q.n > m) {
                (
                    None,
                    Some(format!(
                        "not simulated for n > {max}: intervals are close to nominal at this size (run 'phalanx coverage' to check)"
                    )),
                )
            } else {
                let c = by_n
                    .entry(q.n)
                    .or_insert_with(|| simulate(q.n, q.mean, sd, s))
                    .clone();
                (c, None)
            };
            out.push(QuantityCoverage {
                finger: f.finger,
                quantity: q.name,
                n: q.n,
                coverage,
                note,
            });
        }
    }
    out
}

/// Whether each interval of one sample `xs` holds its target: the t, percentile and BCa
/// intervals the mean `truth`, the prediction interval the further value `new`; `None`
/// when the method gives no interval. The intervals are those the statistics give
/// ([`Intervals::of_mean`]). The bootstrap is the exact `enumeration` when given, else
/// `s.resamples` random resamples from key (`s.seed`, `boot_key`). Shared by the normal
/// model's simulation and [`super::population`]'s ([`samples_cover`] with one column).
pub(super) fn one_sample(
    xs: &[f64],
    new: f64,
    truth: f64,
    s: &CoverageSettings,
    boot_key: u64,
    enumeration: Option<&bootstrap::Enumeration>,
) -> [Option<bool>; 4] {
    samples_cover(&[xs], &[new], &[truth], s, boot_key, enumeration)[0]
}

/// [`one_sample`] for several quantities measured on the same sampled X-rays: column k of
/// `xs` is quantity k's sample, `new[k]` its value on the further X-ray, `truth[k]` its
/// mean. The quantities share one bootstrap (the X-ray is resampled), as in the analysis.
pub(super) fn samples_cover(
    xs: &[&[f64]],
    new: &[f64],
    truth: &[f64],
    s: &CoverageSettings,
    boot_key: u64,
    enumeration: Option<&bootstrap::Enumeration>,
) -> Vec<[Option<bool>; 4]> {
    let dist = match enumeration {
        Some(e) => e.distribution(xs),
        None => bootstrap::resample_means(xs, s.resamples, s.seed, boot_key),
    };
    xs.iter()
        .zip(&dist.means)
        .zip(new.iter().zip(truth))
        .map(|((xs, means), (&new, &truth))| {
            let (Some(m), Some(sd)) = (describe::mean(xs), describe::sd(xs)) else {
                return [None; 4];
            };
            let sorted = Sorted::new(means, &dist.weights);
            // The same four intervals the statistics give.
            let (iv, _) = Intervals::of_mean(xs, m, sd, &sorted, s.confidence);
            let covers = |i: Option<Interval>, x: f64| i.map(|i| i.contains(x));
            [
                covers(iv.ci_t, truth),
                covers(iv.ci_percentile, truth),
                covers(iv.ci_bca, truth),
                covers(iv.pi, new),
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(sims: usize) -> CoverageSettings {
        CoverageSettings {
            sims,
            resamples: 10_000,
            seed: 1,
            confidence: 0.95,
            max_n: None,
        }
    }

    #[test]
    fn small_samples_bootstrap_undercovers_t_holds() {
        let c = simulate(5, 0.5, 0.01, &settings(4000)).unwrap();
        let get = |m: &str| c.methods.iter().find(|x| x.method == m).unwrap().coverage;
        // Theory: the t interval covers exactly 95%; the prediction interval too.
        // 4000 sims: MC SE 0.0034, so allow 4 SE.
        assert!((get("t") - 0.95).abs() < 0.014, "{}", get("t"));
        assert!(
            (get("prediction") - 0.95).abs() < 0.014,
            "{}",
            get("prediction")
        );
        // The percentile interval of the mean at n = 5 covers far less (about 0.83 here; Efron
        // and Tibshirani's "narrowness bias" of sqrt((n-1)/n) and z for t).
        assert!(
            get("percentile") < 0.88 && get("percentile") > 0.75,
            "{}",
            get("percentile")
        );
        assert!(get("bca") < 0.90, "{}", get("bca"));
        assert_eq!(c.bootstrap, bootstrap::Plan::Exact { distinct: 126 });
    }

    #[test]
    fn coverage_is_location_scale_free() {
        let a = simulate(5, 0.0, 1.0, &settings(300)).unwrap();
        let b = simulate(5, 700.0, 35.0, &settings(300)).unwrap();
        for (x, y) in a.methods.iter().zip(&b.methods) {
            assert!(
                (x.coverage - y.coverage).abs() <= 2.0 / 300.0,
                "{x:?} {y:?}"
            );
        }
        assert!(simulate(1, 0.0, 1.0, &settings(10)).is_none());
    }

    #[test]
    fn large_samples_are_skipped_beyond_the_limit() {
        use crate::analysis::{Settings, analyse};
        let text: String = std::iter::once("xray,finger,j1,j2,j3\n".to_string())
            .chain((0..12).map(|i| format!("x{i},index,{},20,10\n", 30 + i)))
            .collect();
        let d = crate::dataset::Dataset::from_bytes("t.csv", text.as_bytes()).unwrap();
        let a = analyse(&d, &Settings::default());
        let limited = CoverageSettings {
            max_n: Some(10),
            ..settings(50)
        };
        let rows = of_analysis(&a, &limited);
        assert!(rows.iter().all(|r| r.coverage.is_none()));
        assert!(
            rows[0]
                .note
                .as_deref()
                .unwrap()
                .contains("not simulated for n > 10")
        );
        let rows = of_analysis(
            &a,
            &CoverageSettings {
                max_n: Some(12),
                ..settings(50)
            },
        );
        // Every quantity with spread is simulated (J3/J2 = 10/20 has none).
        for r in &rows {
            let constant = r.quantity == crate::analysis::Quantity::RatioJ3J2;
            assert_eq!(r.coverage.is_some(), !constant, "{:?}", r.quantity);
        }
        assert!(simulate(5, 0.0, 0.0, &settings(10)).is_none());
    }
}
