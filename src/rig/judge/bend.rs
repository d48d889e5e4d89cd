//! Where a finger's skin bends: for each joint, the point along the finger
//! where the weight of the bones beyond the joint overtakes the weight of the
//! bones before it. A joint far from its bend is a defect of the rig whatever
//! the X-rays say: the mesh folds somewhere else than the bone turns.
//!
//! **Method.** The finger's axis is the polyline through its joints (MCP to
//! tip), extended one first segment before the MCP (the knuckle and palm) and,
//! without a tip, one last segment past the last joint. Each vertex (at its
//! rest position) is projected onto the axis: its arc position u, measured
//! from the MCP. For joint k the vertices considered are those that project
//! between the joint before and the joint after (for the MCP: from one first
//! segment before it to the PIP), lie within the finger's radius of the axis,
//! and carry at least half their weight on the finger's bones on either side:
//! the distal side D = the joint's node and every chain node after it, the
//! proximal side P = the chain nodes before it, the finger's metacarpal and the
//! wrist. Each such vertex has the share s = w(D) / (w(D) + w(P)). The shares in
//! order of u are fitted by the closest non-decreasing sequence (isotonic
//! regression by pool-adjacent-violators, so noise in painted weights pools
//! instead of making several crossings), and the bend is where the fit
//! crosses 1/2, interpolated between the last vertex below 1/2 and the first
//! at or above it. With hard (0/1) weights that is midway between the last
//! vertex of the bone before and the first of the bone after. Vertices at
//! the same position (split seams) count once.
//!
//! Only inner joints (PIP, DIP, IP) are flagged: the skin over an MCP folds
//! at the finger's web, distal of the joint (in WebXR's generic hand, whose
//! inner bends lie within 1.3 mm of their joints, the MCPs' lie 6.5-10 mm
//! distal), so its bend is reported for information.
//!
//! The radius is 1.5 times the median distance from the axis of the vertices
//! whose largest weight is on the MCP's node (the proximal phalanx's skin):
//! the finger's own width, which keeps the neighbouring fingers' knuckles out
//! of the MCP's bend. Cost: O(V m) for V vertices and m chain points, and a
//! sort per joint.

use super::chain::{arc_positions, point_at, project};
use crate::analysis::placement::Joint;
use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::DVec3;
use rustc_hash::FxHashSet;
use schemars::JsonSchema;
use serde::Serialize;

/// A joint further than this from its bend is flagged, in mm, unless
/// `--bend-tolerance` says otherwise.
///
/// 3 mm: less than the half-width of the X-rays' 95% prediction interval for a
/// finger joint's position (3.6 mm for the index PIP of a 90 mm finger, from
/// the paper's data), so a bend further off than that could not be excused by
/// the joint's natural variation; and about the thickness of the skin and
/// subcutis over a finger joint's dorsum, the scale at which a crease visibly
/// moves.
pub const BEND_TOLERANCE_MM: f64 = 3.0;

/// Shares are averaged in bins this fraction of the finger's length wide
/// (about 1 mm): a mesh's rings of vertices lie a few mm apart, and each
/// ring's vertices straddle its mean position.
pub(super) const BIN: f64 = 0.01;

/// New influences by node for vertices of `SkinWeights::primitives`:
/// (primitive, vertex) -> influences (weights carried to moved joints,
/// `super::carry`), read over the painted ones where given.
pub type Remapped = std::collections::BTreeMap<(usize, usize), Vec<(usize, f64)>>;

/// Where the skin bends at one joint.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Bend {
    pub joint: Joint,
    /// Distance along the chain from the joint to where the skin bends
    /// (+ towards the tip); `None` when no crossing was found near the joint.
    pub offset: Option<f64>,
    /// The point on the finger's axis where the skin bends.
    #[schemars(with = "Option<[f64; 3]>")]
    pub at: Option<DVec3>,
    /// Vertices the bend was found from.
    pub vertices: usize,
    /// True when the bend lies further from the joint than the tolerance
    /// (inner joints only; see the module notes).
    pub flagged: bool,
    /// The blend around the bend: from the first to the last vertex whose
    /// share of the distal side is strictly between [`BLEND_EDGE`] and 1 -
    /// [`BLEND_EDGE`], as arc offsets from the bend (the first negative);
    /// `None` without a bend or with hard weights.
    #[serde(skip)]
    #[schemars(skip)]
    pub blend: Option<(f64, f64)>,
}

