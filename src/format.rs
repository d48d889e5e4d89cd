//! Every number phalanx shows becomes text here: statistics, lengths,
//! percentages, confidence levels and intervals, for the terminal tables, the
//! report's views and templates (which receive finished strings), the plots'
//! labels and descriptions, the CSV exporter and messages.
//!
//! A leaf module: it depends on [`crate::stats`] alone, so the dataset, the
//! analysis, the rig code and the report can all use it.

use crate::stats::bootstrap::Plan;
use crate::stats::{Interval, Intervals};

/// Decimals of a relative value or ratio (as the paper prints them).
pub(crate) const UNITLESS_DECIMALS: usize = 4;
/// Decimals of a length in data units (image pixels).
pub(crate) const LENGTH_DECIMALS: usize = 2;

/// Decimals of a quantity: [`UNITLESS_DECIMALS`] when it has no unit (relative
/// values, ratios), [`LENGTH_DECIMALS`] for a length.
pub(crate) fn decimals(unitless: bool) -> usize {
    if unitless {
        UNITLESS_DECIMALS
    } else {
        LENGTH_DECIMALS
    }
}

/// Decimals for positions in a model of total length `l` in tables: about
/// five significant digits, at least one decimal (1000 -> 1, as the paper's
/// worked example; 7.9 -> 4).
pub(crate) fn length_decimals(l: f64) -> usize {
    if !(l.is_finite() && l > 0.0) {
        return 1;
    }
    (4 - l.log10().floor() as i64).clamp(1, 6) as usize
}

/// Decimals for positions in a model of total length `l` on a plot's labels,
/// where room is short: 4 - ceil(log10 l), within 0..=6 (1000 -> 1, 50 -> 2, 1 -> 4).
pub(crate) fn label_decimals(l: f64) -> usize {
    (4.0 - l.log10().ceil()).clamp(0.0, 6.0) as usize
}

/// Decimals for axis ticks `step` apart: enough to tell neighbours apart,
/// ceil(-log10 step) within 0..=6; 2 for a step that is not a positive number.
pub(crate) fn step_decimals(step: f64) -> usize {
    if step.is_finite() && step > 0.0 {
        (-step.log10()).ceil().clamp(0.0, 6.0) as usize
    } else {
        2
    }
}

/// `x` with `d` decimals; "n/a" for a non-finite value (never printed as NaN).
pub(crate) fn num(x: f64, d: usize) -> String {
    if x.is_finite() {
        // Avoid "-0.0000" for tiny negatives.
        let s = format!("{x:.d$}");
        if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
            s[1..].to_string()
        } else {
            s
        }
    } else {
        "n/a".to_string()
    }
}

/// An optional number; "n/a" when absent.
pub(crate) fn opt(x: Option<f64>, d: usize) -> String {
    x.map_or_else(|| "n/a".to_string(), |x| num(x, d))
}

/// `x` with at most `d` decimals, trailing zeros removed: 1000.0 -> "1000", 0.7290 -> "0.729".
pub(crate) fn trimmed(x: f64, d: usize) -> String {
    let s = num(x, d);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A change with its sign and `d` decimals: "+0.0012", "-0.0300"; a change that
/// rounds to zero reads "0.0000", without a sign.
pub(crate) fn signed(x: f64, d: usize) -> String {
    if !x.is_finite() {
        return "n/a".to_string();
    }
    let s = format!("{x:+.d$}");
    if s[1..].chars().all(|c| c == '0' || c == '.') {
        format!("{:.d$}", 0.0)
    } else {
        s
    }
}

/// `x` exactly as given, as briefly as possible: "1000" for 1000.0, "7.9";
/// "n/a" when not finite. For values people typed (a model length).
pub(crate) fn exact(x: f64) -> String {
    if !x.is_finite() {
        "n/a".to_string()
    } else if x == 0.0 {
        // Also for -0.0.
        "0".to_string()
    } else {
        x.to_string()
    }
}

/// An interval as `[low, high]`; "n/a" when absent.
pub(crate) fn interval(i: Option<Interval>, d: usize) -> String {
    match i {
        Some(i) => format!("[{}, {}]", num(i.low, d), num(i.high, d)),
        None => "n/a".to_string(),
    }
}

/// The table cells of the four intervals, in table order (t, percentile, BCa,
/// prediction): each `[low, high]` with `d` decimals, or "n/a".
pub(crate) fn interval_cells(iv: &Intervals, d: usize) -> [String; 4] {
    iv.all().map(|i| interval(i, d))
}

/// A number at full precision for machine-read outputs (CSV): the shortest text
/// that reads back as the same `f64`; empty when absent or not finite.
pub(crate) fn full(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite())
        .map_or_else(String::new, |v| v.to_string())
}

/// Largest relative difference between a [`readable`] number and the value.
const READABLE_TOLERANCE: f64 = 1e-12;

