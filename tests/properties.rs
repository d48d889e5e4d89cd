//! Property tests over random valid datasets: loaded from CSV bytes with
//! `Dataset::from_bytes` and analysed with `analyse` (200 resamples, so
//! X-ray counts up to 5 use the exact bootstrap and 6..11 the random one).
//!
//! Datasets have 2..12 X-rays, each with a random non-empty subset of the five
//! fingers and random positive lengths: mostly continuous values with two
//! decimals (0.01..2000), sometimes one of a few fixed values, so that ties
//! and zero-spread quantities (every X-ray giving the same value) occur too.

use phalanx::analysis::{Analysis, Interval, Quantity, QuantityStats, Settings, analyse};
use phalanx::dataset::{Dataset, Finger};
use proptest::prelude::*;

/// One X-ray: its fingers (a subset, in a random order) with their lengths.
#[derive(Debug, Clone)]
struct Xray {
    fingers: Vec<(Finger, [f64; 3])>,
}

fn length() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (1u32..=200_000).prop_map(|c| f64::from(c) / 100.0),
        1 => prop::sample::select(vec![1.0, 2.5, 10.0]),
    ]
}

fn xray() -> impl Strategy<Value = Xray> {
    (
        1u8..32,
        prop::array::uniform5(prop::array::uniform3(length())),
        any::<u64>(),
    )
        .prop_map(|(mask, lengths, order)| {
            let mut fingers: Vec<(Finger, [f64; 3])> = Finger::ALL
                .iter()
                .zip(lengths)
                .enumerate()
                .filter(|(i, _)| mask & (1 << i) != 0)
                .map(|(_, (&f, l))| (f, l))
                .collect();
            // A random order of the rows within the X-ray.
            let n = fingers.len();
            for i in (1..n).rev() {
                fingers.swap(
                    i,
                    (order.rotate_left(i as u32 * 7) % (i as u64 + 1)) as usize,
                );
            }
            Xray { fingers }
        })
}

fn dataset() -> impl Strategy<Value = Vec<Xray>> {
    prop::collection::vec(xray(), 2..12)
}

/// One CSV row.
fn row(id: usize, finger: Finger, lengths: &[f64; 3], scale: f64) -> String {
    let l = lengths.map(|x| x * scale);
    if finger == Finger::Thumb {
        format!("x{id},{},{},{},\n", finger.name(), l[0], l[1])
    } else {
        format!("x{id},{},{},{},{}\n", finger.name(), l[0], l[1], l[2])
    }
}

/// The rows of a dataset, X-ray by X-ray, every length multiplied by `scale`.
fn rows(xrays: &[Xray], scale: f64) -> Vec<String> {
    xrays
        .iter()
        .enumerate()
        .flat_map(|(id, x)| x.fingers.iter().map(move |(f, l)| row(id, *f, l, scale)))
        .collect()
}

fn csv(rows: &[String]) -> Vec<u8> {
    let mut out = String::from("xray,finger,j1,j2,j3\n");
    for r in rows {
        out.push_str(r);
    }
    out.into_bytes()
}

fn settings() -> Settings {
    Settings {
        resamples: 200,
        ..Default::default()
    }
}

fn analyse_bytes(bytes: &[u8]) -> Analysis {
    let data = Dataset::from_bytes("prop.csv", bytes).expect("a generated dataset is valid");
    analyse(&data, &settings())
}

