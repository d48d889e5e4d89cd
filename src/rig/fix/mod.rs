//! `audit --fix`: a copy of a rig with the joints the audit's explanation
//! moves (see [`crate::rig::judge`]) where it puts them, and everything else
//! kept. Joints the judge holds (at their skin bend, or a move under 1 mm:
//! [`crate::rig::judge::Held`]) stay.
//!
//! For each finger the explanation's joints (MCP, PIP, DIP: the fewest that
//! bring the finger inside the X-rays' prediction intervals; with
//! `--only-outside` only those whose own standing is outside) move to their
//! suggested points on the rig's own chain; the tip and the other joints keep
//! their world positions. Only translations change: a moved node's local
//! translation becomes P'^-1 x (P' its parent's new world matrix, x the
//! target), and every later chain node is re-pinned where it was, so
//! descendants off the chain follow their parent. In a rig whose joints are
//! siblings (WebXR) each joint node moves alone. World rotations and scales
//! are untouched.
//!
//! The mesh's rest shape is kept exactly: a joint whose world matrix goes from
//! W to W' gets the inverse bind matrix B' = W'^-1 W B, so W' B' = W B and every
//! skinned vertex is where it was (up to the f32 the file stores). `audit
//! --fix` leaves the skin weights as painted (the judge keeps every moved
//! joint within 1 mm of where they bend the skin); given `weights`,
//! [`fix_with`] moves each moved finger's weights with its joints (`remap`).
//! Translation keys of moved
//! nodes are offset by their rest translation's change (`anim`);
//! channels with paths glTF does not define are reported and left alone.
//!
//! Inverse bind matrices, weights and keys are rewritten in place in their
//! accessors when nothing else uses them (else a copy is appended), so the
//! fix leaves no unused accessor and a second fix of the fixed copy, which
//! moves nothing, writes the same bytes. Everything else in the file's JSON
//! is kept. The output is one .glb (or a .gltf with its buffer embedded),
//! every buffer merged into one.

pub(crate) mod accessor;
pub(crate) mod anim;
pub mod moves;
pub(crate) mod remap;

use crate::dataset::DataError;
use crate::rig::judge::AuditedFinger;
use crate::rig::read::gltf::{GltfFile, buffers, inverse_binds, local_matrix, world_matrices};
use crate::rig::read::weights::SkinWeights;
use crate::rig::read::{RigJoint, anim as channels};
use base64::Engine;
use glam::{DMat4, DVec3};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::Path;

/// How a fix chooses the joints it moves.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FixOptions {
    /// Move only joints whose own standing is outside the prediction interval.
    pub only_outside: bool,
}

/// The outcome of a fix: the new file's bytes and what was done.
pub struct Fixed {
    pub bytes: Vec<u8>,
    /// (node name, distance moved), in chain order.
    pub moved: Vec<(String, f64)>,
    /// Remarks for the user (animations that drive moved joints, external images).
    pub warnings: Vec<String>,
    /// Each moved joint's node and how many of its finger's vertices took
    /// new weights nearest it (empty when the weights stay as painted).
    pub reweighted: Vec<(String, usize)>,
}

fn pad4(v: &mut Vec<u8>) {
    while !v.len().is_multiple_of(4) {
        v.push(0);
    }
}

/// Writes the fixed copy with the default options and without moving skin
/// weights. `dir` resolves external buffers; `glb` picks the container.
pub fn fix(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    dir: &Path,
    glb: bool,
) -> Result<Fixed, DataError> {
    fix_with(file, fingers, None, dir, glb, &FixOptions::default())
}

