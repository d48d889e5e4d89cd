//! Judging a rig's finger joints against the X-ray statistics.
//!
//! A rig finger is a chain of joint centres P0 (MCP), P1, P2 (PIP, DIP; the
//! thumb has one inner joint, IP) and, when the rig has one, the tip. Its
//! segments are the chords c_k = |P_k - P_(k-1)| and, with a tip, its length is
//! L = sum c_k, so J~k = c_k / L (eq. 2 with the rig's segments for the bones).
//! Each inner joint lies at s = c_1 + ... + c_k from the root, to be compared
//! with the statistics placed at L (see [`crate::analysis::placement`]).
//!
//! Without a tip (VRM, Unreal) L is unknown; a finger is then judged on
//! r = J2/J1 alone, holding MCP and DIP fixed: the PIP then belongs at
//! s(r) = (c_1 + c_2) / (1 + r), which decreases with r, so the statistics of r
//! map onto positions with their ends swapped. The DIP and the whole thumb
//! cannot be judged without a tip.
//!
//! Suggested positions stay on the rig's own chain (the polyline through its
//! joints), with root and tip (or DIP) fixed, and are solved so the new chords
//! have exactly the mean proportions (see `rig::chain`). No files, no glTF.

use super::chain::{arc_positions, on_chain};
use crate::analysis::placement::{Joint, Placed};
use crate::analysis::{Analysis, Interval, Quantity, QuantityStats};
use crate::dataset::Finger;
use glam::DVec3;
use schemars::JsonSchema;
use serde::Serialize;

/// One finger of a rig, as joint centres from the root.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainInput {
    pub finger: Finger,
    /// Root (MCP), the inner joints, then the tip when `has_tip`, in the rig's space.
    pub points: Vec<DVec3>,
    pub has_tip: bool,
}

impl ChainInput {
    /// Number of points a complete chain of `finger` has.
    pub fn expected_points(finger: Finger, has_tip: bool) -> usize {
        1 + Joint::inner(finger).len() + usize::from(has_tip)
    }
}

/// What a finger was judged on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// Relative values J~k: the rig has a tip.
    Relative,
    /// The ratio J2/J1 only: no tip.
    Ratio,
    /// Nothing can be judged (a thumb without a tip).
    None,
}

/// Where a measured value stands against the statistics.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "standing", rename_all = "snake_case")]
pub enum Standing {
    /// Inside the observed range [min, max] of the X-rays.
    InRange,
    /// Outside the observed range, inside the prediction interval for one new hand.
    InPrediction,
    /// Above the prediction interval (above the range when there is none) by `by`.
    Above { by: f64 },
    /// Below it by `by`.
    Below { by: f64 },
}

impl Standing {
    /// Judges `x` against the prediction interval when there is one (else the
    /// range): outside it, by how much; inside it, whether also inside the
    /// observed range. O(1).
    ///
    /// The range is widened by one part in a million of its ends, the precision
    /// a glTF file (f32) keeps: an X-ray's own proportions stored in a rig must
    /// still read as inside the range they set.
    pub fn of(x: f64, range: Interval, pi: Option<Interval>) -> Standing {
        let tol = 1e-6 * range.low.abs().max(range.high.abs());
        let in_range = range.low - tol <= x && x <= range.high + tol;
        let outer = match pi {
            Some(pi) if pi.contains(x) || (in_range && pi.width() >= range.width()) => {
                return if in_range {
                    Standing::InRange
                } else {
                    Standing::InPrediction
                };
            }
            Some(pi) => pi,
            None if in_range => return Standing::InRange,
            None => range,
        };
        if x > outer.high {
            Standing::Above { by: x - outer.high }
        } else {
            Standing::Below { by: outer.low - x }
        }
    }

    /// True when inside the range or the prediction interval.
    pub fn is_consistent(self) -> bool {
        matches!(self, Standing::InRange | Standing::InPrediction)
    }
}

