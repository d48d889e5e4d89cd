//! The explanation that moves the fewest joints ([`super::finger`]'s notes):
//! the line the joints move along, the fit of a placement, and the search
//! over none, one and two moved joints.

use super::chain::{arc_positions, backward_at, on_chain, point_at};
use super::standing::{Basis, ChainInput, Standing, normalised, value_of};
use crate::analysis::placement::Joint;
use crate::analysis::region::{FIX_LEVEL, JointRegion};
use crate::analysis::{Interval, Quantity, QuantityStats};
use crate::stats::describe::t_quantile;
use glam::DVec3;

/// The line the joints move along: the first segment's backward extension,
/// then the rig's joints, ending at the compared tip (the bone tip for a skin
/// tip) or, without a tip, at the last joint.
pub(super) struct Axis {
    pub(super) points: Vec<DVec3>,
    pub(super) arcs: Vec<f64>,
    /// Arc position of each chain joint (MCP, inner joints, compared tip).
    pub(super) joint_arcs: Vec<f64>,
    /// How far the MCP may move: (towards the root, towards the tip).
    pub(super) mcp_reach: (f64, f64),
}

impl Axis {
    pub(super) fn new(chain: &ChainInput, compared: &[f64], correction: f64) -> Axis {
        let p = &chain.points;
        let c1 = p[0].distance(p[1]);
        let back = (p[0] - p[1]).normalize_or_zero();
        let mut points = vec![p[0] + 1.5 * c1 * back];
        points.extend_from_slice(p);
        let n = p.len();
        if chain.has_tip && correction != 0.0 {
            // The compared tip lies on the last segment's line, `correction`
            // nearer the DIP (beyond the tip when negative).
            let dir = (p[n - 1] - p[n - 2]).normalize_or_zero();
            points[n] = p[n - 1] - correction * dir;
        }
        debug_assert_eq!(compared.len(), n - 1);
        let arcs = arc_positions(&points);
        let joint_arcs = arcs[1..].to_vec();
        Axis {
            points,
            arcs,
            joint_arcs,
            mcp_reach: (c1, 0.5 * c1),
        }
    }

    /// The compared segments for joints at arc positions `u`.
    fn segments(&self, u: &[f64]) -> Vec<f64> {
        let q: Vec<DVec3> = u.iter().map(|&x| point_at(&self.points, x)).collect();
        q.windows(2).map(|w| w[0].distance(w[1])).collect()
    }
}

/// An explanation as solved, with the joints' arc positions.
pub(super) struct Solved {
    pub(super) moved: Vec<Joint>,
    /// True when the moved joints, at their best place, bring the finger
    /// inside the fix's inner region ([`Judge::inner`]); for no move, when
    /// the finger is inside the region as it is.
    pub(super) consistent: bool,
    /// The fit after the moves: the normalised distance at the best place.
    pub(super) score: f64,
    /// The fit at the joints' best place (where the score is least), which
    /// chooses among explanations of one size.
    rank: f64,
    /// Arc positions of the chain's joints after the moves (`None`: nothing solved).
    pub(super) arcs: Option<Vec<f64>>,
    pub(super) segments: Option<Vec<f64>>,
    pub(super) also: Vec<Vec<Joint>>,
}

/// What a placement is judged against: the joint region of the finger's
/// relative joint positions when there is one ([`JointRegion`], a finger with
/// a tip), else one prediction interval per quantity (J2/J1 without a tip).
#[derive(Clone, Copy)]
pub(super) struct Judge<'a> {
    pub(super) quantities: &'a [(Quantity, &'a QuantityStats)],
    pub(super) region: Option<&'a JointRegion>,
    /// The normalised distance of the fix's inner region ([`FIX_LEVEL`]):
    /// sqrt(bound_50 / bound_95) with a region (0.30 at n = 5), else
    /// t(0.75; n - 1) / t(c; n - 1), the 50% prediction interval's share of
    /// the 95% one (0.27 at n = 5).
    pub(super) inner: f64,
}

