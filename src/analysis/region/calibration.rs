//! How often the joint region flags a normal finger (its false alarms) and
//! how often it finds one joint moved (its power), by simulation: the table
//! the report's methods and ARCHITECTURE.md publish.
//! `tests/independent/region_calibration.py` draws the same table by brute
//! force (every hand drawn, NumPy's covariance) without this code.
//!
//! A true population of positions u ~ N(mu, Sigma), Sigma = D R D with the
//! data's SDs D and a correlation r from [`CORRELATIONS`] (the paper's index
//! finger's Fisher 95% interval, [0.60, 0.998], and points inside it). Each
//! simulation draws n reference hands as their sufficient statistics
//! ([`crate::stats::region::simulate`], Bartlett's decomposition), builds the
//! region from them, and judges one new normal hand (a false alarm when it is
//! outside) and the same hand with one joint moved on a [`FINGER_MM`]
//! finger (found when outside): the PIP d towards the tip (u1 + d / L), the
//! DIP likewise (u2 + d / L), the MCP d towards the tip with the tip held
//! (u_k' = (u_k L - d) / (L - d)). The rule is unchanged when either
//! position is scaled (S*'s variances are S's), so the false alarms depend on
//! r alone, not on the variances; the power depends on both, and is given at
//! the data's SDs. Each cell draws from its own stream (seed, key, cell), so
//! the table is the same on every machine and thread count.
//! Cost: O(sizes x correlations x simulations).

use super::{ShapePrior, bound_at};
use crate::analysis::placement::Joint;
use crate::stats::region::{self, Population, Shift};
use rayon::prelude::*;

/// The numbers of reference hands the table is drawn at.
pub const SIZES: [usize; 4] = [5, 10, 40, 910];

/// True correlations of the two positions: the ends of the paper's index
/// finger's Fisher 95% interval (r = 0.969 from 5 hands: [0.60, 0.998]),
/// its estimate, and points between.
pub const CORRELATIONS: [f64; 7] = [0.60, 0.70, 0.80, 0.90, 0.969, 0.99, 0.998];

/// The joints moved alone, in the power columns.
pub const JOINTS: [Joint; 3] = [Joint::Pip, Joint::Dip, Joint::Mcp];

/// How far each is moved, in mm, on a [`FINGER_MM`] finger.
pub const MOVES_MM: [f64; 3] = [2.0, 3.0, 5.0];

/// The finger's length, MCP to tip, in mm.
pub const FINGER_MM: f64 = 90.0;

/// Simulations per cell: a rate near 5% has a Monte Carlo SE of 0.15 points.
pub const SIMULATIONS: usize = 20_000;

/// The stream key of the calibration's draws.
const KEY: u64 = 0x7265_6769_6f6e_6361;

/// What the table is drawn for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// The prior shape (as the audit uses it; `None`: the X-rays' own S).
    pub prior: Option<ShapePrior>,
    /// The true mean of u = (J~1, J~1 + J~2).
    pub mean: [f64; 2],
    /// The true SDs of the two positions.
    pub sd: [f64; 2],
    /// The region's level.
    pub confidence: f64,
    pub simulations: usize,
    pub seed: u64,
}

/// A rate under the model's shape and under the X-rays' own S.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rate {
    pub model: f64,
    pub own: f64,
}

/// One cell of the table: n reference hands, true correlation r.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub n: usize,
    pub correlation: f64,
    /// Normal hands outside the region.
    pub false_alarms: Rate,
    /// Hands with one joint moved outside it: `[joint][move]`, in the order
    /// of [`JOINTS`] and [`MOVES_MM`].
    pub power: [[Rate; 3]; 3],
}

