//! The skin weights of a rig: every vertex of every primitive bound to a skin,
//! in any draw mode (points and lines too), with its influences by node and
//! its rest position in world space.
//!
//! Read for three uses: which nodes carry skin weight (a bone with weight is
//! preferred over an unweighted namesake, see [`super::recognise`]), where each finger's
//! skin bends ([`crate::rig::judge::bend`]), and moving the weights with the joints in
//! `--fix` (`rig::fix::remap`). Accessors are checked as [`super::skin`] checks
//! them; a primitive whose weights cannot be read is left out with a note.
//!
//! A vertex v with influences (node j, weight w) rests at sum_j w_j M_j v,
//! M_j = W_j B_j (world matrix times inverse bind matrix, see [`super::skin`]).

use super::gltf::{GltfFile, inverse_binds};
use glam::{DMat4, DVec3};
use std::collections::{BTreeMap, BTreeSet};

/// The vertices of one primitive bound to a skin.
#[derive(Debug, Clone)]
pub struct WeightedPrimitive {
    pub skin: usize,
    pub mesh: usize,
    pub primitive: usize,
    /// Accessor indices of `(JOINTS_n, WEIGHTS_n)` for each set n.
    pub sets: Vec<(usize, usize)>,
    /// Rest positions in world space.
    pub rest: Vec<DVec3>,
    /// Influences per vertex as (node, weight), normalised to sum 1, largest
    /// first (ties by node); empty for a vertex without weight.
    pub influences: Vec<Vec<(usize, f64)>>,
}

/// Every skinned vertex of a file.
#[derive(Debug, Clone, Default)]
pub struct SkinWeights {
    pub primitives: Vec<WeightedPrimitive>,
    /// Per skin: its joints' nodes and their rest skin matrices M_j = W_j B_j.
    pub skins: BTreeMap<usize, (Vec<usize>, Vec<DMat4>)>,
    /// Primitives left out, and why.
    pub notes: Vec<String>,
}

impl SkinWeights {
    /// Reads the weights of every skin of `file` with its buffers `data`.
    /// Each (skin, attribute set) is read once, however many primitives or
    /// nodes share it. O(vertices x influences).
    pub fn read(file: &GltfFile, data: &[Vec<u8>]) -> SkinWeights {
        let mut out = SkinWeights::default();
        for skin in file.document.skins() {
            let s = skin.index();
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            if joints.is_empty() || joints.len() > usize::from(u16::MAX) {
                continue;
            }
            let ibm = match inverse_binds(data, &skin, joints.len()) {
                Ok(m) => m,
                Err(e) => {
                    out.notes
                        .push(format!("/skins/{s}: {e}; its weights are not read"));
                    continue;
                }
            };
            let matrices: Vec<DMat4> = joints
                .iter()
                .zip(&ibm)
                .map(|(&n, b)| file.world.get(n).map_or(DMat4::IDENTITY, |w| *w * *b))
                .collect();
            if matrices.iter().any(|m| !m.is_finite()) {
                out.notes.push(format!(
                    "/skins/{s} has a non-finite skin matrix; its weights are not read"
                ));
                continue;
            }
            let meshes: BTreeSet<usize> = file
                .document
                .nodes()
                .filter(|n| n.skin().is_some_and(|k| k.index() == s))
                .filter_map(|n| n.mesh().map(|m| m.index()))
                .collect();
            let mut seen = BTreeSet::new();
            for m in meshes {
                let Some(mesh) = file.document.meshes().nth(m) else {
                    continue;
                };
                for prim in mesh.primitives() {
                    let at = format!("/meshes/{m}/primitives/{}", prim.index());
                    let Some(pos) = prim.get(&gltf::Semantic::Positions) else {
                        continue;
                    };
                    let mut sets = Vec::new();
                    while let (Some(j), Some(w)) = (
                        prim.get(&gltf::Semantic::Joints(sets.len() as u32)),
                        prim.get(&gltf::Semantic::Weights(sets.len() as u32)),
                    ) {
                        sets.push((j.index(), w.index()));
                    }
                    if !seen.insert((pos.index(), sets.clone())) {
                        continue;
                    }
                    match super::skin::read_vertices(&prim, &at, data, joints.len()) {
                        Ok((positions, influences)) => {
                            let (rest, influences) =
                                by_node(&positions, influences, &joints, &matrices);
                            out.primitives.push(WeightedPrimitive {
                                skin: s,
                                mesh: m,
                                primitive: prim.index(),
                                sets,
                                rest,
                                influences,
                            });
                        }
                        Err(problems) => out.notes.push(format!(
                            "{at}: its skin weights are not read ({})",
                            problems.join("; ")
                        )),
                    }
                }
            }
            out.skins.insert(s, (joints, matrices));
        }
        out
    }

    /// For each node, whether some vertex gives it a weight above zero.
    pub fn weighted_nodes(&self, nodes: usize) -> Vec<bool> {
        let mut out = vec![false; nodes];
        for p in &self.primitives {
            for infl in &p.influences {
                for &(n, w) in infl {
                    if w > 0.0 && n < nodes {
                        out[n] = true;
                    }
                }
            }
        }
        out
    }
}

/// Influences by node (normalised, merged, largest first) and rest positions
/// of one primitive's vertices; a vertex without weight rests where it is stored.
fn by_node(
    positions: &[DVec3],
    influences: Vec<Vec<(u16, f64)>>,
    joints: &[usize],
    matrices: &[DMat4],
) -> (Vec<DVec3>, Vec<Vec<(usize, f64)>>) {
    let mut rest = Vec::with_capacity(positions.len());
    let mut out = Vec::with_capacity(positions.len());
    for (p, infl) in positions.iter().zip(influences) {
        let mut merged: BTreeMap<usize, f64> = BTreeMap::new();
        let mut at = DVec3::ZERO;
        let sum: f64 = infl.iter().map(|x| x.1).sum();
        for (slot, w) in infl {
            let s = usize::from(slot);
            *merged.entry(joints[s]).or_default() += w;
            at += w * matrices[s].transform_point3(*p);
        }
        let mut list: Vec<(usize, f64)> = if sum > 0.0 && sum.is_finite() {
            merged.into_iter().map(|(n, w)| (n, w / sum)).collect()
        } else {
            Vec::new()
        };
        list.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        rest.push(if list.is_empty() { *p } else { at / sum });
        out.push(list);
    }
    (rest, out)
}