impl<'a> Judge<'a> {
    /// The judge of `quantities` (from `n` X-rays) and `region`, at
    /// `confidence`, with its inner region.
    pub(super) fn new(
        quantities: &'a [(Quantity, &'a QuantityStats)],
        region: Option<&'a JointRegion>,
        n: usize,
        confidence: f64,
    ) -> Judge<'a> {
        let inner = match region {
            Some(r) => r.bound_at(FIX_LEVEL).map(|b| (b / r.bound).sqrt()),
            None => n
                .checked_sub(1)
                .and_then(|df| Some(t_quantile(FIX_LEVEL, df)? / t_quantile(confidence, df)?)),
        };
        Judge {
            quantities,
            region,
            inner: inner.filter(|x| x.is_finite() && *x > 0.0).unwrap_or(1.0),
        }
    }

    /// The normalised distance of `segments` from the reference hands (0 at
    /// their mean, 1 at the edge of the 95% region or of a prediction
    /// interval) and whether they are inside. With a region the distance is
    /// sqrt(T^2 / bound); without one, the largest normalised distance of the
    /// judged values, inside when every value is inside its prediction
    /// interval (or range). O(p^2) or O(quantities).
    pub(super) fn fit(&self, segments: &[f64]) -> (f64, bool) {
        if segments.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
            return (f64::INFINITY, false);
        }
        if let Some(r) = self.region {
            let t2 = r.distance_of_segments(segments);
            return ((t2 / r.bound).sqrt(), t2 <= r.bound);
        }
        let mut worst: f64 = 0.0;
        let mut inside = true;
        for &(q, s) in self.quantities {
            let x = value_of(q, segments);
            worst = worst.max(normalised(x, s));
            let range = Interval::new(s.min, s.max);
            inside &= Standing::of(x, range, s.intervals.pi).is_consistent();
        }
        (worst, inside)
    }
}

/// The explanation with the fewest moved joints (see [`super::finger`]'s notes),
/// among moves of the joints not in `hold`.
pub(super) fn explain(axis: &Axis, judge: Judge, basis: Basis, hold: &[Joint]) -> Solved {
    if basis == Basis::None || judge.quantities.is_empty() {
        return none_like();
    }
    let u0 = axis.joint_arcs.clone();
    let n = u0.len();
    // Movable joints: MCP and the inner joints (the last point stays).
    let kinds: Vec<Joint> = std::iter::once(Joint::Mcp)
        .chain(match n {
            3 if basis == Basis::Ratio => vec![Joint::Pip],
            3 => vec![Joint::Ip],
            _ => vec![Joint::Pip, Joint::Dip],
        })
        .collect();
    let free = |k: usize| !hold.contains(&kinds[k]);
    // An explanation is chosen by how well its joints can fit at their best
    // place, and placed there: where they are most likely given the joints
    // that stay (the conditional mode of the predictive distribution along
    // their moves), not at the region's edge, so that the fixed finger is
    // still inside once more X-rays narrow the region. It counts when that
    // place lies inside the inner region ([`FIX_LEVEL`]).
    let solved = |moved: Vec<Joint>, best: Vec<f64>| {
        let s = axis.segments(&best);
        let (score, inside) = judge.fit(&s);
        Solved {
            consistent: if moved.is_empty() {
                inside
            } else {
                score <= judge.inner
            },
            moved,
            score,
            rank: score,
            arcs: Some(best),
            segments: Some(s),
            also: Vec::new(),
        }
    };
    let mut tried: Vec<Vec<Solved>> = vec![vec![solved(Vec::new(), u0.clone())]];
    tried.push(
        (0..kinds.len())
            .filter(|&k| free(k))
            .filter_map(|k| solve_one(axis, judge, &u0, k).map(|u| solved(vec![kinds[k]], u)))
            .collect(),
    );
    if n == 4 {
        tried.push(
            [[1, 2], [0, 1], [0, 2]]
                .into_iter()
                .filter(|pair| pair.iter().all(|&k| free(k)))
                .filter_map(|pair| {
                    solve_pair(axis, judge.quantities, &u0, pair)
                        .map(|u| solved(pair.iter().map(|&k| kinds[k]).collect(), u))
                })
                .collect(),
        );
    }
    choose(tried, &u0)
}

/// The first size at which an explanation fits, its best (the better fit at
/// its joints' best place, then the smaller total move), with the others of
/// that size as `also`;
/// when none fits, the best fit of all, fewer joints first on a tie.
fn choose(mut tried: Vec<Vec<Solved>>, u0: &[f64]) -> Solved {
    let movement = |s: &Solved| -> f64 {
        s.arcs.as_ref().map_or(f64::INFINITY, |a| {
            a.iter().zip(u0).map(|(x, y)| (x - y).abs()).sum()
        })
    };
    // Among explanations that fit, the better fit at the joints' best place
    // wins, then the smaller total move (each is placed at the region's edge
    // nearest the rig, [`EDGE`]).
    let better = |a: &Solved, b: &Solved| -> bool {
        if (a.rank - b.rank).abs() > 1e-6 {
            a.rank < b.rank
        } else {
            movement(a) < movement(b)
        }
    };
    for size in tried.iter_mut() {
        if !size.iter().any(|s| s.consistent) {
            continue;
        }
        let mut fits: Vec<Solved> = size.drain(..).filter(|s| s.consistent).collect();
        let mut best = 0;
        for i in 1..fits.len() {
            if better(&fits[i], &fits[best]) {
                best = i;
            }
        }
        let mut chosen = fits.swap_remove(best);
        chosen.also = fits.into_iter().map(|s| s.moved).collect();
        return chosen;
    }
    let mut best: Option<Solved> = None;
    for s in tried.into_iter().flatten() {
        if best.as_ref().is_none_or(|b| s.score < b.score - 1e-6) {
            best = Some(s);
        }
    }
    best.unwrap_or_else(none_like)
}

