//! The skinned mesh of a glTF skin: positions, triangles, joint influences and
//! inverse bind matrices, read with every accessor checked first.
//!
//! All primitives of every mesh bound to the skin (nodes with both `mesh` and
//! that `skin`) are read, each mesh once, into one vertex list. Only triangle
//! primitives give triangles; other modes are skipped with a note. `JOINTS_n` /
//! `WEIGHTS_n` are read for every set `n` present, decoded by the gltf crate's
//! reader (unsigned byte and short joints; float, normalised unsigned byte and
//! normalised unsigned short weights, as the glTF 2.0 specification allows),
//! merged per vertex, and normalised to sum 1.
//!
//! The gltf crate's reader panics or reads garbage on some malformed accessors
//! (an unexpected component type, a zero count, a stride shorter than the
//! element, offsets past the view); so every accessor is checked here first
//! (type, count, bounds with checked arithmetic), and only then handed to it.
//! Sparse accessors are refused with a message, never read.
//!
//! The glTF rule for skinned vertices: a vertex v with influences (j, w) lands
//! at sum_j w_j W_j B_j v, with W_j the joint node's world matrix and B_j its
//! inverse bind matrix; the mesh node's own transform is ignored. So the bind
//! pose skin matrices are M_j = W_j B_j ([`SkinnedMesh::skin_matrices`]).

use super::gltf::{GltfFile, buffers, inverse_binds};
use crate::dataset::{DataError, Problem};
use glam::{DMat4, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;

/// One skinned mesh, as stored in the file (mesh space, the file's units).
#[derive(Debug, Clone)]
pub struct SkinnedMesh {
    /// Index of the skin in the file.
    pub skin: usize,
    /// Vertex positions as stored (before skinning).
    pub positions: Vec<DVec3>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Each vertex's influences, in `influences[influence_start[v]..influence_start[v + 1]]`:
    /// (joint slot in [`SkinnedMesh::joints`], weight), weights summing to 1,
    /// largest first (ties by slot). Empty for a vertex with no weight.
    pub influences: Vec<(u16, f64)>,
    /// Offsets into `influences`, one more than there are vertices.
    pub influence_start: Vec<usize>,
    /// The skin's joints: node index per joint slot.
    pub joints: Vec<usize>,
    /// Inverse bind matrix per joint slot (identity when the skin has none).
    pub inverse_bind: Vec<DMat4>,
    /// Per vertex: the lowest index of a vertex at exactly the same position,
    /// so vertices split along a UV or normal seam count as one.
    pub welded: Vec<u32>,
    /// Things read differently from the file or left out, one line each.
    pub notes: Vec<String>,
}

impl SkinnedMesh {
    /// The influences of vertex `v`: (joint slot, weight), largest first.
    pub fn influences_of(&self, v: usize) -> &[(u16, f64)] {
        match (self.influence_start.get(v), self.influence_start.get(v + 1)) {
            (Some(&a), Some(&b)) => &self.influences[a..b],
            _ => &[],
        }
    }

    /// The joint slot with the largest weight on vertex `v`, if any.
    pub fn dominant(&self, v: usize) -> Option<u16> {
        self.influences_of(v).first().map(|&(j, _)| j)
    }

    /// Skin matrices `S_j = world[node_j] B_j` for given world matrices of all
    /// nodes (the bind pose M_j with the file's node pose). A joint whose node
    /// is past the end of `world` gets the identity.
    pub fn skin_matrices(&self, world: &[DMat4]) -> Vec<DMat4> {
        self.joints
            .iter()
            .zip(&self.inverse_bind)
            .map(|(&n, b)| world.get(n).map_or(DMat4::IDENTITY, |w| *w * *b))
            .collect()
    }

    /// The joint slot of node `node`, if the node is one of the skin's joints.
    pub fn slot_of(&self, node: usize) -> Option<u16> {
        self.joints
            .iter()
            .position(|&n| n == node)
            .and_then(|s| u16::try_from(s).ok())
    }

    /// Reads skin `skin` of `file`; `dir` resolves external buffers (files
    /// beside the input). Every problem found is reported together.
    pub fn read(file: &GltfFile, dir: &Path, skin: usize) -> Result<SkinnedMesh, DataError> {
        let data = buffers(file, dir)?;
        read_with(file, &data, skin).map_err(|problems| DataError {
            file: file.label.clone(),
            problems: problems.into_iter().map(Problem::file).collect(),
        })
    }
}

/// The skin whose joints include most of `nodes` (lowest index on a tie);
/// `None` when the file has no skin with any of them.
pub fn pick_skin(file: &GltfFile, nodes: &[usize]) -> Option<usize> {
    file.document
        .skins()
        .map(|s| {
            let joints: BTreeSet<usize> = s.joints().map(|j| j.index()).collect();
            (
                nodes.iter().filter(|n| joints.contains(n)).count(),
                s.index(),
            )
        })
        .filter(|&(k, _)| k > 0)
        .max_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)))
        .map(|(_, s)| s)
}

