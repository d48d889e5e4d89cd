//! The skin of a hand as one welded triangle mesh in world space, the surface
//! [`super::find`] searches for fingers.
//!
//! Every node with a mesh is read, each primitive drawn as triangles
//! (triangle strips and fans are unrolled into triangles; points and lines
//! are left out with a note). Positions are world positions in the file's
//! node pose: a skinned primitive's vertex v rests at sum_j w_j M_j v /
//! sum_j w_j with M_j = W_j B_j (the joint's world matrix times its inverse
//! bind matrix, as [`crate::rig::read::weights`] computes them), a vertex
//! without weight where it is stored; an unskinned mesh node's vertices go
//! through the node's world matrix. Morph targets are not applied (noted).
//!
//! **Welding.** Meshes split their vertices along UV and normal seams; the
//! search needs one vertex per point of the surface. Vertices closer than
//! 1e-6 of the mesh's size (its bounding box's diagonal) become one: 0.2 um on
//! a 20 cm hand, far below any modelled detail and far above float noise of a
//! seam exported twice. Triangles that lose a corner to welding are dropped.
//!
//! **Selection** ([`MeshSelect`]): the whole file, or the skinned vertices
//! weighted mostly (at least half their weight) to a node and the nodes below
//! it: a hand bone and its finger bones, one hand of a body. A triangle is
//! kept when its three vertices are.
//!
//! Every accessor is checked before the gltf crate reads it (by
//! [`crate::rig::read::skin`]'s readers), so a malformed file gives an error
//! naming its JSON path, never a panic. Cost: O(V) for V file vertices (the
//! welding hashes each vertex once and looks at its 27 neighbouring cells).

use crate::dataset::{DataError, Problem};
use crate::rig::read::GltfFile;
use crate::rig::read::gltf::inverse_binds;
use crate::rig::read::skin::{read_indices, read_positions, read_vertices};
use glam::{DMat4, DVec3};
use gltf::mesh::Mode;
use rustc_hash::FxHashMap;
use std::path::PathBuf;

/// The hand's skin: welded vertices in world space and their triangles.
#[derive(Debug, Clone, Default)]
pub struct HandMesh {
    /// Welded vertex positions, world space, in the file's node (bind) pose,
    /// in the file's units (metres for glTF).
    pub positions: Vec<DVec3>,
    /// Triangles over the welded vertices (degenerate ones dropped).
    pub triangles: Vec<[u32; 3]>,
    /// For every welded vertex, the file vertices it stands for: (mesh,
    /// primitive, vertex index).
    pub sources: Vec<Vec<(usize, usize, usize)>>,
    /// Notes on what was left out (non-triangle primitives, unskinned meshes
    /// outside a hand region, morph targets, ...).
    pub notes: Vec<String>,
}

/// Which part of a file is the hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshSelect {
    /// Every mesh of the file: a hand-only file, skinned or not.
    Whole,
    /// The skinned vertices with at least half their weight on `node` (a hand
    /// bone) and the nodes below it (its finger bones): one hand of a body or
    /// avatar. Unskinned meshes are left out (a prop held in the hand is not
    /// its skin).
    UnderNode { node: usize },
}

impl MeshSelect {
    /// The part of a file that is one hand: with a hand (wrist) bone, in a
    /// file that names two hands and weights its skin, the vertices under
    /// that bone; otherwise the whole mesh (a file of one hand: its finger
    /// bones need not lie below the wrist, WebXR's are its siblings).
    pub fn for_hand(hand_node: Option<usize>, two_hands: bool, skinned: bool) -> MeshSelect {
        match hand_node {
            Some(node) if two_hands && skinned => MeshSelect::UnderNode { node },
            _ => MeshSelect::Whole,
        }
    }
}

/// A skin's joints (nodes) and their bind-pose skin matrices.
type SkinMatrices = (Vec<usize>, Vec<DMat4>);

/// One file vertex before welding: where it rests and where it came from.
struct Vertex {
    at: DVec3,
    source: (usize, usize, usize),
}