/// Writes the fixed copy; with `weights`, the moved fingers' skin weights
/// move with their joints.
///
/// In steps: the target of every chain node, the nodes moved there (parents
/// first), their new translations written into the JSON, every buffer merged
/// into one, new inverse bind matrices for the skins whose joints moved, the
/// moved nodes' translation keys, the moved fingers' weights, then the
/// output container.
pub fn fix_with(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    weights: Option<&SkinWeights>,
    dir: &Path,
    glb: bool,
    opts: &FixOptions,
) -> Result<Fixed, DataError> {
    let plan = targets(fingers, opts.only_outside);
    let (locals, world) = move_nodes(file, &plan.targets)?;
    let mut json = file.json.clone();
    // Node -> (old, new) local translation.
    let mut touched: BTreeMap<usize, (DVec3, DVec3)> = BTreeMap::new();
    for &(node, _) in &plan.targets {
        let old =
            local_matrix(&file.document.nodes().nth(node).ok_or_else(|| {
                DataError::whole_file(&file.label, format!("has no node {node}"))
            })?)
            .w_axis
            .truncate();
        let new = locals[node].w_axis.truncate();
        touched.insert(node, (old, new));
    }
    write_translations(&mut json, &touched);
    let (data, mut bin) = merge_buffers(file, &mut json, dir)?;
    rebind_skins(file, &mut json, &data, &mut bin, &world)?;
    let delta: BTreeMap<usize, (DVec3, DVec3)> = touched
        .iter()
        .filter(|(_, (old, new))| old != new)
        .map(|(&n, &(old, new))| (n, (old, new - old)))
        .collect();
    let mut warnings = anim::offset_translations(&mut json, &mut bin, &delta);
    let mut reweighted = Vec::new();
    if let Some(w) = weights {
        let mut remapped = remap::Remapped::new();
        for (i, new_positions, _) in &plan.fingers {
            let f = &fingers[*i];
            let m = remap::FingerMove::of(&f.chain, &f.bends, |joint| {
                f.chain
                    .joints
                    .iter()
                    .position(|rj| rj.joint == joint)
                    .map(|k| new_positions[k])
                    .filter(|p| {
                        f.chain
                            .joints
                            .iter()
                            .any(|rj| rj.joint == joint && rj.position != *p)
                    })
            });
            let (carried, _, notes) = crate::rig::judge::carry::carry_finger(
                w,
                &m,
                crate::rig::bend::BEND_TOLERANCE_MM / 1000.0,
            );
            warnings.extend(notes);
            reweighted.extend(remap::changed_per_joint(w, &m, &carried));
            remapped.extend(carried);
        }
        warnings.extend(remap::write(&mut json, &mut bin, w, &remapped));
    }
    let mut buffer = json!({"byteLength": bin.len()});
    if !glb {
        buffer["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bin)
        ));
    }
    if !bin.is_empty() {
        json["buffers"] = json!([buffer]);
    }
    warnings.extend(other_warnings(file));
    let bytes = container(file, &json, bin, glb)?;
    Ok(Fixed {
        bytes,
        moved: plan.moved,
        warnings,
        reweighted,
    })
}

/// A node and the world position it goes to.
type Target = (usize, DVec3);

/// What a fix moves.
struct Plan {
    /// Nodes and the world positions they go to.
    targets: Vec<Target>,
    /// The moved joints' (name, distance).
    moved: Vec<(String, f64)>,
    /// Fingers (index into the audited fingers) with a moved joint, every
    /// joint's new position, and where each moved joint's skin bends now.
    fingers: Vec<(usize, Vec<DVec3>, Vec<Option<DVec3>>)>,
}

/// Where each chain node goes: the joints the explanation moves to their
/// suggestions, and the chain's other nodes after a moved one pinned where
/// they are. A joint the judge holds ([`crate::rig::judge::Held`]: at its
/// skin bend, or a move under the tolerance) stays. With `only_outside`, a
/// joint moves only when its own standing is outside the prediction interval.
fn targets(fingers: &[AuditedFinger], only_outside: bool) -> Plan {
    let mut plan = Plan {
        targets: Vec::new(),
        moved: Vec::new(),
        fingers: Vec::new(),
    };
    for (i, f) in fingers.iter().enumerate() {
        let (chain, audit) = (&f.chain, &f.audit);
        let moves = |rj: &RigJoint| {
            audit
                .joint(rj.joint)
                .filter(|j| j.fix_moves() && !(only_outside && j.standing.is_consistent()))
        };
        if !chain.joints.iter().any(|rj| moves(rj).is_some()) {
            continue;
        }
        let mut after_moved = false;
        let mut positions = Vec::new();
        let mut anchors = Vec::new();
        for rj in &chain.joints {
            let m = moves(rj);
            positions.push(m.map_or(rj.position, |j| j.suggested));
            anchors.push(m.and_then(|_| {
                f.bends
                    .iter()
                    .find(|b| b.joint == rj.joint)
                    .and_then(|b| b.at)
            }));
            let Some(node) = rj.node else { continue };
            match m {
                Some(j) => {
                    plan.moved.push((rj.name.clone(), j.shift));
                    plan.targets.push((node, j.suggested));
                    after_moved = true;
                }
                // Pinned: a later chain node keeps its place when one before it moves.
                None if after_moved => plan.targets.push((node, rj.position)),
                None => {}
            }
        }
        plan.fingers.push((i, positions, anchors));
    }
    plan
}