/// Checks that the gltf crate's reader can iterate `acc` without panicking:
/// one of the `allowed` (component type, shape) pairs, not sparse, at least
/// one element, a buffer view, a stride no shorter than the element, and every
/// byte inside the view and the view inside its buffer (checked arithmetic).
fn check_accessor(
    acc: &gltf::Accessor<'_>,
    what: &str,
    allowed: &[(DataType, Dimensions)],
    data: &[Vec<u8>],
) -> Result<(), String> {
    let at = format!("/accessors/{} ({what})", acc.index());
    let shape = (acc.data_type(), acc.dimensions());
    if !allowed.contains(&shape) {
        let names: Vec<String> = allowed
            .iter()
            .map(|(t, d)| format!("{d:?} of {t:?}"))
            .collect();
        return Err(format!(
            "{at} holds {:?} of {:?}; glTF allows {} here",
            shape.1,
            shape.0,
            names.join(" or ")
        ));
    }
    if acc.sparse().is_some() {
        return Err(format!(
            "{at} is a sparse accessor, which is not read here; re-export without sparse storage"
        ));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("{at} has count 0"));
    }
    let view = acc.view().ok_or_else(|| {
        format!("{at} has no bufferView (all zeros), which cannot describe a mesh")
    })?;
    let elem = acc.size();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "{at}: its bufferView {} has byteStride {stride}, shorter than one element ({elem} bytes)",
            view.index()
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(acc.offset()));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{at}: {count} elements from byteOffset {} do not fit in bufferView {} ({} bytes)",
            acc.offset(),
            view.index(),
            view.length()
        ));
    }
    let buffer = view.buffer().index();
    let have = data.get(buffer).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|e| e > have)
    {
        return Err(format!(
            "{at}: bufferView {} runs past the end of buffer {buffer} ({have} bytes)",
            view.index()
        ));
    }
    Ok(())
}

const POSITION: &[(DataType, Dimensions)] = &[(DataType::F32, Dimensions::Vec3)];
const INDICES: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Scalar),
    (DataType::U16, Dimensions::Scalar),
    (DataType::U32, Dimensions::Scalar),
];
const JOINTS: &[(DataType, Dimensions)] = &[
    (DataType::U8, Dimensions::Vec4),
    (DataType::U16, Dimensions::Vec4),
];
const WEIGHTS: &[(DataType, Dimensions)] = &[
    (DataType::F32, Dimensions::Vec4),
    (DataType::U8, Dimensions::Vec4),
    (DataType::U16, Dimensions::Vec4),
];

/// One primitive's vertices: positions and their (slot, weight) influences, unnormalised.
pub(crate) type PrimitiveData = (Vec<DVec3>, Vec<Vec<(u16, f64)>>);