impl HandMesh {
    /// The stretch of the line `at + t dir` inside the skin nearest `at`:
    /// (t_in, t_out), t_in < t_out, from the crossings with the skin sorted
    /// and paired in and out (crossings within 1e-9 of the mesh's size of
    /// each other are one, a line through an edge); the pair around t = 0
    /// when `at` is inside, else the nearest. `None` when the line misses the
    /// skin or crosses it an odd number of times (an open mesh). O(T).
    pub fn inside_along(&self, at: DVec3, dir: DVec3) -> Option<(f64, f64)> {
        let mut ts = super::geometry::line_crossings(&self.positions, &self.triangles, at, dir);
        ts.sort_by(f64::total_cmp);
        let size = self
            .positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let tol = 1e-9 * (size.1 - size.0).length() / dir.length().max(f64::MIN_POSITIVE);
        ts.dedup_by(|b, a| (*b - *a).abs() <= tol);
        if ts.is_empty() || ts.len() % 2 == 1 {
            return None;
        }
        ts.chunks(2)
            .map(|c| (c[0], c[1]))
            .min_by(|a, b| gap(*a).total_cmp(&gap(*b)))
    }
}

/// How far t = 0 lies outside the stretch (t_in, t_out): 0 inside it.
fn gap((a, b): (f64, f64)) -> f64 {
    if a <= 0.0 && 0.0 <= b {
        0.0
    } else {
        a.abs().min(b.abs())
    }
}

/// Reads the hand's skin from `file` as one welded mesh (see the module doc).
///
/// Errors name the file and each problem with its JSON path: unreadable
/// buffers, a malformed accessor, a position or world matrix that is not
/// finite, a skin whose inverse bind matrices cannot be read; and a selection
/// left without triangles (no mesh, or no vertex weighted to the node).
pub fn hand_mesh(file: &GltfFile, select: &MeshSelect) -> Result<HandMesh, DataError> {
    let dir = file.dir.clone().unwrap_or_else(|| PathBuf::from("."));
    let data = crate::rig::read::gltf::buffers(file, &dir)?;
    let fail = |problems: Vec<String>| DataError {
        file: file.label.clone(),
        problems: problems.into_iter().map(Problem::file).collect(),
    };
    let under = match *select {
        MeshSelect::Whole => None,
        MeshSelect::UnderNode { node } => {
            if node >= file.parent.len() {
                return Err(fail(vec![format!(
                    "has no node {node} (it has {}) to take the hand from",
                    file.parent.len()
                )]));
            }
            Some(subtree(&file.parent, node))
        }
    };
    let mut g = Gathered::default();
    let mut skins: FxHashMap<usize, Option<SkinMatrices>> = FxHashMap::default();
    for node in file.document.nodes() {
        let Some(mesh) = node.mesh() else { continue };
        let n = node.index();
        let m = mesh.index();
        let skin = node.skin();
        if skin.is_none() && under.is_some() {
            g.notes.push(format!(
                "/nodes/{n} (mesh {m}) is not skinned, so it is not part of the hand's region; \
                 left out"
            ));
            continue;
        }
        let matrices = match &skin {
            Some(s) => {
                let entry = skins
                    .entry(s.index())
                    .or_insert_with(|| skin_matrices(file, &data, s, &mut g.problems));
                match entry {
                    Some(x) => Some(x.clone()),
                    None => continue,
                }
            }
            None => {
                let w = file.world.get(n).copied().unwrap_or(DMat4::IDENTITY);
                if !w.is_finite() {
                    g.problems.push(format!(
                        "/nodes/{n} has a non-finite world transform; fix its transform or its \
                         parents'"
                    ));
                    continue;
                }
                None
            }
        };
        for prim in mesh.primitives() {
            let skinned = matrices.as_ref();
            gather_primitive(
                &prim,
                file,
                &data,
                (n, m),
                skinned,
                under.as_deref(),
                &mut g,
            );
        }
    }
    if !g.problems.is_empty() {
        return Err(fail(g.problems));
    }
    let mut out = weld(&g.vertices, &g.triangles);
    out.notes = g.notes;
    if out.triangles.is_empty() {
        let what = match *select {
            MeshSelect::Whole => "has no triangle mesh to find a hand on".to_string(),
            MeshSelect::UnderNode { node } => format!(
                "has no triangles whose vertices are weighted mostly to node {} or the nodes \
                 below it",
                crate::rig::read::naming::shown(&file.node_names()[node])
            ),
        };
        let mut problems = vec![what];
        problems.extend(out.notes);
        return Err(fail(problems));
    }
    Ok(out)
}

/// What the meshes' primitives give as they are read: the vertices kept,
/// the triangles between them, and the notes and problems met.
#[derive(Default)]
struct Gathered {
    notes: Vec<String>,
    problems: Vec<String>,
    vertices: Vec<Vertex>,
    triangles: Vec<[u32; 3]>,
}