/// A vertex whose share of the distal side lies within this of 0 or 1 is
/// not in a joint's blend ([`Bend::blend`]).
pub const BLEND_EDGE: f64 = 0.02;

/// A finger's axis: the joints' polyline, extended before the MCP (and past
/// the last joint without a tip).
#[derive(Debug, Clone)]
pub struct FingerAxis {
    pub points: Vec<DVec3>,
    pub arcs: Vec<f64>,
    /// Arc position of each chain joint (MCP first) on `points`.
    pub joint_arcs: Vec<f64>,
}

impl FingerAxis {
    /// The axis through `joints` (MCP first); `None` for fewer than two
    /// points or a zero-length first or last segment.
    pub fn new(joints: &[DVec3], has_tip: bool) -> Option<FingerAxis> {
        FingerAxis::with_extension(joints, has_tip, 1.0)
    }

    /// The axis extended `factor` first segments before the MCP.
    pub fn with_extension(joints: &[DVec3], has_tip: bool, factor: f64) -> Option<FingerAxis> {
        let n = joints.len();
        if n < 2 || joints.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let first = joints[1] - joints[0];
        let last = joints[n - 1] - joints[n - 2];
        if first.length() <= 0.0 || last.length() <= 0.0 {
            return None;
        }
        let mut points = vec![joints[0] - factor * first];
        points.extend_from_slice(joints);
        if !has_tip {
            points.push(joints[n - 1] + last);
        }
        let arcs = arc_positions(&points);
        let joint_arcs = arcs[1..=n].to_vec();
        Some(FingerAxis {
            points,
            arcs,
            joint_arcs,
        })
    }

    /// The arc position of `p` measured from the MCP, and its distance from the axis.
    pub fn locate(&self, p: DVec3) -> (f64, f64) {
        let (u, foot) = project(&self.points, &self.arcs, p);
        (u - self.joint_arcs[0], foot.distance(p))
    }

    /// The point of the axis at arc position `u` from the MCP.
    pub fn point(&self, u: f64) -> DVec3 {
        point_at(&self.points, u + self.joint_arcs[0])
    }

    /// Arc position of the start of the axis, from the MCP (negative).
    pub fn start(&self) -> f64 {
        -self.joint_arcs[0]
    }

    /// Arc position of joint `k` from the MCP.
    pub fn joint(&self, k: usize) -> f64 {
        self.joint_arcs[k] - self.joint_arcs[0]
    }
}

/// The nodes of a finger for its bends: the chain's nodes (MCP first) and the
/// proximal nodes (metacarpal, wrist). `None` for a chain without nodes.
pub fn finger_nodes(chain: &FingerChain) -> Option<(Vec<usize>, Vec<usize>)> {
    let nodes: Vec<usize> = chain.joints.iter().map(|j| j.node).collect::<Option<_>>()?;
    let before: Vec<usize> = chain
        .metacarpal
        .iter()
        .map(|m| m.node)
        .chain(chain.wrist.iter().map(|w| w.node))
        .collect();
    Some((nodes, before))
}

/// A vertex of a finger: arc position, distance from the axis, influences.
pub struct FingerVertex<'a> {
    pub position: DVec3,
    pub u: f64,
    pub radial: f64,
    pub influences: &'a [(usize, f64)],
}

/// The vertices of `weights` near `axis`, each position once: those with any
/// weight on `nodes` or `before`, within the finger's radius of the axis (see
/// the module notes).
pub fn finger_vertices<'a>(
    axis: &FingerAxis,
    weights: &'a SkinWeights,
    nodes: &[usize],
    before: &[usize],
) -> Vec<FingerVertex<'a>> {
    finger_vertices_with(axis, weights, nodes, before, None)
}

