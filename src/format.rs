//! Number formatting shared by every output: the one place numbers become text.

use crate::analysis::Quantity;
use crate::stats::{Interval, Intervals};

/// Decimals for a quantity: 4 for relative values and ratios (as the paper prints them), 2 for lengths.
pub fn decimals(q: Quantity) -> usize {
    if q.is_unitless() { 4 } else { 2 }
}

/// Decimals for positions in a model of total length `l`: about five significant
/// digits, at least one decimal (1000 -> 1, as the paper's worked example; 7.9 -> 4).
pub fn length_decimals(l: f64) -> usize {
    if !(l.is_finite() && l > 0.0) {
        return 1;
    }
    (4 - l.log10().floor() as i64).clamp(1, 6) as usize
}

/// `x` with `d` decimals; "n/a" for a non-finite value (never printed as NaN).
pub fn num(x: f64, d: usize) -> String {
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
pub fn opt(x: Option<f64>, d: usize) -> String {
    x.map_or_else(|| "n/a".to_string(), |x| num(x, d))
}

/// An interval as `[low, high]`; "n/a" when absent.
pub fn interval(i: Option<Interval>, d: usize) -> String {
    match i {
        Some(i) => format!("[{}, {}]", num(i.low, d), num(i.high, d)),
        None => "n/a".to_string(),
    }
}

/// The table cells of the four intervals, in table order (t, percentile, BCa,
/// prediction): each `[low, high]` with `d` decimals, or "n/a".
pub fn interval_cells(iv: &Intervals, d: usize) -> [String; 4] {
    iv.all().map(|i| interval(i, d))
}

/// A number at full precision for machine-read outputs (CSV): the shortest text
/// that reads back as the same `f64`; empty when absent or not finite.
pub fn full(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite())
        .map_or_else(String::new, |v| v.to_string())
}

/// The CSV cells of the four intervals, in table order: low and high of each
/// at full precision, both empty where the interval is undefined.
pub fn interval_bounds(iv: &Intervals) -> Vec<String> {
    iv.all()
        .iter()
        .flat_map(|i| [full(i.map(|i| i.low)), full(i.map(|i| i.high))])
        .collect()
}

/// A proportion as a percentage with one decimal.
pub fn percent(p: f64) -> String {
    format!("{}%", num(100.0 * p, 1))
}

#[cfg(test)]
mod tests {
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
}
