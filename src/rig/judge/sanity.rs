//! Two checks of a rig's geometry before its judgement is trusted, both from
//! its chains and skin weights:
//!
//! - **Joints far outside the mesh they skin.** A finger joint lies inside its
//!   finger, so within the finger's thickness of the nearest vertex of the
//!   skin. A joint farther from every skinned vertex than its finger is long
//!   (and than a twentieth of the mesh's bounding-box diagonal) is far outside:
//!   a Rigify-like hand whose palm bones are 2.68 m long puts its finger joints
//!   2.2 m outside its 26 cm mesh. Its bends are then "not found", and every
//!   figure measures a skeleton that does not match its skin.
//! - **A rest pose that is not the bind pose.** The audit measures the nodes'
//!   rest (world) transforms W; the skin was bound where its inverse bind
//!   matrices B say, at B⁻¹. A joint p = W's translation lies, in the bind
//!   pose, at M⁻¹ p with M = W B (the skin matrix, identity when the two
//!   poses agree). Where a finger's segments are not as long in the two poses
//!   (by more than 1% and 0.1 mm), the warning names the nodes and both lengths.
//!   A rest pose that only turns the joints (a posed frame) keeps every length
//!   and is not warned about: the audit's figures are lengths. When the bind
//!   pose's fingers are of a plausible length, the disagreement, not the file's
//!   unit, is what makes the fingers too long or short, and the unit warning is
//!   left out ([`super::audited`]).
//!
//! Cost: O(joints x vertices) for the first (each joint stops at its first
//! vertex within reach, so only far joints scan the whole mesh), O(joints x
//! skin joints) for the second.

use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::{DMat4, DVec3};

/// A length in words: metres (2 decimals) from 0.1 m up, else mm (1 decimal).
fn length_words(x: f64) -> String {
    if x.abs() >= 0.1 {
        format!("{} m", crate::format::num(x, 2))
    } else {
        format!("{} mm", crate::format::num(x * 1000.0, 1))
    }
}

/// `name (node i)` of a chain's joint, or its name alone without a node.
fn joint_words(name: &str, node: Option<usize>) -> String {
    match node {
        Some(i) => format!("{name} (node {i})"),
        None => name.to_string(),
    }
}

