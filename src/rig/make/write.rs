//! A made hand written into a copy of its file through the one glTF writer
//! (`fix`'s [`Edit`]): the joint nodes, each skin that draws the hand given
//! them as joints (a new skin for an unskinned mesh), and the weights.
//!
//! **Nodes.** The hand (wrist) bone is the file's own when it has one, else a
//! new root node at the wrist. Each finger's points (the thumb: CMC, MCP,
//! IP, tip; a finger: MCP, PIP, DIP, tip) are the file's own finger nodes
//! when it has them and fingers are replaced (moved to their new places,
//! children following), else new nodes, each under the one before (the
//! first under the hand), named by the convention chosen ([`Names`]).
//!
//! **Weights.** Each vertex of the hand's skin gets the made weights
//! ([`super::weights`]) in the share of its weight that was the hand's: its
//! weight on nodes outside the hand bone's subtree and the hand's finger
//! chains (the forearm, the body) stays as it was, and the rest (on the hand
//! and its fingers, whatever the old finger bones had) is shared out anew. A vertex of a drawn mesh that
//! is not part of the hand keeps its weights (on a new skin: the hand's).
//! The rest shape is kept by the writer (new inverse bind matrices).

use super::names::{Names, Point};
use super::place::MadeHand;
use super::weights::Bone;
use crate::dataset::{DataError, Finger};
use crate::rig::find::HandMesh;
use crate::rig::fix::Edit;
use crate::rig::read::{FingerChain, GltfFile, Rig};
use glam::DVec3;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// How a made hand is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteOptions {
    /// The naming convention of added nodes.
    pub names: Names,
    /// Reuse (move) the file's own finger nodes of this hand.
    pub replace_fingers: bool,
    /// A GLB (else a .gltf with its buffer embedded).
    pub glb: bool,
}

/// A written hand.
#[derive(Debug, Clone)]
pub struct Written {
    pub bytes: Vec<u8>,
    pub warnings: Vec<String>,
    /// Every joint written: its node's name and world position, and whether
    /// the node is new.
    pub joints: Vec<(String, DVec3, bool)>,
    /// How many of the file's vertices got new weights.
    pub reweighted: usize,
}

/// One point of a made finger: its index, where it goes, and the file's
/// node for it when the finger's own nodes are reused.
type Placed = (usize, DVec3, Option<usize>);

/// A primitive's made weights, by vertex.
type VertexWeights<'a> = BTreeMap<usize, &'a [(Bone, f64)]>;