impl Setup {
    /// The setup for `finger` of `a`: the true mean and SDs of u are the
    /// X-rays' own, the prior `prior`, the region's level and the seed the
    /// analysis's; `None` for a finger without two positions or with fewer
    /// than 3 X-rays. O(n).
    pub fn of(
        a: &crate::analysis::Analysis,
        finger: crate::dataset::Finger,
        prior: Option<ShapePrior>,
        simulations: usize,
    ) -> Option<Setup> {
        let u = a.finger(finger)?.positions()?;
        if u.len() < 3 || u.iter().any(|h| h.as_ref().len() != 2) {
            return None;
        }
        let column = |k: usize| -> Vec<f64> { u.iter().map(|h| h.as_ref()[k]).collect() };
        let (x, y) = (column(0), column(1));
        let stat = |v: &[f64]| -> Option<(f64, f64)> {
            Some((
                crate::stats::describe::mean(v)?,
                crate::stats::describe::sd(v)?,
            ))
        };
        let ((m1, s1), (m2, s2)) = (stat(&x)?, stat(&y)?);
        Some(Setup {
            prior,
            mean: [m1, m2],
            sd: [s1, s2],
            confidence: a.settings.confidence,
            simulations,
            seed: a.settings.seed,
        })
    }
}

/// The Fisher 95% interval of a correlation `r` from `n` pairs, tanh(atanh r
/// +- z / sqrt(n - 3)) at `confidence`; `None` for n <= 3 or |r| >= 1.
pub fn fisher_interval(r: f64, n: usize, confidence: f64) -> Option<(f64, f64)> {
    if n <= 3 || r.is_nan() || r.abs() >= 1.0 || !(confidence > 0.0 && confidence < 1.0) {
        return None;
    }
    let z = crate::stats::describe::normal_quantile(0.5 + confidence / 2.0);
    let half = z / ((n - 3) as f64).sqrt();
    let centre = r.atanh();
    Some(((centre - half).tanh(), (centre + half).tanh()))
}

/// The Monte Carlo standard error of a rate `p` from `sims` simulations.
pub fn monte_carlo_se(p: f64, sims: usize) -> f64 {
    (p * (1.0 - p) / sims.max(1) as f64).sqrt()
}

/// The table: every size of [`SIZES`] and correlation of [`CORRELATIONS`],
/// in that order (sizes outer); empty when the setup cannot be simulated
/// (SDs not positive, a level outside (0, 1), no simulations).
pub fn simulate(setup: &Setup) -> Vec<Cell> {
    let ok = setup.sd.iter().all(|s| s.is_finite() && *s > 0.0)
        && setup.mean.iter().all(|m| m.is_finite())
        && setup.confidence > 0.0
        && setup.confidence < 1.0
        && setup.simulations > 0;
    if !ok {
        return Vec::new();
    }
    let cells: Vec<(usize, f64)> = SIZES
        .iter()
        .flat_map(|&n| CORRELATIONS.iter().map(move |&r| (n, r)))
        .collect();
    cells
        .par_iter()
        .enumerate()
        .filter_map(|(k, &(n, r))| cell(setup, n, r, k as u64))
        .collect()
}

