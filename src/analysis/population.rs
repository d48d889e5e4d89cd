//! How often each interval method covers, measured on a real population instead of a model.
//!
//! A large set of values (e.g. the J~2 of the 910 index fingers of an atlas) is taken as
//! the population. Each simulation draws a sample of n values from it, builds every
//! interval the analysis reports (Student t, bootstrap percentile and BCa intervals of the
//! mean, and the prediction interval for one new X-ray), and counts whether the confidence
//! intervals contain the population mean and whether the prediction interval contains one
//! further value drawn from the population. Unlike [`super::coverage`], which draws from a
//! fitted normal model, this keeps the real shape of the data: its skew, tails and ties.
//!
//! Draws are **with replacement** (each value of a sample is an independent uniform draw
//! from the population), so the sample is i.i.d. from the population's distribution, whose
//! mean is exactly the population mean the intervals aim at, and the further value is a
//! new independent draw, as the prediction interval assumes. Drawing without replacement
//! would make the values of a sample slightly dependent (a finite-population correction
//! of sqrt(1 - n/N), 0.997 for n = 5 of 910), which none of the intervals assumes.

use super::coverage::{Coverage, CoverageSettings, samples_cover, stream_key as key, tally};
use super::{Quantity, blocks, group_by, same_xrays};
use crate::dataset::{Dataset, Finger};
use crate::stats::bootstrap::{Enumeration, Plan};
use crate::stats::{describe, rng};
use rayon::prelude::*;
use schemars::JsonSchema;
use serde::Serialize;

/// Tag in the top byte of the random keys of the samples drawn.
const SAMPLE_TAG: u64 = 0x50;
/// Tag in the top byte of the random keys of each sample's bootstrap.
const BOOTSTRAP_TAG: u64 = 0x51;
/// Largest sample size simulated (the key holds it in 24 bits).
pub const MAX_N: usize = (1 << 24) - 1;

/// The coverage of every interval method on samples of one size from a population.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct PopulationCoverage {
    /// Values in the population.
    pub population: usize,
    /// The population mean, the target of the confidence intervals.
    pub mean: f64,
    /// The population SD (divisor N), for the normal model beside it.
    pub sd: f64,
    /// Methods `t`, `percentile`, `bca` and `prediction`, as [`super::coverage::simulate`] gives.
    pub coverage: Coverage,
}

/// Simulates `s.sims` samples of `n` values drawn with replacement from `population`
/// (see the module documentation): [`simulate_all`] with one column. `s.max_n` is not
/// used here.
pub fn simulate(population: &[f64], n: usize, s: &CoverageSettings) -> Option<PopulationCoverage> {
    simulate_all(&[population], n, s, 0)?.pop()
}