/// Writes `made` (its weights `weights`, over `mesh`'s welded vertices)
/// into a copy of `rig`'s file: see the module notes. `chains` are this
/// hand's finger chains in the file and `hand_node` its hand bone. Fails
/// with the writer's errors.
#[allow(clippy::too_many_arguments)]
pub fn write(
    rig: &Rig,
    chains: &[&FingerChain],
    hand_node: Option<usize>,
    mesh: &HandMesh,
    made: &MadeHand,
    weights: &[Vec<(Bone, f64)>],
    opts: &WriteOptions,
    dir: &Path,
) -> Result<Written, DataError> {
    let file = &rig.file;
    let mut edit = Edit::new(file, dir)?;
    let side = made.side;
    let hand = match hand_node {
        Some(n) => n,
        None => edit.add_node(&opts.names.hand(side), None, made.wrist)?,
    };
    let plan = plan_of(made, chains, opts.replace_fingers);
    let moves: Vec<(usize, DVec3)> = plan
        .iter()
        .flat_map(|(_, pts)| pts.iter().filter_map(|&(_, at, n)| n.map(|n| (n, at))))
        .collect();
    edit.move_nodes(&moves)?;
    let mut node_of: BTreeMap<Bone, usize> = BTreeMap::new();
    node_of.insert(Bone::Hand, hand);
    // The palm before each finger: its own metacarpal node when fingers are
    // replaced and it has one (not the thumb's, which is its first bone).
    for f in &made.fingers {
        let metacarpal = chains
            .iter()
            .find(|c| c.finger == f.finger && f.finger != Finger::Thumb)
            .filter(|_| opts.replace_fingers)
            .and_then(|c| c.metacarpal.as_ref().map(|m| m.node));
        node_of.insert(Bone::Palm { finger: f.finger }, metacarpal.unwrap_or(hand));
    }
    let mut joints = Vec::new();
    for (finger, pts) in &plan {
        let mut parent = hand;
        for &(k, at, own) in pts {
            let (node, name, fresh) = match own {
                Some(n) => {
                    let name = file.json["nodes"][n]["name"]
                        .as_str()
                        .map_or_else(|| format!("node {n}"), str::to_string);
                    (n, name, false)
                }
                None => {
                    let name = opts.names.joint(side, Point { finger: *finger, k });
                    (edit.add_node(&name, Some(parent), at)?, name, true)
                }
            };
            joints.push((name, at, fresh));
            node_of.insert(Bone::Finger { finger: *finger, k }, node);
            parent = node;
        }
    }
    // The skin's joints: the hand first, then every made node, the tips too
    // (a leaf no skin lists is an empty node to a glTF validator; the tips
    // take no weight).
    let bones: Vec<usize> = {
        let mut b = vec![hand];
        for &n in node_of.values() {
            if !b.contains(&n) {
                b.push(n);
            }
        }
        b
    };
    let by_vertex = by_vertex(weights, mesh);
    let meshes: BTreeSet<usize> = by_vertex.keys().map(|&(m, _)| m).collect();
    bind_skins(&mut edit, file, &meshes, &bones)?;
    // The hand's own nodes: its bone and those below it, and its finger
    // chains' nodes wherever they hang (WebXR's are the wrist's siblings).
    let subtree = below(&file.parent, hand_node).map(|mut s| {
        for c in chains {
            s.extend(c.joints.iter().filter_map(|j| j.node));
            s.extend(c.metacarpal.as_ref().map(|m| m.node));
        }
        s
    });
    let mut reweighted = 0;
    for &m in &meshes {
        let Some(mesh_doc) = file.document.meshes().nth(m) else {
            continue;
        };
        for prim in mesh_doc.primitives() {
            let p = prim.index();
            let count = prim
                .get(&gltf::Semantic::Positions)
                .map_or(0, |a| a.count());
            let old = rig.weights.as_ref().and_then(|w| {
                w.primitives
                    .iter()
                    .find(|x| x.mesh == m && x.primitive == p)
            });
            let made_here = by_vertex.get(&(m, p));
            let mut influences: Vec<Vec<(usize, f64)>> = Vec::with_capacity(count);
            for v in 0..count {
                let before: &[(usize, f64)] = old
                    .and_then(|o| o.influences.get(v))
                    .map_or(&[], |x| x.as_slice());
                let mine = made_here.and_then(|h| h.get(&v));
                reweighted += usize::from(mine.is_some());
                let list = influence(before, mine.copied(), subtree.as_ref(), &node_of, hand);
                influences.push(list);
            }
            edit.set_weights(m, p, &influences)?;
        }
    }
    let (bytes, warnings) = edit.finish(opts.glb)?;
    Ok(Written {
        bytes,
        warnings,
        joints,
        reweighted,
    })
}

/// The points of each made finger: where they go, and the file's node for
/// each when fingers are replaced (`replace_fingers`).
fn plan_of(
    made: &MadeHand,
    chains: &[&FingerChain],
    replace_fingers: bool,
) -> Vec<(Finger, Vec<Placed>)> {
    let mut plan: Vec<(Finger, Vec<Placed>)> = Vec::new();
    for f in &made.fingers {
        let mut points: Vec<DVec3> = f.cmc.into_iter().collect();
        points.extend(f.joints.iter().map(|j| j.1));
        let own = if replace_fingers {
            chains
                .iter()
                .find(|c| c.finger == f.finger)
                .map(|c| own_nodes(c, points.len()))
                .unwrap_or_else(|| vec![None; points.len()])
        } else {
            vec![None; points.len()]
        };
        plan.push((
            f.finger,
            points
                .into_iter()
                .enumerate()
                .zip(own)
                .map(|((k, at), node)| (k, at, node))
                .collect(),
        ));
    }
    plan
}