/// One cell, from stream `stream`; `None` when n is too small for a region.
fn cell(setup: &Setup, n: usize, r: f64, stream: u64) -> Option<Cell> {
    let bound = bound_at(2, n, setup.confidence)?;
    let shifts: Vec<Shift> = JOINTS
        .iter()
        .flat_map(|joint| {
            MOVES_MM.iter().map(move |mm| {
                let d = mm / FINGER_MM;
                match joint {
                    Joint::Pip => Shift::Add([d, 0.0]),
                    Joint::Dip => Shift::Add([0.0, d]),
                    _ => Shift::Start(d),
                }
            })
        })
        .collect();
    let counts = region::simulate(
        &Population {
            mean: setup.mean,
            sd: setup.sd,
            correlation: r,
        },
        n,
        setup.prior.map(|q| (q.correlation, q.hands)),
        bound,
        &shifts,
        setup.simulations,
        (setup.seed, KEY, stream),
    );
    let sims = counts.simulations;
    if sims == 0 {
        return None;
    }
    let rate = |c: [usize; 2]| Rate {
        model: c[0] as f64 / sims as f64,
        own: c[1] as f64 / sims as f64,
    };
    let mut power = [[Rate {
        model: 0.0,
        own: 0.0,
    }; 3]; 3];
    for (k, c) in counts.shifted.iter().enumerate() {
        power[k / MOVES_MM.len()][k % MOVES_MM.len()] = rate(*c);
    }
    Some(Cell {
        n,
        correlation: r,
        false_alarms: rate(counts.outside),
        power,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(prior: Option<ShapePrior>, simulations: usize) -> Setup {
        // The paper's index finger: u's SDs 0.0131 and 0.0150, mean (0.4846,
        // 0.7572) (phalanx stats; tests/independent/region_calibration.py).
        Setup {
            prior,
            mean: [0.4846, 0.7572],
            sd: [0.0131, 0.0150],
            confidence: 0.95,
            simulations,
            seed: 1,
        }
    }

    #[test]
    fn the_own_shape_flags_five_percent_at_every_correlation() {
        // Hotelling's region is exact for normal hands: 5% false alarms
        // whatever the correlation, within 4 Monte Carlo SEs (0.62 points
        // at 5,000 simulations).
        let table = simulate(&setup(None, 5_000));
        assert_eq!(table.len(), SIZES.len() * CORRELATIONS.len());
        for c in &table {
            let se = monte_carlo_se(0.05, 5_000);
            assert!(
                (c.false_alarms.own - 0.05).abs() < 4.0 * se,
                "n {} r {}: {}",
                c.n,
                c.correlation,
                c.false_alarms.own
            );
            assert_eq!(
                c.false_alarms.own, c.false_alarms.model,
                "no prior: one shape"
            );
        }
    }

    #[test]
    fn the_prior_keeps_false_alarms_at_most_five_percent_and_costs_power_at_small_n() {
        // The atlas's index correlation 0.643 at 10 hands: at most 5% (+ 3
        // SEs) in every cell; at n = 5 the prior widens the thin ellipse
        // the paper's r = 0.969 gives, so a PIP moved 3 mm is found less
        // often than with the X-rays' own S (tests/independent/region_calibration.py:
        // 0.27 against 0.99 at r = 0.969).
        let prior = ShapePrior {
            correlation: 0.643,
            hands: 10.0,
        };
        let table = simulate(&setup(Some(prior), 5_000));
        for c in &table {
            let se = monte_carlo_se(0.05, 5_000);
            assert!(
                c.false_alarms.model <= 0.05 + 3.0 * se,
                "n {} r {}: {}",
                c.n,
                c.correlation,
                c.false_alarms.model
            );
        }
        let at = |n: usize, r: f64| {
            table
                .iter()
                .find(|c| c.n == n && c.correlation == r)
                .unwrap()
        };
        let c = at(5, 0.969);
        assert!(
            c.power[0][1].model < 0.45 && c.power[0][1].own > 0.9,
            "{c:?}"
        );
        // At 910 hands the prior hardly matters.
        let c = at(910, 0.8);
        assert!(
            (c.power[0][1].model - c.power[0][1].own).abs() < 0.03,
            "{c:?}"
        );
    }

    #[test]
    fn the_same_seed_gives_the_same_table() {
        let a = simulate(&setup(None, 300));
        let b = simulate(&setup(None, 300));
        assert_eq!(a, b);
        let mut other = setup(None, 300);
        other.seed = 2;
        assert_ne!(a, simulate(&other));
        assert!(
            simulate(&Setup {
                sd: [0.0, 0.01],
                ..setup(None, 10)
            })
            .is_empty()
        );
    }

    #[test]
    fn the_fisher_interval_of_the_papers_index() {
        // r = 0.969219 from 5 hands: tanh(atanh(r) +- 1.959964 / sqrt(2)) =
        // [0.6001, 0.9980] (numpy; the issue's [0.60, 0.998]).
        let (lo, hi) = fisher_interval(0.969218586749469, 5, 0.95).unwrap();
        assert!(
            (lo - 0.600121).abs() < 1e-5 && (hi - 0.998046).abs() < 1e-5,
            "{lo} {hi}"
        );
        assert_eq!(fisher_interval(0.5, 3, 0.95), None);
        assert_eq!(fisher_interval(1.0, 10, 0.95), None);
    }

    #[test]
    fn the_table_agrees_with_the_independent_brute_force_draws() {
        // tests/independent/region_calibration.py draws every hand with NumPy
        // (and the true SDs varying within their 95% intervals, which the
        // rule's scale invariance makes irrelevant to the false alarms); each
        // rate of both tables has a Monte Carlo SE of at most 0.0035 (at 0.5,
        // 20,000 simulations), so the two agree within 4 x sqrt(2) of it.
        let text = std::fs::read_to_string("tests/independent/region_calibration.txt").unwrap();
        let paper = crate::analysis::analyse_without_bootstrap(
            &crate::dataset::Dataset::load(std::path::Path::new("data/measurements.csv")).unwrap(),
            &crate::analysis::Settings::default(),
        );
        let Some(atlas) = crate::dataset::vendored::atlas() else {
            return;
        };
        let atlas = crate::analysis::analyse_without_bootstrap(
            &atlas,
            &crate::analysis::Settings::default(),
        );
        let prior = atlas.shape_priors(10.0).of(crate::dataset::Finger::Index);
        let setup = Setup::of(&paper, crate::dataset::Finger::Index, prior, SIMULATIONS).unwrap();
        let table = simulate(&setup);
        let tolerance = 4.0 * 2f64.sqrt() * monte_carlo_se(0.5, SIMULATIONS);
        let numbers = |line: &str| -> Vec<f64> {
            line.split(|c: char| !(c.is_ascii_digit() || c == '.'))
                .filter(|w| w.contains('.'))
                .map(|w| w.parse().unwrap())
                .collect()
        };
        let mut checked = 0;
        for &n in &SIZES {
            let line = text
                .lines()
                .find(|l| l.starts_with(&format!("{n:<4} ")))
                .unwrap();
            let values = numbers(line);
            assert_eq!(values.len(), 2 * CORRELATIONS.len(), "{line}");
            for (k, c) in table.iter().filter(|c| c.n == n).enumerate() {
                assert!(
                    (c.false_alarms.model - values[2 * k]).abs() < tolerance,
                    "{n} {c:?}"
                );
                assert!(
                    (c.false_alarms.own - values[2 * k + 1]).abs() < tolerance,
                    "{n} {c:?}"
                );
                checked += 2;
            }
        }
        for (j, joint) in JOINTS.iter().enumerate() {
            for (m, mm) in MOVES_MM.iter().enumerate() {
                let head = format!("{} {} mm", joint.name(), mm);
                let line = text.lines().find(|l| l.starts_with(&head)).unwrap();
                let values = numbers(line.trim_start_matches(&head));
                assert_eq!(values.len(), 4 * SIZES.len(), "{line}");
                for (k, &n) in SIZES.iter().enumerate() {
                    let rates: Vec<Rate> = table
                        .iter()
                        .filter(|c| c.n == n)
                        .map(|c| c.power[j][m])
                        .collect();
                    let lo = |f: fn(&Rate) -> f64| rates.iter().map(f).fold(1.0, f64::min);
                    let hi = |f: fn(&Rate) -> f64| rates.iter().map(f).fold(0.0, f64::max);
                    let want = &values[4 * k..4 * k + 4];
                    let got = [
                        lo(|r| r.model),
                        hi(|r| r.model),
                        lo(|r| r.own),
                        hi(|r| r.own),
                    ];
                    for (g, w) in got.iter().zip(want) {
                        // The text gives two decimals: half a unit of rounding more.
                        assert!(
                            (g - w).abs() < tolerance + 0.005,
                            "{head} n {n}: {got:?} {want:?}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 2 * 28 + 4 * 9 * 4);
    }
}