/// The warning when finger joints lie far outside the mesh they skin (see the
/// module doc), naming the farthest joint of each such finger, its distance,
/// and the mesh's size; `None` when every joint is within reach or the rig
/// has no skinned vertex.
pub(crate) fn joints_outside_mesh(chains: &[FingerChain], w: &SkinWeights) -> Option<String> {
    let vertices: Vec<DVec3> = w
        .primitives
        .iter()
        .flat_map(|p| p.rest.iter().copied())
        .filter(|v| v.is_finite())
        .collect();
    let first = *vertices.first()?;
    let (lo, hi) = vertices
        .iter()
        .fold((first, first), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
    let size = hi - lo;
    let floor = size.length() / 20.0;
    let mut far = Vec::new();
    for chain in chains {
        let points: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
        if points.iter().any(|p| !p.is_finite()) {
            continue;
        }
        let length: f64 = points.windows(2).map(|s| s[0].distance(s[1])).sum();
        let reach = length.max(floor);
        // The farthest joint of the finger beyond reach, with its distance.
        let mut worst: Option<(usize, f64)> = None;
        for (k, p) in points.iter().enumerate() {
            let reach2 = reach * reach;
            let mut nearest2 = f64::INFINITY;
            for v in &vertices {
                let d2 = p.distance_squared(*v);
                if d2 < nearest2 {
                    nearest2 = d2;
                    if d2 <= reach2 {
                        break;
                    }
                }
            }
            if nearest2 > reach2 && worst.is_none_or(|(_, d)| nearest2.sqrt() > d) {
                worst = Some((k, nearest2.sqrt()));
            }
        }
        if let Some((k, d)) = worst {
            let j = &chain.joints[k];
            far.push(format!(
                "{}'s {} {} lies {} from the nearest vertex (the finger is {} long)",
                chain.label(),
                j.joint.name(),
                joint_words(&j.name, j.node),
                length_words(d),
                length_words(length)
            ));
        }
    }
    if far.is_empty() {
        return None;
    }
    Some(format!(
        "finger joints lie far outside the mesh they skin, which spans {} x {} x {}: {}. A \
         joint sits inside its finger, within the finger's thickness of the skin, so these \
         bones do not match their mesh: check the bones above them (a palm or hand bone \
         far too long, a wrong parent or offset) and the armature's transform; their bends \
         cannot be found and every figure measures the bones, not the hand the mesh shows",
        length_words(size.x),
        length_words(size.y),
        length_words(size.z),
        far.join("; ")
    ))
}

/// What [`rest_not_bind`] found: the warning, and each chain's length (MCP to
/// its last point) in the bind pose, to tell whether the unit is off too.
pub(crate) struct RestNotBind {
    pub warning: String,
    pub bind_lengths: Vec<f64>,
}

/// The skin matrix M = W B of `node`: from the first skin that lists it.
fn skin_matrix(w: &SkinWeights, node: usize) -> Option<DMat4> {
    w.skins.values().find_map(|(nodes, matrices)| {
        nodes
            .iter()
            .position(|&n| n == node)
            .and_then(|k| matrices.get(k).copied())
    })
}

/// The warning when the nodes' rest pose gives the fingers' segments other
/// lengths than the skin's bind pose does (see the module doc); `None` when
/// every segment agrees, or no finger joint is skinned.
pub(crate) fn rest_not_bind(chains: &[FingerChain], w: &SkinWeights) -> Option<RestNotBind> {
    let mut found = Vec::new();
    let mut bind_lengths = Vec::new();
    for chain in chains {
        // A joint not in any skin (an unskinned tip leaf) moves with the
        // skinned joint before it.
        let mut last: Option<DMat4> = None;
        let mut bind = Vec::new();
        for j in &chain.joints {
            let m = j.node.and_then(|n| skin_matrix(w, n)).or(last);
            last = m;
            let inv = m
                .filter(|m| m.determinant().abs() > 1e-12)
                .map(|m| m.inverse());
            bind.push(inv.map(|inv| inv.transform_point3(j.position)));
        }
        let Some(bind): Option<Vec<DVec3>> = bind.into_iter().collect() else {
            continue;
        };
        if bind.iter().any(|p| !p.is_finite()) {
            continue;
        }
        bind_lengths.push(bind.windows(2).map(|s| s[0].distance(s[1])).sum::<f64>());
        // The segment whose two lengths differ most.
        let worst = (1..bind.len())
            .map(|k| {
                let rest = chain.joints[k - 1]
                    .position
                    .distance(chain.joints[k].position);
                let bound = bind[k - 1].distance(bind[k]);
                (k, rest, bound)
            })
            .filter(|&(_, r, b)| (r - b).abs() > (0.01 * r.max(b)).max(1e-4))
            .max_by(|a, b| (a.1 - a.2).abs().total_cmp(&(b.1 - b.2).abs()));
        if let Some((k, rest, bound)) = worst {
            let (a, b) = (&chain.joints[k - 1], &chain.joints[k]);
            found.push(format!(
                "{}'s {}-{} segment, {} to {}, is {} long in the nodes' rest pose and {} in the \
                 bind pose ({}x)",
                chain.label(),
                a.joint.name(),
                b.joint.name(),
                joint_words(&a.name, a.node),
                joint_words(&b.name, b.node),
                length_words(rest),
                length_words(bound),
                crate::format::trimmed(rest / bound, 2)
            ));
        }
    }
    if found.is_empty() {
        return None;
    }
    Some(RestNotBind {
        warning: format!(
            "the nodes' rest pose is not the skin's bind pose (their world transforms disagree \
             with the inverse bind matrices): {}. The audit measures the rest pose; if the bind \
             pose is the hand the mesh was made on, check the nodes' transforms and the \
             armature's scale against it, and re-export with the pose applied as the rest pose",
            found.join("; ")
        ),
        bind_lengths,
    })
}