/// A number for a CSV that people read and spreadsheets open: the shortest
/// decimal (at most 15 significant digits) within 1e-12 of the value,
/// relatively; empty when absent or not finite. Twelve digits and more are
/// far beyond what a measurement carries, and the noise of binary arithmetic
/// goes: the thumb's mean total reads "519.998", not "519.9979999999999", and
/// a range max - min of 71.01 not "71.01000000000005". ([`full`] keeps every
/// bit, for files read back.) Cost: at most 15 formatting passes.
pub(crate) fn readable(x: Option<f64>) -> String {
    let Some(v) = x.filter(|v| v.is_finite()) else {
        return String::new();
    };
    if v == 0.0 {
        return "0".to_string();
    }
    (1..=15)
        .filter_map(|digits| {
            format!("{v:.prec$e}", prec = digits - 1)
                .parse::<f64>()
                .ok()
        })
        .find(|r| (r - v).abs() <= READABLE_TOLERANCE * v.abs())
        .unwrap_or(v)
        .to_string()
}

/// A length measured from landmarks, as a data file records it: at least 6 decimals
/// and 7 significant digits, trailing zeros dropped (339.96000412 -> "339.960004",
/// 12.0 -> "12"). The written value is within 5e-7 of the unit (a millionth of a pixel)
/// for lengths of 1 and over, and within a relative 5e-7 below, far finer than any
/// landmark is clicked; shorter than [`full`]'s 17 digits, so an imported file stays
/// readable and diffable.
pub fn measured(x: f64) -> String {
    let decimals = if x.abs() >= 1.0 || x == 0.0 || !x.is_finite() {
        6
    } else {
        // 7 significant digits: one more decimal per factor of 10 below 1, at most 20.
        (6.0 - x.abs().log10().floor()).clamp(6.0, 20.0) as usize
    };
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The CSV cells of the four intervals, in table order: low and high of each
/// as [`readable`] numbers, both empty where the interval is undefined.
pub(crate) fn interval_bounds(iv: &Intervals) -> Vec<String> {
    iv.all()
        .iter()
        .flat_map(|i| [readable(i.map(|i| i.low)), readable(i.map(|i| i.high))])
        .collect()
}

/// A number of X-rays as people read it: "1 X-ray", "5 X-rays" (the sample
/// size n is always shown with its unit).
pub(crate) fn xrays(n: usize) -> String {
    if n == 1 {
        "1 X-ray".to_string()
    } else {
        format!("{n} X-rays")
    }
}

/// A count with its noun, singular for one: `count(1, "joint", "joints")` is
/// "1 joint", `count(0, ..)` "0 joints" (English takes the plural for zero).
/// Every number-noun pair of the output goes through here.
pub(crate) fn count(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("1 {one}")
    } else {
        format!("{n} {many}")
    }
}

/// A proportion as a percentage with one decimal: 0.8312 -> "83.1%" (coverage, CV).
pub(crate) fn percent(p: f64) -> String {
    format!("{}%", num(100.0 * p, 1))
}

/// Most decimals a confidence level is shown with.
const LEVEL_DECIMALS: usize = 15;

/// A confidence level as a percentage, the same in every output: with the
/// fewest decimals that give the level exactly (to 1e-9 of a percentage point)
/// and still lie strictly between 0% and 100%. 0.95 -> "95%", 0.9 -> "90%",
/// 0.975 -> "97.5%", 0.9999 -> "99.99%" (never "100.0%"), 0.99999 -> "99.999%".
pub(crate) fn level(confidence: f64) -> String {
    let p = 100.0 * confidence;
    if !p.is_finite() {
        return "n/a".to_string();
    }
    let fits = |s: &String| {
        s.parse::<f64>()
            .is_ok_and(|v| (v - p).abs() < 1e-9 && v > 0.0 && v < 100.0)
    };
    let text = (0..=LEVEL_DECIMALS)
        .map(|d| num(p, d))
        .find(fits)
        .unwrap_or_else(|| p.to_string());
    format!("{text}%")
}

/// How a bootstrap was done, in one word: "exact" (every distinct resample enumerated)
/// or "random" (seeded resamples). The words of [`plan`] and [`plan_short`].
pub(crate) fn plan_kind(p: Plan) -> &'static str {
    match p {
        Plan::Exact { .. } => "exact",
        Plan::Random { .. } => "random",
    }
}

/// How a bootstrap was done, as the outputs say it: "exact: all 126 distinct resamples
/// enumerated with their multinomial weights", "random: 10000 seeded resamples".
pub(crate) fn plan(p: Plan) -> String {
    match p {
        Plan::Exact { distinct } => format!(
            "{}: all {distinct} distinct resamples enumerated with their multinomial weights",
            plan_kind(p)
        ),
        Plan::Random { resamples } => format!("{}: {resamples} seeded resamples", plan_kind(p)),
    }
}