fn intervals(s: &QuantityStats) -> [(&'static str, Option<Interval>); 4] {
    [
        ("ci_t", s.intervals.ci_t),
        ("ci_percentile", s.intervals.ci_percentile),
        ("ci_bca", s.intervals.ci_bca),
        ("pi", s.intervals.pi),
    ]
}

/// Every (finger, quantity statistics) of an analysis.
fn all_stats(a: &Analysis) -> Vec<(Finger, &QuantityStats)> {
    a.fingers
        .iter()
        .flat_map(|f| f.quantities.iter().map(move |q| (f.finger, q)))
        .collect()
}

/// The magnitude of a quantity's values: max(1, |min|, |max|).
fn magnitude(s: &QuantityStats) -> f64 {
    s.min.abs().max(s.max.abs()).max(1.0)
}

/// |a - b| <= tol, treating two equal infinities or NaNs as equal.
fn close(a: f64, b: f64, tol: f64) -> bool {
    a == b || (a - b).abs() <= tol || (a.is_nan() && b.is_nan())
}

fn close_opt(a: Option<f64>, b: Option<f64>, tol: f64) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => close(a, b, tol),
        (None, None) => true,
        _ => false,
    }
}

fn close_iv(a: Option<Interval>, b: Option<Interval>, tol: f64) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => close(a.low, b.low, tol) && close(a.high, b.high, tol),
        (None, None) => true,
        _ => false,
    }
}

