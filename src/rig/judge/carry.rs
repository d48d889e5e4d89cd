//! Carrying a finger's skin weights with its moved joints, so the skin bends
//! at the new joint: the weights a fix writes (`rig::fix::remap` writes them)
//! and the guard that checks, before a joint moves, that its skin would bend
//! there ([`super::audited`]).
//!
//! **Method.** Each finger vertex has an arc position u along the finger's
//! axis (the old joints' polyline, extended before the MCP; the moved joints
//! lie on it). A piecewise-linear map phi takes the new layout of the joints
//! to the old one: around each moved joint k, within r_k of it, phi(u) = u -
//! (U'_k - A_k), A_k where the skin bent (the joint's old bend, else the old
//! joint), so the blend that bent the skin there is carried to the new joint
//! and keeps its width; linear between those pieces (the segments stretch or
//! shrink); an unmoved joint keeps its own place; the axis' start and whatever
//! lies past the tip stay. r_k is a quarter of the shorter of the joint's
//! neighbouring segments, old or new, for a moved joint, and 0.45 of it for
//! an unmoved one (whose blend, over a knuckle often wide, stays as painted). A vertex at u takes the weights the old
//! rig had at phi(u) on its own side of the finger: the vertices around the
//! axis are sorted into 8 sectors of 45 degrees (angles about the MCP-to-tip
//! direction), and within the vertex's sector the old weights are
//! interpolated linearly in u between the two vertices on either side of
//! phi(u) (the nearest one past the sector's ends; by inverse squared distance
//! from the 4 nearest vertices when the sector is empty). A vertex whose
//! phi(u) = u keeps its own weights exactly. The influences are merged by
//! node, cut to the slots the vertex has (4 per JOINTS_n/WEIGHTS_n set,
//! largest kept) and renormalised.
//!
//! A mesh bends only where it has vertices: a joint moved into a span with no
//! ring of vertices (the rings lie where the artist modelled the old joints)
//! gets no bend at it, however its weights are carried; the guard finds that
//! on the carried weights and holds the joint.
//!
//! **The rest shape is kept.** A vertex rests at sum_j w_j M_j v; when every
//! node it is weighted to, before and after, has the same rest skin matrix M
//! (the usual case: the node pose is the bind pose, M = I), it rests at M v
//! whatever its weights. A vertex for which that does not hold keeps its
//! weights, with a note.

use super::bend::{self, FingerAxis, finger_nodes};
use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::{DMat4, DVec3};
use std::collections::{BTreeMap, BTreeSet};

/// A finger whose joints move: the chain before, every joint's new position,
/// and for each joint where its skin bends now (`None`: at the joint, or
/// the joint stays), so the blend that bent the skin there is carried to
/// the new joint and the skin bends at it.
#[derive(Clone)]
pub struct FingerMove<'a> {
    pub chain: &'a FingerChain,
    pub new_positions: Vec<DVec3>,
    pub anchors: Vec<Option<DVec3>>,
    /// Each joint's blend, as arc offsets from where its skin bends
    /// ([`bend::Bend::blend`]): the span the map keeps whole.
    pub blends: Vec<Option<(f64, f64)>>,
}

impl<'a> FingerMove<'a> {
    /// The move of `chain` whose joints go where `to` says (`None`: they
    /// stay), each moved joint's blend taken from where `bends` says its skin
    /// bends.
    pub fn of(
        chain: &'a FingerChain,
        bends: &[bend::Bend],
        to: impl Fn(crate::analysis::placement::Joint) -> Option<DVec3>,
    ) -> FingerMove<'a> {
        let mut new_positions = Vec::new();
        let mut anchors = Vec::new();
        let mut blends = Vec::new();
        for rj in &chain.joints {
            let target = to(rj.joint);
            let bend = bends.iter().find(|b| b.joint == rj.joint);
            new_positions.push(target.unwrap_or(rj.position));
            // The blend is carried from where it bent the skin; a joint
            // that sat at its bend (within the carry tolerance) keeps its
            // own small offset to it, as the artist painted it.
            anchors.push(target.and_then(|_| {
                bend.filter(|b| b.offset.is_some_and(|o| o.abs() > CARRY_TOLERANCE))
                    .and_then(|b| b.at)
            }));
            blends.push(bend.and_then(|b| b.blend));
        }
        FingerMove {
            chain,
            new_positions,
            anchors,
            blends,
        }
    }
}

