//! One cohort's estimate of one quantity, from per-X-ray values or from a summary table's
//! means, and the Welch-type difference of two estimates.
//!
//! A table's estimate is a ratio of sums of its segment means with a delta-method standard
//! error under an assumed correlation ([`crate::stats::delta`]); df = n - 1 with n the
//! smallest n of the segments used. The difference B - A has SE = sqrt(SE_A^2 + SE_B^2) and
//! Welch-Satterthwaite degrees of freedom. Cost: O(segments^2) per quantity of a table.

use crate::analysis::{Interval, Quantity};
use crate::dataset::{Finger, Segment, SummaryTable, TipKind};
use crate::stats::delta::{self, Part};
use crate::stats::describe;
use schemars::JsonSchema;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// One cohort's estimate of one quantity.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Estimate {
    /// The mean over X-rays (a dataset), or the ratio of the table's means.
    pub mean: f64,
    /// Standard error: SD / sqrt(n), or the delta method's.
    pub se: Option<f64>,
    /// Degrees of freedom of the t quantile: n - 1.
    pub df: Option<f64>,
    /// X-rays or hands.
    pub n: Option<usize>,
    /// SD of one hand's value (for a table, to first order under the correlation).
    pub sd: Option<f64>,
    /// The t interval of the mean.
    pub ci: Option<Interval>,
    /// The prediction interval for one new hand.
    pub pi: Option<Interval>,
    /// Why there is no interval, when there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

impl Estimate {
    /// The estimate from one value per X-ray.
    pub fn of_values(xs: &[f64], confidence: f64) -> Option<Estimate> {
        let mean = describe::mean(xs)?;
        let n = xs.len();
        let sd = describe::sd(xs);
        let se = sd.map(|s| s / (n as f64).sqrt());
        Some(Estimate {
            mean,
            se,
            df: (n > 1).then(|| (n - 1) as f64),
            n: Some(n),
            sd,
            ci: sd.and_then(|s| describe::t_interval(mean, s, n, confidence)),
            pi: sd.and_then(|s| describe::prediction_interval(mean, s, n, confidence)),
            why: (n < 2).then(|| "one X-ray: no spread, so no interval".to_string()),
        })
    }
}

/// The segments of quantity `q` of `finger`, with the fingertip at `tip`, as parts of a
/// ratio of sums of the table's means (at correlation `rho`, for the SE). Err says what
/// the table lacks.
fn table_parts(
    table: &SummaryTable,
    finger: Finger,
    q: Quantity,
    tip: TipKind,
) -> Result<Vec<(Segment, Part)>, String> {
    let ph = Segment::phalanges(finger);
    let last = *ph.last().unwrap_or(&Segment::Distal);
    let skin = tip == TipKind::Skin;
    // Which segments form the numerator and the denominator.
    let mut total: Vec<Segment> = ph.to_vec();
    if skin {
        total.push(Segment::TipSoftTissue);
    }
    let last_part: Vec<Segment> = if skin {
        vec![last, Segment::TipSoftTissue]
    } else {
        vec![last]
    };
    let (num, den): (Vec<Segment>, Vec<Segment>) = match q {
        Quantity::RelJ1 => (vec![ph[0]], total.clone()),
        Quantity::RelJ2 if finger == Finger::Thumb => (last_part.clone(), total.clone()),
        Quantity::RelJ2 => (vec![ph[1]], total.clone()),
        Quantity::RelJ3 if finger == Finger::Thumb => {
            return Err("the thumb has no J3".into());
        }
        Quantity::RelJ3 => (last_part.clone(), total.clone()),
        Quantity::RatioJ2J1 if finger == Finger::Thumb => (last_part.clone(), vec![ph[0]]),
        Quantity::RatioJ2J1 => (vec![ph[1]], vec![ph[0]]),
        Quantity::RatioJ3J2 if finger == Finger::Thumb => {
            return Err("the thumb has no J3".into());
        }
        Quantity::RatioJ3J2 => (last_part.clone(), vec![ph[1]]),
        Quantity::Total => (total.clone(), vec![]),
        Quantity::RatioMcJ => (vec![Segment::Metacarpal], total.clone()),
        Quantity::RatioJ1Mc => (vec![ph[0]], vec![Segment::Metacarpal]),
    };
    let mut used: Vec<Segment> = num.iter().chain(&den).copied().collect();
    used.sort();
    used.dedup();
    used.into_iter()
        .map(|s| {
            let row = table
                .get(finger, s)
                .ok_or_else(|| format!("the table gives no {} {}", finger.name(), s.name()))?;
            Ok((
                s,
                Part {
                    mean: row.mean,
                    sd: row.sd,
                    n: row.n.map(|n| n as f64),
                    num: f64::from(u8::from(num.contains(&s))),
                    den: f64::from(u8::from(den.contains(&s))),
                },
            ))
        })
        .collect()
}