/// One quantity of a rig finger against the X-rays.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ValueCheck {
    pub quantity: Quantity,
    pub measured: f64,
    pub mean: f64,
    pub range: Interval,
    pub pi: Option<Interval>,
    #[serde(flatten)]
    pub standing: Standing,
}

/// One inner joint of a rig finger against the X-rays, in the rig's units.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct JointCheck {
    pub joint: Joint,
    /// Distance from the root along the chain, as the rig has it.
    pub measured: f64,
    /// Where the mean puts it.
    pub expected: f64,
    pub range: Interval,
    pub pi: Option<Interval>,
    /// `Above` means the joint sits too far towards the tip.
    #[serde(flatten)]
    pub standing: Standing,
    /// The joint at the mean, on the rig's chain.
    #[schemars(with = "[f64; 3]")]
    pub suggested: DVec3,
    /// Distance from the rig's joint to the suggested one.
    pub shift: f64,
    /// How far the suggestion lies along the chain from the rig's joint:
    /// positive towards the tip, negative towards the root.
    pub shift_along: f64,
}

/// A rig finger judged against the X-ray statistics.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct FingerAudit {
    pub finger: Finger,
    pub has_tip: bool,
    pub basis: Basis,
    /// X-rays behind the statistics.
    pub n: usize,
    /// The rig's segment lengths c_k (J1, J2[, J3]; without a tip one fewer).
    pub segments: Vec<f64>,
    /// L = sum of the segments, with a tip.
    pub length: Option<f64>,
    pub values: Vec<ValueCheck>,
    pub joints: Vec<JointCheck>,
    /// Inner joints that could not be judged (no tip).
    pub unjudged: Vec<Joint>,
}

impl FingerAudit {
    /// True when every judged joint and value is inside the range or the prediction interval.
    pub fn is_consistent(&self) -> bool {
        self.joints.iter().all(|j| j.standing.is_consistent())
            && self.values.iter().all(|v| v.standing.is_consistent())
    }

    /// The suggested chain: the rig's points with the judged inner joints moved.
    pub fn suggested_chain(&self, chain: &ChainInput) -> Vec<DVec3> {
        let mut out = chain.points.clone();
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(p) = out.get_mut(i + 1) {
                *p = j.suggested;
            }
        }
        out
    }
}

/// The statistics of `quantity` for `finger`, when the data has them.
fn stats(a: &Analysis, finger: Finger, q: Quantity) -> Option<&QuantityStats> {
    a.finger(finger)?.quantity(q)
}

fn value_check(q: Quantity, measured: f64, s: &QuantityStats) -> ValueCheck {
    let range = Interval::new(s.min, s.max);
    ValueCheck {
        quantity: q,
        measured,
        mean: s.mean,
        range,
        pi: s.intervals.pi,
        standing: Standing::of(measured, range, s.intervals.pi),
    }
}

/// Judges one rig finger. `None` when the data has no such finger or the chain
/// has the wrong number of points, a non-finite point or a zero-length
/// segment. O(1) apart from the suggested positions.
pub fn audit(a: &Analysis, chain: &ChainInput) -> Option<FingerAudit> {
    let finger = chain.finger;
    let fa = a.finger(finger)?;
    if chain.points.len() != ChainInput::expected_points(finger, chain.has_tip) {
        return None;
    }
    if chain.points.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let segments: Vec<f64> = chain
        .points
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .collect();
    if segments.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
        return None;
    }
    let mut out = FingerAudit {
        finger,
        has_tip: chain.has_tip,
        basis: Basis::None,
        n: fa.n,
        segments,
        length: None,
        values: Vec::new(),
        joints: Vec::new(),
        unjudged: Vec::new(),
    };
    if chain.has_tip {
        judge_relative(a, chain, &mut out)?;
    } else if finger != Finger::Thumb {
        judge_ratio(a, chain, &mut out)?;
    } else {
        out.unjudged.push(Joint::Ip);
    }
    Some(out)
}

