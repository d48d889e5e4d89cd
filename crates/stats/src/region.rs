//! Prediction regions of one or two dimensions with a pooled correlation,
//! and their calibration by simulation: the numeric kernel of phalanx's
//! joint region (`analysis::region` says what the dimensions mean).
//!
//! From n observations with sample covariance S (p = 1 or 2), a new
//! observation's T^2 = d' [S* (1 + 1/n)]^-1 d, d its difference from the
//! mean, where S* keeps S's variances and pools its correlation r_S with a
//! prior correlation r0 weighted as m observations:
//!
//! r* = (m r0 + (n - 1) r_S) / (m + n - 1),
//!
//! the posterior mean of a Normal-Inverse-Wishart model whose prior scale is
//! r0 set to S's variances (m = 0: S* = S, Hotelling's T^2).

use crate::rng;

/// The inverse of a symmetric 2 x 2 (or 1 x 1) covariance `[a, b, d]` grown
/// by `grow`, row-major, held inline (a simulation builds one per draw): the
/// first p x p of the 4 values; `None` when it is not positive definite. O(1).
pub fn inverse(p: usize, [a, b, d]: [f64; 3], grow: f64) -> Option<[f64; 4]> {
    if p == 1 {
        let v = a * grow;
        return (v.is_finite() && v > 0.0).then(|| [1.0 / v, 0.0, 0.0, 0.0]);
    }
    let (a, b, d) = (a * grow, b * grow, d * grow);
    let det = a * d - b * b;
    (det.is_finite() && det > 0.0 && a > 0.0).then(|| [d / det, -b / det, -b / det, a / det])
}

/// d' M d for the p x p matrix `inverse` (row-major, p = d's length). O(p^2).
pub fn quadratic(d: &[f64], inverse: &[f64]) -> f64 {
    let p = d.len();
    (0..p)
        .map(|i| {
            (0..p)
                .map(|j| d[i] * inverse[i * p + j] * d[j])
                .sum::<f64>()
        })
        .sum()
}

/// The shape of a region: S*'s and S's inverses grown by 1 + 1/n, and
/// their correlations (p = 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    pub p: usize,
    pub inverse: [f64; 4],
    pub own_inverse: [f64; 4],
    pub correlation: Option<f64>,
    pub own_correlation: Option<f64>,
}

impl Shape {
    /// The shape of n observations with sample covariance `[s11, s12, s22]`
    /// (p = 1: `[s11, _, _]`) and the prior correlation `prior` = (r0, m),
    /// used for p = 2 (see the module notes); `None` for p not 1 or 2,
    /// n <= p, a covariance that is not positive definite, or a prior whose
    /// correlation is not in [-1, 1] or whose weight is negative or not
    /// finite. O(1).
    pub fn of(p: usize, n: usize, moments: [f64; 3], prior: Option<(f64, f64)>) -> Option<Shape> {
        if !(p == 1 || p == 2)
            || n <= p
            || prior.is_some_and(|(r0, m)| !(r0.abs() <= 1.0 && m.is_finite() && m >= 0.0))
        {
            return None;
        }
        let [a, b, d] = moments;
        let grow = 1.0 + 1.0 / n as f64;
        let own_inverse = inverse(p, moments, grow)?;
        let own_correlation = (p == 2).then(|| b / (a * d).sqrt());
        let correlation = own_correlation.map(|r| match prior {
            Some((r0, m)) => {
                let w = (n - 1) as f64;
                (m * r0 + w * r) / (m + w)
            }
            None => r,
        });
        let inverse = match correlation {
            Some(r) => inverse(p, [a, r * (a * d).sqrt(), d], grow)?,
            None => own_inverse,
        };
        Some(Shape {
            p,
            inverse,
            own_inverse,
            correlation,
            own_correlation,
        })
    }
}

/// A new observation changed before it is judged (the power of a region).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shift {
    /// Added to it.
    Add([f64; 2]),
    /// Both coordinates measured on a unit span whose start moves `d`
    /// towards its end, the end held: u -> (u - d) / (1 - d).
    Start(f64),
}

impl Shift {
    fn apply(self, u: [f64; 2]) -> [f64; 2] {
        match self {
            Shift::Add([a, b]) => [u[0] + a, u[1] + b],
            Shift::Start(d) => [(u[0] - d) / (1.0 - d), (u[1] - d) / (1.0 - d)],
        }
    }
}

/// What [`simulate`] counts: simulations, and the new observations outside
/// the region on S* and on S, as drawn and with each shift.
#[derive(Debug, Clone, PartialEq)]
pub struct Counts {
    pub simulations: usize,
    pub outside: [usize; 2],
    /// Per shift: [on S*, on S].
    pub shifted: Vec<[usize; 2]>,
}

/// A population for [`simulate`]: the true mean and SDs of a two-dimensional
/// normal and its correlation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Population {
    pub mean: [f64; 2],
    pub sd: [f64; 2],
    pub correlation: f64,
}

