//! The joint prediction region of a finger's relative joint positions: the
//! proportions as one vector with their covariance, not one interval per
//! quantity: the audit's verdict on a finger with a tip and the target of its
//! explanation (ARCHITECTURE.md, "How a ray is judged").
//!
//! For a finger with a tip the vector is u = (J~1, J~1 + J~2), the PIP's and
//! the DIP's positions as shares of the finger's length from the MCP (eq. 2);
//! for the thumb u = (J~1). From n reference hands with mean u_bar and sample
//! covariance S, a new hand's u lies in the 100c% prediction region when
//!
//! T^2 = (u - u_bar)' [S (1 + 1/n)]^-1 (u - u_bar) <= p (n - 1) / (n - p) F(c; p, n - p),
//!
//! p = dim u: under normality, u - u_bar ~ N(0, Sigma (1 + 1/n)) independent of
//! S, so T^2 (n - p) / (p (n - 1)) ~ F(p, n - p) (Hotelling's T^2 for one new
//! observation). At n = 5, p = 2 and c = 0.95 the bound is 25.47; at n = 910,
//! 6.02 (against 5.99 for chi-square with 2 degrees of freedom).
//! `tests/independent/calibration.py` shows the calibration against the
//! per-quantity rule. O(n p^2) to build, O(p^2) per query.

use statrs::distribution::{ContinuousCDF, FisherSnedecor};

/// The prediction region of one finger's relative joint positions (see the
/// module notes), for p = 1 or 2.
#[derive(Debug, Clone, PartialEq)]
pub struct JointRegion {
    /// The reference hands.
    pub n: usize,
    /// The mean position vector u_bar.
    pub mean: Vec<f64>,
    /// The inverse of S (1 + 1/n), row-major, p x p.
    pub inverse: Vec<f64>,
    /// The bound on T^2: p (n - 1) / (n - p) F(c; p, n - p).
    pub bound: f64,
    pub confidence: f64,
}

/// The relative joint positions u of a finger with segments `segments` (J1,
/// J2[, J3], MCP to tip): the cumulative shares of the length before the last
/// segment, (J~1) for the thumb and (J~1, J~1 + J~2) for a finger. `None` for
/// fewer than two segments or more than three, or segments that are not finite
/// and positive.
pub fn positions(segments: &[f64]) -> Option<Vec<f64>> {
    Position::of(segments).map(|u| u.as_ref().to_vec())
}

/// [`positions`] held inline (p is at most 2), so a region over n hands is
/// built without n heap vectors.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Position {
    values: [f64; 2],
    p: usize,
}

impl Position {
    /// As [`positions`].
    pub(crate) fn of(segments: &[f64]) -> Option<Position> {
        if !(2..=3).contains(&segments.len())
            || segments.iter().any(|&s| !(s.is_finite() && s > 0.0))
        {
            return None;
        }
        let total: f64 = segments.iter().sum();
        let mut values = [0.0; 2];
        let mut run = 0.0;
        for (v, s) in values.iter_mut().zip(&segments[..segments.len() - 1]) {
            run += s;
            *v = run / total;
        }
        Some(Position {
            values,
            p: segments.len() - 1,
        })
    }
}

impl AsRef<[f64]> for Position {
    fn as_ref(&self) -> &[f64] {
        &self.values[..self.p]
    }
}

impl JointRegion {
    /// The region from the reference hands' position vectors `hands` (each of
    /// the same length p, 1 or 2) at `confidence`. `None` when p is not 1 or 2,
    /// the vectors differ in length or hold a value that is not finite, there
    /// are not more hands than p (n - p degrees of freedom), `confidence` is
    /// not inside (0, 1), or S is singular.
    pub fn of<H: AsRef<[f64]>>(hands: &[H], confidence: f64) -> Option<JointRegion> {
        let p = hands.first()?.as_ref().len();
        let n = hands.len();
        if !(p == 1 || p == 2)
            || n <= p
            || !(confidence > 0.0 && confidence < 1.0)
            || hands
                .iter()
                .any(|h| h.as_ref().len() != p || h.as_ref().iter().any(|x| !x.is_finite()))
        {
            return None;
        }
        let mean: Vec<f64> = (0..p)
            .map(|k| hands.iter().map(|h| h.as_ref()[k]).sum::<f64>() / n as f64)
            .collect();
        let cov = |a: usize, b: usize| {
            hands
                .iter()
                .map(|h| (h.as_ref()[a] - mean[a]) * (h.as_ref()[b] - mean[b]))
                .sum::<f64>()
                / (n - 1) as f64
        };
        let grow = 1.0 + 1.0 / n as f64;
        let inverse = if p == 1 {
            let v = cov(0, 0) * grow;
            if v.is_nan() || v <= 0.0 {
                return None;
            }
            vec![1.0 / v]
        } else {
            let (a, b, d) = (cov(0, 0) * grow, cov(0, 1) * grow, cov(1, 1) * grow);
            let det = a * d - b * b;
            if !det.is_finite() || det <= 0.0 {
                return None;
            }
            vec![d / det, -b / det, -b / det, a / det]
        };
        let f = FisherSnedecor::new(p as f64, (n - p) as f64)
            .ok()?
            .inverse_cdf(confidence);
        let bound = p as f64 * (n - 1) as f64 / (n - p) as f64 * f;
        bound.is_finite().then_some(JointRegion {
            n,
            mean,
            inverse,
            bound,
            confidence,
        })
    }