/// With a tip: every relative value and ratio against its statistics, and each
/// inner joint against the placement of the statistics at the rig's length.
fn judge_relative(a: &Analysis, chain: &ChainInput, out: &mut FingerAudit) -> Option<()> {
    let finger = chain.finger;
    let segments = &out.segments;
    let length: f64 = segments.iter().sum();
    if length <= 0.0 {
        return None;
    }
    let mut values = Vec::new();
    for &q in Quantity::of(finger) {
        let measured = match q {
            Quantity::RelJ1 => segments[0] / length,
            Quantity::RelJ2 => segments[1] / length,
            Quantity::RelJ3 => segments[2] / length,
            Quantity::RatioJ2J1 => segments[1] / segments[0],
            Quantity::RatioJ3J2 => segments[2] / segments[1],
            // Lengths and the metacarpal are not proportions of the finger's chain.
            Quantity::Total | Quantity::RatioMcJ | Quantity::RatioJ1Mc => continue,
        };
        values.push(value_check(q, measured, stats(a, finger, q)?));
    }
    let shares: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
        .iter()
        .take(segments.len())
        .map(|&q| stats(a, finger, q).map(|s| s.mean))
        .collect::<Option<_>>()?;
    let (suggested, at) = on_chain(&chain.points, &shares)?;
    let arcs = arc_positions(&chain.points);
    let mut joints = Vec::new();
    let mut measured = 0.0;
    for (k, &joint) in Joint::inner(finger).iter().enumerate() {
        measured += segments[k];
        // PIP/IP at J~1 L; DIP at (1 - J~3) L (see placement).
        let placed = if k == 0 {
            Placed::affine(stats(a, finger, Quantity::RelJ1)?, 0.0, length)
        } else {
            Placed::affine(stats(a, finger, Quantity::RelJ3)?, length, -length)
        };
        let range = Interval::new(placed.min, placed.max);
        joints.push(JointCheck {
            joint,
            measured,
            expected: placed.mean,
            range,
            pi: placed.intervals.pi,
            standing: Standing::of(measured, range, placed.intervals.pi),
            suggested: suggested[k + 1],
            shift: chain.points[k + 1].distance(suggested[k + 1]),
            shift_along: at[k] - arcs[k + 1],
        });
    }
    out.basis = Basis::Relative;
    out.length = Some(length);
    out.values = values;
    out.joints = joints;
    Some(())
}