/// [`finger_vertices`] with some vertices' influences replaced by
/// `overrides` ((primitive, vertex) -> influences: weights carried to moved
/// joints).
pub fn finger_vertices_with<'a>(
    axis: &FingerAxis,
    weights: &'a SkinWeights,
    nodes: &[usize],
    before: &[usize],
    overrides: Option<&'a Remapped>,
) -> Vec<FingerVertex<'a>> {
    let mut seen = FxHashSet::default();
    let mut out = Vec::new();
    let wanted = NodeMask::of(nodes, before);
    for (pi, p) in weights.primitives.iter().enumerate() {
        for (v, (pos, painted)) in p.rest.iter().zip(&p.influences).enumerate() {
            let infl: &'a [(usize, f64)] = match overrides.and_then(|o| o.get(&(pi, v))) {
                Some(carried) => carried,
                None => painted,
            };
            if !wanted.any(infl) {
                continue;
            }
            if !seen.insert(pos.to_array().map(|x| (x + 0.0).to_bits())) {
                continue;
            }
            let (u, radial) = axis.locate(*pos);
            out.push(FingerVertex {
                position: *pos,
                u,
                radial,
                influences: infl,
            });
        }
    }
    let radius = finger_radius(&out, nodes.first().copied());
    out.retain(|v| v.radial <= radius);
    out
}

/// Every vertex of `weights` near `axis` as (primitive, vertex, arc position):
/// those with any weight on `nodes` or `before`, within the finger's radius
/// of the axis; split-seam copies included (each is written in a fix).
pub fn finger_vertices_at(
    axis: &FingerAxis,
    weights: &SkinWeights,
    nodes: &[usize],
    before: &[usize],
) -> Vec<(usize, usize, f64)> {
    let mut all = Vec::new();
    let mut located = Vec::new();
    let wanted = NodeMask::of(nodes, before);
    for (pi, p) in weights.primitives.iter().enumerate() {
        for (v, (pos, infl)) in p.rest.iter().zip(&p.influences).enumerate() {
            if wanted.any(infl) {
                let (u, radial) = axis.locate(*pos);
                all.push((pi, v, u));
                located.push(FingerVertex {
                    position: *pos,
                    u,
                    radial,
                    influences: infl,
                });
            }
        }
    }
    let radius = finger_radius(&located, nodes.first().copied());
    all.into_iter()
        .zip(&located)
        .filter(|(_, f)| f.radial <= radius)
        .map(|(a, _)| a)
        .collect()
}

/// The nodes of a finger and those before it, as a mask indexed by node: one
/// look-up per influence instead of a search of both lists.
struct NodeMask(Vec<bool>);

impl NodeMask {
    fn of(nodes: &[usize], before: &[usize]) -> NodeMask {
        let len = nodes.iter().chain(before).max().map_or(0, |&m| m + 1);
        let mut mask = vec![false; len];
        for &n in nodes.iter().chain(before) {
            mask[n] = true;
        }
        NodeMask(mask)
    }

    /// True when any of `influences` is on one of the nodes.
    fn any(&self, influences: &[(usize, f64)]) -> bool {
        influences
            .iter()
            .any(|(n, _)| self.0.get(*n).copied().unwrap_or(false))
    }
}