/// Adds primitive `prim` of mesh `m` (drawn by node `n`) to `g`: its rest
/// positions (skinned with `matrices`, else by the node's world matrix), the
/// vertices `under` keeps, renumbered, and the triangles among them; a
/// primitive not of triangles, or one that cannot be read, is left out with
/// a note or a problem.
fn gather_primitive(
    prim: &gltf::Primitive<'_>,
    file: &GltfFile,
    data: &[Vec<u8>],
    (n, m): (usize, usize),
    matrices: Option<&SkinMatrices>,
    under: Option<&[bool]>,
    g: &mut Gathered,
) {
    let p = prim.index();
    let at = format!("/meshes/{m}/primitives/{p}");
    let mode = prim.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        g.notes.push(format!(
            "{at} is drawn as {mode:?}, not triangles; it is left out"
        ));
        return;
    }
    if prim.morph_targets().next().is_some() {
        g.notes.push(format!(
            "{at} has morph targets; they are not applied (the mesh is read at its base \
             shape)"
        ));
    }
    // Rest positions, and which vertices belong to the hand.
    let read = match matrices {
        Some((joints, mats)) => skinned_rest(prim, &at, data, joints, mats, under),
        None => {
            let mut p = Vec::new();
            read_positions(prim, &at, data, &mut p).and_then(|pos| {
                if p.is_empty() {
                    let w = file.world[n];
                    Ok(pos.iter().map(|&v| (w.transform_point3(v), true)).collect())
                } else {
                    Err(p)
                }
            })
        }
    };
    let rest = match read {
        Ok(r) => r,
        Err(p) => {
            g.problems.extend(p);
            return;
        }
    };
    if let Some(v) = rest.iter().position(|(x, _)| !x.is_finite()) {
        g.problems.push(format!(
            "{at}: vertex {v} rests at a position that is not finite (its skin matrices \
             or node transform overflow)"
        ));
        return;
    }
    let flat = match read_indices(prim, &at, data, rest.len()) {
        Ok(f) => f,
        Err(e) => {
            g.problems.push(e);
            return;
        }
    };
    let tris = unroll(mode, &flat, &at, &mut g.notes);
    // Only the selected vertices, renumbered.
    let mut index = vec![u32::MAX; rest.len()];
    for (v, &(x, keep)) in rest.iter().enumerate() {
        if keep {
            if g.vertices.len() >= u32::MAX as usize {
                g.problems
                    .push(format!("{at}: more than 2^32 vertices in all"));
                break;
            }
            index[v] = g.vertices.len() as u32;
            g.vertices.push(Vertex {
                at: x,
                source: (m, p, v),
            });
        }
    }
    g.triangles.extend(
        tris.iter()
            .map(|t| t.map(|i| index[i as usize]))
            .filter(|t| t.iter().all(|&i| i != u32::MAX)),
    );
}

/// The skin's joints (nodes) and bind-pose skin matrices M_j = W_j B_j, or
/// `None` with the problem added when they cannot be read or are not finite.
fn skin_matrices(
    file: &GltfFile,
    data: &[Vec<u8>],
    skin: &gltf::Skin<'_>,
    problems: &mut Vec<String>,
) -> Option<SkinMatrices> {
    let s = skin.index();
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    if joints.is_empty() || joints.len() > usize::from(u16::MAX) {
        problems.push(format!(
            "/skins/{s} has {} joints; a skin needs 1 to 65535",
            joints.len()
        ));
        return None;
    }
    let ibm = match inverse_binds(data, skin, joints.len()) {
        Ok(m) => m,
        Err(e) => {
            problems.push(format!("/skins/{s}: {e}"));
            return None;
        }
    };
    let mats: Vec<DMat4> = joints
        .iter()
        .zip(&ibm)
        .map(|(&n, b)| file.world.get(n).map_or(DMat4::IDENTITY, |w| *w * *b))
        .collect();
    if let Some(k) = mats.iter().position(|m| !m.is_finite()) {
        problems.push(format!(
            "/skins/{s}: the skin matrix of joint {k} (node {}) is not finite (its inverse bind \
             matrix or world transform)",
            joints[k]
        ));
        return None;
    }
    Some((joints, mats))
}

