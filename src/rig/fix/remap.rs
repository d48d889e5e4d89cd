//! Writing carried skin weights into a fixed copy: the new influences
//! ([`crate::rig::judge::carry`] computes them) go into each primitive's
//! JOINTS_n / WEIGHTS_n accessors in place (floats summing to 1 in f32,
//! normalised bytes or shorts summing to their maximum exactly), so no
//! accessor is added.

use super::accessor;
pub use crate::rig::judge::carry::{FingerMove, Remapped};
use crate::rig::read::weights::SkinWeights;
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};

/// For each moved joint of `m` (its node's name), how many vertices of
/// `carried` took weights other than their painted ones, each vertex counted
/// for the moved joint nearest it along the finger. O(changed x joints).
pub fn changed_per_joint(
    weights: &SkinWeights,
    m: &FingerMove<'_>,
    carried: &Remapped,
) -> Vec<(String, usize)> {
    let moved: Vec<(usize, glam::DVec3)> = m
        .chain
        .joints
        .iter()
        .zip(&m.new_positions)
        .enumerate()
        .filter(|(_, (rj, p))| rj.position.distance(**p) > 0.0)
        .map(|(k, (_, p))| (k, *p))
        .collect();
    let mut counts = vec![0usize; moved.len()];
    for ((pi, v), infl) in carried {
        let painted = &weights.primitives[*pi].influences[*v];
        let same = painted.len() == infl.len()
            && painted
                .iter()
                .zip(infl)
                .all(|(a, b)| a.0 == b.0 && (a.1 - b.1).abs() < 1e-6);
        if same {
            continue;
        }
        let at = weights.primitives[*pi].rest[*v];
        if let Some(i) = (0..moved.len())
            .min_by(|&a, &b| moved[a].1.distance(at).total_cmp(&moved[b].1.distance(at)))
        {
            counts[i] += 1;
        }
    }
    moved
        .iter()
        .zip(counts)
        .map(|((k, _), c)| (m.chain.joints[*k].name.clone(), c))
        .collect()
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
pub(super) fn write_vertex(
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
        _ => float_weights(&w).into_iter().map(f64::from).collect(),
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

/// Weights (summing to 1, largest first) as f32 that sum to 1 in f32: the
/// first takes what rounding left over.
pub(super) fn float_weights(w: &[f64]) -> Vec<f32> {
    let mut f: Vec<f32> = w.iter().map(|&x| x as f32).collect();
    let sum: f32 = f.iter().sum();
    if let Some(first) = f.first_mut() {
        *first += 1.0 - sum;
    }
    f
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
    fn quantised_weights_sum_to_the_maximum() {
        let q = quantise(&[0.5, 0.3, 0.2, 0.0], 255.0);
        assert_eq!(q.iter().sum::<f64>(), 255.0);
        assert_eq!(q, vec![128.0, 76.0, 51.0, 0.0]);
        let q = quantise(&[1.0 / 3.0; 3], 65535.0);
        assert_eq!(q.iter().sum::<f64>(), 65535.0);
    }
}