pub use super::bend::Remapped;

/// The map phi from the new joint layout to the old, as knots (new u, old u),
/// increasing in both; `None` when the joints' order would not be kept.
fn knots(
    old: &[f64],
    new: &[f64],
    blends: &[Option<(f64, f64)>],
    start: f64,
    end: Option<f64>,
) -> Option<Vec<(f64, f64)>> {
    let n = old.len();
    let mut k = vec![(start, start)];
    for i in 0..n {
        // The room each side: under half of the shorter segment there, old or new.
        let side = |a: Option<usize>, b: Option<usize>| -> f64 {
            match (a, b) {
                (Some(a), Some(b)) => (old[b] - old[a]).min(new[b] - new[a]),
                _ => f64::INFINITY,
            }
        };
        let mut below = side(i.checked_sub(1), Some(i));
        let above = side(Some(i), (i + 1 < n).then_some(i + 1));
        if i == 0 {
            below = below.min(old[0] - start).min(new[0] - start);
        }
        let gap = below.min(above);
        // An unmoved joint keeps its blend: the map is the identity almost to
        // the midpoints of its segments. A moved joint carries its blend whole
        // (the span where the skin's share is neither 0 nor 1, and a little),
        // a quarter segment where the blend is not known.
        let unmoved = (old[i] - new[i]).abs() < 1e-12;
        let (lo, hi) = match blends.get(i).copied().flatten() {
            Some((a, b)) if !unmoved => (-a + 0.05 * gap, b + 0.05 * gap),
            _ => {
                let r = if unmoved { 0.45 } else { 0.25 } * gap;
                (r, r)
            }
        };
        let (lo, hi) = (lo.min(0.45 * below), hi.min(0.45 * above));
        if lo.is_nan() || hi.is_nan() || lo <= 0.0 || hi <= 0.0 {
            return None;
        }
        k.extend([
            (new[i] - lo, old[i] - lo),
            (new[i], old[i]),
            (new[i] + hi, old[i] + hi),
        ]);
    }
    if let Some(e) = end {
        k.push((e, e));
    }
    k.windows(2)
        .all(|w| w[0].0 < w[1].0 && w[0].1 < w[1].1)
        .then_some(k)
}

/// phi(u) by the knots; the identity outside them.
fn phi(knots: &[(f64, f64)], u: f64) -> f64 {
    let (Some(first), Some(last)) = (knots.first(), knots.last()) else {
        return u;
    };
    if u <= first.0 || u >= last.0 {
        return u;
    }
    let i = knots.partition_point(|k| k.0 <= u).max(1);
    let (a, b) = (knots[i - 1], knots[i]);
    a.1 + (u - a.0) / (b.0 - a.0) * (b.1 - a.1)
}