/// Moves each node to its target (world position), parents first, by changing
/// its local translation only; returns the new local and world matrices.
/// Fails when the transform above a node is singular.
fn move_nodes(file: &GltfFile, targets: &[Target]) -> Result<(Vec<DMat4>, Vec<DMat4>), DataError> {
    let mut locals: Vec<DMat4> = file.document.nodes().map(|nd| local_matrix(&nd)).collect();
    let depth = |mut i: usize| {
        let mut d = 0;
        while let Some(p) = file.parent[i] {
            d += 1;
            i = p;
        }
        d
    };
    let mut order = targets.to_vec();
    order.sort_by_key(|&(node, _)| depth(node));
    let mut world = file.world.clone();
    for &(node, target) in &order {
        let up = file.parent[node].map_or(DMat4::IDENTITY, |p| world[p]);
        let det = up.determinant();
        let t = up.inverse().transform_point3(target);
        if !(det.is_finite() && det.abs() > 1e-300 && t.is_finite()) {
            return Err(DataError::whole_file(
                &file.label,
                format!(
                    "cannot move node {node} ('{}'): the transform above it is singular (a zero scale?); fix that first",
                    file.document
                        .nodes()
                        .nth(node)
                        .and_then(|n| n.name())
                        .unwrap_or("unnamed")
                ),
            ));
        }
        // Stored at the f32 precision glTF files keep (so a second fix reads
        // back exactly what it would write); the inverse bind matrices are
        // computed from the rounded translation.
        locals[node].w_axis = t.as_vec3().as_dvec3().extend(1.0);
        world = world_matrices(&file.parent, &locals).unwrap_or(world);
    }
    Ok((locals, world))
}

/// Writes new translations into the nodes' JSON (into `matrix` when a node
/// has one); `touched` maps a node to its (old, new) local translation.
fn write_translations(json: &mut Value, touched: &BTreeMap<usize, (DVec3, DVec3)>) {
    for (&node, (_, t)) in touched {
        let nd = &mut json["nodes"][node];
        if let Some(m) = nd.get_mut("matrix").and_then(Value::as_array_mut) {
            for (k, v) in t.to_array().into_iter().enumerate() {
                m[12 + k] = json!(v);
            }
        } else {
            nd["translation"] = json!(t.to_array());
        }
    }
}

/// Merges every buffer into one (each start 4-byte aligned) and points the
/// buffer views into it; returns the buffers as read and the merged bytes.
fn merge_buffers(
    file: &GltfFile,
    json: &mut Value,
    dir: &Path,
) -> Result<(Vec<Vec<u8>>, Vec<u8>), DataError> {
    if let Some(k) = json["bufferViews"]
        .as_array()
        .and_then(|v| v.iter().position(|v| v.get("extensions").is_some()))
    {
        return Err(DataError::whole_file(
            &file.label,
            format!(
                "bufferView {k} carries an extension (EXT_meshopt_compression?) that points into buffers; \
                 --fix cannot rewrite it: decompress the file first (e.g. gltf-transform)"
            ),
        ));
    }
    let data = buffers(file, dir)?;
    let mut bin = Vec::new();
    let mut starts = Vec::new();
    for d in &data {
        pad4(&mut bin);
        starts.push(bin.len());
        bin.extend_from_slice(d);
    }
    if let Some(views) = json.get_mut("bufferViews").and_then(Value::as_array_mut) {
        for (k, v) in views.iter_mut().enumerate() {
            let b = v["buffer"].as_u64().unwrap_or(0) as usize;
            let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
            let moved = starts
                .get(b)
                .and_then(|s| s.checked_add(off))
                .ok_or_else(|| {
                    DataError::whole_file(
                        &file.label,
                        format!("bufferView {k} has an impossible byteOffset"),
                    )
                })?;
            v["buffer"] = json!(0);
            v["byteOffset"] = json!(moved);
        }
    }
    Ok((data, bin))
}

