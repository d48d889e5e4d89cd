//! Tracking a growing dataset: snapshots, changes between them, outlier flags,
//! and how many X-rays a target precision needs.

use super::{Analysis, Interval, Quantity, xray_values};
use crate::dataset::history::{Event, FingerCount, QuantityRecord, Snapshot, SnapshotSettings};
use crate::dataset::{Finger, Row};
use crate::format;
use crate::stats::describe;
use serde::Serialize;

/// The history record of an analysis.
pub fn snapshot(a: &Analysis, time: String, event: Event) -> Snapshot {
    Snapshot {
        time,
        event,
        dataset: a.dataset.path.clone(),
        sha256: a.dataset.sha256.clone(),
        xrays: a.dataset.xrays,
        fingers: a
            .fingers
            .iter()
            .map(|f| FingerCount {
                finger: f.finger,
                n: f.n,
            })
            .collect(),
        settings: SnapshotSettings {
            resamples: a.settings.resamples,
            seed: a.settings.seed,
            confidence: a.settings.confidence,
        },
        quantities: a
            .fingers
            .iter()
            .flat_map(|f| {
                f.quantities.iter().map(move |q| QuantityRecord {
                    finger: f.finger,
                    quantity: q.name,
                    n: q.n,
                    mean: q.mean,
                    sd: q.sd,
                    intervals: q.intervals,
                })
            })
            .collect(),
    }
}

/// How one quantity moved between two snapshots.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Change {
    pub finger: Finger,
    pub quantity: Quantity,
    pub n_before: usize,
    pub n_after: usize,
    pub mean_before: f64,
    pub mean_after: f64,
    /// mean_after - mean_before.
    pub mean_shift: f64,
    /// Width of the t interval before and after; null where undefined.
    pub ci_width_before: Option<f64>,
    pub ci_width_after: Option<f64>,
}

/// Changes of every quantity present in both snapshots, in the order of `after`.
pub fn changes(before: &Snapshot, after: &Snapshot) -> Vec<Change> {
    after
        .quantities
        .iter()
        .filter_map(|q| {
            let b = before
                .quantities
                .iter()
                .find(|p| p.finger == q.finger && p.quantity == q.quantity)?;
            let width = |i: Option<Interval>| i.map(|i| i.width());
            Some(Change {
                finger: q.finger,
                quantity: q.quantity,
                n_before: b.n,
                n_after: q.n,
                mean_before: b.mean,
                mean_after: q.mean,
                mean_shift: q.mean - b.mean,
                ci_width_before: width(b.intervals.ci_t),
                ci_width_after: width(q.intervals.ci_t),
            })
        })
        .collect()
}

/// One quantity's history: (X-rays, mean, t interval) per snapshot, in order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityHistory {
    pub finger: Finger,
    pub quantity: Quantity,
    pub points: Vec<(usize, f64, Option<Interval>)>,
}

/// The history of every quantity present in the snapshots, in first-seen order.
pub fn histories(snaps: &[Snapshot]) -> Vec<QuantityHistory> {
    let mut out: Vec<QuantityHistory> = Vec::new();
    for s in snaps {
        for q in &s.quantities {
            let point = (q.n, q.mean, q.intervals.ci_t);
            match out
                .iter_mut()
                .find(|h| h.finger == q.finger && h.quantity == q.quantity)
            {
                Some(h) => h.points.push(point),
                None => out.push(QuantityHistory {
                    finger: q.finger,
                    quantity: q.quantity,
                    points: vec![point],
                }),
            }
        }
    }
    out
}

/// The (finger, quantity) pairs present in a history, in first-seen order,
/// narrowed to one finger and/or quantity.
pub fn selected(
    snaps: &[Snapshot],
    finger: Option<Finger>,
    quantity: Option<Quantity>,
) -> Vec<(Finger, Quantity)> {
    let mut out: Vec<(Finger, Quantity)> = Vec::new();
    for s in snaps {
        for r in &s.quantities {
            let keep =
                finger.is_none_or(|f| f == r.finger) && quantity.is_none_or(|q| q == r.quantity);
            let key = (r.finger, r.quantity);
            if keep && !out.contains(&key) {
                out.push(key);
            }
        }
    }
    out
}

/// Largest n [`xrays_needed`] searches.
pub const MAX_NEEDED: usize = 100_000_000;