/// Reads one triangle primitive's positions and influences, or says what is wrong.
pub(crate) fn read_vertices(
    prim: &gltf::Primitive<'_>,
    at: &str,
    data: &[Vec<u8>],
    joints: usize,
) -> Result<PrimitiveData, Vec<String>> {
    let mut problems = Vec::new();
    let positions = read_positions(prim, at, data, &mut problems)?;
    let mut influences: Vec<Vec<(u16, f64)>> = vec![Vec::new(); positions.len()];
    let mut set = 0u32;
    loop {
        let (j_acc, w_acc) = match weight_set(prim, at, set) {
            Ok(Some(pair)) => pair,
            Ok(None) => break,
            Err(e) => {
                problems.push(e);
                break;
            }
        };
        let set_at = SetAt {
            joints: format!("JOINTS_{set} of {at}"),
            weights: format!("WEIGHTS_{set} of {at}"),
        };
        let checks = [
            check_accessor(&j_acc, &set_at.joints, JOINTS, data),
            check_accessor(&w_acc, &set_at.weights, WEIGHTS, data),
        ];
        let failed: Vec<String> = checks.into_iter().filter_map(Result::err).collect();
        if failed.is_empty() {
            let reader = prim.reader(|b| data.get(b.index()).map(Vec::as_slice));
            check_set_shape(&j_acc, &w_acc, &set_at, positions.len(), &mut problems);
            let js: Vec<[u16; 4]> = reader
                .read_joints(set)
                .map(|it| it.into_u16().collect())
                .unwrap_or_default();
            let ws: Vec<[f32; 4]> = reader
                .read_weights(set)
                .map(|it| it.into_f32().collect())
                .unwrap_or_default();
            let (bad_joint, bad_weight) = add_influences(&js, &ws, joints, &mut influences);
            if let Some((v, j)) = bad_joint {
                problems.push(format!(
                    "/accessors/{} ({}): vertex {v} names joint {j}, but the skin has {joints} joints",
                    j_acc.index(),
                    set_at.joints
                ));
            }
            if let Some((v, w)) = bad_weight {
                problems.push(format!(
                    "/accessors/{} ({}): vertex {v} has weight {w}; weights must be finite and not negative",
                    w_acc.index(),
                    set_at.weights
                ));
            }
        } else {
            problems.extend(failed);
        }
        set += 1;
    }
    if set == 0 {
        problems.push(format!(
            "{at} has no JOINTS_0/WEIGHTS_0: it is bound to the skin but not weighted to any joint"
        ));
    }
    if problems.is_empty() {
        Ok((positions, influences))
    } else {
        Err(problems)
    }
}

/// What one joint set's two accessors are called in messages ("JOINTS_0 of /meshes/0/...").
struct SetAt {
    joints: String,
    weights: String,
}

/// The primitive's checked POSITION accessor read as vertices; a vertex that is not
/// finite is added to `problems`, a missing or malformed accessor ends the read.
pub(crate) fn read_positions(
    prim: &gltf::Primitive<'_>,
    at: &str,
    data: &[Vec<u8>],
    problems: &mut Vec<String>,
) -> Result<Vec<DVec3>, Vec<String>> {
    let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
        return Err(vec![format!("{at} has no POSITION attribute")]);
    };
    check_accessor(&pos_acc, &format!("POSITION of {at}"), POSITION, data).map_err(|e| vec![e])?;
    let reader = prim.reader(|b| data.get(b.index()).map(Vec::as_slice));
    let positions: Vec<DVec3> = reader
        .read_positions()
        .map(|it| it.map(|p| DVec3::from_array(p.map(f64::from))).collect())
        .unwrap_or_default();
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        problems.push(format!(
            "/accessors/{} (POSITION of {at}): vertex {v} is not finite",
            pos_acc.index()
        ));
    }
    Ok(positions)
}