/// New inverse bind matrices B' = W'^-1 W B for every skin whose joints
/// moved, so the mesh keeps its rest shape: written over the old ones when
/// that accessor serves this skin alone, else as a new accessor (a skin
/// without inverse bind matrices gets one).
fn rebind_skins(
    file: &GltfFile,
    json: &mut Value,
    data: &[Vec<u8>],
    bin: &mut Vec<u8>,
    world: &[DMat4],
) -> Result<(), DataError> {
    for skin in file.document.skins() {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        if !joints.iter().any(|&j| world[j] != file.world[j]) {
            continue;
        }
        let ibm = inverse_binds(data, &skin, joints.len())
            .map_err(|e| DataError::whole_file(&file.label, e))?;
        let mut new = Vec::with_capacity(joints.len());
        for (&j, b) in joints.iter().zip(&ibm) {
            let m = world[j].inverse() * file.world[j] * *b;
            if !m.is_finite() {
                return Err(DataError::whole_file(
                    &file.label,
                    format!(
                        "joint node {j} has a singular world transform; cannot update its inverse bind matrix"
                    ),
                ));
            }
            new.push(m.to_cols_array().map(|v| v as f32));
        }
        let own = skin
            .inverse_bind_matrices()
            .map(|a| a.index())
            .filter(|&a| accessor::references(json).get(&a) == Some(&1));
        let span = own.and_then(|a| accessor::span(json, a, bin.len()).map(|s| (a, s)));
        match span {
            Some((a, span)) if span.component == 5126 && span.components == 16 => {
                for (k, m) in new.iter().enumerate() {
                    span.write_f32(bin, k, m);
                }
                accessor::refresh_bounds(json, a, &span, bin);
            }
            _ => {
                pad4(bin);
                let offset = bin.len();
                for m in &new {
                    for v in m {
                        bin.extend_from_slice(&v.to_le_bytes());
                    }
                }
                let view = push(
                    json,
                    "bufferViews",
                    json!({"buffer": 0, "byteOffset": offset, "byteLength": 64 * joints.len()}),
                );
                let accessor = push(
                    json,
                    "accessors",
                    json!({"bufferView": view, "componentType": 5126, "count": joints.len(), "type": "MAT4"}),
                );
                json["skins"][skin.index()]["inverseBindMatrices"] = json!(accessor);
            }
        }
    }
    Ok(())
}

/// Remarks on what the fix leaves alone: animation channels with paths glTF
/// does not define, and images left as external files.
fn other_warnings(file: &GltfFile) -> Vec<String> {
    let mut warnings = channels::unknown_paths(&file.json);
    if file.document.images().any(
        |i| matches!(i.source(), gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:")),
    ) {
        warnings.push(
            "images referenced by file name stay external: copy them beside the output".into(),
        );
    }
    warnings
}

/// The output file: the JSON alone (`.gltf`, buffer embedded), or a GLB with the bytes.
fn container(file: &GltfFile, json: &Value, bin: Vec<u8>, glb: bool) -> Result<Vec<u8>, DataError> {
    let bytes = if glb {
        crate::rig::read::gltf::glb(json, bin)
    } else {
        serde_json::to_vec(json).map_err(|e| e.to_string())
    };
    bytes.map_err(|e| DataError::whole_file(&file.label, e))
}

/// Appends `value` to the array `json[key]` (created when absent); returns its index.
fn push(json: &mut Value, key: &str, value: Value) -> usize {
    if !json[key].is_array() {
        json[key] = json!([]);
    }
    let arr = json[key].as_array_mut().expect("just made an array");
    arr.push(value);
    arr.len() - 1
}