/// 1.5 times the median distance from the axis of the vertices whose largest
/// weight is on `mcp`; infinite when there are none.
fn finger_radius(vertices: &[FingerVertex<'_>], mcp: Option<usize>) -> f64 {
    let mut r: Vec<f64> = vertices
        .iter()
        .filter(|v| v.influences.first().map(|x| x.0) == mcp)
        .map(|v| v.radial)
        .collect();
    if r.is_empty() {
        return f64::INFINITY;
    }
    r.sort_by(f64::total_cmp);
    1.5 * r[r.len() / 2]
}

/// How far the finger's skin reaches past its last joint (DIP; the thumb's
/// IP), along the last segment's direction: the farthest projection of the
/// vertices that carry at least half their weight on the last bone (the last
/// joint's node and the tip's). `None` for a chain without a tip or nodes, or
/// when no vertex is found.
pub fn skin_end(chain: &FingerChain, weights: &SkinWeights) -> Option<f64> {
    if !chain.has_tip {
        return None;
    }
    let (nodes, before) = finger_nodes(chain)?;
    let points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let axis = FingerAxis::new(&points, true)?;
    let n = points.len();
    let (dip, tip) = (points[n - 2], points[n - 1]);
    let dir = (tip - dip).normalize_or_zero();
    let vertices = finger_vertices(&axis, weights, &nodes, &before);
    reaches(&vertices, &nodes[n - 2..], dip, dir).max_by(f64::total_cmp)
}

/// How far each of `vertices` that carries at least half its weight on the
/// nodes `last` (a finger's last bone) lies past `from` along `dir`.
fn reaches<'v>(
    vertices: &'v [FingerVertex<'_>],
    last: &'v [usize],
    from: DVec3,
    dir: DVec3,
) -> impl Iterator<Item = f64> + 'v {
    vertices
        .iter()
        .filter(move |v| {
            v.influences
                .iter()
                .filter(|(node, _)| last.contains(node))
                .map(|x| x.1)
                .sum::<f64>()
                >= 0.5
        })
        .map(move |v| (v.position - from).dot(dir))
}

/// Where the mesh ends along a tipless finger's last bone: how far past the
/// last joint (DIP; the thumb's IP) the skin reaches, along the last
/// segment's direction, or why no clear end was found.
///
/// The vertices are those within the finger's radius of its axis (the axis
/// runs on two last segments past the last joint) that carry at least half
/// their weight on the last joint's node; the reach is the farthest
/// projection of them along the last segment. It is a clear end when at
/// least [`MESH_END_VERTICES`] such vertices are found and the reach is
/// between [`MESH_END_RANGE`] times the last segment (PIP to DIP; the thumb's
/// MCP to IP): a human distal phalanx with its pulp is 0.86-1.09 times its
/// middle phalanx, the thumb's 0.86 times its proximal (the means of
/// Buryanov & Kotiuk 2010's 66 adults: index (15.82 + 3.84) / 22.38, little
/// (15.96 + 3.73) / 18.11, thumb (21.67 + 5.67) / 31.57), so a reach far
/// outside that is a mesh that does not end at the finger (a glove, a
/// mitten, a hand merged with its sleeve), not a fingertip. O(V m).
pub fn mesh_end(chain: &FingerChain, weights: &SkinWeights) -> Result<f64, String> {
    if chain.has_tip {
        return Err("the chain has a tip node".to_string());
    }
    let (nodes, before) = finger_nodes(chain).ok_or("its joints have no nodes")?;
    let mut points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let n = points.len();
    if n < 2 {
        return Err("the chain has fewer than two joints".to_string());
    }
    let (prev, last) = (points[n - 2], points[n - 1]);
    let segment = prev.distance(last);
    if !(segment.is_finite() && segment > 0.0) {
        return Err("its last segment has zero length".to_string());
    }
    let dir = (last - prev) / segment;
    points.push(last + 2.0 * segment * dir);
    let axis = FingerAxis::new(&points, true).ok_or("its axis is degenerate")?;
    let vertices = finger_vertices(&axis, weights, &nodes, &before);
    let reach: Vec<f64> = reaches(&vertices, &nodes[n - 1..], last, dir).collect();
    let far = reach.iter().copied().max_by(f64::total_cmp);
    match far {
        Some(r) if reach.len() >= MESH_END_VERTICES => {
            let (lo, hi) = MESH_END_RANGE;
            if r >= lo * segment && r <= hi * segment {
                Ok(r)
            } else {
                Err(format!(
                    "the skin weighted to its last bone reaches {} times the segment before \
                     it, outside {lo}-{hi} times",
                    crate::format::num(r / segment, 2)
                ))
            }
        }
        _ => Err(format!(
            "{} vertices carry half their weight on its last bone (at least \
             {MESH_END_VERTICES} are needed)",
            reach.len()
        )),
    }
}