/// The `JOINTS_set` and `WEIGHTS_set` accessors: `None` past the last set, an error
/// when only one of the two is there.
fn weight_set<'a>(
    prim: &gltf::Primitive<'a>,
    at: &str,
    set: u32,
) -> Result<Option<(gltf::Accessor<'a>, gltf::Accessor<'a>)>, String> {
    match (
        prim.get(&gltf::Semantic::Joints(set)),
        prim.get(&gltf::Semantic::Weights(set)),
    ) {
        (None, None) => Ok(None),
        (Some(j), Some(w)) => Ok(Some((j, w))),
        (Some(_), None) => Err(format!(
            "{at} has JOINTS_{set} but no WEIGHTS_{set}; each joint set needs its weights"
        )),
        (None, Some(_)) => Err(format!(
            "{at} has WEIGHTS_{set} but no JOINTS_{set}; each weight set needs its joints"
        )),
    }
}

/// Checks that a joint set has one element per vertex and that integer weights are normalised.
fn check_set_shape(
    j_acc: &gltf::Accessor<'_>,
    w_acc: &gltf::Accessor<'_>,
    set_at: &SetAt,
    n: usize,
    problems: &mut Vec<String>,
) {
    for (acc, what) in [(j_acc, &set_at.joints), (w_acc, &set_at.weights)] {
        if acc.count() != n {
            problems.push(format!(
                "/accessors/{} ({what}) has {} elements for {n} vertices",
                acc.index(),
                acc.count()
            ));
        }
    }
    if w_acc.data_type() != DataType::F32 && !w_acc.normalized() {
        problems.push(format!(
            "/accessors/{} ({}) stores integer weights without \"normalized\": true, as glTF requires",
            w_acc.index(),
            set_at.weights
        ));
    }
}

/// Adds one joint set's non-zero weights to each vertex's influences; returns the first
/// vertex naming a joint past `joints` and the first with a negative or non-finite weight.
#[allow(clippy::type_complexity)]
fn add_influences(
    js: &[[u16; 4]],
    ws: &[[f32; 4]],
    joints: usize,
    influences: &mut [Vec<(u16, f64)>],
) -> (Option<(usize, u16)>, Option<(usize, f64)>) {
    let mut bad_joint = None;
    let mut bad_weight = None;
    for (v, (j4, w4)) in js.iter().zip(ws).enumerate().take(influences.len()) {
        for (&j, &w) in j4.iter().zip(w4) {
            let w = f64::from(w);
            if !(w.is_finite() && w >= 0.0) {
                bad_weight.get_or_insert((v, w));
                continue;
            }
            if w == 0.0 {
                continue;
            }
            if usize::from(j) >= joints {
                bad_joint.get_or_insert((v, j));
                continue;
            }
            influences[v].push((j, w));
        }
    }
    (bad_joint, bad_weight)
}

/// One primitive's vertex indices as drawn (its checked `indices` accessor, or
/// 0..n without one, for `n` vertices), or what is wrong: an index past the
/// last vertex is named with its accessor.
pub(crate) fn read_indices(
    prim: &gltf::Primitive<'_>,
    at: &str,
    data: &[Vec<u8>],
    n: usize,
) -> Result<Vec<u32>, String> {
    Ok(match prim.indices() {
        Some(acc) => {
            check_accessor(&acc, &format!("indices of {at}"), INDICES, data)?;
            let reader = prim.reader(|b| data.get(b.index()).map(Vec::as_slice));
            let idx: Vec<u32> = reader
                .read_indices()
                .map(|it| it.into_u32().collect())
                .unwrap_or_default();
            if let Some(&i) = idx.iter().find(|&&i| i as usize >= n) {
                return Err(format!(
                    "/accessors/{} (indices of {at}) names vertex {i}, but the primitive has {n}",
                    acc.index()
                ));
            }
            idx
        }
        None => (0..u32::try_from(n).unwrap_or(u32::MAX)).collect(),
    })
}