/// A bootstrap briefly, for a table cell: "exact (126)", "random (200)".
pub(crate) fn plan_short(p: Plan) -> String {
    match p {
        Plan::Exact { distinct } => format!("{} ({distinct})", plan_kind(p)),
        Plan::Random { resamples } => format!("{} ({resamples})", plan_kind(p)),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_take_the_singular_for_one_only() {
        assert_eq!(super::count(1, "joint", "joints"), "1 joint");
        assert_eq!(super::count(0, "joint", "joints"), "0 joints");
        assert_eq!(super::count(2, "vertex", "vertices"), "2 vertices");
        assert_eq!(super::xrays(1), "1 X-ray");
    }

    use super::*;

    #[test]
    fn formats() {
        assert_eq!(num(0.48464, 4), "0.4846");
        assert_eq!(num(-0.00001, 4), "0.0000");
        assert_eq!(num(f64::NAN, 2), "n/a");
        assert_eq!(interval(Some(Interval::new(0.1, 0.25)), 2), "[0.10, 0.25]");
        assert_eq!(interval(None, 2), "n/a");
        assert_eq!(percent(0.8312), "83.1%");
        assert_eq!(opt(None, 3), "n/a");
        assert_eq!(length_decimals(1000.0), 1);
        assert_eq!(length_decimals(7.9), 4);
        assert_eq!(length_decimals(87.5), 3);
        assert_eq!(length_decimals(1e9), 1);
        assert_eq!(length_decimals(0.001), 6);
    }

    #[test]
    fn label_decimals_follow_the_model_length() {
        assert_eq!(label_decimals(1000.0), 1);
        assert_eq!(label_decimals(50.0), 2);
        assert_eq!(label_decimals(1.0), 4);
    }

    #[test]
    fn confidence_levels_read_the_same_everywhere() {
        assert_eq!(level(0.95), "95%");
        assert_eq!(level(0.9), "90%");
        assert_eq!(level(0.99), "99%");
        assert_eq!(level(0.975), "97.5%");
        assert_eq!(level(0.9999), "99.99%");
        assert_eq!(level(0.99999), "99.999%");
        assert_eq!(level(0.5), "50%");
        assert_eq!(level(0.0001), "0.01%");
        // Close to the ends, more decimals rather than "100%" or "0%".
        assert_eq!(level(1.0 - 1e-12), "99.9999999999%");
        assert_eq!(level(1e-12), "0.0000000001%");
        // A level without a short decimal form: to within 1e-9 of a percentage point.
        assert_eq!(level(1.0 / 3.0), "33.333333333%");
    }

    #[test]
    fn signs_trims_and_exact_values() {
        assert_eq!(signed(0.00123, 4), "+0.0012");
        assert_eq!(signed(-0.03, 4), "-0.0300");
        assert_eq!(signed(0.00001, 4), "0.0000");
        assert_eq!(signed(-0.00001, 4), "0.0000");
        assert_eq!(signed(f64::NAN, 4), "n/a");
        assert_eq!(trimmed(1000.0, 4), "1000");
        assert_eq!(trimmed(0.729_04, 3), "0.729");
        assert_eq!(trimmed(0.5, 3), "0.5");
        assert_eq!(exact(1000.0), "1000");
        assert_eq!(exact(7.9), "7.9");
        assert_eq!(exact(-0.0), "0");
        assert_eq!(full(Some(0.95)), "0.95");
        assert_eq!(full(Some(f64::INFINITY)), "");
        assert_eq!(full(None), "");
        assert_eq!(step_decimals(0.0025), 3);
        assert_eq!(step_decimals(50.0), 0);
        assert_eq!(step_decimals(0.0), 2);
    }

    #[test]
    fn readable_numbers_drop_float_noise_only() {
        // The mean total J of the paper's thumb, 519.998 from Table 1, as the
        // analysis computes it in f64 (`phalanx stats --format json`).
        let total = 519.997_999_999_999_9;
        assert_eq!(full(Some(total)), "519.9979999999999");
        assert_eq!(readable(Some(total)), "519.998");
        // Its range, 566.39 - 495.38.
        assert_eq!(readable(Some(566.39 - 495.38)), "71.01");
        assert_eq!(readable(Some(0.1 + 0.2)), "0.3");
        assert_eq!(readable(Some(0.484_636_048_070_876_83)), "0.484636048071");
        assert_eq!(readable(Some(1e-20)), "0.00000000000000000001");
        assert_eq!(readable(Some(-2.5)), "-2.5");
        assert_eq!(readable(Some(-0.0)), "0");
        assert_eq!(readable(Some(f64::NAN)), "");
        assert_eq!(readable(None), "");
        for x in [
            519.997_999_999_999_9,
            0.026_144_100_660_300_842,
            1_234_567.891,
            3e-7,
            1.0 / 3.0,
        ] {
            let back: f64 = readable(Some(x)).parse().unwrap();
            assert!((back - x).abs() <= 1e-12 * x.abs(), "{x} -> {back}");
        }
    }

    #[test]
    fn interval_cells_in_table_order() {
        let iv = Intervals {
            ci_t: Some(Interval::new(0.1, 0.2)),
            ci_percentile: None,
            ci_bca: Some(Interval::point(0.15)),
            pi: Some(Interval::new(0.05, 0.25)),
        };
        assert_eq!(
            interval_cells(&iv, 2),
            ["[0.10, 0.20]", "n/a", "[0.15, 0.15]", "[0.05, 0.25]"]
        );
        assert_eq!(
            interval_bounds(&iv),
            ["0.1", "0.2", "", "", "0.15", "0.15", "0.05", "0.25"]
        );
    }
}
