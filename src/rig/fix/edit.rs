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

use super::accessor::{self, push};
use super::{anim, remap};
use crate::dataset::DataError;
use crate::rig::judge::carry::Remapped;
use crate::rig::read::anim as channels;
use crate::rig::read::gltf::{GltfFile, buffers, inverse_binds, local_matrix, world_matrices};
use crate::rig::read::weights::SkinWeights;
use base64::Engine;
use glam::{DMat4, DQuat, DVec3};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

/// The glTF componentType of unsigned shorts, and of floats.
const UNSIGNED_SHORT: u64 = 5123;
const FLOAT: u64 = 5126;
/// The buffer view target of vertex attributes.
const ARRAY_BUFFER: u64 = 34962;

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

    fn fail(&self, what: impl Into<String>) -> DataError {
        DataError::whole_file(&self.file.label, what)
    }

    fn check_node(&self, node: usize) -> Result<(), DataError> {
        if node < self.parent.len() {
            Ok(())
        } else {
            Err(self.fail(format!("has no node {node}")))
        }
    }

    /// How many ancestors `node` has.
    fn depth(&self, mut node: usize) -> usize {
        let mut d = 0;
        while let Some(p) = self.parent[node] {
            d += 1;
            node = p;
        }
        d
    }

    fn root_of(&self, mut node: usize) -> usize {
        while let Some(p) = self.parent[node] {
            node = p;
        }
        node
    }

    /// Whether `a` is `node` or one of its ancestors.
    fn above(&self, a: usize, mut node: usize) -> bool {
        loop {
            if node == a {
                return true;
            }
            match self.parent[node] {
                Some(p) => node = p,
                None => return false,
            }
        }
    }

    /// Joints must share one root, and a skeleton be an ancestor (or one) of
    /// each, as glTF requires.
    fn check_skeleton(
        &self,
        what: &str,
        joints: &[usize],
        skeleton: Option<usize>,
    ) -> Result<(), DataError> {
        let root = self.root_of(joints[0]);
        if let Some(&n) = joints.iter().find(|&&n| self.root_of(n) != root) {
            return Err(self.fail(format!(
                "the joints of {what} must share one root node: node {n}'s root is node {}, node {}'s is node {root}",
                self.root_of(n),
                joints[0]
            )));
        }
        if let Some(k) = skeleton
            && let Some(&n) = joints.iter().find(|&&n| !self.above(k, n))
        {
            return Err(self.fail(format!(
                "node {n} is not under node {k}, the skeleton of {what}"
            )));
        }
        Ok(())
    }

    /// The scene the file shows by default: `scene`, else the first.
    fn default_scene(&self) -> Option<usize> {
        let scenes = self.json["scenes"].as_array().map_or(0, Vec::len);
        let s = self.json["scene"].as_u64().map_or(0, |s| s as usize);
        (s < scenes).then_some(s)
    }

    /// The scenes that list root node `root`.
    fn scenes_with(&self, root: usize) -> Vec<usize> {
        let list = self.json["scenes"].as_array().map(Vec::as_slice);
        list.unwrap_or_default()
            .iter()
            .enumerate()
            .filter(|(_, s)| {
                s["nodes"]
                    .as_array()
                    .is_some_and(|n| n.iter().any(|n| n.as_u64() == Some(root as u64)))
            })
            .map(|(i, _)| i)
            .collect()
    }

    fn skin_count(&self) -> usize {
        self.json["skins"].as_array().map_or(0, Vec::len)
    }

    /// The joints of skin `skin` as the edit leaves them.
    fn skin_joints(&self, skin: usize) -> Option<Vec<usize>> {
        let joints = self.json["skins"].get(skin)?["joints"].as_array()?;
        Some(
            joints
                .iter()
                .filter_map(|j| j.as_u64().map(|j| j as usize))
                .collect(),
        )
    }

    /// The nodes that draw mesh `mesh`.
    fn drawers(&self, mesh: usize) -> Vec<usize> {
        let nodes = self.json["nodes"].as_array().map(Vec::as_slice);
        nodes
            .unwrap_or_default()
            .iter()
            .enumerate()
            .filter(|(_, n)| n["mesh"].as_u64() == Some(mesh as u64))
            .map(|(i, _)| i)
            .collect()
    }

    /// The one skin with which every node that draws `mesh` draws it.
    fn skin_of_mesh(&self, mesh: usize) -> Result<usize, DataError> {
        let drawers = self.drawers(mesh);
        let skins: BTreeSet<Option<u64>> = drawers
            .iter()
            .map(|&n| self.json["nodes"][n]["skin"].as_u64())
            .collect();
        match skins.into_iter().collect::<Vec<_>>().as_slice() {
            [Some(s)] => Ok(*s as usize),
            [] => Err(self.fail(format!("no node draws mesh {mesh}"))),
            [None] => Err(self.fail(format!(
                "mesh {mesh} has no skin to weight it to; bind it to one first (a new skin)"
            ))),
            _ => Err(self.fail(format!(
                "mesh {mesh} is drawn by nodes {drawers:?} with different skins (or none); its weights cannot serve them all"
            ))),
        }
    }

    /// The rest skin matrices M = W B of the file's skin `skin`, by joint slot.
    fn file_rest(&self, skin: usize) -> Result<(Vec<usize>, Vec<DMat4>), DataError> {
        let s = self
            .file
            .document
            .skins()
            .nth(skin)
            .ok_or_else(|| self.fail(format!("has no skin {skin}")))?;
        let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
        let ibm = inverse_binds(&self.data, &s, joints.len()).map_err(|e| self.fail(e))?;
        let rest = joints
            .iter()
            .zip(&ibm)
            .map(|(&j, b)| self.file.world[j] * *b)
            .collect();
        Ok((joints, rest))
    }

    /// Where a joint added to skin `skin` binds: a new skin's mesh's rest
    /// matrix, or the rest skin matrix of the node's nearest ancestor among
    /// the file's joints of the skin (its first joint when none is one).
    fn rest_of_new_joint(&self, skin: usize, node: usize) -> Result<DMat4, DataError> {
        if let Some(&m) = self.new_skins.get(&skin) {
            return Ok(m);
        }
        let (joints, rest) = self.file_rest(skin)?;
        let mut at = Some(node);
        while let Some(n) = at {
            if let Some(k) = joints.iter().position(|&j| j == n) {
                return Ok(rest[k]);
            }
            at = self.parent[n];
        }
        rest.first()
            .copied()
            .ok_or_else(|| self.fail(format!("skin {skin} has no joints")))
    }

    /// When new weights move vertices of the file's skin `skin` off their
    /// rest (its joints bind at different rest matrices), a remark saying how
    /// many and how far.
    fn rest_drift(
        &self,
        skin: usize,
        mesh: usize,
        primitive: usize,
        slots: &[Vec<(u32, f64)>],
    ) -> Option<String> {
        if self.new_skins.contains_key(&skin) {
            return None;
        }
        let (joints, mut rest) = self.file_rest(skin).ok()?;
        rest.extend(self.added.get(&skin).into_iter().flatten().map(|a| a.1));
        if rest.iter().all(|m| m.abs_diff_eq(rest[0], 1e-9)) {
            return None;
        }
        let prim = self
            .file
            .document
            .meshes()
            .nth(mesh)?
            .primitives()
            .nth(primitive)?;
        let at = format!("/meshes/{mesh}/primitives/{primitive}");
        let (positions, old) =
            crate::rig::read::skin::read_vertices(&prim, &at, &self.data, joints.len()).ok()?;
        let was = |v: usize| {
            let sum: f64 = old[v].iter().map(|x| x.1).sum();
            let at: DVec3 = old[v]
                .iter()
                .map(|&(s, w)| w * rest[usize::from(s)].transform_point3(positions[v]))
                .sum();
            (sum > 0.0).then(|| at / sum)
        };
        let (lo, hi) = positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let tolerance = 1e-5 * lo.distance(hi).max(1e-9);
        let (mut moved, mut most) = (0usize, 0.0f64);
        for (v, s) in slots.iter().enumerate() {
            let Some(before) = was(v) else { continue };
            let now: DVec3 = s
                .iter()
                .filter_map(|&(k, w)| {
                    rest.get(k as usize)
                        .map(|m| w * m.transform_point3(positions[v]))
                })
                .sum();
            let d = now.distance(before);
            if d > tolerance {
                moved += 1;
                most = most.max(d);
            }
        }
        (moved > 0).then(|| {
            format!(
                "{at}: {moved} vertices rest up to {most:.6} (the file's units) from where they did: \
                 skin {skin} binds its joints at different rest matrices (its bind pose is not its \
                 rest pose), so new weights move them"
            )
        })
    }

    /// Every primitive of a mesh bound to a new skin must have weights.
    fn check_new_skins_weighted(&self) -> Result<(), DataError> {
        for &skin in self.new_skins.keys() {
            let meshes: BTreeSet<usize> = (0..self.parent.len())
                .filter(|&n| self.json["nodes"][n]["skin"].as_u64() == Some(skin as u64))
                .filter_map(|n| self.json["nodes"][n]["mesh"].as_u64().map(|m| m as usize))
                .collect();
            for m in meshes {
                let prims = self.json["meshes"][m]["primitives"].as_array();
                for (p, prim) in prims.into_iter().flatten().enumerate() {
                    let set = self.writes.iter().any(|w| {
                        matches!(w, Write::Set { mesh, primitive, .. } if *mesh == m && *primitive == p)
                    });
                    if !set && prim["attributes"].get("JOINTS_0").is_none() {
                        return Err(self.fail(format!(
                            "/meshes/{m}/primitives/{p} is bound to new skin {skin} but has no weights; set them"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// Inverse bind matrices for every skin of the file whose joints moved or
    /// were added, and for every new skin: written over the old ones when
    /// that accessor serves this skin alone and keeps its count, else as a
    /// new accessor (the old one, when it served only this skin, joins
    /// `unused`).
    fn rebind(&mut self, unused: &mut BTreeSet<usize>) -> Result<(), DataError> {
        let file = self.file;
        for skin in file.document.skins() {
            let s = skin.index();
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            let added = self.added.get(&s).cloned().unwrap_or_default();
            if added.is_empty() && !joints.iter().any(|&j| self.world[j] != file.world[j]) {
                continue;
            }
            let ibm = inverse_binds(&self.data, &skin, joints.len()).map_err(|e| self.fail(e))?;
            let mut new = Vec::with_capacity(joints.len() + added.len());
            for (&j, b) in joints.iter().zip(&ibm) {
                new.push(self.checked(j, self.world[j].inverse() * file.world[j] * *b)?);
            }
            for &(n, m) in &added {
                new.push(self.checked(n, self.world[n].inverse() * m)?);
            }
            let own = skin
                .inverse_bind_matrices()
                .map(|a| a.index())
                .filter(|&a| accessor::references(&self.json).get(&a) == Some(&1));
            let span = own
                .filter(|_| added.is_empty())
                .and_then(|a| accessor::span(&self.json, a, self.bin.len()).map(|s| (a, s)));
            match span {
                Some((a, span)) if span.component == FLOAT && span.components == 16 => {
                    for (k, m) in new.iter().enumerate() {
                        span.write_f32(&mut self.bin, k, m);
                    }
                    accessor::refresh_bounds(&mut self.json, a, &span, &self.bin);
                }
                _ => {
                    self.append_binds(s, &new);
                    if !added.is_empty() {
                        unused.extend(own);
                    }
                }
            }
        }
        let new_skins: Vec<usize> = self.new_skins.keys().copied().collect();
        for s in new_skins {
            let mut new = Vec::new();
            for &(n, m) in self.added.get(&s).map(Vec::as_slice).unwrap_or_default() {
                new.push(self.checked(n, self.world[n].inverse() * m)?);
            }
            self.append_binds(s, &new);
        }
        Ok(())
    }

    /// An inverse bind matrix as stored, or the error of a singular joint.
    fn checked(&self, joint: usize, m: DMat4) -> Result<[f32; 16], DataError> {
        if m.is_finite() {
            Ok(m.to_cols_array().map(|v| v as f32))
        } else {
            Err(self.fail(format!(
                "joint node {joint} has a singular world transform; cannot update its inverse bind matrix"
            )))
        }
    }

    /// Appends inverse bind matrices as a new accessor of skin `skin`.
    fn append_binds(&mut self, skin: usize, matrices: &[[f32; 16]]) {
        let bytes: Vec<u8> = matrices
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = accessor::append_view(&mut self.json, &mut self.bin, &bytes, None);
        let acc = push(
            &mut self.json["accessors"],
            json!({"bufferView": view, "componentType": FLOAT, "count": matrices.len(), "type": "MAT4"}),
        );
        self.json["skins"][skin]["inverseBindMatrices"] = json!(acc);
    }

    /// Writes one primitive's weights (see [`Edit::set_weights`]); the
    /// accessors a replacement stops naming join `unused`.
    fn write_set(
        &mut self,
        mesh: usize,
        primitive: usize,
        slots: &[Vec<(u32, f64)>],
        unused: &mut BTreeSet<usize>,
    ) {
        let attrs = &self.json["meshes"][mesh]["primitives"][primitive]["attributes"];
        let mut sets = Vec::new();
        while let (Some(j), Some(w)) = (
            attrs[format!("JOINTS_{}", sets.len())].as_u64(),
            attrs[format!("WEIGHTS_{}", sets.len())].as_u64(),
        ) {
            sets.push((j as usize, w as usize));
        }
        let named = accessor::references(&self.json);
        let count = slots.len();
        let plain = |a: usize, joints: bool| {
            let sp = accessor::span(&self.json, a, self.bin.len())?;
            let stored = if joints {
                matches!(sp.component, 5121 | 5123) && !sp.normalized
            } else {
                matches!(
                    (sp.component, sp.normalized),
                    (FLOAT, false) | (5121 | 5123, true)
                )
            };
            (named.get(&a) == Some(&1) && sp.count == count && sp.components == 4 && stored)
                .then_some(sp)
        };
        let spans: Option<Vec<_>> = sets
            .iter()
            .map(|&(j, w)| Some((plain(j, true)?, plain(w, false)?)))
            .collect();
        let top = slots.iter().flatten().map(|s| s.0).max().unwrap_or(0);
        if let Some(spans) = spans.filter(|s| s.first().is_some_and(|(j, _)| top <= j.uint_max())) {
            for (v, s) in slots.iter().enumerate() {
                remap::write_vertex(&mut self.bin, &spans, v, s);
            }
            for (&(j, w), (js, ws)) in sets.iter().zip(&spans) {
                accessor::refresh_bounds(&mut self.json, j, js, &self.bin);
                accessor::refresh_bounds(&mut self.json, w, ws, &self.bin);
            }
            return;
        }
        let mut joints = Vec::with_capacity(8 * count);
        let mut weights = Vec::with_capacity(16 * count);
        for s in slots {
            let mut j = [0u16; 4];
            let mut w = [0.0f64; 4];
            for (k, &(slot, x)) in s.iter().take(4).enumerate() {
                j[k] = slot as u16;
                w[k] = x;
            }
            joints.extend(j.iter().flat_map(|x| x.to_le_bytes()));
            weights.extend(
                remap::float_weights(&w)
                    .iter()
                    .flat_map(|x| x.to_le_bytes()),
            );
        }
        let mut add = |bytes: &[u8], component: u64| {
            let view =
                accessor::append_view(&mut self.json, &mut self.bin, bytes, Some(ARRAY_BUFFER));
            push(
                &mut self.json["accessors"],
                json!({"bufferView": view, "componentType": component, "count": count, "type": "VEC4"}),
            )
        };
        let (j, w) = (add(&joints, UNSIGNED_SHORT), add(&weights, FLOAT));
        if let Some(attrs) =
            self.json["meshes"][mesh]["primitives"][primitive]["attributes"].as_object_mut()
        {
            for (n, &(js, ws)) in sets.iter().enumerate() {
                attrs.remove(&format!("JOINTS_{n}"));
                attrs.remove(&format!("WEIGHTS_{n}"));
                unused.extend([js, ws]);
            }
            attrs.insert("JOINTS_0".into(), json!(j));
            attrs.insert("WEIGHTS_0".into(), json!(w));
        }
    }
}

/// A node named `name` whose translation, rotation and scale (at f32
/// precision, defaults left out) make `local`, and the local matrix they
/// make as a reader computes it; `None` when `local` shears.
fn trs_node(name: &str, local: &DMat4) -> Option<(Value, DMat4)> {
    let (s, r, t) = local.to_scale_rotation_translation();
    let snap = |x: f64| if x.abs() < 1e-12 { 0.0 } else { x };
    let f32s = |v: [f64; 3]| v.map(|x| f64::from(snap(x) as f32));
    let t = f32s(t.to_array());
    let s = f32s(s.to_array()).map(|x| if (x - 1.0).abs() < 1e-12 { 1.0 } else { x });
    let r = r.to_array().map(|x| f64::from(snap(x) as f32));
    let stored = DMat4::from_scale_rotation_translation(
        DVec3::from_array(s),
        DQuat::from_array(r).normalize(),
        DVec3::from_array(t),
    );
    // A rotation and scale reproduce the upper 3x3 up to f32 rounding; a shear they cannot.
    let size = (0..3)
        .map(|c| local.col(c).truncate().abs().max_element())
        .fold(0.0, f64::max);
    let off = (0..3)
        .map(|c| {
            (stored.col(c) - local.col(c))
                .truncate()
                .abs()
                .max_element()
        })
        .fold(0.0, f64::max);
    if off.is_nan() || off > 1e-5 * size {
        return None;
    }
    let mut node = json!({"name": name, "translation": t});
    if r != [0.0, 0.0, 0.0, 1.0] && r != [0.0, 0.0, 0.0, -1.0] {
        node["rotation"] = json!(r);
    }
    if s != [1.0; 3] {
        node["scale"] = json!(s);
    }
    Some((node, stored))
}

/// Writes a node's new local translation into its JSON (into `matrix` when it has one).
fn write_translation(node: &mut Value, t: DVec3) {
    if let Some(m) = node.get_mut("matrix").and_then(Value::as_array_mut) {
        for (k, v) in t.to_array().into_iter().enumerate() {
            m[12 + k] = json!(v);
        }
    } else {
        node["translation"] = json!(t.to_array());
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
        accessor::pad4(&mut bin);
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

/// Remarks on what an edit leaves alone: animation channels with paths glTF
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

#[cfg(test)]
mod tests;