    /// T^2 of the position vector `u` (see the module notes); infinite for a
    /// vector of the wrong length or with a value that is not finite.
    pub fn distance(&self, u: &[f64]) -> f64 {
        let p = self.mean.len();
        if u.len() != p || u.iter().any(|x| !x.is_finite()) {
            return f64::INFINITY;
        }
        let d: Vec<f64> = u.iter().zip(&self.mean).map(|(x, m)| x - m).collect();
        (0..p)
            .map(|i| {
                (0..p)
                    .map(|j| d[i] * self.inverse[i * p + j] * d[j])
                    .sum::<f64>()
            })
            .sum()
    }

    /// T^2 of a finger with segments `segments` (J1, J2[, J3]): the
    /// [`distance`](Self::distance) of their [`positions`]; infinite for
    /// segments `positions` refuses.
    pub fn distance_of_segments(&self, segments: &[f64]) -> f64 {
        positions(segments).map_or(f64::INFINITY, |u| self.distance(&u))
    }

    /// True when `u` lies inside the region (T^2 at most the bound).
    pub fn contains(&self, u: &[f64]) -> bool {
        self.distance(u) <= self.bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::rng;

    #[test]
    fn the_bound_is_hotellings() {
        // F(0.95; 2, 3) = 9.5521 (scipy.stats.f.ppf(0.95, 2, 3)), so the bound
        // at n = 5 is 2 * 4 / 3 * 9.5521 = 25.472; at n = 910, 2 * 909 / 908 *
        // F(0.95; 2, 908) = 6.0179 (scipy; tests/independent/calibration.py
        // prints 25.47 and 6.02); p = 1, n = 5: t(0.975, 4)^2 = 2.7764^2 = 7.7086.
        let hands = |n: usize, p: usize| -> Vec<Vec<f64>> {
            (0..n)
                .map(|i| {
                    (0..p)
                        .map(|k| 0.5 + 0.01 * ((i * 7 + k * 3) % 5) as f64 + 0.001 * i as f64)
                        .collect()
                })
                .collect()
        };
        let r = JointRegion::of(&hands(5, 2), 0.95).unwrap();
        assert!((r.bound - 25.4723).abs() < 0.0001, "{}", r.bound);
        let r = JointRegion::of(&hands(910, 2), 0.95).unwrap();
        assert!((r.bound - 6.0179).abs() < 0.0001, "{}", r.bound);
        let r = JointRegion::of(&hands(5, 1), 0.95).unwrap();
        assert!((r.bound - 7.7086).abs() < 0.0001, "{}", r.bound);
    }

    #[test]
    fn one_dimension_is_the_t_prediction_interval() {
        // For p = 1 the region is mean +- t(0.975, n-1) s sqrt(1 + 1/n).
        let xs = [0.50, 0.53, 0.52, 0.55, 0.51];
        let hands: Vec<Vec<f64>> = xs.iter().map(|&x| vec![x]).collect();
        let r = JointRegion::of(&hands, 0.95).unwrap();
        let mean = xs.iter().sum::<f64>() / 5.0;
        let s = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 4.0).sqrt();
        let half = 2.776_445_105_2 * s * (1.0 + 0.2_f64).sqrt();
        assert!(r.contains(&[mean + 0.999 * half]));
        assert!(!r.contains(&[mean + 1.001 * half]));
        assert!(!r.contains(&[mean - 1.001 * half]));
    }

    #[test]
    fn positions_are_the_cumulative_shares() {
        // The paper's X-ray 1a index: J1 339.96, J2 188.83, J3 169.67 (Table 1);
        // J = 698.46, so u = (0.48674, 0.75709) by hand.
        let u = positions(&[339.96, 188.83, 169.67]).unwrap();
        assert!((u[0] - 339.96 / 698.46).abs() < 1e-12);
        assert!((u[1] - 528.79 / 698.46).abs() < 1e-12);
        assert_eq!(positions(&[1.0]), None);
        assert_eq!(positions(&[1.0, f64::NAN]), None);
        assert_eq!(positions(&[1.0, -1.0, 2.0]), None);
        assert_eq!(positions(&[1.0, 1.0, 1.0, 1.0]), None);
    }

