//! The interval estimates around a mean: the Student-t, bootstrap percentile
//! and BCa confidence intervals of the mean, and the prediction interval for
//! one new observation, held together as one [`Intervals`].

use super::Interval;
use super::bootstrap::{self, Sorted};
use super::describe;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The four intervals around a mean; each is `None` where it is undefined.
///
/// Serialised as the four keys `ci_t`, `ci_percentile`, `ci_bca` and `pi`, each
/// `[low, high]` or null; a struct that holds it with `#[serde(flatten)]` keeps
/// those keys at its own level. A missing key reads as null.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, JsonSchema, Deserialize)]
pub struct Intervals {
    /// Student-t confidence interval of the mean: mean +/- t sd / sqrt(n).
    pub ci_t: Option<Interval>,
    /// Bootstrap percentile confidence interval of the mean.
    pub ci_percentile: Option<Interval>,
    /// Bootstrap BCa confidence interval of the mean.
    pub ci_bca: Option<Interval>,
    /// Prediction interval for one new observation: mean +/- t sd sqrt(1 + 1/n).
    pub pi: Option<Interval>,
}

impl Intervals {
    /// Every interval undefined.
    pub const NONE: Intervals = Intervals {
        ci_t: None,
        ci_percentile: None,
        ci_bca: None,
        pi: None,
    };

    /// Every interval collapsed to the single value `x` (a sample without spread).
    pub fn point(x: f64) -> Intervals {
        let p = Some(Interval::point(x));
        Intervals {
            ci_t: p,
            ci_percentile: p,
            ci_bca: p,
            pi: p,
        }
    }

    /// The four intervals of the mean of `sample` (n >= 2, with spread) at
    /// level `confidence`, given its mean, its SD and the sorted bootstrap
    /// distribution of its mean. BCa may be undefined; the reason comes back
    /// with it. Cost: O(n) plus O(log m) per bootstrap quantile.
    pub fn of_mean(
        sample: &[f64],
        mean: f64,
        sd: f64,
        boot: &Sorted,
        confidence: f64,
    ) -> (Intervals, Option<&'static str>) {
        let n = sample.len();
        let (ci_bca, why) = match bootstrap::bca_interval(boot, sample, mean, confidence) {
            Ok(i) => (Some(i), None),
            Err(reason) => (None, Some(reason)),
        };
        let intervals = Intervals {
            ci_percentile: Some(bootstrap::percentile_interval(boot, confidence)),
            ci_bca,
            ..Intervals::parametric(mean, sd, n, confidence)
        };
        (intervals, why)
    }

    /// The t interval and the prediction interval of a mean of n values with SD `sd` at
    /// level `confidence`, the bootstrap intervals left undefined: the two
    /// [`of_mean`](Self::of_mean) gives that need no resample. O(1).
    pub fn parametric(mean: f64, sd: f64, n: usize, confidence: f64) -> Intervals {
        Intervals {
            ci_t: describe::t_interval(mean, sd, n, confidence),
            pi: describe::prediction_interval(mean, sd, n, confidence),
            ..Intervals::NONE
        }
    }

    /// The four in table order: t, percentile, BCa, prediction.
    pub fn all(&self) -> [Option<Interval>; 4] {
        [self.ci_t, self.ci_percentile, self.ci_bca, self.pi]
    }

    /// The intervals of `offset + scale * x`, from those of x: each end is
    /// mapped, and the ends swap when `scale < 0`. Exact for all four, which are
    /// equivariant under affine maps. O(1).
    pub fn affine(&self, offset: f64, scale: f64) -> Intervals {
        let map = |i: Option<Interval>| {
            i.map(|i| {
                let (a, b) = (offset + scale * i.low, offset + scale * i.high);
                Interval::new(a.min(b), a.max(b))
            })
        };
        Intervals {
            ci_t: map(self.ci_t),
            ci_percentile: map(self.ci_percentile),
            ci_bca: map(self.ci_bca),
            pi: map(self.pi),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn of_mean_by_hand() {
        // x = (1, 3): mean 2, sd sqrt(2); t_{0.975, 1} = 12.706205 (scipy.stats.t.ppf(0.975, 1)),
        // so the t interval is 2 +/- 12.706205 * sqrt(2) / sqrt(2) and the prediction
        // interval 2 +/- 12.706205 * sqrt(2) * sqrt(1.5) = 2 +/- 22.007792.
        let xs = [1.0, 3.0];
        let d = bootstrap::resample_means(&[&xs], 100, 0, 0);
        let boot = Sorted::new(&d.means[0], &d.weights);
        let (iv, why) = Intervals::of_mean(&xs, 2.0, 2f64.sqrt(), &boot, 0.95);
        let t = iv.ci_t.unwrap();
        assert!((t.high - 2.0 - 12.706_205).abs() < 1e-5, "{t:?}");
        let p = iv.pi.unwrap();
        assert!((p.high - 2.0 - 22.007_792).abs() < 1e-5, "{p:?}");
        // The exact bootstrap of (1, 3) puts 1/4 on 1 and on 3: the 2.5% and 97.5% quantiles.
        assert_eq!(iv.ci_percentile, Some(Interval::new(1.0, 3.0)));
        // Symmetric: z0 = Phi^-1(1/4 + 1/2 / 2) = 0 and a = 0, so BCa is the percentile interval.
        assert_eq!(iv.ci_bca, iv.ci_percentile);
        assert_eq!(why, None);
        assert_eq!(iv.all(), [iv.ci_t, iv.ci_percentile, iv.ci_bca, iv.pi]);
    }

    #[test]
    fn affine_maps_and_flips() {
        let iv = Intervals {
            ci_t: Some(Interval::new(0.2, 0.3)),
            ci_percentile: None,
            ci_bca: Some(Interval::new(0.1, 0.4)),
            pi: Some(Interval::point(0.25)),
        };
        let m = iv.affine(100.0, -100.0);
        assert_eq!(m.ci_t, Some(Interval::new(70.0, 80.0)));
        assert_eq!(m.ci_percentile, None);
        assert_eq!(m.ci_bca, Some(Interval::new(60.0, 90.0)));
        assert_eq!(m.pi, Some(Interval::point(75.0)));
        assert_eq!(Intervals::point(1.5).all(), [Some(Interval::point(1.5)); 4]);
        assert_eq!(Intervals::NONE.all(), [None; 4]);
    }

    #[test]
    fn serialises_as_four_keys_and_reads_missing_ones_as_null() {
        let iv = Intervals {
            ci_t: Some(Interval::new(0.25, 0.5)),
            ..Intervals::NONE
        };
        let json = serde_json::to_string(&iv).unwrap();
        assert_eq!(
            json,
            r#"{"ci_t":[0.25,0.5],"ci_percentile":null,"ci_bca":null,"pi":null}"#
        );
        let back: Intervals = serde_json::from_str(r#"{"ci_t":[0.25,0.5]}"#).unwrap();
        assert_eq!(back, iv);
    }
}