/// The table's ratio of means for quantity `q` of `finger`, with the fingertip at `tip`,
/// its delta-method SE and per-hand SD under correlation `rho`, and the t interval of the
/// ratio of means and the prediction interval for one hand (df = n - 1 with n the smallest
/// n of the segments used). Err says what the table lacks.
pub fn table_estimate(
    table: &SummaryTable,
    finger: Finger,
    q: Quantity,
    tip: TipKind,
    rho: f64,
    confidence: f64,
) -> Result<Estimate, String> {
    let parts = table_parts(table, finger, q, tip)?;
    let plain: Vec<Part> = parts.iter().map(|(_, p)| *p).collect();
    let r = delta::ratio_of_sums(&plain, rho).ok_or_else(|| {
        format!(
            "the table's {} {} cannot be formed",
            finger.name(),
            q.symbol()
        )
    })?;
    let n = parts
        .iter()
        .map(|(_, p)| p.n)
        .collect::<Option<Vec<f64>>>()
        .and_then(|ns| ns.into_iter().reduce(f64::min))
        .map(|n| n as usize);
    let missing: Vec<&str> = parts
        .iter()
        .filter(|(_, p)| p.sd.is_none() || p.n.is_none())
        .map(|(s, _)| s.name())
        .collect();
    let df = n.filter(|&n| n > 1).map(|n| (n - 1) as f64);
    let t = df.and_then(|df| t_quantile(confidence, df));
    let ci = match (r.se, t) {
        (Some(se), Some(t)) => Some(Interval::new(r.value - t * se, r.value + t * se)),
        _ => None,
    };
    let pi = match (r.sd, t, n) {
        (Some(sd), Some(t), Some(n)) => {
            let h = t * sd * (1.0 + 1.0 / n as f64).sqrt();
            Some(Interval::new(r.value - h, r.value + h))
        }
        _ => None,
    };
    let why = if !missing.is_empty() {
        Some(format!(
            "the table gives no SD or no n for the {} {}, so no interval",
            finger.name(),
            missing.join(", ")
        ))
    } else if df.is_none() {
        Some("the table's n is 1, so no interval".to_string())
    } else {
        None
    };
    Ok(Estimate {
        mean: r.value,
        se: r.se,
        df,
        n,
        sd: r.sd,
        ci,
        pi,
        why,
    })
}

/// The t quantile at (possibly fractional) df, as Welch's interval uses it.
fn t_quantile(confidence: f64, df: f64) -> Option<f64> {
    let p = 1.0 - (1.0 - confidence) / 2.0;
    if df > 1_000.0 {
        return describe::t_quantile(confidence, df.floor() as usize);
    }
    let t = StudentsT::new(0.0, 1.0, df).ok()?.inverse_cdf(p);
    t.is_finite().then_some(t)
}

/// The difference B - A of two estimates at one correlation, with its interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Difference {
    /// The correlation assumed for the table's side(s).
    pub rho: f64,
    /// mean_B - mean_A.
    pub difference: f64,
    /// sqrt(SE_A^2 + SE_B^2).
    pub se: Option<f64>,
    /// Welch-Satterthwaite degrees of freedom.
    pub df: Option<f64>,
    pub interval: Option<Interval>,
    /// The interval holds 0: equal means are not rejected (false: the interval excludes 0,
    /// the two differ). Not rejected is not shown equal. `None`: no interval.
    pub not_rejected: Option<bool>,
}

