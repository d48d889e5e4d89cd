//! The delta method for a ratio of sums of means, and Pearson's correlation.
//!
//! A published table gives the mean m_i, SD s_i and n_i of each part (a segment length),
//! not the per-hand values. A ratio of sums of its means, R = (sum_i a_i m_i) / (sum_i b_i m_i)
//! with weights a, b of 0 or 1 (the distal phalanx over the finger: a = distal,
//! b = every phalanx), has to first order (the delta method)
//!
//!   Var(R) = g' C g,   g_i = (a_i D - b_i N) / D^2,   N = a.m, D = b.m,
//!
//! where C is the covariance matrix of the means: C_ii = s_i^2 / n_i and
//! C_ij = rho s_i s_j / sqrt(n_i n_j) for an assumed correlation rho between parts measured
//! on the same hands (for equal n, rho s_i s_j / n). With the covariance of single hands,
//! rho s_i s_j, the same g gives the SD of one hand's ratio to first order, which a
//! prediction interval needs. With b = 0 (no denominator) R is the plain sum N.
//! Cost: O(k^2) for k parts.

/// One part of a ratio: its mean, SD and number of hands (`None`: not published).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Part {
    pub mean: f64,
    pub sd: Option<f64>,
    pub n: Option<f64>,
    /// Weight in the numerator (0 or 1).
    pub num: f64,
    /// Weight in the denominator (0 or 1); all 0 means no denominator.
    pub den: f64,
}

/// A ratio of sums of means with its first-order spread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ratio {
    pub value: f64,
    /// Standard error of the ratio of means; `None` when a part it depends on has no SD or n.
    pub se: Option<f64>,
    /// SD of one hand's ratio; `None` when a part it depends on has no SD.
    pub sd: Option<f64>,
}

/// The ratio (sum of num-weighted means) / (sum of den-weighted means) and its delta-method
/// SE and per-hand SD under correlation `rho` between every two parts. `None` for no parts,
/// a non-positive denominator or a non-finite result.
pub fn ratio_of_sums(parts: &[Part], rho: f64) -> Option<Ratio> {
    if parts.is_empty() || !rho.is_finite() {
        return None;
    }
    let n: f64 = parts.iter().map(|p| p.num * p.mean).sum();
    let has_den = parts.iter().any(|p| p.den != 0.0);
    let d: f64 = if has_den {
        parts.iter().map(|p| p.den * p.mean).sum()
    } else {
        1.0
    };
    if !(d > 0.0 && d.is_finite() && n.is_finite()) {
        return None;
    }
    let g: Vec<f64> = parts
        .iter()
        .map(|p| {
            if has_den {
                (p.num * d - p.den * n) / (d * d)
            } else {
                p.num
            }
        })
        .collect();
    // Only parts with a non-zero gradient need their spread.
    let used: Vec<usize> = (0..parts.len()).filter(|&i| g[i] != 0.0).collect();
    let quad = |scale: &dyn Fn(usize) -> Option<f64>| -> Option<f64> {
        let mut v = 0.0;
        for &i in &used {
            for &j in &used {
                let r = if i == j { 1.0 } else { rho };
                v += g[i] * g[j] * r * scale(i)? * scale(j)?;
            }
        }
        (v >= 0.0 && v.is_finite()).then(|| v.sqrt())
    };
    let se = quad(&|i| {
        let p = &parts[i];
        Some(p.sd? / p.n.filter(|&n| n > 0.0)?.sqrt())
    });
    let sd = quad(&|i| parts[i].sd);
    let value = n / d;
    value.is_finite().then_some(Ratio { value, se, sd })
}

