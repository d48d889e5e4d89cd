//! What the bootstrap and the coverage simulation can serve: limits on the
//! options that set their size, checked before any work starts.
//!
//! Memory: a bootstrap holds every resample's means, 8 bytes x quantities each
//! (28 quantities for a whole hand), so [`MAX_RESAMPLES`] = 10^6 needs 224 MB.
//! Time: a bootstrap of B resamples of n X-rays costs B x n resample-X-ray
//! pairs (x quantities, all in one pass); BENCHMARKS.md measures about 155
//! million pairs a second on two cores, so [`MAX_WORK`] = 10^10 pairs is about
//! a minute. Exact enumeration (n <= 8) costs C(2n-1, n) x n whatever B is.
//! A coverage simulation repeats a bootstrap per simulated dataset.

use super::coverage;
use crate::stats::bootstrap::Plan;

/// Most bootstrap resamples (memory: 8 bytes x quantities per resample).
pub(crate) const MAX_RESAMPLES: usize = 1_000_000;

/// Most simulated datasets of a coverage simulation (Monte-Carlo SE 0.0007 at 10^5).
pub(crate) const MAX_SIMS: usize = 100_000;

/// Most resample-X-ray pairs one command may cost: about a minute on two cores.
pub(crate) const MAX_WORK: u128 = 10_000_000_000;

/// Resample-X-ray pairs of one bootstrap of n X-rays with `resamples` asked for.
pub(crate) fn bootstrap_work(n: usize, resamples: usize) -> u128 {
    Plan::choose(n, resamples.max(1)).len() as u128 * n as u128
}

/// Refuses a bootstrap of n X-rays that would exceed [`MAX_WORK`], saying how
/// many resamples fit.
pub(crate) fn check_bootstrap(n: usize, resamples: usize) -> Result<(), String> {
    let work = bootstrap_work(n, resamples);
    if work <= MAX_WORK {
        return Ok(());
    }
    let fits = (MAX_WORK / n.max(1) as u128).max(1);
    Err(format!(
        "--resamples {resamples} on {n} X-rays is {work} resample-X-ray pairs, more than {MAX_WORK} \
         (about a minute of work): give --resamples {fits} or fewer"
    ))
}

/// Refuses a coverage simulation of `sims` datasets at sample sizes with their
/// own resamples, `(n, resamples)` each (the coverage curve uses fewer), that
/// would exceed [`MAX_WORK`] in total, saying how many fit; `asked` is the
/// `--resamples` the message quotes.
pub(crate) fn check_coverage_runs(
    runs: &[(usize, usize)],
    sims: usize,
    asked: usize,
) -> Result<(), String> {
    let per_sim: u128 = runs.iter().map(|&(n, b)| bootstrap_work(n, b)).sum();
    let work = per_sim * sims as u128;
    if work <= MAX_WORK {
        return Ok(());
    }
    let fits = (MAX_WORK / per_sim.max(1)).max(1);
    Err(format!(
        "--sims {sims} with --resamples {asked} at n = {} is {work} resample-X-ray pairs, more than {MAX_WORK} \
         (about a minute of work): give --sims {fits} or fewer, or fewer --resamples",
        {
            let mut sizes: Vec<usize> = runs.iter().map(|&(n, _)| n).collect();
            sizes.sort_unstable();
            sizes.dedup();
            sizes
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        }
    ))
}

/// Refuses a coverage simulation too large to serve, before any work: at the
/// data's sizes, and with `curve` at the sizes of [`coverage::curve`] too
/// (the sizes the commands `report` and `coverage` simulate).
pub(crate) fn check_coverage(
    data: &crate::dataset::Dataset,
    s: &coverage::CoverageSettings,
    curve: bool,
) -> Result<(), String> {
    let mut sizes: Vec<usize> = crate::dataset::Finger::ALL
        .into_iter()
        .map(|f| data.rows_of(f).count())
        .filter(|&n| n >= 2 && s.max_n.is_none_or(|m| n <= m))
        .collect();
    sizes.sort_unstable();
    sizes.dedup();
    let runs = if curve {
        coverage::curve_runs(&sizes, s)
    } else {
        sizes.iter().map(|&n| (n, s.resamples)).collect()
    };
    check_coverage_runs(&runs, s.sims, s.resamples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_by_hand() {
        // n = 5: 126 exact resamples x 5 X-rays = 630 pairs, whatever B.
        assert_eq!(bootstrap_work(5, 1_000_000), 630);
        assert!(check_bootstrap(5, MAX_RESAMPLES).is_ok());
        // 10^6 X-rays x 10^4 resamples = 10^10: the limit, accepted; one more X-ray is not.
        assert!(check_bootstrap(1_000_000, 10_000).is_ok());
        let e = check_bootstrap(1_000_001, 10_000).unwrap_err();
        assert!(e.contains("give --resamples 9999 or fewer"), "{e}");
        // Coverage: 4000 sims x 10^4 resamples x 200 X-rays = 8e9 fits; 300 X-rays does not.
        assert!(check_coverage_runs(&[(200, 10_000)], 4000, 10_000).is_ok());
        let e = check_coverage_runs(&[(5, 10_000), (300, 10_000)], 4000, 10_000).unwrap_err();
        assert!(e.contains("at n = 5, 300"), "{e}");
        assert!(e.contains("give --sims 3332 or fewer"), "{e}");
    }
}