/// B - A with a Welch-type interval: SE = sqrt(SE_A^2 + SE_B^2),
/// df = (v_A + v_B)^2 / (v_A^2 / df_A + v_B^2 / df_B), interval difference -/+ t SE.
pub fn difference(a: &Estimate, b: &Estimate, rho: f64, confidence: f64) -> Difference {
    let d = b.mean - a.mean;
    let parts = match (a.se, a.df, b.se, b.df) {
        (Some(sa), Some(da), Some(sb), Some(db)) => Some((sa * sa, da, sb * sb, db)),
        _ => None,
    };
    let (se, df, interval) = match parts {
        Some((va, da, vb, db)) if va + vb > 0.0 => {
            let se = (va + vb).sqrt();
            let df = (va + vb).powi(2) / (va * va / da + vb * vb / db);
            let iv = t_quantile(confidence, df).map(|t| Interval::new(d - t * se, d + t * se));
            (Some(se), Some(df), iv)
        }
        _ => (None, None, None),
    };
    Difference {
        rho,
        difference: d,
        se,
        df,
        interval,
        not_rejected: interval.map(|i| i.contains(0.0)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn bk() -> SummaryTable {
        SummaryTable::load(Path::new("data/literature/buryanov-kotiuk-2010.csv")).unwrap()
    }

    #[test]
    fn ratios_of_the_tables_means_by_hand() {
        // index: 15.82 / (39.78 + 22.38 + 15.82); with the soft tissue 3.84 added to the
        // distal phalanx and to the finger: 19.66 / 81.82 (the table: 0.2029, 0.2403).
        let t = bk();
        let e = |tip| table_estimate(&t, Finger::Index, Quantity::RelJ3, tip, 0.0, 0.95).unwrap();
        assert!((e(TipKind::Bone).mean - 15.82 / 77.98).abs() < 1e-15);
        assert!((e(TipKind::Skin).mean - 19.66 / 81.82).abs() < 1e-15);
        // thumb J~2: 21.67 / 53.24 and 27.34 / 58.91; J2/J1 and mc/J.
        let th = |q, tip| {
            table_estimate(&t, Finger::Thumb, q, tip, 0.0, 0.95)
                .unwrap()
                .mean
        };
        assert!((th(Quantity::RelJ2, TipKind::Bone) - 21.67 / 53.24).abs() < 1e-15);
        assert!((th(Quantity::RelJ2, TipKind::Skin) - 27.34 / 58.91).abs() < 1e-15);
        assert!((th(Quantity::RatioJ2J1, TipKind::Bone) - 21.67 / 31.57).abs() < 1e-15);
        assert!((th(Quantity::RatioMcJ, TipKind::Bone) - 46.22 / 53.24).abs() < 1e-15);
        assert!(
            table_estimate(&t, Finger::Thumb, Quantity::RelJ3, TipKind::Bone, 0.0, 0.95).is_err()
        );
    }

    #[test]
    fn a_table_without_spread_has_no_interval_and_says_why() {
        let text = "finger,segment,mean,sd,n,unit\nindex,proximal,39.78,,,mm\nindex,middle,22.38,2.51,66,mm\nindex,distal,15.82,2.26,66,mm\n";
        let t = SummaryTable::from_bytes("t.csv", text.as_bytes()).unwrap();
        let e =
            table_estimate(&t, Finger::Index, Quantity::RelJ3, TipKind::Bone, 0.5, 0.95).unwrap();
        assert!((e.mean - 15.82 / 77.98).abs() < 1e-15);
        assert_eq!((e.se, e.ci), (None, None));
        assert!(
            e.why
                .unwrap()
                .contains("no SD or no n for the index proximal")
        );
        // J3/J2 does not need the proximal phalanx, so it has its interval.
        let r = table_estimate(
            &t,
            Finger::Index,
            Quantity::RatioJ3J2,
            TipKind::Bone,
            0.5,
            0.95,
        )
        .unwrap();
        assert!(r.ci.is_some() && r.why.is_none());
    }

    #[test]
    fn higher_correlation_narrows_a_share_of_the_finger() {
        let t = bk();
        let se = |rho| {
            table_estimate(
                &t,
                Finger::Middle,
                Quantity::RelJ3,
                TipKind::Bone,
                rho,
                0.95,
            )
            .unwrap()
            .se
            .unwrap()
        };
        assert!(se(0.9) < se(0.5) && se(0.5) < se(0.0));
    }
}