/// Pearson's correlation of paired values; `None` for fewer than 3 pairs, unequal lengths or
/// a constant series. O(n), two passes.
pub fn pearson(xs: &[f64], ys: &[f64]) -> Option<f64> {
    if xs.len() != ys.len() || xs.len() < 3 {
        return None;
    }
    let (mx, my) = (super::describe::mean(xs)?, super::describe::mean(ys)?);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in xs.iter().zip(ys) {
        let (dx, dy) = (x - mx, y - my);
        sxy += dx * dy;
        sxx += dx * dx;
        syy += dy * dy;
    }
    let r = sxy / (sxx * syy).sqrt();
    r.is_finite().then(|| r.clamp(-1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng;

    fn part(mean: f64, sd: f64, num: f64, den: f64) -> Part {
        Part {
            mean,
            sd: Some(sd),
            n: Some(66.0),
            num,
            den,
        }
    }

    /// B&K's index finger: distal over the three phalanges, bone only.
    fn index_parts() -> Vec<Part> {
        vec![
            part(39.78, 4.94, 0.0, 1.0),
            part(22.38, 2.51, 0.0, 1.0),
            part(15.82, 2.26, 1.0, 1.0),
        ]
    }

    #[test]
    fn by_hand_at_correlation_zero() {
        // g = ((T - D)/T^2, -D/T^2, -D/T^2) with T = 77.98, D = 15.82;
        // Var = sum g_i^2 s_i^2 / 66 = 1.12294e-5 (computed by hand from these figures).
        let r = ratio_of_sums(&index_parts(), 0.0).unwrap();
        assert!((r.value - 15.82 / 77.98).abs() < 1e-15);
        let t: f64 = 77.98;
        let g = [-15.82 / (t * t), -15.82 / (t * t), (t - 15.82) / (t * t)];
        let s = [4.94, 2.51, 2.26];
        let v: f64 = (0..3).map(|i| (g[i] * s[i]).powi(2)).sum::<f64>() / 66.0;
        assert!((r.se.unwrap() - v.sqrt()).abs() < 1e-15);
        assert!((r.sd.unwrap() - (v * 66.0).sqrt()).abs() < 1e-14);
    }

    #[test]
    fn no_denominator_is_a_sum_and_missing_spread_gives_no_se() {
        let mut p = index_parts();
        for x in &mut p {
            x.num = 1.0;
            x.den = 0.0;
        }
        let r = ratio_of_sums(&p, 0.5).unwrap();
        assert!((r.value - 77.98).abs() < 1e-12);
        p[0].sd = None;
        assert_eq!(ratio_of_sums(&p, 0.5).unwrap().se, None);
        // A part with zero gradient may lack its spread: distal / middle ignores the proximal.
        let mut q = index_parts();
        q[0].den = 0.0;
        q[0].sd = None;
        q[2].den = 0.0;
        q[1].den = 1.0;
        assert!(ratio_of_sums(&q, 0.3).unwrap().se.is_some());
    }

    /// The delta-method SE against a seeded simulation of the table's design: 66 hands
    /// drawn from a multivariate normal with B&K's index means and SDs and correlation rho
    /// between every two segments, the ratio of the sample means recorded, 4,000 times.
    /// The simulated SD has a Monte Carlo SE of about sd / sqrt(2 (M - 1)); the two must agree
    /// within 3 of those (plus the delta method's own second-order error, far smaller here).
    #[test]
    fn delta_method_se_agrees_with_a_seeded_simulation() {
        let parts = index_parts();
        let sims = 4_000usize;
        for (k, rho) in [0.0, 0.5, 0.9].into_iter().enumerate() {
            let want = ratio_of_sums(&parts, rho).unwrap().se.unwrap();
            // Equicorrelated normals: x_i = m_i + s_i (sqrt(rho) z0 + sqrt(1 - rho) z_i).
            let mut rng = rng::stream(2010, 0xde17a, k as u64);
            let mut ratios = Vec::with_capacity(sims);
            for _ in 0..sims {
                let mut sums = [0.0f64; 3];
                for _ in 0..66 {
                    let z0 = rng::standard_normal(&mut rng);
                    for (i, p) in parts.iter().enumerate() {
                        let z = rng::standard_normal(&mut rng);
                        sums[i] +=
                            p.mean + p.sd.unwrap() * (rho.sqrt() * z0 + (1.0 - rho).sqrt() * z);
                    }
                }
                ratios.push(sums[2] / (sums[0] + sums[1] + sums[2]));
            }
            let sd = crate::describe::sd(&ratios).unwrap();
            let mc = sd / (2.0 * (sims as f64 - 1.0)).sqrt();
            assert!(
                (sd - want).abs() < 3.0 * mc,
                "rho {rho}: simulated {sd} vs delta {want} (MC SE {mc})"
            );
        }
    }

    #[test]
    fn pearson_by_hand() {
        // x = 1..5, y = 2x + noise: r by hand
        let x = [1.0, 2.0, 3.0, 4.0, 5.0];
        let y = [2.1, 3.9, 6.2, 7.8, 10.1];
        let r = pearson(&x, &y).unwrap();
        // sxy = 19.9, sxx = 10, syy = 39.708 (by hand): r = 19.9 / sqrt(397.08).
        assert!((r - 19.9 / 397.08f64.sqrt()).abs() < 1e-12, "{r}");
        assert_eq!(pearson(&x, &[1.0; 5]), None);
        assert_eq!(pearson(&x[..2], &y[..2]), None);
    }
}