    #[test]
    fn inline_positions_are_the_vectors_and_give_the_same_region() {
        // Position (inline, for building a region over many hands) against
        // positions (a vector): the same values, refusals and region.
        let thumb = [0.9, 0.7];
        let finger = [339.96, 188.83, 169.67];
        for seg in [&thumb[..], &finger[..]] {
            assert_eq!(
                Position::of(seg).unwrap().as_ref(),
                &positions(seg).unwrap()[..]
            );
        }
        for bad in [
            &[1.0][..],
            &[1.0, f64::NAN],
            &[1.0, -1.0, 2.0],
            &[1.0, 1.0, 1.0, 1.0],
        ] {
            assert!(Position::of(bad).is_none());
        }
        let mut g = rng::stream(7, 1, 0);
        let hands: Vec<Vec<f64>> = (0..40)
            .map(|_| {
                let j: Vec<f64> = (0..3)
                    .map(|_| 1.0 + rng::standard_normal(&mut g).abs())
                    .collect();
                j
            })
            .collect();
        let vectors: Vec<Vec<f64>> = hands.iter().map(|h| positions(h).unwrap()).collect();
        let inline: Vec<Position> = hands.iter().map(|h| Position::of(h).unwrap()).collect();
        let (a, b) = (
            JointRegion::of(&vectors, 0.95),
            JointRegion::of(&inline, 0.95),
        );
        assert!(a.is_some());
        assert_eq!(a, b);
    }

    #[test]
    fn bad_input_gives_no_region() {
        assert_eq!(JointRegion::of::<Vec<f64>>(&[], 0.95), None);
        assert_eq!(
            JointRegion::of(&[vec![0.5, 0.7], vec![0.6, 0.8]], 0.95),
            None
        );
        let same = vec![vec![0.5, 0.7]; 5];
        assert_eq!(JointRegion::of(&same, 0.95), None, "singular S");
        let ok = vec![
            vec![0.5, 0.7],
            vec![0.6, 0.75],
            vec![0.55, 0.8],
            vec![0.52, 0.71],
        ];
        assert_eq!(JointRegion::of(&ok, 1.0), None);
        assert_eq!(JointRegion::of(&ok, f64::NAN), None);
        let r = JointRegion::of(&ok, 0.95).unwrap();
        assert_eq!(r.distance(&[0.5]), f64::INFINITY);
        assert_eq!(r.distance(&[0.5, f64::NAN]), f64::INFINITY);
    }

    /// Draws of a two-dimensional normal with mean `mu` and covariance
    /// [[a, b], [b, d]] by its Cholesky factor.
    fn draw(r: &mut rand_chacha::ChaCha8Rng, mu: [f64; 2], a: f64, b: f64, d: f64) -> Vec<f64> {
        let l11 = a.sqrt();
        let l21 = b / l11;
        let l22 = (d - l21 * l21).sqrt();
        let (z1, z2) = (rng::standard_normal(r), rng::standard_normal(r));
        vec![mu[0] + l11 * z1, mu[1] + l21 * z1 + l22 * z2]
    }

    #[test]
    fn a_new_hand_falls_inside_about_as_often_as_the_confidence_says() {
        // The calibration the per-quantity rule fails (83% at n = 5, see
        // tests/independent/calibration.py): simulated reference sets of n
        // hands and one new hand from the same population (the atlas index
        // finger's scale of spread, correlated positions); the new hand is
        // inside the 95% region in 95% +- 1.1 points (3 Monte-Carlo SEs of
        // 4000 simulations) at n = 5 and at n = 40.
        let mut r = rng::stream(1, 0x7265_6769_6f6e, 0);
        let (mu, a, b, d) = ([0.485, 0.757], 4.0e-4, 2.5e-4, 3.0e-4);
        for n in [5usize, 40] {
            let sims = 4000;
            let mut inside = 0;
            for _ in 0..sims {
                let hands: Vec<Vec<f64>> = (0..n).map(|_| draw(&mut r, mu, a, b, d)).collect();
                let new = draw(&mut r, mu, a, b, d);
                let region = JointRegion::of(&hands, 0.95).unwrap();
                inside += usize::from(region.contains(&new));
            }
            let rate = inside as f64 / sims as f64;
            assert!((rate - 0.95).abs() < 0.011, "n = {n}: {rate}");
        }
    }
}