/// Fewest vertices on a tipless finger's last bone for [`mesh_end`].
pub const MESH_END_VERTICES: usize = 8;
/// The reach of a clear mesh end, in last segments ([`mesh_end`]).
pub const MESH_END_RANGE: (f64, f64) = (0.25, 1.5);

/// Where the shares `samples` (arc position, share of the distal side) cross
/// 1/2: the samples are averaged in bins `bin` wide along the finger (so a
/// ring of vertices, whose vertices' shares straddle its mean, counts as one
/// sample), the bins' means are fitted by the closest non-decreasing sequence
/// (pool-adjacent-violators, weighted by the bins' counts), and the crossing
/// is interpolated between the two neighbouring bins where the fit passes
/// 1/2: the last bin of the last pooled block below 1/2 and the first bin of
/// the first block at or above it, at their centres (mean arc positions),
/// by the fitted values (the blocks' means). A long pooled block (a
/// violation far from the crossing) so moves the crossing no further than
/// its own end. `None` without a crossing (all on one side). O(n log n).
pub fn crossing(samples: &mut [(f64, f64)], bin: f64) -> Option<f64> {
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let index = |u: f64| if bin > 0.0 { (u / bin).floor() } else { u };
    // Bins: (sum of shares, count, sum of u), one per bin index met.
    let mut bins: Vec<(f64, f64, f64)> = Vec::new();
    let mut last = None;
    for &(u, s) in samples.iter() {
        if last != Some(index(u)) {
            bins.push((0.0, 0.0, 0.0));
            last = Some(index(u));
        }
        if let Some(b) = bins.last_mut() {
            *b = (b.0 + s, b.1 + 1.0, b.2 + u);
        }
    }
    // Pool adjacent violators over the bins: (sum s, count, centre of its
    // first bin, centre of its last bin).
    let mut blocks: Vec<(f64, f64, f64, f64)> = Vec::new();
    for b in bins {
        let c = b.2 / b.1;
        blocks.push((b.0, b.1, c, c));
        while blocks.len() >= 2 {
            let (y, x) = (blocks[blocks.len() - 1], blocks[blocks.len() - 2]);
            if x.0 / x.1 <= y.0 / y.1 {
                break;
            }
            blocks.pop();
            let last = blocks.len() - 1;
            blocks[last] = (x.0 + y.0, x.1 + y.1, x.2, y.3);
        }
    }
    let mean = |b: &(f64, f64, f64, f64)| b.0 / b.1;
    let i = blocks.iter().position(|b| mean(b) >= 0.5)?;
    if i == 0 {
        return None;
    }
    let (lo, hi) = (blocks[i - 1], blocks[i]);
    let t = (0.5 - mean(&lo)) / (mean(&hi) - mean(&lo));
    Some(lo.3 + t * (hi.2 - lo.3))
}

/// Fewer finger vertices than this around a joint cannot carry its bend: a
/// skin that coarse (a vertex or two per bone) has no blend for a moved
/// joint to take with it, and no bend to check it by.
pub const CARRY_VERTICES: usize = 8;

/// A vertex weighted this much to another finger's bones is shared with it.
const SHARED_WEIGHT: f64 = 0.2;

