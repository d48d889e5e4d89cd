//! The one glTF writer: an edit of a glTF file that keeps everything it does
//! not touch and the mesh's rest shape whatever it does. `audit --fix`
//! ([`super::fix_with`]) moves joints and carries weights with it; a command
//! that rigs a hand adds joint nodes, a skin and weights with it.
//!
//! An edit starts with every buffer merged into one ([`Edit::new`]). Its
//! steps change the JSON and the world matrices at once; what depends on the
//! final node transforms waits for [`Edit::finish`]: the inverse bind
//! matrices, the moved nodes' translation keys (`anim`) and the
//! weights, written in that order.
//!
//! The rest shape is kept: a skinned vertex v with influences (j, w) rests at
//! sum_j w_j W_j B_j v (W_j the joint node's world matrix, B_j its inverse
//! bind matrix), so every joint keeps its rest skin matrix M_j = W_j B_j. A
//! joint that was one moves from W to W' and gets B' = W'^-1 W B. A joint
//! added to a skin gets B' = W'^-1 M, with M where the vertices it takes
//! rested: for a skin made here, the world matrix of the node that drew the
//! mesh unskinned (glTF ignores a skinned mesh node's own transform); for a
//! skin of the file, the rest skin matrix of the new joint's nearest ancestor
//! among the skin's joints (its first joint when none is an ancestor). New
//! weights then leave every vertex where it was, unless the file's skin binds
//! its joints at different rest matrices (its bind pose is not its rest pose):
//! that is said in a warning.
//!
//! Everything is written in place where one user owns it (inverse bind
//! matrices, keys, weights), else appended, so an edit that moves nothing
//! writes the file's own bytes again (a second fix changes nothing). An
//! accessor an edit stops using is removed (every reference renumbered), with
//! the buffer views only it used and their bytes. New buffer views start on
//! 4-byte boundaries, vertex data views carry their target, and no byteStride
//! is written.

mod files;
mod finishing;
mod lookup;

use super::accessor::{self, push};
use super::{anim, remap};
use crate::dataset::DataError;
use crate::rig::judge::carry::Remapped;
use crate::rig::read::anim as channels;
use crate::rig::read::gltf::{GltfFile, local_matrix, world_matrices};
use crate::rig::read::weights::SkinWeights;
use base64::Engine;
use files::{container, merge_buffers, other_warnings, trs_node, write_translation};
use glam::{DMat4, DVec3};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

/// A glTF file being edited: its JSON, its buffers merged into one, and
/// every node's local and world matrix as the edit leaves them.
pub struct Edit<'a> {
    file: &'a GltfFile,
    json: Value,
    /// The file's buffers as read (the inverse bind matrices are read from them).
    data: Vec<Vec<u8>>,
    /// The merged buffer being written.
    bin: Vec<u8>,
    parent: Vec<Option<usize>>,
    locals: Vec<DMat4>,
    world: Vec<DMat4>,
    /// Moved nodes: their local translation before the first move and now.
    moved: BTreeMap<usize, (DVec3, DVec3)>,
    /// Per skin, the joints added to it and the rest skin matrix each binds at.
    added: BTreeMap<usize, Vec<(usize, DMat4)>>,
    /// The skins made here and the rest skin matrix of their mesh.
    new_skins: BTreeMap<usize, DMat4>,
    /// Weights to write, in the order they were given.
    writes: Vec<Write<'a>>,
    /// Remarks made while editing.
    remarks: Vec<String>,
}

/// Weights waiting for [`Edit::finish`].
enum Write<'a> {
    /// Influences by (primitive of the weights, vertex), as `audit --fix` carries them.
    Carried(&'a SkinWeights, Remapped),
    /// Every vertex of a primitive: (joint slot, weight), at most four, summing to 1.
    Set {
        mesh: usize,
        primitive: usize,
        slots: Vec<Vec<(u32, f64)>>,
    },
}

