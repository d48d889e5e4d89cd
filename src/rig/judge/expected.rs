//! Where the X-rays put each joint of a finger given the rest of it as the
//! rig has it (the standings of [`super::finger`]'s notes): on the relative
//! values with a tip, on J2/J1 without one.

use super::standing::stats;
use crate::analysis::placement::{Joint, Placed};
use crate::analysis::{Analysis, Interval, Quantity, QuantityStats};
use crate::dataset::Finger;

/// A joint's standing inputs: (joint, measured, expected, range, prediction interval).
pub(super) type StandingInput = (Joint, f64, f64, Interval, Option<Interval>);

/// x -> base x / (1 - x), the length a relative value x gives one segment
/// when the others sum to `base`; `None` at x >= 1.
fn share_to_length(base: f64, x: f64) -> Option<f64> {
    (x < 1.0).then(|| base * x / (1.0 - x))
}

/// The MCP and tip standings of a finger with a tip, and the inner joints'.
pub(super) fn relative_standings(
    a: &Analysis,
    finger: Finger,
    segments: &[f64],
    compared: &[f64],
    correction: f64,
) -> Option<Vec<StandingInput>> {
    let length: f64 = compared.iter().sum();
    let m = compared.len();
    let last = match m {
        2 => Quantity::RelJ2,
        _ => Quantity::RelJ3,
    };
    let rel1 = stats(a, finger, Quantity::RelJ1)?;
    let rel_last = stats(a, finger, last)?;
    // A monotone increasing map of a relative value's statistics onto positions.
    let mapped = |s: &QuantityStats,
                  f: &dyn Fn(f64) -> Option<f64>|
     -> Option<(f64, Interval, Option<Interval>)> {
        let mean = f(s.mean)?;
        let range = Interval::new(f(s.min)?, f(s.max)?);
        let pi = match s.intervals.pi {
            Some(pi) => Some(Interval::new(f(pi.low.max(0.0))?, f(pi.high.min(0.999))?)),
            None => None,
        };
        Some((mean, range, pi))
    };
    let flip = |i: Interval| Interval::new(i.high, i.low);
    let mut out = Vec::new();
    // MCP: at s_1 - J1, J1 = (L - s_1) x / (1 - x), decreasing in x.
    let rest = length - compared[0];
    let (mean, range, pi) = mapped(rel1, &|x| {
        share_to_length(rest, x).map(|j1| compared[0] - j1)
    })?;
    out.push((Joint::Mcp, 0.0, mean, flip(range), pi.map(flip)));
    let mut measured = 0.0;
    for (k, &joint) in Joint::inner(finger).iter().enumerate() {
        measured += segments[k];
        // PIP/IP at J~1 L; DIP at (1 - J~3) L (see placement).
        let placed = if k == 0 {
            Placed::affine(rel1, 0.0, length)
        } else {
            Placed::affine(stats(a, finger, Quantity::RelJ3)?, length, -length)
        };
        out.push((
            joint,
            measured,
            placed.mean,
            Interval::new(placed.min, placed.max),
            placed.intervals.pi,
        ));
    }
    // Tip: at (L - s_last) + J_last + correction, increasing in x.
    let base = length - compared[m - 1];
    let (mean, range, pi) = mapped(rel_last, &|x| {
        share_to_length(base, x).map(|j| base + j + correction)
    })?;
    out.push((Joint::Tip, segments.iter().sum(), mean, range, pi));
    Some(out)
}

/// The MCP and PIP standings of a finger without a tip, on J2/J1.
pub(super) fn ratio_standings(
    a: &Analysis,
    finger: Finger,
    s: &[f64],
) -> Option<Vec<StandingInput>> {
    let st = stats(a, finger, Quantity::RatioJ2J1)?;
    // A ratio is never negative, even where an interval's formula says so.
    let r = |x: f64| x.max(1e-9);
    let span = s[0] + s[1];
    let pip = |x: f64| span / (1.0 + r(x));
    let mcp = |x: f64| s[0] - s[1] / r(x);
    // The PIP's position falls with r, the MCP's rises.
    let flip = |f: &dyn Fn(f64) -> f64, i: Interval| Interval::new(f(i.high), f(i.low));
    let keep = |f: &dyn Fn(f64) -> f64, i: Interval| Interval::new(f(i.low), f(i.high));
    let range = Interval::new(st.min, st.max);
    Some(vec![
        (
            Joint::Mcp,
            0.0,
            mcp(st.mean),
            keep(&mcp, range),
            st.intervals.pi.map(|i| keep(&mcp, i)),
        ),
        (
            Joint::Pip,
            s[0],
            pip(st.mean),
            flip(&pip, range),
            st.intervals.pi.map(|i| flip(&pip, i)),
        ),
    ])
}