/// The file's vertices that are the hand's (by mesh and primitive), each
/// with its made weights.
fn by_vertex<'a>(
    weights: &'a [Vec<(Bone, f64)>],
    mesh: &HandMesh,
) -> BTreeMap<(usize, usize), VertexWeights<'a>> {
    let mut by_vertex: BTreeMap<(usize, usize), VertexWeights> = BTreeMap::new();
    for (w, sources) in weights.iter().zip(&mesh.sources) {
        for &(m, p, v) in sources {
            by_vertex.entry((m, p)).or_default().insert(v, w.as_slice());
        }
    }
    by_vertex
}

/// Skins: each node drawing one of `meshes` has its skin given the `bones`;
/// an unskinned one gets a new skin of them.
fn bind_skins(
    edit: &mut Edit<'_>,
    file: &GltfFile,
    meshes: &BTreeSet<usize>,
    bones: &[usize],
) -> Result<(), DataError> {
    for &m in meshes {
        let drawers: Vec<gltf::Node> = file
            .document
            .nodes()
            .filter(|n| n.mesh().is_some_and(|x| x.index() == m))
            .collect();
        for node in drawers {
            match node.skin() {
                Some(s) => edit.add_joints(s.index(), bones)?,
                None => {
                    edit.new_skin(node.index(), bones, None)?;
                }
            }
        }
    }
    Ok(())
}

/// A vertex's influences: with made weights (`mine`), those of nodes not
/// the hand's (outside `subtree`) kept and the made ones sharing the rest;
/// else its own, or the hand bone's alone when it had none.
fn influence(
    before: &[(usize, f64)],
    mine: Option<&[(Bone, f64)]>,
    subtree: Option<&BTreeSet<usize>>,
    node_of: &BTreeMap<Bone, usize>,
    hand: usize,
) -> Vec<(usize, f64)> {
    match mine {
        Some(mine) => {
            let kept: Vec<(usize, f64)> = before
                .iter()
                .copied()
                .filter(|(n, _)| subtree.is_some_and(|s| !s.contains(n)))
                .collect();
            let share = (1.0 - kept.iter().map(|x| x.1).sum::<f64>()).max(0.0);
            let mut list = kept;
            for &(bone, w) in mine.iter() {
                if let Some(&n) = node_of.get(&bone) {
                    list.push((n, w * share));
                }
            }
            list
        }
        None if before.is_empty() => vec![(hand, 1.0)],
        None => before.to_vec(),
    }
}

/// The file's nodes of a finger chain for a made finger of `n` points
/// (the thumb from its CMC: the metacarpal node first).
fn own_nodes(chain: &FingerChain, n: usize) -> Vec<Option<usize>> {
    let mut out: Vec<Option<usize>> = Vec::with_capacity(n);
    if chain.finger == Finger::Thumb {
        out.push(chain.metacarpal.as_ref().map(|m| m.node));
    }
    out.extend(chain.joints.iter().map(|j| j.node));
    out.resize(n, None);
    out
}

/// The nodes at and below `root` (`None`: no hand bone, so every weight is
/// the hand's).
fn below(parent: &[Option<usize>], root: Option<usize>) -> Option<BTreeSet<usize>> {
    let root = root?;
    let mut out = BTreeSet::new();
    for n in 0..parent.len() {
        let mut at = Some(n);
        while let Some(a) = at {
            if a == root {
                out.insert(n);
                break;
            }
            at = parent[a];
        }
    }
    Some(out)
}