impl<'a> Edit<'a> {
    /// Starts an edit of `file` (`dir` resolves external buffers): every
    /// buffer merged into one, each start 4-byte aligned, the buffer views
    /// pointed into it. Refuses buffer views with extensions (meshopt
    /// compression points them into other buffers) and buffers that cannot
    /// be read.
    pub fn new(file: &'a GltfFile, dir: &Path) -> Result<Edit<'a>, DataError> {
        let mut json = file.json.clone();
        let (data, bin) = merge_buffers(file, &mut json, dir)?;
        Ok(Edit {
            file,
            json,
            data,
            bin,
            parent: file.parent.clone(),
            locals: file.document.nodes().map(|n| local_matrix(&n)).collect(),
            world: file.world.clone(),
            moved: BTreeMap::new(),
            added: BTreeMap::new(),
            new_skins: BTreeMap::new(),
            writes: Vec::new(),
            remarks: Vec::new(),
        })
    }

    /// How many nodes the edited file has.
    pub fn nodes(&self) -> usize {
        self.parent.len()
    }

    /// The world matrix of `node` as the edit leaves it so far.
    pub fn world(&self, node: usize) -> Option<DMat4> {
        self.world.get(node).copied()
    }

    /// Adds a remark to the warnings [`Edit::finish`] returns (after those on
    /// translation keys, before those on written weights).
    pub fn warn(&mut self, remark: impl Into<String>) {
        self.remarks.push(remark.into());
    }

    /// Moves nodes to world positions by changing their local translations
    /// only, parents first (so a child moved after its parent is placed in the
    /// parent's new frame); a descendant not named follows its parent. World
    /// rotations and scales are untouched. The translations are stored at the
    /// f32 precision glTF keeps, and the world matrices computed from them.
    /// Returns each target's node with its local translation before the edit's
    /// first move of it and now. Fails on a node that does not exist or whose
    /// parent's world transform is singular.
    pub fn move_nodes(
        &mut self,
        targets: &[(usize, DVec3)],
    ) -> Result<Vec<(usize, DVec3, DVec3)>, DataError> {
        for &(node, _) in targets {
            self.check_node(node)?;
        }
        let before: Vec<DVec3> = targets
            .iter()
            .map(|&(n, _)| self.locals[n].w_axis.truncate())
            .collect();
        let mut order = targets.to_vec();
        order.sort_by_key(|&(node, _)| self.depth(node));
        for &(node, target) in &order {
            let up = self.parent[node].map_or(DMat4::IDENTITY, |p| self.world[p]);
            let det = up.determinant();
            let t = up.inverse().transform_point3(target);
            if !(det.is_finite() && det.abs() > 1e-300 && t.is_finite()) {
                return Err(self.fail(format!(
                    "cannot move node {node} ('{}'): the transform above it is singular (a zero scale?); fix that first",
                    self.json["nodes"][node]["name"].as_str().unwrap_or("unnamed")
                )));
            }
            // Stored at the f32 precision glTF files keep (so a second fix reads
            // back exactly what it would write); the inverse bind matrices are
            // computed from the rounded translation.
            self.locals[node].w_axis = t.as_vec3().as_dvec3().extend(1.0);
            self.world = world_matrices(&self.parent, &self.locals)
                .unwrap_or_else(|| std::mem::take(&mut self.world));
        }
        let mut out = Vec::with_capacity(targets.len());
        for (&(node, _), old) in targets.iter().zip(before) {
            let new = self.locals[node].w_axis.truncate();
            let entry = self.moved.entry(node).or_insert((old, new));
            entry.1 = new;
            out.push((node, entry.0, new));
            write_translation(&mut self.json["nodes"][node], new);
        }
        Ok(out)
    }

    /// Adds a node named `name` under `parent` (`None`: a root of the default
    /// scene, when the file has scenes) at world position `at`, with the
    /// identity rotation and unit scale in world space: its local transform
    /// is the parent's world inverse times a translation, written as
    /// translation, rotation and scale (the defaults left out) at f32
    /// precision. Returns its index. Fails when the parent does not exist,
    /// `at` is not finite, or the parent's world transform is singular or
    /// shears (a non-uniform scale under a rotation, which no node's
    /// translation, rotation and scale can undo).
    pub fn add_node(
        &mut self,
        name: &str,
        parent: Option<usize>,
        at: DVec3,
    ) -> Result<usize, DataError> {
        if let Some(p) = parent {
            self.check_node(p)?;
        }
        if !at.is_finite() {
            return Err(self.fail(format!(
                "cannot add node '{name}' at a position that is not finite ({at})"
            )));
        }
        let up = parent.map_or(DMat4::IDENTITY, |p| self.world[p]);
        let det = up.determinant();
        let local = up.inverse() * DMat4::from_translation(at);
        let under = || parent.map_or_else(String::new, |p| format!(" under node {p}"));
        if !(det.is_finite() && det.abs() > 1e-300 && local.is_finite()) {
            return Err(self.fail(format!(
                "cannot add node '{name}'{}: the transform above it is singular (a zero scale?)",
                under()
            )));
        }
        let (node, stored) = trs_node(name, &local).ok_or_else(|| {
            self.fail(format!(
                "cannot add node '{name}'{}: its parent's world transform shears (a non-uniform \
                 scale under a rotation), so no translation, rotation and scale of the node can \
                 leave it unrotated and unscaled",
                under()
            ))
        })?;
        let index = push(&mut self.json["nodes"], node);
        match parent {
            Some(p) => {
                push(&mut self.json["nodes"][p]["children"], json!(index));
            }
            None => {
                if let Some(s) = self.default_scene() {
                    push(&mut self.json["scenes"][s]["nodes"], json!(index));
                }
            }
        }
        self.parent.push(parent);
        self.locals.push(stored);
        self.world.push(up * stored);
        Ok(index)
    }

    /// Makes every node of `nodes` a joint of skin `skin`, appended in order
    /// when it is not one already. Each binds where the vertices it will take
    /// rested (see the module's words), so weights given to it later keep the
    /// rest shape. Fails when the skin or a node does not exist, or a node
    /// does not share the root of the skin's joints, or lies outside its
    /// skeleton (glTF requires both).
    pub fn add_joints(&mut self, skin: usize, nodes: &[usize]) -> Result<(), DataError> {
        let Some(joints) = self.skin_joints(skin) else {
            return Err(self.fail(format!("has no skin {skin}")));
        };
        let mut fresh: Vec<usize> = Vec::new();
        for &n in nodes {
            self.check_node(n)?;
            if !joints.contains(&n) && !fresh.contains(&n) {
                fresh.push(n);
            }
        }
        let Some(&first) = joints.first() else {
            return Err(self.fail(format!("skin {skin} has no joints")));
        };
        let mut all = vec![first];
        all.extend_from_slice(&fresh);
        let skeleton = self.json["skins"][skin]["skeleton"]
            .as_u64()
            .map(|k| k as usize);
        self.check_skeleton(&format!("skin {skin}"), &all, skeleton)?;
        let mut binds = Vec::with_capacity(fresh.len());
        for &n in &fresh {
            binds.push((n, self.rest_of_new_joint(skin, n)?));
        }
        for &(n, _) in &binds {
            push(&mut self.json["skins"][skin]["joints"], json!(n));
        }
        self.added.entry(skin).or_default().extend(binds);
        Ok(())
    }

    /// A new skin with joints `nodes` (in order, repeats left out) and
    /// skeleton root `skeleton`, bound to the mesh drawn by `mesh_node`, which
    /// has no skin; returns the skin's index. The mesh keeps resting where its
    /// node put it: every joint binds at that node's world matrix.
    ///
    /// glTF ignores a skinned mesh node's transform and wants it a root: so
    /// the node draws the skinned mesh itself, made a root without a transform,
    /// when that changes nothing else (it is a root without a transform, or a
    /// leaf that is no joint), and is not animated by translation, rotation or
    /// scale; otherwise a new root node named after it ("NAME (skinned)")
    /// draws the mesh (with its morph weights and their channels), and the
    /// node keeps its place and children. Every primitive of the mesh must be
    /// given weights ([`Edit::set_weights`]) before [`Edit::finish`].
    ///
    /// Fails when the node has no mesh, has a skin, or shares its mesh with
    /// another node, when a joint does not exist, when the joints do not share
    /// one root or the skeleton is not an ancestor of them all, or when the
    /// joints are missing from a scene that shows the mesh.
    pub fn new_skin(
        &mut self,
        mesh_node: usize,
        nodes: &[usize],
        skeleton: Option<usize>,
    ) -> Result<usize, DataError> {
        self.check_node(mesh_node)?;
        let node = &self.json["nodes"][mesh_node];
        let Some(mesh) = node["mesh"].as_u64() else {
            return Err(self.fail(format!("node {mesh_node} draws no mesh to skin")));
        };
        if node.get("skin").is_some() {
            return Err(self.fail(format!("node {mesh_node} already has a skin")));
        }
        let drawers = self.drawers(mesh as usize);
        if drawers.len() > 1 {
            return Err(self.fail(format!(
                "mesh {mesh} is drawn by nodes {drawers:?}; a new skin binds a mesh that one node draws"
            )));
        }
        let mut joints: Vec<usize> = Vec::new();
        for &n in nodes {
            self.check_node(n)?;
            if !joints.contains(&n) {
                joints.push(n);
            }
        }
        if joints.is_empty() {
            return Err(self.fail("a new skin needs at least one joint"));
        }
        if let Some(k) = skeleton {
            self.check_node(k)?;
        }
        self.check_skeleton("the new skin", &joints, skeleton)?;
        let root = self.root_of(mesh_node);
        let shown = self.scenes_with(root);
        let joint_root = self.root_of(joints[0]);
        if let Some(s) = shown
            .iter()
            .find(|&&s| !self.scenes_with(joint_root).contains(&s))
        {
            return Err(self.fail(format!(
                "scene {s} shows node {mesh_node}'s mesh but not the new skin's joints (their root \
                 is node {joint_root}); glTF requires them in every scene that shows the mesh"
            )));
        }
        let rest = self.world[mesh_node];
        let skin = push(&mut self.json["skins"], json!({ "joints": joints }));
        if let Some(k) = skeleton {
            self.json["skins"][skin]["skeleton"] = json!(k);
        }
        let animated = channels::channels(&self.json).iter().any(|c| {
            c.node == Some(mesh_node)
                && matches!(
                    c.path.as_deref(),
                    Some("translation" | "rotation" | "scale")
                )
        });
        let is_joint = joints.contains(&mesh_node)
            || skeleton == Some(mesh_node)
            || (0..self.skin_count())
                .any(|s| self.skin_joints(s).is_some_and(|j| j.contains(&mesh_node)));
        let leaf = self.json["nodes"][mesh_node].get("children").is_none();
        let plain_root =
            self.parent[mesh_node].is_none() && self.locals[mesh_node] == DMat4::IDENTITY;
        if !animated && (plain_root || (leaf && !is_joint)) {
            self.draw_skinned_itself(mesh_node, skin, &shown);
        } else {
            self.draw_skinned_from_new_root(mesh_node, skin, &shown);
        }
        self.new_skins.insert(skin, rest);
        self.added
            .insert(skin, joints.iter().map(|&n| (n, rest)).collect());
        Ok(skin)
    }

    /// Sets the weights of every vertex of primitive `primitive` of mesh
    /// `mesh`: per vertex its influences as (node, weight), any number of them
    /// (a node named twice counts once with the sum); the largest four are
    /// kept (ties: the lower joint slot) and renormalised to sum 1. Every node
    /// must be a joint of the skin bound to the mesh (add it first with
    /// [`Edit::add_joints`]); weights must be finite and not negative, and
    /// every vertex needs some.
    ///
    /// Written by [`Edit::finish`]: in place into JOINTS_n/WEIGHTS_n when set
    /// 0 exists, no other user names any set's accessors, they are stored
    /// plainly and JOINTS_0's type can hold every slot (later sets are then
    /// zeroed; float, normalised byte and short weights sum to 1 exactly in
    /// their type); otherwise new accessors (JOINTS_0 unsigned short,
    /// WEIGHTS_0 float) replace the primitive's sets, and accessors nothing
    /// names any more are removed.
    pub fn set_weights(
        &mut self,
        mesh: usize,
        primitive: usize,
        influences: &[Vec<(usize, f64)>],
    ) -> Result<(), DataError> {
        let at = format!("/meshes/{mesh}/primitives/{primitive}");
        let prim = &self.json["meshes"][mesh]["primitives"][primitive];
        if prim.is_null() {
            return Err(self.fail(format!("{at} does not exist")));
        }
        let count = prim["attributes"]["POSITION"]
            .as_u64()
            .and_then(|a| self.json["accessors"][a as usize]["count"].as_u64())
            .ok_or_else(|| self.fail(format!("{at} has no POSITION to weight")))?
            as usize;
        if influences.len() != count {
            return Err(self.fail(format!(
                "{at} has {count} vertices but {} were given weights",
                influences.len()
            )));
        }
        let skin = self.skin_of_mesh(mesh)?;
        let joints = self.skin_joints(skin).unwrap_or_default();
        let mut slot_of: HashMap<usize, u32> = HashMap::new();
        for (s, &n) in joints.iter().enumerate().rev() {
            slot_of.insert(n, s as u32);
        }
        let mut slots = Vec::with_capacity(count);
        for (v, list) in influences.iter().enumerate() {
            let mut merged: BTreeMap<u32, f64> = BTreeMap::new();
            for &(node, w) in list {
                if !(w.is_finite() && w >= 0.0) {
                    return Err(self.fail(format!(
                        "{at}: vertex {v} gives node {node} the weight {w}; weights are finite and not negative"
                    )));
                }
                let Some(&s) = slot_of.get(&node) else {
                    return Err(self.fail(format!(
                        "{at}: vertex {v} is weighted to node {node}, which is not a joint of skin {skin}"
                    )));
                };
                if s > u32::from(u16::MAX) {
                    return Err(self.fail(format!(
                        "{at}: vertex {v} is weighted to joint slot {s} of skin {skin}; glTF's JOINTS hold at most 65535"
                    )));
                }
                *merged.entry(s).or_default() += w;
            }
            let mut list: Vec<(u32, f64)> = merged.into_iter().filter(|x| x.1 > 0.0).collect();
            list.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            list.truncate(4);
            let sum: f64 = list.iter().map(|x| x.1).sum();
            if !(sum > 0.0 && sum.is_finite()) {
                return Err(self.fail(format!(
                    "{at}: vertex {v} has no weight; every skinned vertex needs one"
                )));
            }
            for x in &mut list {
                x.1 /= sum;
            }
            slots.push(list);
        }
        if let Some(remark) = self.rest_drift(skin, mesh, primitive, &slots) {
            self.remarks.push(remark);
        }
        self.writes.push(Write::Set {
            mesh,
            primitive,
            slots,
        });
        Ok(())
    }

    /// Writes the influences `carried` (by primitive of `weights` and
    /// vertex) into their JOINTS_n/WEIGHTS_n accessors in place, as
    /// `remap::write` does, when [`Edit::finish`] runs.
    pub fn write_carried(&mut self, weights: &'a SkinWeights, carried: Remapped) {
        self.writes.push(Write::Carried(weights, carried));
    }

    /// Finishes the edit: inverse bind matrices for every skin whose joints
    /// moved or were added and for every new skin, the moved nodes'
    /// translation keys offset by their rest translation's change, the
    /// weights, unused accessors removed, then the container: a GLB (`glb`)
    /// or a .gltf with its buffer embedded as a data URI. Returns the bytes and
    /// the warnings: on translation keys, the remarks made while editing, on
    /// the weights written, and on what the edit leaves alone (animation
    /// channels it does not understand, external images). Fails when a new
    /// skin's mesh has a primitive without weights or a joint's world
    /// transform is singular.
    pub fn finish(mut self, glb: bool) -> Result<(Vec<u8>, Vec<String>), DataError> {
        self.check_new_skins_weighted()?;
        let mut unused = BTreeSet::new();
        self.rebind(&mut unused)?;
        let delta: BTreeMap<usize, (DVec3, DVec3)> = self
            .moved
            .iter()
            .filter(|(_, (old, new))| old != new)
            .map(|(&n, &(old, new))| (n, (old, new - old)))
            .collect();
        let mut warnings = anim::offset_translations(&mut self.json, &mut self.bin, &delta);
        warnings.append(&mut self.remarks);
        for write in std::mem::take(&mut self.writes) {
            match write {
                Write::Carried(weights, carried) => {
                    warnings.extend(remap::write(
                        &mut self.json,
                        &mut self.bin,
                        weights,
                        &carried,
                    ));
                }
                Write::Set {
                    mesh,
                    primitive,
                    slots,
                } => self.write_set(mesh, primitive, &slots, &mut unused),
            }
        }
        accessor::drop_unused(&mut self.json, &mut self.bin, &unused);
        let (file, mut json, bin) = (self.file, self.json, self.bin);
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
        Ok((bytes, warnings))
    }

    /// Node `node` draws its mesh with skin `skin`, made a root (listed in
    /// the scenes `shown`) without a transform.
    fn draw_skinned_itself(&mut self, node: usize, skin: usize, shown: &[usize]) {
        if let Some(p) = self.parent[node] {
            let children = &mut self.json["nodes"][p];
            if let Some(list) = children.get_mut("children").and_then(Value::as_array_mut) {
                list.retain(|c| c.as_u64() != Some(node as u64));
                if list.is_empty()
                    && let Some(o) = children.as_object_mut()
                {
                    o.remove("children");
                }
            }
            for &s in shown {
                push(&mut self.json["scenes"][s]["nodes"], json!(node));
            }
            self.parent[node] = None;
        }
        if let Some(o) = self.json["nodes"][node].as_object_mut() {
            for key in ["matrix", "translation", "rotation", "scale"] {
                o.remove(key);
            }
            o.insert("skin".into(), json!(skin));
        }
        self.locals[node] = DMat4::IDENTITY;
        self.world = world_matrices(&self.parent, &self.locals)
            .unwrap_or_else(|| std::mem::take(&mut self.world));
    }

    /// A new root node (listed in the scenes `shown`) draws node `node`'s
    /// mesh with skin `skin`, with its morph weights and their channels; the
    /// node keeps its place and children.
    fn draw_skinned_from_new_root(&mut self, node: usize, skin: usize, shown: &[usize]) {
        let mesh = self.json["nodes"][node]["mesh"].clone();
        let name = self.json["nodes"][node]["name"].as_str().map_or_else(
            || format!("node {node} (skinned)"),
            |n| format!("{n} (skinned)"),
        );
        let mut drawer = json!({"name": name, "mesh": mesh, "skin": skin});
        if let Some(o) = self.json["nodes"][node].as_object_mut() {
            o.remove("mesh");
            if let Some(w) = o.remove("weights") {
                drawer["weights"] = w;
            }
        }
        let index = push(&mut self.json["nodes"], drawer);
        for &s in shown {
            push(&mut self.json["scenes"][s]["nodes"], json!(index));
        }
        for ch in channels::channels(&self.json) {
            if ch.node == Some(node) && ch.path.as_deref() == Some("weights") {
                self.json["animations"][ch.animation]["channels"][ch.channel]["target"]["node"] =
                    json!(index);
            }
        }
        self.parent.push(None);
        self.locals.push(DMat4::IDENTITY);
        self.world.push(DMat4::IDENTITY);
    }
}

#[cfg(test)]
mod tests;