/// How often a new observation (as drawn, and with each of `shifts`) lies
/// outside the region of n observations with the prior `prior` and the bound
/// `bound` on T^2, from `sims` simulations on the stream (seed, key, stream).
/// Each simulation draws the n observations as their sufficient statistics:
/// the mean mu + L z / sqrt(n) and the covariance S = L A A' L' / (n - 1) by
/// Bartlett's decomposition (A lower triangular, A11^2 ~ chi2(n - 1),
/// A22^2 ~ chi2(n - 2), A21 ~ N(0, 1); Sigma = L L'), then one new
/// observation. O(sims x shifts), whatever n.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    population: &Population,
    n: usize,
    prior: Option<(f64, f64)>,
    bound: f64,
    shifts: &[Shift],
    sims: usize,
    (seed, key, stream): (u64, u64, u64),
) -> Counts {
    let mut g = rng::stream(seed, key, stream);
    let [s1, s2] = population.sd;
    let r = population.correlation;
    let (l11, l21, l22) = (s1, r * s2, s2 * (1.0 - r * r).max(0.0).sqrt());
    let mu = population.mean;
    let df = n.saturating_sub(1) as f64;
    let root = (n as f64).sqrt();
    let mut counts = Counts {
        simulations: 0,
        outside: [0; 2],
        shifted: vec![[0; 2]; shifts.len()],
    };
    if n < 3 {
        return counts;
    }
    for _ in 0..sims {
        let (z1, z2) = (rng::standard_normal(&mut g), rng::standard_normal(&mut g));
        let mean = [
            mu[0] + l11 * z1 / root,
            mu[1] + (l21 * z1 + l22 * z2) / root,
        ];
        let a11 = rng::chi_squared(&mut g, df).sqrt();
        let a22 = rng::chi_squared(&mut g, df - 1.0).sqrt();
        let a21 = rng::standard_normal(&mut g);
        // B = L A; S = B B' / (n - 1).
        let (b11, b21, b22) = (l11 * a11, l21 * a11 + l22 * a21, l22 * a22);
        let moments = [b11 * b11 / df, b11 * b21 / df, (b21 * b21 + b22 * b22) / df];
        let (w1, w2) = (rng::standard_normal(&mut g), rng::standard_normal(&mut g));
        let new = [mu[0] + l11 * w1, mu[1] + l21 * w1 + l22 * w2];
        let Some(shape) = Shape::of(2, n, moments, prior) else {
            continue;
        };
        counts.simulations += 1;
        let outside = |u: [f64; 2]| -> [bool; 2] {
            let d = [u[0] - mean[0], u[1] - mean[1]];
            [
                quadratic(&d, &shape.inverse) > bound,
                quadratic(&d, &shape.own_inverse) > bound,
            ]
        };
        for (c, out) in counts.outside.iter_mut().zip(outside(new)) {
            *c += usize::from(out);
        }
        for (shift, count) in shifts.iter().zip(counts.shifted.iter_mut()) {
            for (c, out) in count.iter_mut().zip(outside(shift.apply(new))) {
                *c += usize::from(out);
            }
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_prior_is_the_sample_shape_and_the_pool_is_a_weighted_mean() {
        let moments = [4.0e-4, 3.0e-4, 5.0e-4];
        let s = Shape::of(2, 5, moments, None).unwrap();
        assert_eq!(s.inverse, s.own_inverse);
        let r_s = 3.0e-4 / (4.0e-4f64 * 5.0e-4).sqrt();
        assert!((s.own_correlation.unwrap() - r_s).abs() < 1e-15);
        let p = Shape::of(2, 5, moments, Some((0.2, 6.0))).unwrap();
        // (6 x 0.2 + 4 r_S) / 10.
        assert!((p.correlation.unwrap() - (1.2 + 4.0 * r_s) / 10.0).abs() < 1e-15);
        assert_eq!(Shape::of(2, 2, moments, None), None);
        assert_eq!(Shape::of(2, 5, moments, Some((1.5, 1.0))), None);
        assert_eq!(
            Shape::of(2, 5, [1.0, 2.0, 1.0], None),
            None,
            "not positive definite"
        );
        // The 1 x 1 inverse, and a quadratic form by hand: [1 2] [[2 1] [1 3]] [1 2]' = 18.
        assert_eq!(inverse(1, [4.0, 0.0, 0.0], 2.0).unwrap()[0], 0.125);
        assert_eq!(quadratic(&[1.0, 2.0], &[2.0, 1.0, 1.0, 3.0]), 18.0);
    }

    #[test]
    fn a_shift_moves_the_observation_as_documented() {
        let [a, b] = Shift::Add([0.1, -0.2]).apply([0.5, 0.7]);
        assert!((a - 0.6).abs() < 1e-15 && (b - 0.5).abs() < 1e-15);
        let [a, b] = Shift::Start(0.5).apply([0.75, 1.0]);
        assert!((a - 0.5).abs() < 1e-15 && (b - 1.0).abs() < 1e-15);
    }
}