/// The smallest number of X-rays n >= 2 whose t interval half-width
/// t_{(1+c)/2, n-1} * sd / sqrt(n) is at most `target`, taking the SD as known.
/// `None` when more than [`MAX_NEEDED`] would be needed or the input is unusable.
/// Cost: O(log n) quantile evaluations (bisection on a monotone function).
pub fn xrays_needed(sd: f64, target: f64, confidence: f64) -> Option<usize> {
    if !(sd.is_finite() && target.is_finite() && target > 0.0 && sd >= 0.0) {
        return None;
    }
    let half =
        |n: usize| describe::t_quantile(confidence, n - 1).map(|t| t * sd / (n as f64).sqrt());
    if half(2)? <= target {
        return Some(2);
    }
    if half(MAX_NEEDED)? > target {
        return None;
    }
    // half(n) decreases in n: bisect for the first n with half(n) <= target.
    let (mut lo, mut hi) = (2usize, MAX_NEEDED);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if half(mid)? <= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// A new row's value that falls outside what the current data predicts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Flag {
    pub xray: String,
    pub finger: String,
    pub quantity: String,
    pub value: f64,
    /// The current prediction interval (null when n < 2).
    pub interval: Option<[f64; 2]>,
    /// Why this is flagged and what may be wrong, in words.
    pub reason: String,
}

/// Robust z-score above which a value is flagged whatever the prediction interval says.
pub const ROBUST_Z: f64 = 5.0;

/// Why a value is unusual, if it is: outside the prediction interval of the
/// current data, or more than [`ROBUST_Z`] robust SDs (1.4826 MAD) from the
/// median. The robust rule still works after an earlier outlier has widened
/// the prediction interval; it needs at least 5 X-rays.
fn unusual(v: f64, pi: Option<Interval>, values: &[f64]) -> Option<String> {
    if let Some(pi) = pi.filter(|pi| !pi.contains(v)) {
        return Some(format!(
            "outside the prediction interval {}",
            format::interval(Some(pi), 4)
        ));
    }
    if values.len() < 5 {
        return None;
    }
    let (m, s) = (describe::median(values)?, describe::mad(values)?);
    let z = (v - m).abs() / s;
    (s > 0.0 && z > ROBUST_Z).then(|| {
        format!(
            "{} robust SDs from the median {} (more than {})",
            format::num(z, 1),
            format::num(m, 4),
            format::exact(ROBUST_Z)
        )
    })
}