/// Simulates `s.sims` samples of `n` X-rays drawn with replacement from a population of
/// X-rays measured on several quantities: column k holds quantity k of every X-ray, all
/// columns in one X-ray order. Each simulation draws n X-rays and one further X-ray, and
/// every quantity is scored on them; the quantities share each sample's bootstrap, as the
/// analysis shares its resamples. `group` separates the streams of populations simulated
/// under one seed (below 32).
///
/// Simulation `i` draws its n sample indices and then the further X-ray's index from
/// ChaCha8 stream `i` of key (seed, [`key`](SAMPLE_TAG, n, group)) with the crate's
/// unbiased index draw; a random bootstrap (when the exact enumeration of C(2n-1, n)
/// resamples exceeds `s.resamples`) uses key (seed, key(BOOTSTRAP_TAG, n, i)) for group 0
/// and key(0x60 + group, n, i) for the others. The result is the same on every machine
/// and thread count, and a quantity's coverage does not depend on the other columns.
///
/// `None` when n < 2 or above [`MAX_N`], `s.sims` is 0 or above 2^32, `group` is 32 or
/// more, there are no columns, or a column has under 2 values, 2^32 or more, a length
/// other than the first's, a value that is not finite, or no spread.
/// Cost: O(sims (n + B n q)) for B bootstrap points per sample and q columns.
pub fn simulate_all(
    columns: &[&[f64]],
    n: usize,
    s: &CoverageSettings,
    group: u64,
) -> Option<Vec<PopulationCoverage>> {
    let first = columns.first()?;
    let size = u32::try_from(first.len()).ok()?;
    if !(2..=MAX_N).contains(&n) || s.sims == 0 || u32::try_from(s.sims).is_err() || size < 2 {
        return None;
    }
    if group >= 32 || columns.iter().any(|c| c.len() != first.len()) {
        return None;
    }
    let moments = column_moments(columns, size)?;
    let truths: Vec<f64> = moments.iter().map(|m| m.0).collect();
    let plan = Plan::choose(n, s.resamples);
    let enumeration = match plan {
        Plan::Exact { distinct } => Some(Enumeration::new(n, distinct)),
        Plan::Random { .. } => None,
    };
    let boot_tag = if group == 0 {
        BOOTSTRAP_TAG
    } else {
        0x60 + group
    };
    let q = columns.len();
    let outcomes: Vec<Vec<[Option<bool>; 4]>> = (0..s.sims as u64)
        .into_par_iter()
        .map_init(
            || (vec![vec![0.0f64; n]; q], vec![0.0f64; q]),
            |(xs, further), sim| {
                let mut r = rng::stream(s.seed, key(SAMPLE_TAG, n, group), sim);
                draw_sample(&mut r, columns, size, xs, further);
                let cols: Vec<&[f64]> = xs.iter().map(Vec::as_slice).collect();
                let boot_key = key(boot_tag, n, sim);
                samples_cover(&cols, further, &truths, s, boot_key, enumeration.as_ref())
            },
        )
        .collect();
    Some(
        moments
            .iter()
            .enumerate()
            .map(|(k, &(mean, sd))| {
                let column: Vec<[Option<bool>; 4]> = outcomes.iter().map(|o| o[k]).collect();
                PopulationCoverage {
                    population: first.len(),
                    mean,
                    sd,
                    coverage: Coverage {
                        n,
                        sims: s.sims,
                        bootstrap: plan,
                        methods: tally(
                            &column,
                            ["the population mean", "one further X-ray of the population"],
                            s,
                        ),
                    },
                }
            })
            .collect(),
    )
}

/// Each column's mean and population SD (divisor `size`); `None` when a value is not
/// finite or a column has no spread.
fn column_moments(columns: &[&[f64]], size: u32) -> Option<Vec<(f64, f64)>> {
    let mut moments = Vec::with_capacity(columns.len());
    for c in columns {
        if c.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let mean = describe::mean(c)?;
        let var = c.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / f64::from(size);
        if var.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        moments.push((mean, var.sqrt()));
    }
    Some(moments)
}

/// Draws one sample of `xs[0].len()` X-rays (every column's values at the same rows) into
/// `xs`, then one further X-ray into `further`, each row uniform over the `size` rows.
fn draw_sample(
    r: &mut rand_chacha::ChaCha8Rng,
    columns: &[&[f64]],
    size: u32,
    xs: &mut [Vec<f64>],
    further: &mut [f64],
) {
    let n = xs.first().map_or(0, Vec::len);
    for i in 0..n {
        let row = rng::index(r, size) as usize;
        for (x, c) in xs.iter_mut().zip(columns) {
            x[i] = c[row];
        }
    }
    let row = rng::index(r, size) as usize;
    for (f, c) in further.iter_mut().zip(columns) {
        *f = c[row];
    }
}

/// The coverage of one quantity of one finger at each sample size.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct QuantityPopulation {
    pub finger: Finger,
    pub quantity: Quantity,
    /// X-rays in the population.
    pub population: usize,
    /// The population mean (the target) and SD (divisor N).
    pub mean: f64,
    pub sd: f64,
    /// One per size of [`PopulationStudy::sizes`] that could be simulated, in order.
    pub by_n: Vec<Coverage>,
}

/// Every method's coverage over the quantities at one sample size: the mean, lowest and
/// highest of the quantities' coverages.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Pooled {
    pub n: usize,
    pub method: &'static str,
    pub mean: f64,
    pub min: f64,
    pub max: f64,
}