/// Without a tip (not the thumb): J2/J1 against its statistics, and the PIP
/// against the positions those put it at with MCP and DIP fixed.
fn judge_ratio(a: &Analysis, chain: &ChainInput, out: &mut FingerAudit) -> Option<()> {
    let s = stats(a, chain.finger, Quantity::RatioJ2J1)?;
    let segments = &out.segments;
    let r = segments[1] / segments[0];
    let value = value_check(Quantity::RatioJ2J1, r, s);
    let span = segments[0] + segments[1];
    // A ratio is never negative, even where an interval's formula says so.
    let at = |r: f64| span / (1.0 + r.max(0.0));
    let flip = |i: Interval| Interval::new(at(i.high), at(i.low));
    let range = flip(Interval::new(s.min, s.max));
    let pi = s.intervals.pi.map(flip);
    let mean_r = s.mean;
    let (suggested, at_new) = on_chain(
        &chain.points,
        &[1.0 / (1.0 + mean_r), mean_r / (1.0 + mean_r)],
    )?;
    let arcs = arc_positions(&chain.points);
    let joint = JointCheck {
        joint: Joint::Pip,
        measured: segments[0],
        expected: at(mean_r),
        range,
        pi,
        standing: Standing::of(segments[0], range, pi),
        suggested: suggested[1],
        shift: chain.points[1].distance(suggested[1]),
        shift_along: at_new[0] - arcs[1],
    };
    out.basis = Basis::Ratio;
    out.values.push(value);
    out.joints.push(joint);
    out.unjudged.push(Joint::Dip);
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use crate::rig::chain::on_chain;
    use std::path::Path;

    fn paper() -> Analysis {
        let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        analyse(&d, &Settings::default())
    }

    /// A straight finger along x with the given segment lengths (and a tip).
    fn straight(finger: Finger, segs: &[f64]) -> ChainInput {
        let mut points = vec![DVec3::ZERO];
        let mut x = 0.0;
        for s in segs {
            x += s;
            points.push(DVec3::new(x, 0.0, 0.0));
        }
        ChainInput {
            finger,
            points,
            has_tip: true,
        }
    }

    #[test]
    fn standing_orders_range_then_prediction_then_outside() {
        let range = Interval::new(0.4, 0.5);
        let pi = Some(Interval::new(0.3, 0.6));
        assert_eq!(Standing::of(0.45, range, pi), Standing::InRange);
        assert_eq!(Standing::of(0.55, range, pi), Standing::InPrediction);
        match Standing::of(0.7, range, pi) {
            Standing::Above { by } => assert!((by - 0.1).abs() < 1e-12),
            s => panic!("{s:?}"),
        }
        match Standing::of(0.35, range, None) {
            Standing::Below { by } => assert!((by - 0.05).abs() < 1e-12),
            s => panic!("{s:?}"),
        }
    }

    #[test]
    fn a_finger_with_the_paper_means_is_in_range_and_needs_no_move() {
        let a = paper();
        let f = a.finger(Finger::Index).unwrap();
        let m: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
            .iter()
            .map(|&q| f.quantity(q).unwrap().mean * 80.0)
            .collect();
        let r = audit(&a, &straight(Finger::Index, &m)).unwrap();
        assert_eq!(r.basis, Basis::Relative);
        assert!(r.is_consistent());
        for j in &r.joints {
            assert_eq!(j.standing, Standing::InRange);
            assert!(j.shift < 1e-9, "{j:?}");
            assert!((j.measured - j.expected).abs() < 1e-9);
        }
        // PIP at J~1 L = 0.4846 x 80 (the corrected eq. 6 mean).
        assert!((r.joints[0].expected - 0.4846 * 80.0).abs() < 0.01);
    }

    #[test]
    fn a_pip_far_towards_the_tip_is_flagged_above_with_its_distance() {
        let a = paper();
        // J~1 = 0.6 of 100 units: the paper's index max is 0.5047.
        let r = audit(&a, &straight(Finger::Index, &[60.0, 22.0, 18.0])).unwrap();
        let pip = &r.joints[0];
        let pi = pip.pi.unwrap();
        match pip.standing {
            Standing::Above { by } => assert!((by - (60.0 - pi.high)).abs() < 1e-9),
            s => panic!("{s:?}"),
        }
        assert!(!r.is_consistent());
        // The suggestion is the mean position, on the (straight) chain.
        assert!((pip.suggested[0] - pip.expected).abs() < 1e-9);
        assert!((pip.shift - (60.0 - pip.expected)).abs() < 1e-9);
    }

    #[test]
    fn sharp_bends_keep_the_joints_in_order_or_decline() {
        // 120 degrees at each joint, segments 20, 40, 40 (a case a per-point
        // correction got out of order).
        let turn = |a: f64| DVec3::new(a.cos(), a.sin(), 0.0);
        let mut pts = vec![DVec3::ZERO];
        let mut dir = 0.0f64;
        for len in [20.0, 40.0, 40.0] {
            let p = *pts.last().unwrap();
            pts.push(p + len * turn(dir));
            dir += 120f64.to_radians();
        }
        let shares = [0.48, 0.29, 0.23];
        // A finger curled 60 degrees at each joint is solved exactly, in order.
        let mut bent = vec![DVec3::ZERO];
        let mut dir = 0.0f64;
        for len in [45.0, 28.0, 22.0] {
            let p = *bent.last().unwrap();
            bent.push(p + len * turn(dir));
            dir += 60f64.to_radians();
        }
        let (q, u) = on_chain(&bent, &shares).expect("a 60-degree curl is solvable");
        assert!(u[0] < u[1]);
        let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = c.iter().sum();
        for (ck, s) in c.iter().zip(shares) {
            assert!((ck / total - s).abs() < 1e-9, "{c:?}");
        }
        if let Some((q, u)) = on_chain(&pts, &shares) {
            assert!(u.windows(2).all(|w| w[0] <= w[1]), "{u:?}");
            let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
            let total: f64 = c.iter().sum();
            for (ck, s) in c.iter().zip(shares) {
                assert!((ck / total - s).abs() < 1e-9, "{c:?}");
            }
        }
        // Degenerate chains are declined, never a panic.
        assert!(on_chain(&[DVec3::ZERO; 4], &shares).is_none());
        assert!(
            on_chain(
                &[
                    DVec3::new(f64::NAN, 0.0, 0.0),
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(2.0, 0.0, 0.0),
                    DVec3::new(3.0, 0.0, 0.0)
                ],
                &shares
            )
            .is_none()
        );
        let a = paper();
        let nan = ChainInput {
            finger: Finger::Index,
            points: vec![
                DVec3::ZERO,
                DVec3::new(f64::INFINITY, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(3.0, 0.0, 0.0),
            ],
            has_tip: true,
        };
        assert!(audit(&a, &nan).is_none());
        let zero = ChainInput {
            points: vec![
                DVec3::ZERO,
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(3.0, 0.0, 0.0),
            ],
            ..nan
        };
        assert!(audit(&a, &zero).is_none());
    }

    #[test]
    fn with_many_xrays_the_prediction_interval_decides() {
        // Range wider than the interval (large n): inside the range but outside the interval is outside.
        let range = Interval::new(0.3, 0.7);
        let pi = Some(Interval::new(0.45, 0.55));
        assert!(matches!(
            Standing::of(0.65, range, pi),
            Standing::Above { .. }
        ));
        assert_eq!(Standing::of(0.5, range, pi), Standing::InRange);
    }

    #[test]
    fn without_a_tip_a_finger_is_judged_on_its_ratio_and_the_thumb_not_at_all() {
        let a = paper();
        let s = a
            .finger(Finger::Middle)
            .unwrap()
            .quantity(Quantity::RatioJ2J1)
            .unwrap();
        let chain = ChainInput {
            finger: Finger::Middle,
            points: vec![
                DVec3::ZERO,
                DVec3::new(0.0, 50.0, 0.0),
                DVec3::new(0.0, 50.0 + 50.0 * s.mean, 0.0),
            ],
            has_tip: false,
        };
        let r = audit(&a, &chain).unwrap();
        assert_eq!(r.basis, Basis::Ratio);
        assert_eq!(r.unjudged, vec![Joint::Dip]);
        assert!((r.values[0].measured - s.mean).abs() < 1e-12);
        assert!(r.joints[0].shift < 1e-9);
        // A PIP too close to the root makes J2/J1 too large: flagged below.
        let close = ChainInput {
            points: vec![
                DVec3::ZERO,
                DVec3::new(0.0, 20.0, 0.0),
                DVec3::new(0.0, 80.0, 0.0),
            ],
            ..chain
        };
        let r = audit(&a, &close).unwrap();
        assert!(matches!(r.joints[0].standing, Standing::Below { .. }));
        assert!(matches!(r.values[0].standing, Standing::Above { .. }));
        assert!(r.joints[0].range.low < r.joints[0].range.high);
        let thumb = ChainInput {
            finger: Finger::Thumb,
            points: vec![DVec3::ZERO, DVec3::new(1.0, 0.0, 0.0)],
            has_tip: false,
        };
        let r = audit(&a, &thumb).unwrap();
        assert_eq!(r.basis, Basis::None);
        assert!(r.joints.is_empty() && r.values.is_empty());
    }
}