/// The rest positions of a skinned primitive's vertices, each with whether it
/// belongs to the hand (`under`: the nodes of the region; `None`: all).
fn skinned_rest(
    prim: &gltf::Primitive<'_>,
    at: &str,
    data: &[Vec<u8>],
    joints: &[usize],
    mats: &[DMat4],
    under: Option<&[bool]>,
) -> Result<Vec<(DVec3, bool)>, Vec<String>> {
    let (positions, influences) = read_vertices(prim, at, data, joints.len())?;
    Ok(positions
        .iter()
        .zip(&influences)
        .map(|(&p, infl)| {
            let sum: f64 = infl.iter().map(|x| x.1).sum();
            if !(sum > 0.0 && sum.is_finite()) {
                return (p, under.is_none());
            }
            let mut at = DVec3::ZERO;
            let mut inside = 0.0;
            for &(slot, w) in infl {
                let s = usize::from(slot);
                at += w * mats[s].transform_point3(p);
                if under.is_some_and(|u| u.get(joints[s]).copied().unwrap_or(false)) {
                    inside += w;
                }
            }
            (at / sum, under.is_none() || inside >= 0.5 * sum)
        })
        .collect())
}

/// Per node, whether it is `node` or below it. O(n depth).
fn subtree(parent: &[Option<usize>], node: usize) -> Vec<bool> {
    (0..parent.len())
        .map(|i| {
            let mut at = Some(i);
            for _ in 0..=parent.len() {
                match at {
                    Some(a) if a == node => return true,
                    Some(a) => at = parent[a],
                    None => return false,
                }
            }
            false
        })
        .collect()
}