/// Why the skin weights of `chain` cannot follow its joint `joint` when a
/// fix moves it (`--fix` moves a finger's weights with its joints): too few
/// vertices around it (within half the way to each neighbouring joint,
/// [`CARRY_VERTICES`]), or more than a tenth of them
/// weighted at least [`SHARED_WEIGHT`] to the bones of another finger
/// (`others`: the nodes of the rig's other fingers), whose skin would move
/// too. `None` when they can follow, and when the finger has no weighted
/// vertex at all (nothing to carry). O(V m).
pub fn cannot_carry(
    chain: &FingerChain,
    weights: &SkinWeights,
    others: &[usize],
    joint: Joint,
) -> Option<String> {
    let (nodes, before) = finger_nodes(chain)?;
    let points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let axis = FingerAxis::new(&points, chain.has_tip)?;
    let k = chain.joints.iter().position(|j| j.joint == joint)?;
    let vertices = finger_vertices(&axis, weights, &nodes, &before);
    if vertices.is_empty() {
        return None;
    }
    let lo = if k == 0 {
        axis.start()
    } else {
        axis.joint(k - 1)
    };
    let hi = if k + 1 < nodes.len() {
        axis.joint(k + 1)
    } else {
        axis.arcs[axis.arcs.len() - 1] - axis.joint_arcs[0]
    };
    // Around the joint: half the way to each neighbour, the span whose
    // weights a move carries (the web, shared between fingers, lies further
    // back, at the MCP's side of the proximal phalanx).
    let c = axis.joint(k);
    let (lo, hi) = (c - 0.5 * (c - lo), c + 0.5 * (hi - c));
    let near: Vec<&FingerVertex<'_>> = vertices.iter().filter(|v| v.u >= lo && v.u <= hi).collect();
    if near.len() < CARRY_VERTICES {
        return Some(format!(
            "{} vertices around it, too few to carry a bend (a skin of a vertex or two per bone)",
            near.len()
        ));
    }
    let shared = near
        .iter()
        .filter(|v| {
            v.influences
                .iter()
                .filter(|(n, _)| others.contains(n))
                .map(|(_, w)| w)
                .sum::<f64>()
                >= SHARED_WEIGHT
        })
        .count();
    (10 * shared > near.len()).then(|| {
        format!(
            "{shared} of its {} vertices are weighted to another finger too, whose skin would move with it",
            near.len()
        )
    })
}

/// The bend at every joint of `chain` that has a bone on both sides (the
/// MCP only with a metacarpal or wrist bone), flagged beyond `tolerance`
/// (rig units). Empty without nodes or a usable axis.
pub fn bends(chain: &FingerChain, weights: &SkinWeights, tolerance: f64) -> Vec<Bend> {
    bends_with(chain, weights, tolerance, None)
}