/// Compares a new row's relative values with the current analysis (see
/// [`unusual`]): an unusual value is flagged as a likely measurement or typing
/// error, with a hint when one length 10 times too large or too small explains
/// it (a misplaced decimal point).
pub fn flag_row(a: &Analysis, row: &Row) -> Vec<Flag> {
    let Some(fa) = a.finger(row.finger) else {
        return Vec::new();
    };
    let relative: Vec<Quantity> = Quantity::of(row.finger)
        .iter()
        .copied()
        .filter(|q| q.is_relative())
        .collect();
    let columns: Vec<Vec<f64>> = (0..relative.len())
        .map(|k| fa.xrays.iter().map(|x| x.relative[k]).collect())
        .collect();
    let check = |r: &Row| -> Vec<(usize, String)> {
        let x = xray_values(r);
        relative
            .iter()
            .enumerate()
            .filter_map(|(k, q)| {
                let pi = fa.quantity(*q).and_then(|s| s.intervals.pi);
                unusual(x.relative[k], pi, &columns[k]).map(|why| (k, why))
            })
            .collect()
    };
    let found = check(row);
    if found.is_empty() {
        return Vec::new();
    }
    // Candidate fixes: one length times 10 or 0.1. For a two-segment thumb,
    // "j1 too small" and "j2 too large" give the same proportions; the total
    // length then decides: the fix whose total is nearest the current mean total.
    let mean_total = fa.quantity(Quantity::Total).map(|t| t.mean);
    let hint = (0..row.finger.segments())
        .flat_map(|k| [(k, 10.0), (k, 0.1)])
        .filter_map(|(k, factor)| {
            let mut fixed = row.clone();
            fixed.lengths[k] *= factor;
            let distance = mean_total.map_or(0.0, |m| (fixed.total() - m).abs());
            check(&fixed).is_empty().then_some((k, factor, distance))
        })
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .map(|(k, factor, _)| {
            format!(
                "; j{} looks 10 times too {} (a misplaced decimal point?)",
                k + 1,
                if factor < 1.0 { "large" } else { "small" }
            )
        })
        .unwrap_or_default();
    let x = xray_values(row);
    found
        .into_iter()
        .map(|(k, why)| {
            let q = relative[k];
            let pi = fa.quantity(q).and_then(|s| s.intervals.pi);
            Flag {
                xray: row.xray.to_string(),
                finger: row.finger.name().to_string(),
                quantity: q.name().to_string(),
                value: x.relative[k],
                interval: pi.map(|p| [p.low, p.high]),
                reason: format!(
                    "{} {} of X-ray '{}' is {}, {why} of the current {} X-rays: a likely measurement or typing error{hint}",
                    row.finger,
                    q.label(),
                    row.xray,
                    format::num(x.relative[k], 4),
                    fa.n
                ),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use std::path::Path;

    fn paper() -> (Dataset, Analysis) {
        let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        let a = analyse(&d, &Settings::default());
        (d, a)
    }

    #[test]
    fn needed_xrays_by_hand() {
        // sd 0.0131 (index J~1), target 0.005, 95%: the normal approximation gives
        // (1.96 * 0.0131 / 0.005)^2 = 26.4; with t quantiles n = 29 (scipy: t.ppf(.975, 28) * 0.0131 / sqrt(29)
        // = 0.00498, t.ppf(.975, 27) * 0.0131 / sqrt(28) = 0.00508).
        assert_eq!(xrays_needed(0.0131, 0.005, 0.95), Some(29));
        assert_eq!(xrays_needed(0.0, 0.005, 0.95), Some(2));
        assert_eq!(xrays_needed(1.0, 1e-9, 0.95), None);
        assert_eq!(xrays_needed(f64::NAN, 0.005, 0.95), None);
    }

    #[test]
    fn a_tenfold_typo_is_flagged_with_a_hint() {
        let (_, a) = paper();
        let text = "xray,finger,j1,j2,j3\nnew,index,3399.6,188.83,169.67\nok,index,340,189,170\n";
        let d = Dataset::from_bytes("n.csv", text.as_bytes()).unwrap();
        let flags = flag_row(&a, &d.rows[0]);
        assert!(!flags.is_empty());
        assert!(
            flags[0].reason.contains("j1 looks 10 times too large"),
            "{}",
            flags[0].reason
        );
        assert!(flag_row(&a, &d.rows[1]).is_empty());
    }

    #[test]
    fn a_thumb_typo_is_told_apart_by_the_total_length() {
        // J2 typed 10x too large: proportions alone would also fit "j1 10x too small",
        // but that would make the thumb ~5x longer than the others (mean total 520).
        let (_, a) = paper();
        let d =
            Dataset::from_bytes("n.csv", b"xray,finger,j1,j2,j3\nt,thumb,270.5,2310.2,\n").unwrap();
        let flags = flag_row(&a, &d.rows[0]);
        assert!(
            flags[0].reason.contains("j2 looks 10 times too large"),
            "{}",
            flags[0].reason
        );
    }

    #[test]
    fn the_robust_rule_catches_a_second_typo_after_a_first() {
        // After one tenfold typo is added, the prediction interval is wide enough to let
        // a second one through; the median/MAD rule still flags it.
        let (d, _) = paper();
        let mut bad = d.clone();
        let extra = Dataset::from_bytes(
            "n.csv",
            b"xray,finger,j1,j2,j3\nz,ring,3584,226.47,191.09\n",
        )
        .unwrap();
        bad.rows.extend(extra.rows.clone());
        let a = analyse(&bad, &Settings::default());
        let second = Dataset::from_bytes(
            "n.csv",
            b"xray,finger,j1,j2,j3\ny,ring,3729.8,226.72,212.12\n",
        )
        .unwrap();
        let pi = a
            .finger(Finger::Ring)
            .unwrap()
            .quantity(Quantity::RelJ1)
            .unwrap()
            .intervals
            .pi
            .unwrap();
        assert!(
            pi.contains(second.rows[0].lengths[0] / second.rows[0].total()),
            "premise: inside the PI"
        );
        let flags = flag_row(&a, &second.rows[0]);
        assert!(!flags.is_empty());
        assert!(
            flags[0].reason.contains("robust SDs from the median"),
            "{}",
            flags[0].reason
        );
    }

    #[test]
    fn snapshot_and_changes() {
        let (d, a) = paper();
        let s1 = snapshot(&a, "t1".into(), Event::Snapshot);
        assert_eq!(s1.quantities.len(), 28); // thumb 4 + 4 fingers x 6
        assert_eq!(s1.xrays, 5);
        let mut d2 = d.clone();
        let extra =
            Dataset::from_bytes("n.csv", b"xray,finger,j1,j2,j3\nz,index,350,190,170\n").unwrap();
        d2.rows.extend(extra.rows);
        let s2 = snapshot(&analyse(&d2, &Settings::default()), "t2".into(), Event::Add);
        let c = changes(&s1, &s2);
        assert_eq!(c.len(), 28);
        let idx = c
            .iter()
            .find(|c| c.finger == Finger::Index && c.quantity == Quantity::RelJ1)
            .unwrap();
        assert_eq!((idx.n_before, idx.n_after), (5, 6));
        let expect = (0.484636 * 5.0 + 350.0 / 710.0) / 6.0 - 0.484636;
        assert!((idx.mean_shift - expect).abs() < 1e-5, "{}", idx.mean_shift);
        let thumb = c.iter().find(|c| c.finger == Finger::Thumb).unwrap();
        assert_eq!(thumb.mean_shift, 0.0);
    }
}