/// A primitive's indices as triangles: as they are for triangles, unrolled
/// for strips (every other one turned to keep the winding) and fans;
/// degenerate ones dropped. A count that is not whole triangles is noted.
fn unroll(mode: Mode, flat: &[u32], at: &str, notes: &mut Vec<String>) -> Vec<[u32; 3]> {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (2..flat.len())
            .map(|i| {
                if i % 2 == 0 {
                    [flat[i - 2], flat[i - 1], flat[i]]
                } else {
                    [flat[i - 1], flat[i - 2], flat[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..flat.len())
            .map(|i| [flat[0], flat[i - 1], flat[i]])
            .collect(),
        _ => {
            if !flat.len().is_multiple_of(3) {
                notes.push(format!(
                    "{at}: {} indices are not a whole number of triangles; the last {} are \
                     ignored",
                    flat.len(),
                    flat.len() % 3
                ));
            }
            flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        }
    };
    tris.into_iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect()
}

/// Welds `vertices` closer than 1e-6 of the bounding box's diagonal (see the
/// module doc) and renumbers `triangles` over them, dropping the ones that
/// lose a corner and repeats of one triangle. O(V).
fn weld(vertices: &[Vertex], triangles: &[[u32; 3]]) -> HandMesh {
    let (lo, hi) = vertices.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(v.at), hi.max(v.at)),
    );
    let diagonal = if vertices.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    };
    let tol = 1e-6 * diagonal;
    let cell = |p: DVec3| -> [i64; 3] {
        if tol > 0.0 && tol.is_finite() {
            // Saturating casts: a far-off vertex lands in an edge cell, never panics.
            ((p - lo) / tol).floor().to_array().map(|x| x as i64)
        } else {
            [0, 0, 0]
        }
    };
    let mut grid: FxHashMap<[i64; 3], Vec<u32>> = FxHashMap::default();
    let mut out = HandMesh::default();
    let mut map = Vec::with_capacity(vertices.len());
    for v in vertices {
        let c = cell(v.at);
        let mut found = None;
        'search: for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                for dz in -1..=1i64 {
                    let k = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    if let Some(list) = grid.get(&k) {
                        for &w in list {
                            if out.positions[w as usize].distance(v.at) <= tol {
                                found = Some(w);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let w = found.unwrap_or_else(|| {
            let w = out.positions.len() as u32;
            out.positions.push(v.at);
            out.sources.push(Vec::new());
            grid.entry(c).or_default().push(w);
            w
        });
        out.sources[w as usize].push(v.source);
        map.push(w);
    }
    let mut seen = rustc_hash::FxHashSet::default();
    for t in triangles {
        let w = t.map(|i| map[i as usize]);
        if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
            continue;
        }
        let mut key = w;
        key.sort_unstable();
        if seen.insert(key) {
            out.triangles.push(w);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A GLB of two meshes: mesh 0, a unit square (0,0,0)-(1,1,0) of two
    /// triangles, skinned to joints 0 (node "hand") and 1 (node "finger",
    /// below it, at y = 2): vertices 0 and 1 weighted to the hand, 2 and 3 to
    /// the finger; the hand's inverse bind matrix identity, the finger's a
    /// translation by -2 in y (bound where it stands). Mesh 1, an unskinned
    /// triangle strip of 4 vertices on node "prop" translated by (10, 0, 0).
    /// `edit` changes the JSON first.
    fn file(edit: impl Fn(&mut serde_json::Value)) -> GltfFile {
        let mut bin: Vec<u8> = Vec::new();
        let mut views = Vec::new();
        let mut push = |bytes: Vec<u8>| {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
            bin.extend(bytes);
            views.len() - 1
        };
        let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let square = [0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.];
        let p = push(f32s(&square));
        let idx = push(
            [0u16, 1, 2, 0, 2, 3]
                .iter()
                .flat_map(|x| x.to_le_bytes())
                .collect(),
        );
        let joints = push([0u8, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0].to_vec());
        let weights = push(f32s(&[
            1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0.,
        ]));
        let mut ibm = Vec::new();
        for m in [
            glam::Mat4::IDENTITY,
            glam::Mat4::from_translation(glam::Vec3::new(0.0, -2.0, 0.0)),
        ] {
            ibm.extend(m.to_cols_array());
        }
        let ibm = push(f32s(&ibm));
        let strip = push(f32s(&square));
        let mut doc = json!({
            "asset": {"version": "2.0"},
            "nodes": [
                {"name": "hand", "children": [1]},
                {"name": "finger", "translation": [0.0, 2.0, 0.0]},
                {"name": "skinned", "mesh": 0, "skin": 0},
                {"name": "prop", "mesh": 1, "translation": [10.0, 0.0, 0.0]}
            ],
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": 0, "JOINTS_0": 2, "WEIGHTS_0": 3}, "indices": 1}]},
                {"primitives": [{"attributes": {"POSITION": 5}, "mode": 5}]}
            ],
            "skins": [{"joints": [0, 1], "inverseBindMatrices": 4}],
            "accessors": [
                {"bufferView": p, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
                {"bufferView": idx, "componentType": 5123, "count": 6, "type": "SCALAR"},
                {"bufferView": joints, "componentType": 5121, "count": 4, "type": "VEC4"},
                {"bufferView": weights, "componentType": 5126, "count": 4, "type": "VEC4"},
                {"bufferView": ibm, "componentType": 5126, "count": 2, "type": "MAT4"},
                {"bufferView": strip, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}
            ],
            "bufferViews": views,
            "buffers": [{"byteLength": bin.len()}]
        });
        edit(&mut doc);
        let bytes = crate::rig::read::gltf::glb(&doc, bin).unwrap();
        GltfFile::from_bytes("hand.glb", &bytes).unwrap()
    }

    #[test]
    fn skinned_and_unskinned_meshes_in_world_space() {
        let m = hand_mesh(&file(|_| {}), &MeshSelect::Whole).unwrap();
        // The square rests where it is stored (both skin matrices are the
        // identity in the bind pose); the strip is moved 10 along x and
        // unrolled into two triangles.
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.positions[2], DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.positions[5], DVec3::new(11.0, 0.0, 0.0));
        assert_eq!(
            m.triangles,
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [6, 5, 7]]
        );
        assert_eq!(m.sources[5], vec![(1, 0, 1)]);
        // Posed: the finger node moved up by 1 carries vertices 2 and 3.
        let mut f = file(|_| {});
        f.world[1] = DMat4::from_translation(DVec3::new(0.0, 3.0, 0.0));
        let m = hand_mesh(&f, &MeshSelect::Whole).unwrap();
        assert_eq!(m.positions[2], DVec3::new(1.0, 2.0, 0.0));
        assert_eq!(m.positions[0], DVec3::ZERO);
    }

    #[test]
    fn the_region_under_a_node() {
        let f = file(|_| {});
        // Under the hand: both joints, so the whole square; the prop is left out.
        let m = hand_mesh(&f, &MeshSelect::UnderNode { node: 0 }).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles.len(), 2);
        assert!(
            m.notes.iter().any(|n| n.contains("/nodes/3")),
            "{:?}",
            m.notes
        );
        // Under the finger: vertices 2 and 3 only, no whole triangle.
        let e = hand_mesh(&f, &MeshSelect::UnderNode { node: 1 })
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no triangles whose vertices are weighted mostly to node 'finger'"),
            "{e}"
        );
        let e = hand_mesh(&f, &MeshSelect::UnderNode { node: 9 })
            .unwrap_err()
            .to_string();
        assert!(e.contains("has no node 9"), "{e}");
    }

    #[test]
    fn malformed_data_is_named_by_its_json_path() {
        // Indices as 2 VEC3 of shorts: the same bytes, a shape glTF refuses.
        let f = file(|d| {
            d["accessors"][1]["type"] = json!("VEC3");
            d["accessors"][1]["count"] = json!(2);
        });
        let e = hand_mesh(&f, &MeshSelect::Whole).unwrap_err().to_string();
        assert!(
            e.contains("/accessors/1 (indices of /meshes/0/primitives/0)"),
            "{e}"
        );
        let f = file(|d| d["meshes"][1]["primitives"][0]["mode"] = json!(1));
        let m = hand_mesh(&f, &MeshSelect::Whole).unwrap();
        assert!(
            m.notes
                .iter()
                .any(|n| n.contains("/meshes/1/primitives/0 is drawn as Lines"))
        );
        let mut f = file(|_| {});
        f.world[3] = DMat4::from_cols_array(&[f64::NAN; 16]);
        let e = hand_mesh(&f, &MeshSelect::Whole).unwrap_err().to_string();
        assert!(
            e.contains("/nodes/3 has a non-finite world transform"),
            "{e}"
        );
        let f = file(|d| {
            d["meshes"][0]["primitives"][0]["mode"] = json!(0);
            d["meshes"][1]["primitives"][0]["mode"] = json!(0);
        });
        let e = hand_mesh(&f, &MeshSelect::Whole).unwrap_err().to_string();
        assert!(e.contains("has no triangle mesh"), "{e}");
    }

    fn vertex(x: f64, y: f64, z: f64, i: usize) -> Vertex {
        Vertex {
            at: DVec3::new(x, y, z),
            source: (0, 0, i),
        }
    }

    #[test]
    fn welding_merges_seams_within_a_millionth_of_the_size() {
        // A unit square of two triangles whose shared edge was split (vertices 4
        // and 5 repeat 0 and 2, one of them off by 1e-9, below the 1.4e-6
        // tolerance of a 1.41 diagonal), and a third triangle that welding
        // makes degenerate (7 lies 1e-7 from 1).
        let v = vec![
            vertex(0.0, 0.0, 0.0, 0),
            vertex(1.0, 0.0, 0.0, 1),
            vertex(1.0, 1.0, 0.0, 2),
            vertex(0.0, 1.0, 0.0, 3),
            vertex(0.0, 0.0, 0.0, 4),
            vertex(1.0, 1.0 + 1e-9, 0.0, 5),
            vertex(0.5, 0.5, 0.0, 6),
            vertex(1.0, 1e-7, 0.0, 7),
        ];
        let t = [[0, 1, 2], [4, 5, 3], [6, 1, 7], [2, 1, 0]];
        let m = weld(&v, &t);
        assert_eq!(m.positions.len(), 5);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.sources[0], vec![(0, 0, 0), (0, 0, 4)]);
        assert_eq!(m.sources[1], vec![(0, 0, 1), (0, 0, 7)]);
        assert_eq!(m.sources[2], vec![(0, 0, 2), (0, 0, 5)]);
        // 1e-5 apart on a unit square: two vertices.
        let m = weld(
            &[
                vertex(0.0, 0.0, 0.0, 0),
                vertex(1e-5, 0.0, 0.0, 1),
                vertex(1.0, 1.0, 0.0, 2),
            ],
            &[],
        );
        assert_eq!(m.positions.len(), 3);
    }

    #[test]
    fn strips_and_fans_unroll_with_their_winding() {
        let mut notes = Vec::new();
        assert_eq!(
            unroll(Mode::TriangleStrip, &[0, 1, 2, 3, 4], "s", &mut notes),
            vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]
        );
        assert_eq!(
            unroll(Mode::TriangleFan, &[0, 1, 2, 3], "f", &mut notes),
            vec![[0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(
            unroll(Mode::Triangles, &[0, 1, 2, 3, 3], "t", &mut notes),
            vec![[0, 1, 2]]
        );
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("5 indices"), "{notes:?}");
    }

    #[test]
    fn the_subtree_of_a_node() {
        // 0 -> 1 -> 2, 0 -> 3, 4 alone.
        let parent = [None, Some(0), Some(1), Some(0), None];
        assert_eq!(subtree(&parent, 1), vec![false, true, true, false, false]);
        assert_eq!(subtree(&parent, 0), vec![true, true, true, true, false]);
    }
}