/// The new weights of every finger vertex the moves change (see the module
/// notes), and remarks. O(F V^2) for F fingers of V vertices each (the
/// nearest-vertex search is by brute force over the finger's vertices).
pub fn remap(weights: &SkinWeights, moves: &[FingerMove<'_>]) -> (Remapped, Vec<String>) {
    let mut out = Remapped::new();
    let mut notes = Vec::new();
    for m in moves {
        let chain = m.chain;
        let Some((nodes, before)) = finger_nodes(chain) else {
            continue;
        };
        let points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
        let Some(axis) = FingerAxis::with_extension(&points, chain.has_tip, 2.0) else {
            continue;
        };
        let joints: Vec<f64> = (0..points.len()).map(|k| axis.joint(k)).collect();
        let new: Vec<f64> = m.new_positions.iter().map(|p| axis.locate(*p).0).collect();
        if joints.iter().zip(&new).all(|(a, b)| (a - b).abs() < 1e-12) {
            continue;
        }
        // A moved joint takes the blend from where the skin bent (its old
        // bend); the others keep theirs.
        let old: Vec<f64> = joints
            .iter()
            .zip(&new)
            .enumerate()
            .map(|(k, (&j, &n))| match m.anchors.get(k).copied().flatten() {
                Some(at) if (j - n).abs() >= 1e-12 => axis.locate(at).0,
                _ => j,
            })
            .collect();
        let end = (!chain.has_tip).then(|| axis.arcs[axis.arcs.len() - 1] - axis.joint_arcs[0]);
        let Some(knots) = knots(&old, &new, &m.blends, axis.start(), end)
            .or_else(|| knots(&joints, &new, &[], axis.start(), end))
        else {
            notes.push(format!(
                "{}: the joints' new order along the finger cannot carry the weights; they are \
                 left as they were",
                chain.label()
            ));
            continue;
        };
        // The finger's vertices: (primitive, vertex, u).
        let found = bend::finger_vertices_at(&axis, weights, &nodes, &before);
        let sectors = Sectors::new(&axis, weights, &found, points[points.len() - 1] - points[0]);
        let mut skipped = 0usize;
        for &(pi, v, u) in &found {
            let target = phi(&knots, u);
            if (target - u).abs() < 1e-12 {
                continue;
            }
            let p = weights.primitives[pi].rest[v];
            let infl = match sectors.along(weights, sectors.of(&axis, p, u), target) {
                Some(i) => i,
                None => interpolate(weights, &found, axis.point(target) + (p - axis.point(u))),
            };
            match fit_to_skin(weights, pi, v, infl) {
                Some(list) => {
                    out.insert((pi, v), list);
                }
                None => skipped += 1,
            }
        }
        if skipped > 0 {
            notes.push(format!(
                "{}: {skipped} vertices keep their weights: the nodes they would be weighted to \
                 do not share one rest skin matrix (the file's node pose is not its bind pose), \
                 so new weights would change the rest shape",
                chain.label()
            ));
        }
    }
    (out, notes)
}

/// How far from a moved joint its carried weights may bend the skin (metres):
/// half the bend guard (1 mm), the other half left for the bins a bend is
/// found in, the precision the file stores weights at, and other readers of
/// the same weights (a bin of 0.5 mm read without pooling puts a bend up to
/// 0.3 mm from where this one does). A joint within it of its bend sat at it
/// as the artist painted it: its blend is carried from the joint.
pub const CARRY_TOLERANCE: f64 = 0.5 * super::standing::BEND_GUARD;

/// Where a carried blend is aimed (metres): a warp that lands farther than
/// this from its joint, but within [`CARRY_TOLERANCE`], is warped again from
/// a place shifted by its miss. Other readings of the same weights differ by
/// more than the tolerance's other half: on Godot XR Tools' left middle DIP
/// the warp bent 0.38 mm from the joint by this reading and 1.16 mm by
/// blocks of vertices along the axis (where the distal share crosses 1/2).
pub const CARRY_AIM: f64 = 0.25 * super::standing::BEND_GUARD;

/// Each moved joint of a finger (its index along the chain) with where its
/// skin bends from it on the carried weights (`None`: no bend found).
pub type MovedBends = Vec<(usize, Option<f64>)>;

/// The weights of one finger carried to its moved joints: warped
/// ([`remap`]); a moved joint whose warped blend bends the skin a little off
/// it (beyond [`CARRY_AIM`]) warped again from a place shifted by the miss;
/// one that would not bend it within [`CARRY_TOLERANCE`] blended anew
/// ([`reblend`], at most twice); with each moved joint's bend offset on the
/// result (`None`: no bend found). O(V m) and at most three bend searches.
pub fn carry_finger(
    weights: &SkinWeights,
    m: &FingerMove<'_>,
    tolerance: f64,
) -> (Remapped, MovedBends, Vec<String>) {
    let (mut out, notes) = remap(weights, std::slice::from_ref(m));
    let mut moved = m.chain.clone();
    for (rj, p) in moved.joints.iter_mut().zip(&m.new_positions) {
        rj.position = *p;
    }
    let is_moved = |k: usize| {
        m.chain
            .joints
            .get(k)
            .zip(m.new_positions.get(k))
            .is_some_and(|(rj, p)| rj.position.distance(*p) > 0.0)
    };
    let offsets = |out: &Remapped| -> MovedBends {
        let after = bend::bends_with(&moved, weights, tolerance, Some(out));
        (0..moved.joints.len())
            .filter(|&k| is_moved(k))
            .map(|k| {
                let o = after
                    .iter()
                    .find(|b| b.joint == moved.joints[k].joint)
                    .and_then(|b| b.offset);
                (k, o)
            })
            .collect()
    };
    let missed = |offsets: &[(usize, Option<f64>)]| -> Vec<usize> {
        offsets
            .iter()
            .filter(|(_, o)| o.is_none_or(|o| o.abs() > CARRY_TOLERANCE))
            .map(|(k, _)| *k)
            .collect()
    };
    let mut now = offsets(&out);
    // A warped blend that lands off its joint is carried again from a place
    // shifted by its miss (the map takes the new joint to where the old
    // weights cross by that much more), so the artist's blend keeps its
    // shape; kept when every moved joint then bends within the tolerance.
    // A warped blend that lands a little off its joint (beyond CARRY_AIM,
    // within the tolerance) is carried again from a place shifted
    // by its miss: the map takes the new joint to where the old weights
    // cross that much farther on, so the artist's blend keeps its shape. The
    // shifted carry is kept when no moved joint then bends farther from it.
    let small: Vec<usize> = now
        .iter()
        .filter(|(_, o)| o.is_some_and(|o| o.abs() > CARRY_AIM && o.abs() <= CARRY_TOLERANCE))
        .map(|(k, _)| *k)
        .collect();
    if !small.is_empty() {
        let old: Vec<DVec3> = m.chain.joints.iter().map(|j| j.position).collect();
        let mut again = m.clone();
        for &(k, o) in &now {
            let (Some(o), true) = (o, small.contains(&k)) else {
                continue;
            };
            let (a, b) = (k.saturating_sub(1), (k + 1).min(old.len() - 1));
            let dir = (old[b] - old[a]).normalize_or_zero();
            let from = again.anchors[k].unwrap_or(old[k]);
            again.anchors[k] = Some(from + dir * o);
        }
        let (shifted, _) = remap(weights, std::slice::from_ref(&again));
        let then = offsets(&shifted);
        let no_worse = now.iter().zip(&then).all(|((_, a), (_, b))| match (a, b) {
            (Some(a), Some(b)) => b.abs() <= a.abs(),
            (None, _) => true,
            (Some(_), None) => false,
        });
        if no_worse {
            out = shifted;
            now = then;
        }
    }
    // Twice at most: a joint blended anew can shift the bend its neighbour's
    // warped weights gave.
    for _ in 0..2 {
        let again = missed(&now);
        if again.is_empty() {
            break;
        }
        for k in again {
            reblend(weights, &moved, k, &mut out);
        }
        now = offsets(&out);
    }
    (out, now, notes)
}

/// Blends the skin anew across joint `k` of the moved chain `moved`, over
/// `out` (the weights carried so far): within half the way to each
/// neighbouring joint, each vertex's weight on the finger's bones (and the
/// metacarpal or wrist before it) goes to the bone before the joint and the
/// bone after it by a linear ramp centred on the joint, s(u) = clamp((u - c +
/// h) / 2h, 0, 1). Its half-width h is 0.6 times the finger's local radius
/// (the median distance of those vertices from the axis), widened to reach
/// the nearest vertex on either side: a mesh whose rings of vertices lie far
/// from the new joint still bends there (the bend is where the ramp between
/// the rings either side crosses 1/2). Weights on other bones are kept.
/// O(V).
pub fn reblend(weights: &SkinWeights, moved: &FingerChain, k: usize, out: &mut Remapped) {
    let Some((nodes, before)) = finger_nodes(moved) else {
        return;
    };
    let (prox, dist) = match k {
        0 => match before.first() {
            Some(&b) => (b, nodes[0]),
            None => return,
        },
        _ => (nodes[k - 1], nodes[k]),
    };
    let points: Vec<DVec3> = moved.joints.iter().map(|j| j.position).collect();
    let Some(axis) = FingerAxis::with_extension(&points, moved.has_tip, 2.0) else {
        return;
    };
    let c = axis.joint(k);
    let lo = if k == 0 {
        axis.start()
    } else {
        axis.joint(k - 1)
    };
    let hi = if k + 1 < points.len() {
        axis.joint(k + 1)
    } else {
        axis.arcs[axis.arcs.len() - 1] - axis.joint_arcs[0]
    };
    let (w_lo, w_hi) = (c - 0.5 * (c - lo), c + 0.5 * (hi - c));
    let finger: Vec<usize> = nodes.iter().chain(&before).copied().collect();
    let window: Vec<(usize, usize, f64, f64)> =
        bend::finger_vertices_at(&axis, weights, &nodes, &before)
            .into_iter()
            .filter(|&(_, _, u)| u > w_lo && u < w_hi)
            .map(|(pi, v, u)| {
                let radial = axis.locate(weights.primitives[pi].rest[v]).1;
                (pi, v, u, radial)
            })
            .collect();
    if window.is_empty() {
        return;
    }
    let mut radii: Vec<f64> = window.iter().map(|w| w.3).collect();
    radii.sort_by(f64::total_cmp);
    let radius = radii[radii.len() / 2];
    let gap_below = window
        .iter()
        .filter(|w| w.2 <= c)
        .map(|w| c - w.2)
        .fold(f64::INFINITY, f64::min);
    let gap_above = window
        .iter()
        .filter(|w| w.2 >= c)
        .map(|w| w.2 - c)
        .fold(f64::INFINITY, f64::min);
    let reach = [gap_below, gap_above]
        .into_iter()
        .filter(|g| g.is_finite())
        .fold(0.0, f64::max);
    let h = (0.6 * radius)
        .max(1.05 * reach)
        .min(0.95 * (c - w_lo).min(w_hi - c));
    if !(h.is_finite() && h > 0.0) {
        return;
    }
    for (pi, v, u, _) in window {
        let current = out
            .get(&(pi, v))
            .cloned()
            .unwrap_or_else(|| weights.primitives[pi].influences[v].clone());
        let total: f64 = current
            .iter()
            .filter(|(n, _)| finger.contains(n))
            .map(|(_, w)| w)
            .sum();
        if total <= 0.0 {
            continue;
        }
        let s = ((u - c + h) / (2.0 * h)).clamp(0.0, 1.0);
        let mut merged: BTreeMap<usize, f64> = current
            .iter()
            .filter(|(n, _)| !finger.contains(n))
            .copied()
            .collect();
        *merged.entry(prox).or_default() += total * (1.0 - s);
        *merged.entry(dist).or_default() += total * s;
        let mut list: Vec<(usize, f64)> = merged.into_iter().filter(|x| x.1 > 0.0).collect();
        list.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        if let Some(fit) = fit_to_skin(weights, pi, v, list) {
            out.insert((pi, v), fit);
        }
    }
}

/// Sectors around a finger's axis, each its vertices sorted by arc position.
struct Sectors {
    /// Two directions across the finger, for the angle about it.
    across: (DVec3, DVec3),
    lists: Vec<Vec<(f64, usize, usize)>>,
}

impl Sectors {
    const COUNT: usize = 8;

    fn new(
        axis: &FingerAxis,
        weights: &SkinWeights,
        found: &[(usize, usize, f64)],
        along: DVec3,
    ) -> Sectors {
        let d = along.normalize_or_zero();
        // The world axis least aligned with the finger, made perpendicular to it.
        let e = [DVec3::X, DVec3::Y, DVec3::Z]
            .into_iter()
            .min_by(|a, b| a.dot(d).abs().total_cmp(&b.dot(d).abs()))
            .unwrap_or(DVec3::X);
        let r = (e - e.dot(d) * d).normalize_or_zero();
        let mut s = Sectors {
            across: (r, d.cross(r)),
            lists: vec![Vec::new(); Self::COUNT],
        };
        for &(pi, v, u) in found {
            let k = s.of(axis, weights.primitives[pi].rest[v], u);
            s.lists[k].push((u, pi, v));
        }
        for l in &mut s.lists {
            l.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        s
    }

    /// The sector of a vertex at `p` with arc position `u`.
    fn of(&self, axis: &FingerAxis, p: DVec3, u: f64) -> usize {
        let rho = p - axis.point(u);
        let angle = rho.dot(self.across.1).atan2(rho.dot(self.across.0));
        let k =
            ((angle + std::f64::consts::PI) / std::f64::consts::TAU * Self::COUNT as f64) as usize;
        k.min(Self::COUNT - 1)
    }

    /// The influences at arc position `u` in sector `k`: linear between the
    /// vertices either side of it, the nearest past an end; `None` when empty.
    fn along(&self, weights: &SkinWeights, k: usize, u: f64) -> Option<Vec<(usize, f64)>> {
        let list = &self.lists[k];
        let infl = |i: usize| &weights.primitives[list[i].1].influences[list[i].2];
        let after = list.partition_point(|x| x.0 < u);
        if list.is_empty() {
            return None;
        }
        if after == 0 {
            return Some(infl(0).clone());
        }
        if after == list.len() {
            return Some(infl(list.len() - 1).clone());
        }
        let (a, b) = (after - 1, after);
        let span = list[b].0 - list[a].0;
        let t = if span > 0.0 {
            (u - list[a].0) / span
        } else {
            0.5
        };
        let mut merged: BTreeMap<usize, f64> = BTreeMap::new();
        for (i, f) in [(a, 1.0 - t), (b, t)] {
            for &(n, w) in infl(i) {
                *merged.entry(n).or_default() += f * w;
            }
        }
        let mut out: Vec<(usize, f64)> = merged.into_iter().filter(|x| x.1 > 0.0).collect();
        out.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
        Some(out)
    }
}

/// The influences at `at`, from the 4 vertices of `found` nearest to it by
/// inverse squared distance (the vertex itself when one lies there).
fn interpolate(
    weights: &SkinWeights,
    found: &[(usize, usize, f64)],
    at: DVec3,
) -> Vec<(usize, f64)> {
    let mut near: Vec<(f64, usize, usize)> = Vec::with_capacity(5);
    for &(pi, v, _) in found {
        let d = weights.primitives[pi].rest[v].distance_squared(at);
        if near.len() < 4 || d < near[near.len() - 1].0 {
            let i = near.partition_point(|x| x.0 <= d);
            near.insert(i, (d, pi, v));
            near.truncate(4);
        }
    }
    let mut merged: BTreeMap<usize, f64> = BTreeMap::new();
    if let Some(&(d, pi, v)) = near.first()
        && d < 1e-24
    {
        return weights.primitives[pi].influences[v].clone();
    }
    for &(d, pi, v) in &near {
        let k = 1.0 / d;
        for &(n, w) in &weights.primitives[pi].influences[v] {
            *merged.entry(n).or_default() += k * w;
        }
    }
    let total: f64 = merged.values().sum();
    let mut list: Vec<(usize, f64)> = merged.into_iter().map(|(n, w)| (n, w / total)).collect();
    list.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    list
}

/// `infl` cut to the nodes of the vertex's skin and to its slots, largest
/// kept, renormalised; `None` when the vertex's rest position would change
/// (its old and new nodes do not share one rest skin matrix) or nothing is left.
fn fit_to_skin(
    weights: &SkinWeights,
    pi: usize,
    v: usize,
    infl: Vec<(usize, f64)>,
) -> Option<Vec<(usize, f64)>> {
    let prim = &weights.primitives[pi];
    let (joints, matrices) = weights.skins.get(&prim.skin)?;
    let slots = 4 * prim.sets.len();
    let mut list: Vec<(usize, f64)> = infl
        .into_iter()
        .filter(|(n, w)| *w > 1e-6 && joints.contains(n))
        .collect();
    list.truncate(slots);
    let total: f64 = list.iter().map(|x| x.1).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    list.iter_mut().for_each(|x| x.1 /= total);
    let matrix =
        |n: usize| -> Option<DMat4> { joints.iter().position(|&j| j == n).map(|s| matrices[s]) };
    let used: BTreeSet<usize> = list
        .iter()
        .chain(&prim.influences[v])
        .map(|x| x.0)
        .collect();
    let first = matrix(*used.iter().next()?)?;
    let same = used.iter().all(|&n| {
        matrix(n).is_some_and(|m| {
            m.to_cols_array()
                .iter()
                .zip(first.to_cols_array())
                .all(|(a, b)| (a - b).abs() <= 1e-6)
        })
    });
    same.then_some(list)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phi_translates_around_joints_and_stretches_between() {
        // Joints at 0, 40, 65, 85 (tip); the PIP moves to 35. Around the PIP,
        // within a quarter of its shortest neighbouring segment (old 65 - 40 =
        // 25: r = 6.25), phi translates by 5.
        let old = [0.0, 40.0, 65.0, 85.0];
        let new = [0.0, 35.0, 65.0, 85.0];
        let k = knots(&old, &new, &[], -40.0, None).unwrap();
        assert!((phi(&k, 35.0) - 40.0).abs() < 1e-12);
        assert!((phi(&k, 37.0) - 42.0).abs() < 1e-12);
        assert!((phi(&k, 65.0) - 65.0).abs() < 1e-12);
        assert_eq!(phi(&k, -50.0), -50.0);
        assert_eq!(phi(&k, 90.0), 90.0);
        // Monotone between the pieces.
        let mut last = f64::NEG_INFINITY;
        for i in 0..1000 {
            let y = phi(&k, -40.0 + 0.13 * i as f64);
            assert!(y >= last);
            last = y;
        }
        // A joint passing its neighbour cannot be mapped.
        assert!(knots(&old, &[0.0, 70.0, 65.0, 85.0], &[], -40.0, None).is_none());
    }
}