/// The statistics that do not depend on the order of the X-rays (everything
/// but the bootstrap intervals, whose random resamples index X-rays by their
/// order of first appearance), compared within `rel` times the quantity's
/// magnitude (at least 1: relative values are below 1, totals and ratios may
/// be large, and a sum in another order differs in its last bits).
fn same_order_free_stats(a: &QuantityStats, b: &QuantityStats, rel: f64) -> Result<(), String> {
    let tol = rel * magnitude(a);
    let scalars = [
        ("mean", a.mean, b.mean),
        ("median", a.median, b.median),
        ("min", a.min, b.min),
        ("max", a.max, b.max),
        ("range", a.range, b.range),
    ];
    for (what, x, y) in scalars {
        if !close(x, y, tol) {
            return Err(format!("{what}: {x} vs {y}"));
        }
    }
    for (what, x, y) in [("sd", a.sd, b.sd), ("se", a.se, b.se), ("cv", a.cv, b.cv)] {
        if !close_opt(x, y, tol) {
            return Err(format!("{what}: {x:?} vs {y:?}"));
        }
    }
    for (what, x, y) in [
        ("ci_t", a.intervals.ci_t, b.intervals.ci_t),
        ("pi", a.intervals.pi, b.intervals.pi),
    ] {
        if !close_iv(x, y, tol) {
            return Err(format!("{what}: {x:?} vs {y:?}"));
        }
    }
    if a.n != b.n {
        return Err(format!("n: {} vs {}", a.n, b.n));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// J~1 + J~2 (+ J~3) = 1 for every X-ray of every finger.
    #[test]
    fn relative_values_sum_to_one(xrays in dataset()) {
        let a = analyse_bytes(&csv(&rows(&xrays, 1.0)));
        for f in &a.fingers {
            for x in &f.xrays {
                let sum: f64 = x.relative.iter().sum();
                prop_assert!((sum - 1.0).abs() <= 1e-12, "{} of X-ray {}: relative values sum to {sum}", f.finger, x.xray);
                prop_assert_eq!(x.relative.len(), f.finger.segments());
            }
        }
    }

    /// mean in [min, max]; every interval has low <= high; the t and
    /// prediction intervals contain the mean; the PI contains the t interval.
    #[test]
    fn means_and_intervals_are_ordered(xrays in dataset()) {
        let a = analyse_bytes(&csv(&rows(&xrays, 1.0)));
        for (finger, s) in all_stats(&a) {
            let what = format!("{finger} {}", s.name.name());
            prop_assert!(s.min <= s.mean && s.mean <= s.max, "{what}: mean {} outside [{}, {}]", s.mean, s.min, s.max);
            prop_assert!(s.min <= s.median && s.median <= s.max, "{what}: median {} outside [{}, {}]", s.median, s.min, s.max);
            prop_assert!(s.range >= 0.0, "{what}: range {}", s.range);
            for (name, iv) in intervals(s) {
                if let Some(iv) = iv {
                    prop_assert!(iv.low.is_finite() && iv.high.is_finite(), "{what} {name}: {iv:?}");
                    prop_assert!(iv.low <= iv.high, "{what} {name}: low > high: {iv:?}");
                } else {
                    prop_assert!(!s.notes.is_empty(), "{what} {name} is null without a note");
                }
            }
            for (name, iv) in [("ci_t", s.intervals.ci_t), ("pi", s.intervals.pi)] {
                if let Some(iv) = iv {
                    prop_assert!(iv.contains(s.mean), "{what} {name} {iv:?} lacks the mean {}", s.mean);
                }
            }
            if let (Some(t), Some(pi)) = (s.intervals.ci_t, s.intervals.pi) {
                prop_assert!(pi.low <= t.low && t.high <= pi.high, "{what}: pi {pi:?} narrower than t {t:?}");
            }
            if s.n >= 2 {
                prop_assert!(s.intervals.ci_t.is_some() && s.intervals.pi.is_some(), "{what}: n = {} but no t interval or PI", s.n);
            }
        }
    }

    /// Row order. X-rays are ordered by their first appearance, and the random
    /// bootstrap (n >= 6 here) draws X-ray indices in that order, so:
    /// (a) permuting the rows within each X-ray's block keeps the order of
    ///     the X-rays, and every statistic, bootstrap intervals included, must
    ///     be unchanged (within 1e-12);
    /// (b) an arbitrary permutation of the rows may reorder the X-rays, so only
    ///     the order-free statistics (mean, median, min, max, range, SD, SE, CV,
    ///     t interval, PI) are compared (within 1e-12 of max(1, |values|)), plus the bootstrap
    ///     intervals when both runs enumerate every resample exactly.
    #[test]
    fn statistics_do_not_depend_on_row_order(
        xrays in dataset(),
        keys in prop::collection::vec(any::<u64>(), 60),
    ) {
        let base = analyse_bytes(&csv(&rows(&xrays, 1.0)));

        // (a) rows reversed within each X-ray's block.
        let within: Vec<Xray> = xrays
            .iter()
            .map(|x| Xray { fingers: x.fingers.iter().rev().cloned().collect() })
            .collect();
        let a = analyse_bytes(&csv(&rows(&within, 1.0)));
        let pairs = all_stats(&base).into_iter().zip(all_stats(&a));
        for ((f, s), (g, t)) in pairs {
            prop_assert_eq!(f, g);
            prop_assert_eq!(s.name, t.name);
            let what = format!("{f} {}", s.name.name());
            if let Err(e) = same_order_free_stats(s, t, 1e-12) {
                return Err(TestCaseError::fail(format!("{what} (block order kept): {e}")));
            }
            for ((name, x), (_, y)) in intervals(s).into_iter().zip(intervals(t)) {
                prop_assert!(close_iv(x, y, 1e-12 * magnitude(s)), "{what} {name}: {x:?} vs {y:?}");
            }
        }

        // (b) rows in an arbitrary order.
        let mut shuffled: Vec<(u64, String)> = keys.iter().copied().zip(rows(&xrays, 1.0)).collect();
        shuffled.sort_by_key(|(k, _)| *k);
        let shuffled: Vec<String> = shuffled.into_iter().map(|(_, r)| r).collect();
        let b = analyse_bytes(&csv(&shuffled));
        prop_assert_eq!(base.fingers.len(), b.fingers.len());
        for (fa, fb) in base.fingers.iter().zip(&b.fingers) {
            prop_assert_eq!(fa.finger, fb.finger);
            for (s, t) in fa.quantities.iter().zip(&fb.quantities) {
                let what = format!("{} {}", fa.finger, s.name.name());
                if let Err(e) = same_order_free_stats(s, t, 1e-12) {
                    return Err(TestCaseError::fail(format!("{what} (rows shuffled): {e}")));
                }
                let exact = |p: phalanx::stats::bootstrap::Plan| matches!(p, phalanx::stats::bootstrap::Plan::Exact { .. });
                if exact(fa.bootstrap) && exact(fb.bootstrap) {
                    let tol = 1e-12 * magnitude(s);
                    prop_assert!(close_iv(s.intervals.ci_percentile, t.intervals.ci_percentile, tol), "{what} percentile: {:?} vs {:?}", s.intervals.ci_percentile, t.intervals.ci_percentile);
                    prop_assert!(close_iv(s.intervals.ci_bca, t.intervals.ci_bca, tol), "{what} BCa: {:?} vs {:?}", s.intervals.ci_bca, t.intervals.ci_bca);
                }
            }
            // The same X-ray values, matched by id.
            for x in &fa.xrays {
                let y = fb.xrays.iter().find(|y| y.xray == x.xray);
                prop_assert!(y.is_some_and(|y| y.relative == x.relative && y.total == x.total), "X-ray {} of {}", x.xray, fa.finger);
            }
        }
    }

    /// Multiplying every length by k leaves the relative values and ratios
    /// (and every statistic and interval of them) unchanged within 1e-9
    /// relative to the quantity's magnitude, and multiplies every statistic
    /// and interval of the total by k. The bootstrap resamples are the same
    /// (same X-rays in the same order, same seed), so bootstrap intervals are
    /// compared too.
    #[test]
    fn statistics_scale_with_the_lengths(
        xrays in dataset(),
        k in prop_oneof![Just(1000.0), Just(0.001), Just(25.4), 1e-3f64..1e3],
    ) {
        let a = analyse_bytes(&csv(&rows(&xrays, 1.0)));
        let b = analyse_bytes(&csv(&rows(&xrays, k)));
        for ((f, s), (_, t)) in all_stats(&a).into_iter().zip(all_stats(&b)) {
            let what = format!("{f} {}", s.name.name());
            let factor = if s.name == Quantity::Total { k } else { 1.0 };
            let magnitude = s.min.abs().max(s.max.abs()) * factor;
            let tol = 1e-9 * magnitude;
            let scalars = [
                ("mean", s.mean, t.mean),
                ("median", s.median, t.median),
                ("min", s.min, t.min),
                ("max", s.max, t.max),
                ("range", s.range, t.range),
            ];
            for (name, x, y) in scalars {
                prop_assert!(close(x * factor, y, tol), "{what} {name}: {x} x {factor} vs {y}");
            }
            for (name, x, y) in [("sd", s.sd, t.sd), ("se", s.se, t.se)] {
                prop_assert!(close_opt(x.map(|v| v * factor), y, tol), "{what} {name}: {x:?} x {factor} vs {y:?}");
            }
            prop_assert!(close_opt(s.cv, t.cv, 1e-9 * s.cv.unwrap_or(0.0).abs().max(1e-300)) || close_opt(s.cv, t.cv, 1e-12), "{what} cv: {:?} vs {:?}", s.cv, t.cv);
            for ((name, x), (_, y)) in intervals(s).into_iter().zip(intervals(t)) {
                prop_assert!(close_iv(x.map(|i| i.scaled(factor)), y, tol), "{what} {name}: {x:?} x {factor} vs {y:?}");
            }
        }
    }

    /// The same data and seed give identical statistics, bit for bit.
    #[test]
    fn the_same_seed_gives_the_same_intervals(xrays in dataset()) {
        let bytes = csv(&rows(&xrays, 1.0));
        let a = analyse_bytes(&bytes);
        let b = analyse_bytes(&bytes);
        for ((f, s), (_, t)) in all_stats(&a).into_iter().zip(all_stats(&b)) {
            for ((name, x), (_, y)) in intervals(s).into_iter().zip(intervals(t)) {
                let bits = |i: Option<Interval>| i.map(|i| (i.low.to_bits(), i.high.to_bits()));
                prop_assert_eq!(bits(x), bits(y), "{} {} {}", f, s.name.name(), name);
            }
            prop_assert_eq!(s.mean.to_bits(), t.mean.to_bits());
            prop_assert_eq!(s.sd.map(f64::to_bits), t.sd.map(f64::to_bits));
        }
    }
}
