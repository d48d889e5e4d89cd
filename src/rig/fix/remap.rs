//! Moving a finger's skin weights with its joints in `--fix`, so the skin
//! bends where the moved joint now is (see [`crate::rig::judge::bend`] for the bend).
//!
//! **Method.** Each finger vertex has an arc position u along the finger's
//! axis (the old joints' polyline, extended before the MCP; the moved joints
//! lie on it). A piecewise-linear map phi takes the new layout of the joints
//! to the old one: around each joint k, within r_k of it, phi(u) = u - (U'_k -
//! U_k) (a translation, so the bend keeps its distance to its joint), and
//! linear between those pieces (the segments stretch or shrink); the axis'
//! start and whatever lies past the tip stay. r_k is a quarter of the shorter
//! of the joint's neighbouring segments, old or new. A vertex at u takes the
//! weights the old rig had at phi(u) on its own side of the finger: the
//! vertices around the axis are sorted into 8 sectors of 45 degrees (angles
//! about the MCP-to-tip direction), and within the vertex's sector the old
//! weights are interpolated linearly in u between the two vertices on either
//! side of phi(u) (the nearest one past the sector's ends; by inverse squared
//! distance from the 4 nearest vertices when the sector is empty). A vertex
//! whose phi(u) = u keeps its own weights exactly. The influences are merged
//! by node, cut to the slots the vertex has (4 per JOINTS_n/WEIGHTS_n set,
//! largest kept) and renormalised.
//!
//! **The rest shape is kept.** A vertex rests at sum_j w_j M_j v; when every
//! node it is weighted to, before and after, has the same rest skin matrix M
//! (the usual case: the node pose is the bind pose, M = I), it rests at M v
//! whatever its weights. A vertex for which that does not hold keeps its
//! weights, with a note. The weights are written in place into the
//! primitive's JOINTS_n / WEIGHTS_n accessors (floats summing to 1 in f32,
//! normalised bytes or shorts summing to their maximum exactly), so no
//! accessor is added.

use super::accessor;
use crate::rig::judge::bend::{self, FingerAxis, finger_nodes};
use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::{DMat4, DVec3};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};

/// A finger whose joints move: the chain before, and every joint's new position.
pub struct FingerMove<'a> {
    pub chain: &'a FingerChain,
    pub new_positions: Vec<DVec3>,
}

/// New influences by node for vertices of `SkinWeights::primitives`: (primitive, vertex) -> influences.
pub type Remapped = BTreeMap<(usize, usize), Vec<(usize, f64)>>;