/// A dataset taken as the population: every quantity's coverage at each sample size, and
/// the normal model's beside it.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct PopulationStudy {
    pub sizes: Vec<usize>,
    pub settings: CoverageSettings,
    pub quantities: Vec<QuantityPopulation>,
    /// The normal model's coverage at each size ([`super::coverage::simulate`]; it depends
    /// on n alone).
    pub normal: Vec<Coverage>,
    /// What was not simulated and why.
    pub notes: Vec<String>,
}

impl PopulationStudy {
    /// Each method's coverage over the quantities, per size in order, then per method.
    pub fn pooled(&self) -> Vec<Pooled> {
        let mut out = Vec::new();
        for &n in &self.sizes {
            for method in ["t", "percentile", "bca", "prediction"] {
                let values: Vec<f64> = self
                    .quantities
                    .iter()
                    .flat_map(|q| q.by_n.iter().filter(|c| c.n == n))
                    .flat_map(|c| c.methods.iter().filter(|m| m.method == method))
                    .map(|m| m.coverage)
                    .collect();
                if let (Some(mean), Some((min, max))) =
                    (describe::mean(&values), describe::min_max(&values))
                {
                    out.push(Pooled {
                        n,
                        method,
                        mean,
                        min,
                        max,
                    });
                }
            }
        }
        out
    }
}

/// Takes `data` as the population (its X-rays drawn with replacement) and simulates, at
/// each of `sizes`, the coverage of every quantity `keep` accepts ([`simulate_all`]:
/// quantities of the same X-rays share samples and bootstraps), with the normal model's
/// coverage beside it. Quantities without spread, and sizes below 2, are left out with a
/// note. Cost: O(sizes sims (n + B n q)).
pub fn of_dataset(
    data: &Dataset,
    sizes: &[usize],
    s: &CoverageSettings,
    keep: impl Fn(Quantity) -> bool,
) -> PopulationStudy {
    let mut notes = Vec::new();
    let sizes = valid_sizes(sizes, &mut notes);
    let blocks = blocks(data);
    let groups = group_by(&blocks, |a, b| same_xrays(&a.xrays, &b.xrays));
    let mut quantities = Vec::new();
    for (g, group) in groups.iter().enumerate() {
        let cols = group_columns(&blocks, group, &keep, &mut notes);
        if cols.is_empty() {
            continue;
        }
        quantities.extend(simulate_group(cols, &sizes, s, g, &mut notes));
    }
    quantities.sort_by_key(|q| (q.finger, q.quantity));
    let normal = sizes
        .iter()
        .filter_map(|&n| super::coverage::simulate(n, 0.0, 1.0, s))
        .collect();
    PopulationStudy {
        sizes,
        settings: *s,
        quantities,
        normal,
        notes,
    }
}

/// The sizes from 2 to [`MAX_N`], in order; each other one is left out with a note.
fn valid_sizes(sizes: &[usize], notes: &mut Vec<String>) -> Vec<usize> {
    sizes
        .iter()
        .copied()
        .filter(|&n| {
            let ok = (2..=MAX_N).contains(&n);
            if !ok {
                notes.push(format!("n = {n}: samples need 2 to {MAX_N} X-rays"));
            }
            ok
        })
        .collect()
}

/// (finger, quantity, values) of a group's kept quantities with spread; those with
/// fewer than 2 X-rays or no spread are left out with a note.
fn group_columns(
    blocks: &[super::Block],
    group: &[usize],
    keep: &impl Fn(Quantity) -> bool,
    notes: &mut Vec<String>,
) -> Vec<(Finger, Quantity, Vec<f64>)> {
    let mut cols = Vec::new();
    for &i in group {
        let b = &blocks[i];
        for (&q, col) in b.quantities.iter().zip(b.columns()) {
            if !keep(q) {
                continue;
            }
            match describe::min_max(&col) {
                Some((lo, hi)) if col.len() >= 2 && hi > lo => cols.push((b.finger, q, col)),
                _ => notes.push(format!(
                    "{} {}: fewer than 2 X-rays or no spread, not simulated",
                    b.finger.name(),
                    q.name()
                )),
            }
        }
    }
    cols
}