/// Reads one primitive's triangles (local vertex indices), or says what is wrong.
fn read_triangles(
    prim: &gltf::Primitive<'_>,
    at: &str,
    data: &[Vec<u8>],
    n: usize,
    notes: &mut Vec<String>,
) -> Result<Vec<[u32; 3]>, String> {
    let flat = read_indices(prim, at, data, n)?;
    if !flat.len().is_multiple_of(3) {
        notes.push(format!(
            "{at}: {} indices are not a whole number of triangles; the last {} are ignored",
            flat.len(),
            flat.len() % 3
        ));
    }
    Ok(flat
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect())
}

/// Reads skin `skin` given the file's buffer data; every problem as one line.
pub(crate) fn read_with(
    file: &GltfFile,
    data: &[Vec<u8>],
    skin: usize,
) -> Result<SkinnedMesh, Vec<String>> {
    let (sk, joints) = skin_joints(file, skin)?;
    let mut problems = Vec::new();
    let inverse_bind = checked_inverse_binds(data, &sk, joints.len(), &mut problems);
    let meshes = skinned_meshes(file, skin, &mut problems);
    let mut notes = Vec::new();
    let gathered = gather_primitives(file, data, &meshes, joints.len(), &mut notes, &mut problems);
    if problems.is_empty() && gathered.triangles.is_empty() {
        problems.push(format!(
            "/skins/{skin}: its meshes have no triangles to deform{}",
            if notes.is_empty() {
                String::new()
            } else {
                format!(" ({})", notes.join("; "))
            }
        ));
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let Gathered {
        positions,
        influences,
        triangles,
    } = gathered;
    let (flat, start, unweighted) = normalise_influences(influences);
    if unweighted > 0 {
        notes.push(format!(
            "{unweighted} vertices of /skins/{skin}'s mesh have no weight; they stay where they are stored"
        ));
    }
    let welded = weld(&positions);
    Ok(SkinnedMesh {
        skin,
        positions,
        triangles,
        influences: flat,
        influence_start: start,
        joints,
        inverse_bind,
        welded,
        notes,
    })
}

/// Skin `skin` and its joints' node indices, or why it cannot be read (missing, or
/// not 1 to 65535 joints).
fn skin_joints(file: &GltfFile, skin: usize) -> Result<(gltf::Skin<'_>, Vec<usize>), Vec<String>> {
    let Some(sk) = file.document.skins().nth(skin) else {
        return Err(vec![format!(
            "has no skin {skin} (it has {})",
            file.document.skins().count()
        )]);
    };
    let joints: Vec<usize> = sk.joints().map(|j| j.index()).collect();
    if joints.is_empty() || joints.len() > usize::from(u16::MAX) {
        return Err(vec![format!(
            "/skins/{skin} has {} joints; a skin needs 1 to 65535",
            joints.len()
        )]);
    }
    Ok((sk, joints))
}

/// The skin's inverse bind matrices (empty when unreadable), each one finite or a problem.
fn checked_inverse_binds(
    data: &[Vec<u8>],
    sk: &gltf::Skin<'_>,
    joints: usize,
    problems: &mut Vec<String>,
) -> Vec<DMat4> {
    let skin = sk.index();
    let inverse_bind = match inverse_binds(data, sk, joints) {
        Ok(m) => m,
        Err(e) => {
            problems.push(format!("/skins/{skin}: {e}"));
            Vec::new()
        }
    };
    if let Some(k) = inverse_bind.iter().position(|m| !m.is_finite()) {
        problems.push(format!(
            "/skins/{skin}: inverse bind matrix {k} is not finite"
        ));
    }
    inverse_bind
}

/// The meshes of the nodes bound to skin `skin`, each once, in index order; none is a problem.
fn skinned_meshes(file: &GltfFile, skin: usize, problems: &mut Vec<String>) -> Vec<usize> {
    let mut meshes: Vec<usize> = file
        .document
        .nodes()
        .filter(|n| n.skin().is_some_and(|s| s.index() == skin))
        .filter_map(|n| n.mesh().map(|m| m.index()))
        .collect();
    meshes.sort_unstable();
    meshes.dedup();
    if meshes.is_empty() {
        problems.push(format!(
            "/skins/{skin} is used by no node with a mesh, so there is no skin to deform"
        ));
    }
    meshes
}

/// The vertices of all triangle primitives of some meshes, as one list.
struct Gathered {
    positions: Vec<DVec3>,
    /// Per vertex, its (joint slot, weight) influences, unnormalised.
    influences: Vec<Vec<(u16, f64)>>,
    /// Triangles as indices into `positions`.
    triangles: Vec<[u32; 3]>,
}

/// Reads every triangle primitive of `meshes` into one vertex list; primitives drawn
/// otherwise are left out with a note, a primitive with a problem is left out.
fn gather_primitives(
    file: &GltfFile,
    data: &[Vec<u8>],
    meshes: &[usize],
    joints: usize,
    notes: &mut Vec<String>,
    problems: &mut Vec<String>,
) -> Gathered {
    let mut out = Gathered {
        positions: Vec::new(),
        influences: Vec::new(),
        triangles: Vec::new(),
    };
    for &m in meshes {
        let Some(mesh) = file.document.meshes().nth(m) else {
            continue;
        };
        for prim in mesh.primitives() {
            let at = format!("/meshes/{m}/primitives/{}", prim.index());
            if prim.mode() != Mode::Triangles {
                notes.push(format!(
                    "{at} is drawn as {:?}, not triangles; it is left out",
                    prim.mode()
                ));
                continue;
            }
            if prim.morph_targets().next().is_some() {
                notes.push(format!(
                    "{at} has morph targets; they are not applied (the mesh is read at its base shape)"
                ));
            }
            let (pos, infl) = match read_vertices(&prim, &at, data, joints) {
                Ok(v) => v,
                Err(p) => {
                    problems.extend(p);
                    continue;
                }
            };
            let base = out.positions.len();
            if base + pos.len() > u32::MAX as usize {
                problems.push(format!("{at}: more than 2^32 vertices in all"));
                continue;
            }
            match read_triangles(&prim, &at, data, pos.len(), notes) {
                Ok(tris) => out
                    .triangles
                    .extend(tris.into_iter().map(|t| t.map(|i| i + base as u32))),
                Err(e) => {
                    problems.push(e);
                    continue;
                }
            }
            out.positions.extend(pos);
            out.influences.extend(infl);
        }
    }
    out
}

/// Per vertex: repeated joints merged, weights normalised to sum 1, largest first (ties
/// by slot). Returns the flat influences, each vertex's start offset (one more than
/// there are vertices) and how many vertices have no weight (left with none).
fn normalise_influences(influences: Vec<Vec<(u16, f64)>>) -> (Vec<(u16, f64)>, Vec<usize>, usize) {
    let mut flat = Vec::new();
    let mut start = Vec::with_capacity(influences.len() + 1);
    let mut unweighted = 0usize;
    for mut infl in influences {
        start.push(flat.len());
        infl.sort_by_key(|&(j, _)| j);
        let mut merged: Vec<(u16, f64)> = Vec::with_capacity(infl.len());
        for (j, w) in infl {
            match merged.last_mut() {
                Some(last) if last.0 == j => last.1 += w,
                _ => merged.push((j, w)),
            }
        }
        let sum: f64 = merged.iter().map(|&(_, w)| w).sum();
        if !(sum > 0.0 && sum.is_finite()) {
            unweighted += 1;
            continue;
        }
        merged.iter_mut().for_each(|(_, w)| *w /= sum);
        merged.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        flat.extend(merged);
    }
    start.push(flat.len());
    (flat, start, unweighted)
}

/// For each position, the lowest index of a position with the same bits. O(n).
pub fn weld(positions: &[DVec3]) -> Vec<u32> {
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // +0.0 and -0.0 are one position.
            let key = p.to_array().map(|x| (x + 0.0).to_bits());
            *first.entry(key).or_insert(i as u32)
        })
        .collect()
}

#[cfg(test)]
mod tests;
