//! Descriptive statistics and Student-t intervals of one quantity.

use super::Interval;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// Arithmetic mean, the paper's eq. (5): (1/M) sum x_m. `None` for no values. O(n).
pub fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// Sample standard deviation with n - 1 in the denominator (two-pass). `None` for n < 2. O(n).
pub fn sd(xs: &[f64]) -> Option<f64> {
    let n = xs.len();
    if n < 2 {
        return None;
    }
    let m = mean(xs)?;
    let ss: f64 = xs.iter().map(|x| (x - m) * (x - m)).sum();
    Some((ss / (n - 1) as f64).sqrt())
}

/// Minimum and maximum, the paper's eq. (7). `None` for no values. O(n).
pub fn min_max(xs: &[f64]) -> Option<(f64, f64)> {
    let first = *xs.first()?;
    Some(
        xs.iter()
            .fold((first, first), |(lo, hi), &x| (lo.min(x), hi.max(x))),
    )
}

/// Median: the middle value, or the mean of the two middle values. O(n log n).
pub fn median(xs: &[f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[k]
    } else {
        (v[k - 1] + v[k]) / 2.0
    })
}

/// Degrees of freedom above which the t quantile comes from its expansion in 1/df.
const T_EXPANSION_DF: usize = 1_000;

/// Two-sided Student-t quantile t_{1-(1-c)/2, df}. `None` when `df` < 1.
///
/// Up to 1,000 degrees of freedom from `statrs`; above, from the Cornish-Fisher
/// expansion in 1/df (Abramowitz and Stegun 26.7.5), whose error there is below
/// 1e-11. (`statrs`'s inverse loses accuracy for large df and does not terminate
/// near 1e8.)
pub fn t_quantile(confidence: f64, df: usize) -> Option<f64> {
    if df == 0 {
        return None;
    }
    // The coverage simulations ask for the same few (confidence, df) pairs millions of
    // times, and statrs's inverse (an iterative inverse of the regularised incomplete
    // beta) costs about as much as the rest of a simulated sample. The answer depends
    // on the pair alone, so each thread remembers the last few: the same bits as
    // computing it afresh.
    const REMEMBERED: usize = 8;
    type Memo = [(u64, usize, Option<f64>); REMEMBERED];
    thread_local! {
        static MEMO: std::cell::Cell<(Memo, usize)> =
            const { std::cell::Cell::new(([(0, 0, None); REMEMBERED], 0)) };
    }
    let bits = confidence.to_bits();
    let (memo, next) = MEMO.get();
    if let Some(&(_, _, q)) = memo.iter().find(|m| m.0 == bits && m.1 == df) {
        return q;
    }
    let q = t_quantile_uncached(confidence, df);
    let mut memo = memo;
    memo[next] = (bits, df, q);
    MEMO.set((memo, (next + 1) % REMEMBERED));
    q
}

/// [`t_quantile`] computed afresh (`df` >= 1).
fn t_quantile_uncached(confidence: f64, df: usize) -> Option<f64> {
    let p = 1.0 - (1.0 - confidence) / 2.0;
    if df > T_EXPANSION_DF {
        return Some(t_expansion(p, df as f64));
    }
    let t = StudentsT::new(0.0, 1.0, df as f64).ok()?;
    let q = t.inverse_cdf(p);
    q.is_finite().then_some(q)
}

/// t quantile at probability p by the Cornish-Fisher expansion to 1/df^3:
/// z + g1/v + g2/v^2 + g3/v^3 with g1 = (z^3 + z)/4, g2 = (5z^5 + 16z^3 + 3z)/96,
/// g3 = (3z^7 + 19z^5 + 17z^3 - 15z)/384.
fn t_expansion(p: f64, v: f64) -> f64 {
    let z = normal_quantile(p);
    let (z2, z3) = (z * z, z * z * z);
    let (z5, z7) = (z3 * z2, z3 * z2 * z2);
    let g1 = (z3 + z) / 4.0;
    let g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
    let g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
    z + g1 / v + g2 / (v * v) + g3 / (v * v * v)
}

/// Standard normal quantile Phi^-1(p).
pub fn normal_quantile(p: f64) -> f64 {
    standard_normal().inverse_cdf(p)
}

/// Standard normal distribution function Phi(z).
pub fn normal_cdf(z: f64) -> f64 {
    standard_normal().cdf(z)
}

fn standard_normal() -> Normal {
    Normal::standard()
}

/// Student-t confidence interval of the mean: mean +/- t * sd / sqrt(n).
/// `None` for n < 2.
pub fn t_interval(mean: f64, sd: f64, n: usize, confidence: f64) -> Option<Interval> {
    let t = t_quantile(confidence, n.checked_sub(1)?)?;
    let half = t * sd / (n as f64).sqrt();
    Some(Interval::new(mean - half, mean + half))
}

/// Prediction interval for one new observation: mean +/- t * sd * sqrt(1 + 1/n).
/// `None` for n < 2.
pub fn prediction_interval(mean: f64, sd: f64, n: usize, confidence: f64) -> Option<Interval> {
    let t = t_quantile(confidence, n.checked_sub(1)?)?;
    let half = t * sd * (1.0 + 1.0 / n as f64).sqrt();
    Some(Interval::new(mean - half, mean + half))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_of_a_hand_computed_sample() {
        // By hand: 2, 4, 4, 4, 5, 5, 7, 9 -> mean 5, sum of squares 32, sd sqrt(32/7).
        let xs = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(mean(&xs), Some(5.0));
        assert!((sd(&xs).unwrap() - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!(median(&xs), Some(4.5));
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(min_max(&xs), Some((2.0, 9.0)));
        assert_eq!(sd(&[1.0]), None);
        assert_eq!(mean(&[]), None);
    }

    #[test]
    fn t_quantiles_match_tables() {
        // Student-t tables (scipy.stats.t.ppf(0.975, 4) = 2.776445, ppf(0.975, 1) = 12.7062, ppf(0.95, 9) = 1.833113).
        assert!((t_quantile(0.95, 4).unwrap() - 2.776_445).abs() < 1e-5);
        assert!((t_quantile(0.95, 1).unwrap() - 12.706_20).abs() < 1e-4);
        assert!((t_quantile(0.90, 9).unwrap() - 1.833_113).abs() < 1e-5);
        assert_eq!(t_quantile(0.95, 0), None);
        // The expansion agrees with statrs where both are accurate, and with R
        // (scipy.stats.t.ppf(0.975, 1000) = 1.962339, ppf(0.975, 1e5) = 1.959988); huge df terminate.
        for p in [0.95, 0.975, 0.995] {
            let exact = StudentsT::new(0.0, 1.0, 1000.0).unwrap().inverse_cdf(p);
            assert!((t_expansion(p, 1000.0) - exact).abs() < 1e-9, "{p}");
        }
        assert!((t_quantile(0.95, 1000).unwrap() - 1.962_339).abs() < 1e-6);
        assert!((t_quantile(0.95, 100_000).unwrap() - 1.959_988).abs() < 1e-6);
        assert!((t_quantile(0.95, 100_000_000).unwrap() - 1.959_964).abs() < 1e-6);
        // Normal: scipy.stats.norm.ppf(0.975) = 1.959964.
        assert!((normal_quantile(0.975) - 1.959_964).abs() < 1e-6);
        assert!((normal_cdf(1.959_964) - 0.975).abs() < 1e-6);
    }
}