/// The coverage of group `g`'s columns at each size ([`simulate_all`]: they share
/// samples and bootstraps); a size that cannot be simulated is left out with a note.
fn simulate_group(
    cols: Vec<(Finger, Quantity, Vec<f64>)>,
    sizes: &[usize],
    s: &CoverageSettings,
    g: usize,
    notes: &mut Vec<String>,
) -> Vec<QuantityPopulation> {
    let slices: Vec<&[f64]> = cols.iter().map(|c| c.2.as_slice()).collect();
    let mut by_n: Vec<Vec<Coverage>> = vec![Vec::new(); cols.len()];
    let mut moments: Vec<(f64, f64)> = vec![(0.0, 0.0); cols.len()];
    for &n in sizes {
        let Some(all) = simulate_all(&slices, n, s, g as u64) else {
            notes.push(format!("group {g} at n = {n} could not be simulated"));
            continue;
        };
        for (k, p) in all.into_iter().enumerate() {
            moments[k] = (p.mean, p.sd);
            by_n[k].push(p.coverage);
        }
    }
    cols.into_iter()
        .zip(by_n.into_iter().zip(moments))
        .map(
            |((finger, quantity, col), (by_n, (mean, sd)))| QuantityPopulation {
                finger,
                quantity,
                population: col.len(),
                mean,
                sd,
                by_n,
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::coverage::MethodCoverage;
    use crate::dataset::Finger;
    use crate::dataset::landmarks::{self, Layout};

    fn settings(sims: usize, resamples: usize) -> CoverageSettings {
        CoverageSettings {
            sims,
            resamples,
            seed: 20_130_101,
            confidence: 0.95,
            max_n: None,
        }
    }

    /// The relative value J~k of one finger of every atlas hand, or `None` (with the
    /// reason printed) when the atlas is absent.
    fn atlas_values(finger: Finger, k: usize) -> Option<Vec<f64>> {
        let bytes = crate::dataset::vendored::read(crate::dataset::vendored::ATLAS_LANDMARKS)?;
        let i = landmarks::import(Layout::Atlas37, "atlas", &bytes, &Default::default()).ok()?;
        Some(
            i.rows
                .iter()
                .filter(|r| r.finger == finger)
                .map(|r| r.lengths[k] / r.total())
                .collect(),
        )
    }

    fn get(c: &PopulationCoverage, method: &str) -> MethodCoverage {
        c.coverage
            .methods
            .iter()
            .find(|m| m.method == method)
            .cloned()
            .unwrap()
    }

    /// Section 3 of tests/independent/atlas_reference.py (NumPy, 200,000 simulations of
    /// n = 5 drawn with replacement from the atlas, the exact bootstrap enumerated there
    /// too): coverage of t, percentile, BCa and prediction intervals.
    const NUMPY_N5: [(Finger, usize, [f64; 4]); 2] = [
        (Finger::Index, 1, [0.94942, 0.83906, 0.83925, 0.94849]),
        (Finger::Little, 2, [0.95813, 0.83239, 0.82282, 0.93955]),
    ];

    /// Simulates `sims` samples of 5 from each population of [`NUMPY_N5`] and checks each
    /// method against NumPy within 4 binomial SEs of the difference,
    /// 4 sqrt(p(1-p)/sims + p(1-p)/200000).
    fn check_against_numpy(sims: usize) {
        for (finger, k, want) in NUMPY_N5 {
            let Some(pop) = atlas_values(finger, k) else {
                return;
            };
            assert_eq!(pop.len(), 910);
            let c = simulate(&pop, 5, &settings(sims, 10_000)).unwrap();
            assert_eq!(c.coverage.bootstrap, Plan::Exact { distinct: 126 });
            for (method, p) in ["t", "percentile", "bca", "prediction"].iter().zip(want) {
                let got = get(&c, method);
                let se = (p * (1.0 - p) / sims as f64 + p * (1.0 - p) / 200_000.0).sqrt();
                assert!(
                    (got.coverage - p).abs() < 4.0 * se,
                    "{finger} J~{} {method}: {} vs {p} (4 SE = {})",
                    k + 1,
                    got.coverage,
                    4.0 * se
                );
                assert_eq!(got.undefined, 0);
            }
        }
    }

    #[test]
    fn coverage_on_the_atlas_matches_an_independent_simulation() {
        // 2000 simulations: 4 SE is 0.020 for t and prediction, 0.033 for the percentile
        // and BCa intervals, which still tells their 0.83 from the nominal 0.95.
        check_against_numpy(2000);
    }

    #[test]
    #[ignore = "40,000 simulations take about half a minute in a debug build; run with --ignored"]
    fn coverage_on_the_atlas_matches_an_independent_simulation_closely() {
        // 4 SE: 0.0045 for t and prediction, 0.0077 for the percentile and BCa intervals.
        check_against_numpy(40_000);
    }

    #[test]
    fn a_normal_population_gives_nominal_t_and_prediction_coverage() {
        // 20,000 values with the shape of a normal distribution (its quantiles at
        // (i + 0.5) / N): the t interval and the prediction interval cover 95% up to the
        // discreteness of the population; 2000 simulations, 4 SE = 0.0195. With 64
        // resamples n = 5 takes a random bootstrap (C(9, 5) = 126 > 64), whose percentile
        // interval covers far less (about 0.83 at n = 5, as the exact one).
        let pop: Vec<f64> = (0..20_000)
            .map(|i| describe::normal_quantile((i as f64 + 0.5) / 20_000.0))
            .collect();
        let c = simulate(&pop, 5, &settings(2000, 64)).unwrap();
        assert_eq!(c.coverage.bootstrap, Plan::Random { resamples: 64 });
        assert!(c.mean.abs() < 1e-12);
        assert!((c.sd - 1.0).abs() < 1e-3, "{}", c.sd);
        assert!((get(&c, "t").coverage - 0.95).abs() < 0.0195);
        assert!((get(&c, "prediction").coverage - 0.95).abs() < 0.0195);
        let pct = get(&c, "percentile").coverage;
        assert!(pct > 0.74 && pct < 0.90, "{pct}");
    }

    #[test]
    fn seeded_and_thread_count_independent() {
        let pop: Vec<f64> = (0..300).map(|i| ((i * 7919) % 1000) as f64).collect();
        let run = |threads: usize, seed: u64| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    simulate(
                        &pop,
                        10,
                        &CoverageSettings {
                            seed,
                            ..settings(200, 100)
                        },
                    )
                })
        };
        let one = run(1, 1);
        assert_eq!(one, run(3, 1));
        assert_ne!(one, run(1, 2));
        let t = get(one.as_ref().unwrap(), "t");
        assert_eq!(t.target, "the population mean");
        assert!((t.mc_se - (t.coverage * (1.0 - t.coverage) / 200.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn degenerate_populations_and_sizes() {
        let s = settings(10, 100);
        assert!(simulate(&[1.0, 2.0, 3.0], 1, &s).is_none());
        assert!(simulate(&[1.0], 5, &s).is_none());
        assert!(simulate(&[2.0, 2.0, 2.0], 5, &s).is_none());
        assert!(simulate(&[1.0, f64::NAN, 3.0], 5, &s).is_none());
        assert!(simulate(&[1.0, 2.0], 5, &settings(0, 100)).is_none());
        // A two-valued population: samples of equal values give no BCa (counted undefined).
        let c = simulate(&[0.0, 1.0], 3, &settings(400, 100)).unwrap();
        assert!(get(&c, "bca").undefined > 0);
        assert_eq!(key(SAMPLE_TAG, 5, 0) >> 56, SAMPLE_TAG);
        assert_ne!(key(SAMPLE_TAG, 5, 7), key(BOOTSTRAP_TAG, 5, 7));
        assert_ne!(key(BOOTSTRAP_TAG, 5, 7), key(BOOTSTRAP_TAG, 6, 7));
    }
}