/// [`bends`] with some vertices' influences replaced by `overrides`
/// ([`finger_vertices_with`]): where carried weights would bend the skin.
pub fn bends_with(
    chain: &FingerChain,
    weights: &SkinWeights,
    tolerance: f64,
    overrides: Option<&Remapped>,
) -> Vec<Bend> {
    let Some((nodes, before)) = finger_nodes(chain) else {
        return Vec::new();
    };
    let points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let Some(axis) = FingerAxis::new(&points, chain.has_tip) else {
        return Vec::new();
    };
    let vertices = finger_vertices_with(&axis, weights, &nodes, &before, overrides);
    let last = nodes.len() - usize::from(chain.has_tip);
    let first = if before.is_empty() { 1 } else { 0 };
    let mut out = Vec::new();
    for k in first..last {
        let lo = if k == 0 {
            axis.start()
        } else {
            axis.joint(k - 1)
        };
        let hi = if k + 1 < nodes.len() {
            axis.joint(k + 1)
        } else {
            axis.arcs[axis.arcs.len() - 1] - axis.joint_arcs[0]
        };
        let distal = &nodes[k..];
        let mut samples: Vec<(f64, f64)> = vertices
            .iter()
            .filter(|v| v.u >= lo && v.u <= hi)
            .filter_map(|v| {
                let (mut d, mut p) = (0.0, 0.0);
                for &(n, w) in v.influences {
                    if distal.contains(&n) {
                        d += w;
                    } else if nodes[..k].contains(&n) || before.contains(&n) {
                        p += w;
                    }
                }
                (d + p >= 0.5).then(|| (v.u, d / (d + p)))
            })
            .collect();
        let count = samples.len();
        let at = crossing(&mut samples, BIN * axis.joint(nodes.len() - 1));
        let offset = at.map(|u| u - axis.joint(k));
        let blend = at.and_then(|c| {
            let inside = samples
                .iter()
                .filter(|(_, s)| *s > BLEND_EDGE && *s < 1.0 - BLEND_EDGE)
                .map(|(u, _)| u - c);
            let (lo, hi) = inside.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
            (lo.is_finite() && hi.is_finite()).then_some((lo.min(0.0), hi.max(0.0)))
        });
        out.push(Bend {
            joint: chain.joints[k].joint,
            offset,
            at: at.map(|u| axis.point(u)),
            vertices: count,
            flagged: k > 0 && offset.is_some_and(|o| o.abs() > tolerance),
            blend,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_crossing_of_smooth_hard_and_noisy_shares() {
        // Linear from 0 at u = 0 to 1 at u = 10: crosses 1/2 at 5 (by hand).
        let mut s: Vec<(f64, f64)> = (0..=10).map(|i| (i as f64, i as f64 / 10.0)).collect();
        assert!((crossing(&mut s, 0.1).unwrap() - 5.0).abs() < 1e-12);
        // Hard weights: 0 up to u = 4, 1 from u = 6: midway, 5.
        let mut s = vec![(0.0, 0.0), (2.0, 0.0), (4.0, 0.0), (6.0, 1.0), (8.0, 1.0)];
        assert!((crossing(&mut s, 0.1).unwrap() - 5.0).abs() < 1e-12);
        // A dip out of order pools: (3, 0.6), (4, 0.4) pool to 0.5 over
        // 3-4; the fit rises from 0.2 at 2 to 0.5 at the pooled block's first
        // bin, 3, and reaches 1/2 there.
        let mut s = vec![(1.0, 0.1), (2.0, 0.2), (3.0, 0.6), (4.0, 0.4), (5.0, 0.9)];
        assert!((crossing(&mut s, 0.1).unwrap() - 3.0).abs() < 1e-12);
        // A violation far from the crossing pools a long block below 1/2
        // (0.06 at 1, 0.0 at 2-6); the crossing lies between that block's
        // last bin (6, fit 0.01) and the next (8, 0.81): 6 + (0.49 / 0.8) x 2
        // = 7.225, not pulled back towards the block's centre.
        let mut s = vec![
            (1.0, 0.06),
            (2.0, 0.0),
            (3.0, 0.0),
            (4.0, 0.0),
            (5.0, 0.0),
            (6.0, 0.0),
            (8.0, 0.81),
        ];
        let x = crossing(&mut s, 0.1).unwrap();
        assert!((x - 7.225).abs() < 1e-12, "{x}");
        // A ring of vertices at 2.1-2.3 with shares 0.2-0.6 is one sample of
        // 0.4 at 2.2 in a bin 1 wide; the next ring, 0.8 at 3.05: crossing at
        // 2.2 + (0.1 / 0.4) x 0.85 = 2.4125.
        let mut s = vec![(2.1, 0.2), (2.2, 0.4), (2.3, 0.6), (3.0, 0.8), (3.1, 0.8)];
        let x = crossing(&mut s, 1.0).unwrap();
        assert!((x - 2.4125).abs() < 1e-12, "{x}");
        // All on one side: no crossing.
        assert!(crossing(&mut [(0.0, 0.7), (1.0, 0.9)], 0.1).is_none());
        assert!(crossing(&mut [(0.0, 0.1), (1.0, 0.2)], 0.1).is_none());
        assert!(crossing(&mut [], 0.1).is_none());
    }

    #[test]
    fn the_axis_measures_from_the_mcp_and_extends_before_it() {
        let j = [
            DVec3::ZERO,
            DVec3::new(0.0, 4.0, 0.0),
            DVec3::new(0.0, 6.0, 0.0),
        ];
        let a = FingerAxis::new(&j, true).unwrap();
        assert_eq!(a.start(), -4.0);
        assert_eq!(a.joint(2), 6.0);
        assert_eq!(a.locate(DVec3::new(1.0, -2.0, 0.0)), (-2.0, 1.0));
        assert_eq!(a.point(5.0), DVec3::new(0.0, 5.0, 0.0));
        // Without a tip the axis runs one last segment past the last joint.
        let a = FingerAxis::new(&j, false).unwrap();
        assert_eq!(a.locate(DVec3::new(0.0, 7.5, 0.0)).0, 7.5);
    }
}