fn none_like() -> Solved {
    Solved {
        moved: Vec::new(),
        consistent: false,
        score: f64::INFINITY,
        rank: f64::INFINITY,
        arcs: None,
        segments: None,
        also: Vec::new(),
    }
}

/// The arc positions with joint `k` alone moved to where the fit is best: a
/// scan of 200 points over its span, then golden-section search around the
/// best (T^2 is a quadratic form in positions that move monotonically with
/// the joint, and the worst value a maximum of functions each monotone in it,
/// so either falls then rises). `None` for an empty span.
fn solve_one(axis: &Axis, judge: Judge, u0: &[f64], k: usize) -> Option<Vec<f64>> {
    let n = u0.len();
    let gap = 1e-4 * (u0[n - 1] - u0[0]);
    let (lo, hi) = if k == 0 {
        (
            (u0[0] - axis.mcp_reach.0).max(axis.arcs[0]),
            (u0[0] + axis.mcp_reach.1).min(u0[1] - gap),
        )
    } else {
        (u0[k - 1] + gap, u0[k + 1] - gap)
    };
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let mut u = u0.to_vec();
    let mut eval = |x: f64| {
        u[k] = x;
        judge.fit(&axis.segments(&u)).0
    };
    const STEPS: usize = 200;
    let step = (hi - lo) / STEPS as f64;
    let mut best = (f64::INFINITY, lo);
    for i in 0..=STEPS {
        let x = lo + step * i as f64;
        let f = eval(x);
        if f < best.0 {
            best = (f, x);
        }
    }
    let (mut a, mut b) = ((best.1 - step).max(lo), (best.1 + step).min(hi));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (eval(c), eval(d));
    for _ in 0..100 {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = eval(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = eval(d);
        }
    }
    let x = if fc <= fd { c } else { d };
    let x = if eval(x) <= best.0 { x } else { best.1 };
    let mut out = u0.to_vec();
    out[k] = x;
    Some(out)
}

/// The arc positions with the joints `pair` (of MCP 0, PIP 1, DIP 2; a finger
/// with a tip) moved so the compared segments have the mean relative values
/// exactly; the other joint and the tip stay. `None` when no such placement
/// exists on the chain or the MCP would leave its reach.
fn solve_pair(
    axis: &Axis,
    quantities: &[(Quantity, &QuantityStats)],
    u0: &[f64],
    pair: [usize; 2],
) -> Option<Vec<f64>> {
    let mean = |q: Quantity| {
        quantities
            .iter()
            .find(|(x, _)| *x == q)
            .map(|(_, s)| s.mean)
    };
    let m = [
        mean(Quantity::RelJ1)?,
        mean(Quantity::RelJ2)?,
        mean(Quantity::RelJ3)?,
    ];
    let (pts, arcs) = (&axis.points, &axis.arcs);
    let p = |x: f64| point_at(pts, x);
    let mut u = u0.to_vec();
    match pair {
        [1, 2] => {
            let sub: Vec<DVec3> = u0.iter().map(|&x| p(x)).collect();
            let (_, at) = on_chain(&sub, &m)?;
            u[1] = u0[0] + at[0];
            u[2] = u0[0] + at[1];
        }
        [0, 1] => {
            let l = p(u0[2]).distance(p(u0[3])) / m[2];
            u[1] = backward_at(pts, arcs, u0[2], p(u0[2]), m[1] * l)?;
            u[0] = backward_at(pts, arcs, u[1], p(u[1]), m[0] * l)?;
        }
        [0, 2] => {
            let sub = [p(u0[1]), p(u0[2]), p(u0[3])];
            let share = m[1] / (m[1] + m[2]);
            let (q, at) = on_chain(&sub, &[share, 1.0 - share])?;
            u[2] = u0[1] + at[0];
            let l = (q[0].distance(q[1]) + q[1].distance(q[2])) / (m[1] + m[2]);
            u[0] = backward_at(pts, arcs, u0[1], p(u0[1]), m[0] * l)?;
        }
        _ => return None,
    }
    let within = u[0] >= u0[0] - axis.mcp_reach.0 - 1e-12 && u[0] <= u0[0] + axis.mcp_reach.1;
    (within && u.windows(2).all(|w| w[0] < w[1])).then_some(u)
}