/// The map phi from the new joint layout to the old, as knots (new u, old u),
/// increasing in both; `None` when the joints' order would not be kept.
fn knots(old: &[f64], new: &[f64], start: f64, end: Option<f64>) -> Option<Vec<(f64, f64)>> {
    let n = old.len();
    let mut k = vec![(start, start)];
    for i in 0..n {
        let mut gap = f64::INFINITY;
        for (lo, hi) in [
            (i.checked_sub(1), Some(i)),
            (Some(i), (i + 1 < n).then_some(i + 1)),
        ] {
            if let (Some(a), Some(b)) = (lo, hi) {
                gap = gap.min(old[b] - old[a]).min(new[b] - new[a]);
            }
        }
        if i == 0 {
            gap = gap.min(old[0] - start).min(new[0] - start);
        }
        let r = 0.25 * gap;
        if r.is_nan() || r <= 0.0 {
            return None;
        }
        k.extend([
            (new[i] - r, old[i] - r),
            (new[i], old[i]),
            (new[i] + r, old[i] + r),
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
        let old: Vec<f64> = (0..points.len()).map(|k| axis.joint(k)).collect();
        let new: Vec<f64> = m.new_positions.iter().map(|p| axis.locate(*p).0).collect();
        if old.iter().zip(&new).all(|(a, b)| (a - b).abs() < 1e-12) {
            continue;
        }
        let end = (!chain.has_tip).then(|| axis.arcs[axis.arcs.len() - 1] - axis.joint_arcs[0]);
        let Some(knots) = knots(&old, &new, axis.start(), end) else {
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

/// A vertex of a primitive and its new influences by node.
type VertexInfluences<'a> = (usize, &'a Vec<(usize, f64)>);

/// Writes the new influences into their primitives' JOINTS_n / WEIGHTS_n
/// accessors in the merged buffer. A primitive whose accessors cannot be
/// written in place (shared with another skin's mesh, sparse, or a joint slot
/// its JOINTS type cannot hold) keeps its weights, with a note.
pub fn write(
    json: &mut Value,
    bin: &mut [u8],
    weights: &SkinWeights,
    remapped: &Remapped,
) -> Vec<String> {
    let mut notes = Vec::new();
    let mut by_prim: BTreeMap<usize, Vec<VertexInfluences<'_>>> = BTreeMap::new();
    for ((pi, v), infl) in remapped {
        by_prim.entry(*pi).or_default().push((*v, infl));
    }
    let skins_of_mesh = mesh_skins(json);
    for (pi, list) in by_prim {
        let prim = &weights.primitives[pi];
        let at = format!("/meshes/{}/primitives/{}", prim.mesh, prim.primitive);
        let shared = prim.sets.iter().any(|&(j, w)| {
            users(json, j).into_iter().chain(users(json, w)).any(|m| {
                skins_of_mesh
                    .get(&m)
                    .is_none_or(|s| s.len() != 1 || !s.contains(&Some(prim.skin)))
            })
        });
        let spans: Option<Vec<(accessor::Span, accessor::Span)>> = prim
            .sets
            .iter()
            .map(|&(j, w)| {
                Some((
                    accessor::span(json, j, bin.len())?,
                    accessor::span(json, w, bin.len())?,
                ))
            })
            .collect();
        let Some(spans) = spans.filter(|_| !shared) else {
            notes.push(format!(
                "{at}: its weights are shared with another skin's mesh or not stored plainly; \
                 they are not moved with the joints"
            ));
            continue;
        };
        let Some((joints, _)) = weights.skins.get(&prim.skin) else {
            continue;
        };
        let mut unwritable = 0usize;
        for (v, infl) in list {
            let slots: Option<Vec<(u32, f64)>> = infl
                .iter()
                .map(|&(n, w)| joints.iter().position(|&j| j == n).map(|s| (s as u32, w)))
                .collect();
            let Some(slots) = slots.filter(|s| {
                s.iter()
                    .all(|&(j, _)| spans.iter().all(|(js, _)| j <= js.uint_max()))
            }) else {
                unwritable += 1;
                continue;
            };
            write_vertex(bin, &spans, v, &slots);
        }
        if unwritable > 0 {
            notes.push(format!(
                "{at}: {unwritable} vertices keep their weights (a joint their JOINTS type cannot hold)"
            ));
        }
        for (&(j, w), (js, ws)) in prim.sets.iter().zip(&spans) {
            accessor::refresh_bounds(json, j, js, bin);
            accessor::refresh_bounds(json, w, ws, bin);
        }
    }
    notes
}

/// For each mesh, the skins of the nodes that draw it (none for an unskinned one).
fn mesh_skins(json: &Value) -> BTreeMap<usize, BTreeSet<Option<usize>>> {
    let mut out: BTreeMap<usize, BTreeSet<Option<usize>>> = BTreeMap::new();
    for n in json["nodes"].as_array().into_iter().flatten() {
        if let Some(m) = n["mesh"].as_u64() {
            out.entry(m as usize)
                .or_default()
                .insert(n["skin"].as_u64().map(|s| s as usize));
        }
    }
    out
}

/// The meshes whose primitives use accessor `acc` as an attribute.
fn users(json: &Value, acc: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for (m, mesh) in json["meshes"].as_array().into_iter().flatten().enumerate() {
        for prim in mesh["primitives"].as_array().into_iter().flatten() {
            if prim["attributes"]
                .as_object()
                .into_iter()
                .flatten()
                .any(|(_, v)| v.as_u64() == Some(acc as u64))
            {
                out.push(m);
            }
        }
    }
    out
}

/// Writes one vertex's (joint slot, weight) list over its sets: largest
/// first, unused slots joint 0 weight 0, weights quantised so they sum to 1
/// exactly in the stored type.
fn write_vertex(
    bin: &mut [u8],
    spans: &[(accessor::Span, accessor::Span)],
    v: usize,
    slots: &[(u32, f64)],
) {
    let n = 4 * spans.len();
    let mut joints = vec![0u32; n];
    let mut w = vec![0.0f64; n];
    for (i, &(j, x)) in slots.iter().enumerate().take(n) {
        joints[i] = j;
        w[i] = x;
    }
    // All sets share one storage type in practice; quantise by the first's.
    let ws = spans[0].1;
    let stored: Vec<f64> = match (ws.component, ws.normalized) {
        (5121, true) => quantise(&w, 255.0),
        (5123, true) => quantise(&w, 65535.0),
        _ => {
            let mut f: Vec<f32> = w.iter().map(|&x| x as f32).collect();
            let sum: f32 = f.iter().sum();
            f[0] += 1.0 - sum;
            f.into_iter().map(f64::from).collect()
        }
    };
    for (s, (js, wspan)) in spans.iter().enumerate() {
        let range = 4 * s..4 * s + 4;
        js.write_uint(bin, v, &joints[range.clone()]);
        match (wspan.component, wspan.normalized) {
            (5126, _) => {
                let f: Vec<f32> = stored[range].iter().map(|&x| x as f32).collect();
                wspan.write_f32(bin, v, &f);
            }
            _ => {
                let u: Vec<u32> = stored[range].iter().map(|&x| x as u32).collect();
                wspan.write_uint(bin, v, &u);
            }
        }
    }
}

/// Integer parts of `w x max` summing to `max` exactly (largest remainders
/// rounded up), as raw stored values.
fn quantise(w: &[f64], max: f64) -> Vec<f64> {
    let scaled: Vec<f64> = w.iter().map(|x| x * max).collect();
    let mut out: Vec<f64> = scaled.iter().map(|x| x.floor()).collect();
    let mut left = (max - out.iter().sum::<f64>()).round() as i64;
    let mut order: Vec<usize> = (0..w.len()).collect();
    order.sort_by(|&a, &b| (scaled[b] - out[b]).total_cmp(&(scaled[a] - out[a])));
    for &i in order.iter().cycle().take(w.len() * 2) {
        if left <= 0 {
            break;
        }
        out[i] += 1.0;
        left -= 1;
    }
    out
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
        let k = knots(&old, &new, -40.0, None).unwrap();
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
        assert!(knots(&old, &[0.0, 70.0, 65.0, 85.0], -40.0, None).is_none());
    }

    #[test]
    fn quantised_weights_sum_to_the_maximum() {
        let q = quantise(&[0.5, 0.3, 0.2, 0.0], 255.0);
        assert_eq!(q.iter().sum::<f64>(), 255.0);
        assert_eq!(q, vec![128.0, 76.0, 51.0, 0.0]);
        let q = quantise(&[1.0 / 3.0; 3], 65535.0);
        assert_eq!(q.iter().sum::<f64>(), 65535.0);
    }
}
