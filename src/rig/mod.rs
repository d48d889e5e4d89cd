//! Rigged hands: reading their finger chains from a glTF 2.0 file, judging
//! them against the X-ray statistics ([`judge`], on the chain geometry of
//! `chain`) and writing a fixed copy ([`fix`]).
//!
//! Joint positions are the world translations of the joint nodes in the
//! file's node pose (the bind pose of an exported rig), in the file's units
//! (metres by the glTF specification). Candidate nodes are the joints of any
//! skin and their descendants (tip nodes are often unskinned leaves); a file
//! without skins is read as a bare skeleton, every node a candidate. Names are
//! read by [`naming`], VRM's humanoid bone tables when present, and a
//! `--map` file ([`map`]) first of all.

pub(crate) mod accessor;
pub(crate) mod anim;
pub mod bend;
pub(crate) mod chain;
pub mod deform;
pub mod fix;
pub mod judge;
pub mod map;
pub mod naming;
pub mod ray;
pub mod reference;
pub(crate) mod remap;
pub mod session;
pub mod skin;
pub mod weights;

use crate::analysis::placement::Joint;
use crate::dataset::{DataError, Finger, Problem};
use glam::{DMat4, DQuat, DVec3};
use judge::ChainInput;
use map::NameMap;
use naming::{Part, Side, Slot};
use schemars::JsonSchema;
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// One joint of a rig finger.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RigJoint {
    pub joint: Joint,
    /// Index of the node in the glTF file (`None` for reference rigs).
    pub node: Option<usize>,
    /// The node's name.
    pub name: String,
    /// World position in the node pose.
    #[schemars(with = "[f64; 3]")]
    pub position: DVec3,
    /// Whether the node carries skin weight (`None` when unknown: no skin, or
    /// weights that could not be read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weighted: Option<bool>,
}

/// A node next to a finger: its metacarpal bone or the hand's wrist bone.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RigNode {
    pub node: usize,
    pub name: String,
    /// World position of the node's origin (the CMC joint for a metacarpal,
    /// the wrist joint for a hand bone).
    #[schemars(with = "[f64; 3]")]
    pub position: DVec3,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weighted: Option<bool>,
}

/// One finger chain found in a rig: root (MCP), inner joints, and the tip when present.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct FingerChain {
    /// `None` when the names do not say (a one-hand file such as WebXR's).
    pub side: Option<Side>,
    pub finger: Finger,
    pub joints: Vec<RigJoint>,
    pub has_tip: bool,
    /// The finger's metacarpal bone (the thumb's CMC bone), when recognised.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metacarpal: Option<RigNode>,
    /// The hand's wrist (hand) bone, when recognised.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrist: Option<RigNode>,
    /// False when the joints are not parent and child in the node hierarchy
    /// (WebXR's siblings): the chain is read from the names alone.
    pub hierarchy: bool,
}

impl FingerChain {
    /// The chain's geometry, for the analysis.
    pub fn input(&self) -> ChainInput {
        ChainInput {
            finger: self.finger,
            points: self.joints.iter().map(|j| j.position).collect(),
            has_tip: self.has_tip,
        }
    }

    /// "right index", "left thumb", or "index" when the side is unknown.
    pub fn label(&self) -> String {
        match self.side {
            Some(s) => format!("{} {}", s.name(), self.finger),
            None => self.finger.to_string(),
        }
    }
}

/// A glTF file, parsed, with its node hierarchy evaluated.
pub struct GltfFile {
    /// The file as the user named it.
    pub label: String,
    pub document: gltf::Document,
    /// The JSON part, for edits that must keep every field of the file.
    pub json: serde_json::Value,
    /// The binary chunk of a .glb file.
    pub blob: Option<Vec<u8>>,
    /// Each node's parent.
    pub parent: Vec<Option<usize>>,
    /// Each node's world matrix in the node pose.
    pub world: Vec<DMat4>,
    /// The folder of the file, where external buffers are read (`None` for
    /// bytes not read from a file: external buffers are then not read).
    pub dir: Option<PathBuf>,
}

/// The local matrix of a node, in f64.
pub(crate) fn local_matrix(node: &gltf::Node<'_>) -> DMat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => DMat4::from_scale_rotation_translation(
            DVec3::from_array(scale.map(f64::from)),
            DQuat::from_array(rotation.map(f64::from)).normalize(),
            DVec3::from_array(translation.map(f64::from)),
        ),
    }
}

impl GltfFile {
    /// Reads a .gltf or .glb file (external buffers are not needed to audit).
    pub fn load(path: &Path) -> Result<GltfFile, DataError> {
        let label = path.display().to_string();
        let bytes = crate::dataset::csvinput::read_input(path)?;
        let mut file = GltfFile::from_bytes(&label, &bytes)?;
        file.dir = Some(path.parent().unwrap_or(Path::new(".")).to_path_buf());
        Ok(file)
    }

    /// The data of every buffer, when all can be read: from the GLB chunk
    /// and data URIs, and from files beside it when read from a file.
    pub fn buffer_data(&self) -> Option<Vec<Vec<u8>>> {
        let external = self
            .document
            .buffers()
            .any(|b| matches!(b.source(), gltf::buffer::Source::Uri(u) if !u.starts_with("data:")));
        let dir = match (&self.dir, external) {
            (Some(d), _) => d.clone(),
            (None, false) => PathBuf::from("."),
            (None, true) => return None,
        };
        fix::buffers(self, &dir).ok()
    }

    /// Parses the bytes of a glTF file; `label` names it in errors.
    ///
    /// The JSON is validated by the gltf crate, except `extensionsRequired`:
    /// an audit reads only nodes and skins, so a file needing, say, mesh
    /// compression is still read. Node transforms must give finite world
    /// matrices. Never panics: the few inputs known to panic inside the gltf
    /// crate are refused first, and any other panic there becomes an error.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<GltfFile, DataError> {
        let fail = |what: String| DataError::whole_file(label, what);
        let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
            split_glb(bytes).map_err(|e| fail(format!("has a broken GLB container: {e}")))?
        } else {
            (bytes, None)
        };
        let json: serde_json::Value = serde_json::from_slice(json_bytes).map_err(|e| {
            fail(format!(
                "is not a valid glTF 2.0 file (its JSON is unreadable: {e}); export it as glTF 2.0 (.glb or .gltf)"
            ))
        })?;
        precheck(&json).map_err(|e| fail(format!("is not a valid glTF 2.0 file ({e})")))?;
        let mut for_document = json.clone();
        if let Some(o) = for_document.as_object_mut() {
            o.remove("extensionsRequired");
        }
        // Channels the gltf crate cannot read (a path it does not know, or
        // KHR_animation_pointer's target without a node) are left out of its
        // copy: the raw JSON keeps them, reported and untouched (see anim).
        // (`get_mut`, not indexing: indexing a missing key would add a null.)
        if let Some(list) = for_document
            .get_mut("animations")
            .and_then(serde_json::Value::as_array_mut)
        {
            for anim in list.iter_mut() {
                if let Some(chs) = anim.get_mut("channels").and_then(|c| c.as_array_mut()) {
                    chs.retain(anim::is_plain);
                }
            }
            list.retain(|a| a["channels"].as_array().is_some_and(|c| !c.is_empty()));
        }
        let root: gltf::json::Root = serde_json::from_value(for_document).map_err(|e| {
            fail(format!(
                "is not a valid glTF 2.0 file ({e}); export it as glTF 2.0 (.glb or .gltf)"
            ))
        })?;
        let document = quietly(|| gltf::Document::from_json(root))
            .ok_or_else(|| {
                fail("could not be parsed: the glTF reader failed on it; re-export it".into())
            })?
            .map_err(|e| {
                fail(format!(
                    "is not a valid glTF 2.0 file ({e}); export it as glTF 2.0 (.glb or .gltf)"
                ))
            })?;
        let n = document.nodes().len();
        let mut parent = vec![None; n];
        for node in document.nodes() {
            for child in node.children() {
                if parent[child.index()].is_some() {
                    return Err(fail(format!(
                        "node {} has two parents; a glTF node hierarchy must be a forest",
                        child.index()
                    )));
                }
                parent[child.index()] = Some(node.index());
            }
        }
        let locals: Vec<DMat4> = document.nodes().map(|n| local_matrix(&n)).collect();
        let world = world_matrices(&parent, &locals).ok_or_else(|| {
            fail("has a cycle in its node hierarchy; a node cannot be its own ancestor".into())
        })?;
        Ok(GltfFile {
            label: label.to_string(),
            document,
            json,
            blob: blob.map(<[u8]>::to_vec),
            parent,
            world,
            dir: None,
        })
    }

    /// The names of all nodes (index order), unnamed ones as `#i`.
    pub fn node_names(&self) -> Vec<String> {
        self.document
            .nodes()
            .map(|n| {
                n.name()
                    .map_or_else(|| format!("#{}", n.index()), str::to_string)
            })
            .collect()
    }
}

/// The JSON and binary chunks of a GLB file, with every length checked.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at.checked_add(4)?)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = word(4).ok_or("the header is cut short")?;
    if version != 2 {
        return Err(format!("version {version}; only glTF 2.0 is read"));
    }
    let total = word(8).ok_or("the header is cut short")? as usize;
    if total < 20 || total > bytes.len() {
        return Err(format!("it declares {total} bytes but has {}", bytes.len()));
    }
    let mut chunks = Vec::new();
    let mut at = 12usize;
    while at < total {
        let len = word(at).ok_or("a chunk header is cut short")? as usize;
        let kind = word(at + 4).ok_or("a chunk header is cut short")?;
        let start = at + 8;
        let end = start
            .checked_add(len)
            .filter(|&e| e <= total)
            .ok_or("a chunk runs past the end")?;
        chunks.push((kind, &bytes[start..end]));
        at = end;
    }
    match chunks.as_slice() {
        [(0x4E4F_534A, json), rest @ ..] => {
            let bin = rest
                .iter()
                .find(|(k, _)| *k == 0x004E_4942)
                .map(|(_, b)| *b);
            Ok((json, bin))
        }
        _ => Err("its first chunk is not JSON".into()),
    }
}

/// Refuses what is known to panic inside the gltf crate's validation: a mesh
/// attribute naming an accessor that does not exist.
fn precheck(json: &serde_json::Value) -> Result<(), String> {
    let accessors = json["accessors"].as_array().map_or(0, Vec::len);
    for (m, mesh) in json["meshes"].as_array().into_iter().flatten().enumerate() {
        for (p, prim) in mesh["primitives"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            let targets = prim["targets"].as_array().into_iter().flatten();
            for attrs in std::iter::once(&prim["attributes"]).chain(targets) {
                for (name, v) in attrs.as_object().into_iter().flatten() {
                    if v.as_u64().is_none_or(|i| i >= accessors as u64) {
                        return Err(format!(
                            "mesh {m} primitive {p} attribute {name} names accessor {v}, which does not exist"
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The joint a slot stands for on `finger`, for messages.
fn slot_name(finger: Finger, slot: Slot) -> &'static str {
    match (slot, finger) {
        (Slot::Carpal, _) => "CMC",
        (Slot::Mcp, _) => "MCP",
        (Slot::First, Finger::Thumb) => "IP",
        (Slot::First, _) => "PIP",
        (Slot::Second, _) => "DIP",
        (Slot::Tip, _) => "tip",
    }
}

/// True when `node` lies below `ancestor` in the node hierarchy (or is it).
fn below(parent: &[Option<usize>], node: usize, ancestor: usize) -> bool {
    let mut at = Some(node);
    let mut steps = 0;
    while let Some(i) = at {
        if i == ancestor {
            return true;
        }
        steps += 1;
        if steps > parent.len() {
            return false;
        }
        at = parent[i];
    }
    false
}

/// A node name fit for a message or a terminal: quoted, control characters
/// replaced, at most 80 characters.
pub(crate) fn shown(name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| if c.is_control() { '\u{FFFD}' } else { c })
        .collect();
    crate::dataset::csvinput::quote(&clean)
}

thread_local! {
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, turning a panic into `None` without printing it. One panic hook,
/// installed once, stays silent while its thread is inside `quietly` and
/// otherwise passes on to the hook that was there before, so concurrent
/// callers cannot leave the process with a silent hook.
fn quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).ok();
    QUIET.with(|q| q.set(false));
    out
}

/// World matrices from parents and local matrices; `None` on a cycle. O(n depth).
pub(crate) fn world_matrices(parent: &[Option<usize>], locals: &[DMat4]) -> Option<Vec<DMat4>> {
    let n = locals.len();
    let mut world: Vec<Option<DMat4>> = vec![None; n];
    for start in 0..n {
        let mut path = vec![start];
        while let Some(p) = parent[*path.last()?] {
            if world[p].is_some() {
                break;
            }
            if path.len() > n {
                return None;
            }
            path.push(p);
        }
        for &i in path.iter().rev() {
            if world[i].is_none() {
                let up = parent[i].map_or(DMat4::IDENTITY, |p| world[p].unwrap_or(DMat4::IDENTITY));
                world[i] = Some(up * locals[i]);
            }
        }
    }
    world.into_iter().collect()
}

/// A rig's fingers, as found in a glTF file.
pub struct Rig {
    pub file: GltfFile,
    pub chains: Vec<FingerChain>,
    /// Fingers seen but incomplete, and other remarks.
    pub notes: Vec<String>,
    /// The skin weights, when the file has skins whose weights could be read.
    pub weights: Option<weights::SkinWeights>,
}

/// How a node was recognised: (side, finger, slot, priority; lower wins).
type Found = (Option<Side>, Finger, Slot, u8);

/// Priorities of the nodes that fit a joint (lower wins): a `--map` entry, a
/// VRM humanoid table, then a bone carrying skin weight (a Rigify `DEF-` bone
/// first), a `DEF-` bone without weight, a skin joint, any other node.
mod priority {
    pub const MAP: u8 = 0;
    pub const VRM: u8 = 1;
    pub const WEIGHTED_DEFORM: u8 = 2;
    pub const WEIGHTED: u8 = 3;
    pub const DEFORM: u8 = 4;
    pub const SKIN_JOINT: u8 = 5;
    pub const OTHER: u8 = 6;

    /// The priority of a node recognised by its name.
    pub fn of(deform: bool, weighted: bool, skin_joint: bool) -> u8 {
        match (weighted, deform, skin_joint) {
            (true, true, _) => WEIGHTED_DEFORM,
            (true, false, _) => WEIGHTED,
            (false, true, _) => DEFORM,
            (false, false, true) => SKIN_JOINT,
            _ => OTHER,
        }
    }

    /// True when the priority says the node carries skin weight.
    pub fn weighted(p: u8) -> bool {
        p == WEIGHTED_DEFORM || p == WEIGHTED
    }
}

/// VRM humanoid bones (0.x `extensions.VRM`, 1.0 `extensions.VRMC_vrm`) as (node, bone name, 0.x?).
fn vrm_bones(json: &serde_json::Value) -> Vec<(usize, String, bool)> {
    let mut out = Vec::new();
    let ext = &json["extensions"];
    if let Some(bones) = ext["VRMC_vrm"]["humanoid"]["humanBones"].as_object() {
        for (name, b) in bones {
            if let Some(node) = b["node"].as_u64() {
                out.push((node as usize, name.clone(), false));
            }
        }
    }
    if let Some(bones) = ext["VRM"]["humanoid"]["humanBones"].as_array() {
        for b in bones {
            if let (Some(name), Some(node)) = (b["bone"].as_str(), b["node"].as_u64()) {
                out.push((node as usize, name.to_string(), true));
            }
        }
    }
    out
}

/// Which nodes may be finger joints (the joints of any skin and everything
/// below them; every node of a file without skins), and which are skinned. O(n).
fn candidates(file: &GltfFile) -> (Vec<bool>, Vec<bool>) {
    let n = file.parent.len();
    let mut candidate = vec![false; n];
    let mut skinned = vec![false; n];
    let skins: Vec<_> = file.document.skins().collect();
    for skin in &skins {
        for j in skin.joints() {
            skinned[j.index()] = true;
        }
    }
    if skins.is_empty() {
        candidate.fill(true);
    } else {
        // Skinned joints and everything below them, each node visited once.
        let mut children = vec![Vec::new(); n];
        for (i, p) in file.parent.iter().enumerate() {
            if let Some(p) = *p {
                children[p].push(i);
            }
        }
        let mut stack: Vec<usize> = (0..n).filter(|&i| skinned[i]).collect();
        while let Some(i) = stack.pop() {
            if !std::mem::replace(&mut candidate[i], true) {
                stack.extend_from_slice(&children[i]);
            }
        }
    }
    (candidate, skinned)
}

/// The skin weights of a file with a skin whose buffers are at hand.
fn skin_weights(file: &GltfFile) -> Option<weights::SkinWeights> {
    (file.document.skins().next().is_some())
        .then(|| file.buffer_data())
        .flatten()
        .map(|data| weights::SkinWeights::read(file, &data))
}

/// Per node, whether any vertex is weighted to it (empty without weights).
fn weighted_nodes(weights: Option<&weights::SkinWeights>, nodes: usize) -> Vec<bool> {
    weights.map_or_else(Vec::new, |w| w.weighted_nodes(nodes))
}

/// How each node is recognised: by the `--map` file first, then by a VRM
/// humanoid table, then by its name; with the priority of each (lower wins).
fn recognise(
    file: &GltfFile,
    names: &[String],
    map: Option<&NameMap>,
    weighted: &[bool],
) -> Result<Vec<Option<Found>>, DataError> {
    let n = names.len();
    let (candidate, skinned) = candidates(file);
    let mut found: Vec<Option<Found>> = vec![None; n];
    let mut problems = Vec::new();
    if let Some(map) = map {
        for (name, &(side, finger, slot, line)) in &map.entries {
            match names.iter().position(|x| x == name) {
                Some(i) => found[i] = Some((side, finger, slot, priority::MAP)),
                None => problems.push(Problem::line(
                    line,
                    format!(
                        "node {} is not in {}; node names must match exactly",
                        crate::dataset::csvinput::quote(name),
                        file.label
                    ),
                )),
            }
        }
        if !problems.is_empty() {
            problems.sort_by_key(|p| p.line);
            return Err(DataError {
                file: map.file.clone(),
                problems,
            });
        }
    }
    // VRM tables, then names; a VRM 0.x thumb shifts by one (see naming).
    let mut parsed: Vec<Option<(naming::Parsed, Option<bool>)>> = vec![None; n];
    for (node, bone, vrm0) in vrm_bones(&file.json) {
        if let (Some(slot), Some(p)) = (parsed.get_mut(node), naming::parse(&bone)) {
            *slot = Some((p, Some(vrm0)));
        }
    }
    for (i, name) in names.iter().enumerate() {
        if parsed[i].is_none() && candidate[i] {
            parsed[i] = naming::parse(name).map(|p| (p, None));
        }
    }
    let vrm0_thumb: Vec<Option<Side>> = parsed
        .iter()
        .flatten()
        .filter(|(p, _)| p.finger == Finger::Thumb && p.part == Part::Intermediate)
        .map(|(p, _)| p.side)
        .collect();
    for i in 0..n {
        if found[i].is_some() {
            continue;
        }
        if let Some((p, vrm)) = parsed[i] {
            let vrm0 = vrm.unwrap_or_else(|| vrm0_thumb.contains(&p.side));
            if let Some(slot) = naming::slot(p.finger, p.part, vrm0) {
                let prio = if vrm.is_some() {
                    priority::VRM
                } else {
                    priority::of(p.deform, weighted.get(i) == Some(&true), skinned[i])
                };
                found[i] = Some((p.side, p.finger, slot, prio));
            }
        }
    }
    Ok(found)
}

impl Rig {
    /// Reads a rig and finds its finger chains. Fails, listing the names it
    /// saw, when no complete finger is found.
    pub fn load(path: &Path, map: Option<&NameMap>) -> Result<Rig, DataError> {
        Rig::from_file(GltfFile::load(path)?, map)
    }

    /// Finds the finger chains of a parsed file: the best node for each joint
    /// of each finger, then each finger's chain from those, with its
    /// metacarpal and the hand's wrist bone when recognised.
    pub fn from_file(file: GltfFile, map: Option<&NameMap>) -> Result<Rig, DataError> {
        let names = file.node_names();
        let weights = skin_weights(&file);
        let weighted = weighted_nodes(weights.as_ref(), names.len());
        let known = |i: usize| weights.as_ref().map(|_| weighted.get(i) == Some(&true));
        let found = recognise(&file, &names, map, &weighted)?;
        let (best, ties) = choose_nodes(&found);
        let mut notes = tie_notes(&best, &ties, &names);
        notes.extend(weight_note(&best, &found, &names));
        let hands = wrists(&file, &names, &weighted);
        let mut groups: BTreeMap<(Option<Side>, Finger), HashMap<Slot, usize>> = BTreeMap::new();
        for (&(side, finger, slot), &(_, node)) in &best {
            groups.entry((side, finger)).or_default().insert(slot, node);
        }
        let mut chains = Vec::new();
        let mut bad = Vec::new();
        let mut by_name = Vec::new();
        for ((side, finger), slots) in groups {
            let unambiguous = !ties.keys().any(|k| k.0 == side && k.1 == finger);
            let found = FingerFound {
                side,
                finger,
                slots: &slots,
                unambiguous,
            };
            match finger_chain(&file, &names, &found, &mut notes) {
                Ok(Some(mut chain)) => {
                    for j in &mut chain.joints {
                        j.weighted = j.node.and_then(known);
                    }
                    let node = |i: usize| RigNode {
                        node: i,
                        name: names[i].clone(),
                        position: file.world[i].w_axis.truncate(),
                        weighted: known(i),
                    };
                    chain.metacarpal = slots
                        .get(&Slot::Carpal)
                        .filter(|&&i| file.world[i].is_finite())
                        .map(|&i| node(i));
                    chain.wrist = wrist_of(&hands, side)
                        .filter(|&i| file.world[i].is_finite())
                        .map(node);
                    if !chain.hierarchy {
                        by_name.push(chain.label());
                    }
                    chains.push(chain);
                }
                Ok(None) => {}
                Err(problem) => bad.push(problem),
            }
        }
        if !bad.is_empty() {
            return Err(DataError {
                file: file.label.clone(),
                problems: bad,
            });
        }
        if !by_name.is_empty() {
            notes.push(format!(
                "{}: the joints are not parent and child in the node hierarchy (siblings, as in \
                 WebXR's hands); each finger is read from its joint names alone, its lengths from \
                 the joints' world positions, and --fix moves each joint node with its own inverse \
                 bind matrix",
                by_name.join(", ")
            ));
        }
        if chains.is_empty() {
            return Err(no_hand(&file.label, &names, notes));
        }
        if let Some(w) = &weights {
            notes.extend(w.notes.iter().cloned());
        }
        Ok(Rig {
            file,
            chains,
            notes,
            weights,
        })
    }

    /// The chains of each hand for the deformation measures ([`deform`]):
    /// per side, the fingers' metacarpal, bending joints and tip nodes and the
    /// wrist. Fingers whose names carry no side (WebXR) are given `unsided`,
    /// or left out when it is `None`. Reference chains without nodes are left out.
    pub fn hand_chains(&self, unsided: Option<Side>) -> Vec<deform::HandChains> {
        let mut hands: BTreeMap<Side, deform::HandChains> = BTreeMap::new();
        for c in &self.chains {
            let Some(side) = c.side.or(unsided) else {
                continue;
            };
            if c.joints.iter().any(|j| j.node.is_none()) {
                continue;
            }
            let bending: Vec<usize> = c
                .joints
                .iter()
                .filter(|j| j.joint != Joint::Tip)
                .filter_map(|j| j.node)
                .collect();
            let hand = hands.entry(side).or_insert_with(|| deform::HandChains {
                side,
                wrist: c.wrist.as_ref().map(|w| w.node),
                fingers: Vec::new(),
            });
            if hand.wrist.is_none() {
                hand.wrist = c.wrist.as_ref().map(|w| w.node);
            }
            hand.fingers.push(deform::FingerNodes {
                finger: c.finger,
                metacarpal: c.metacarpal.as_ref().map(|m| m.node),
                joints: bending,
                tip: c
                    .joints
                    .iter()
                    .find(|j| j.joint == Joint::Tip)
                    .and_then(|j| j.node),
            });
        }
        hands.into_values().collect()
    }
}

/// What was found for one finger: its nodes per slot, and whether no other
/// node would fit any of them as well.
struct FingerFound<'a> {
    side: Option<Side>,
    finger: Finger,
    slots: &'a HashMap<Slot, usize>,
    unambiguous: bool,
}

/// The wrist (hand) bones recognised: (side, priority, node), best first per side.
fn wrists(file: &GltfFile, names: &[String], weighted: &[bool]) -> Vec<(Option<Side>, u8, usize)> {
    let (candidate, skinned) = candidates(file);
    let mut out: Vec<(Option<Side>, u8, usize)> = names
        .iter()
        .enumerate()
        .filter(|&(i, _)| candidate[i] || skinned[i])
        .filter_map(|(i, name)| {
            naming::parse_hand(name).map(|h| {
                let p = priority::of(h.deform, weighted.get(i) == Some(&true), skinned[i]);
                (h.side, p, i)
            })
        })
        .collect();
    out.sort();
    out
}

/// The wrist of the hand on `side`: the best of that side; for a finger
/// without a side, the only hand bone of the file.
fn wrist_of(hands: &[(Option<Side>, u8, usize)], side: Option<Side>) -> Option<usize> {
    if let Some(&(_, _, i)) = hands.iter().find(|h| h.0 == side) {
        return Some(i);
    }
    let sides: std::collections::BTreeSet<Option<Side>> = hands.iter().map(|h| h.0).collect();
    (side.is_none() && sides.len() == 1).then(|| hands[0].2)
}

/// One note for the joints where a bone carrying skin weight was chosen over
/// an unweighted namesake (Rigify's `DEF-thumb.02.R` over `ORG-thumb.02.R`).
fn weight_note(best: &Best, found: &[Option<Found>], names: &[String]) -> Option<String> {
    let mut pairs = Vec::new();
    for (&(side, finger, slot), &(prio, chosen)) in best {
        if !priority::weighted(prio) {
            continue;
        }
        let losers: Vec<usize> = found
            .iter()
            .enumerate()
            .filter(|&(i, f)| {
                i != chosen
                    && f.is_some_and(|(s, g, t, p)| {
                        (s, g, t) == (side, finger, slot) && p > priority::WEIGHTED
                    })
            })
            .map(|(i, _)| i)
            .collect();
        if let Some(&l) = losers.first() {
            pairs.push(format!(
                "{} over {}",
                shown(&names[chosen]),
                shown(&names[l])
            ));
        }
    }
    if pairs.is_empty() {
        return None;
    }
    let n = pairs.len();
    pairs.truncate(3);
    Some(format!(
        "{n} joint{} had a namesake without skin weight; the bone that carries skin weight was \
         used: {}{}",
        if n == 1 { "" } else { "s" },
        pairs.join(", "),
        if n > 3 { ", ..." } else { "" }
    ))
}

/// A joint of a finger of a hand: (side, finger, slot).
type JointKey = (Option<Side>, Finger, Slot);
/// The node chosen for each joint, with its priority: joint -> (priority, node).
type Best = BTreeMap<JointKey, (u8, usize)>;
/// Other nodes as fit as the chosen one, per joint.
type Ties = BTreeMap<JointKey, Vec<usize>>;

/// The best node for each joint (lowest priority value, then the first node),
/// with (priority, node); and the other nodes of the same priority, per joint.
fn choose_nodes(found: &[Option<Found>]) -> (Best, Ties) {
    let mut best = Best::new();
    let mut ties = Ties::new();
    for (i, f) in found.iter().enumerate() {
        if let Some((side, finger, slot, prio)) = *f {
            let key = (side, finger, slot);
            let e = best.entry(key).or_insert((prio, i));
            if prio < e.0 {
                *e = (prio, i);
                ties.remove(&key);
            } else if prio == e.0 && e.1 != i {
                ties.entry(key).or_default().push(i);
            }
        }
    }
    (best, ties)
}

/// A note for each joint that other nodes would fit as well as the chosen one.
fn tie_notes(best: &Best, ties: &Ties, names: &[String]) -> Vec<String> {
    let mut notes = Vec::new();
    for ((side, finger, slot), others) in ties {
        let chosen = best[&(*side, *finger, *slot)].1;
        let side = side.map_or(String::new(), |s| format!("{} ", s.name()));
        let also: Vec<String> = others.iter().map(|&i| shown(&names[i])).collect();
        notes.push(format!(
            "{side}{finger} {}: {} was used; {} would also fit (give --map to choose)",
            slot_name(*finger, *slot),
            shown(&names[chosen]),
            also.join(", ")
        ));
    }
    notes
}

/// The chain of one finger from the nodes chosen for its slots. `Ok(None)`, with
/// a note why when it helps, when the finger lacks a joint, or its nodes are
/// not one chain in the hierarchy while other nodes would fit as well (when
/// the names leave no doubt, the chain needs no hierarchy); an error when a
/// node's world transform is not finite.
fn finger_chain(
    file: &GltfFile,
    names: &[String],
    found: &FingerFound<'_>,
    notes: &mut Vec<String>,
) -> Result<Option<FingerChain>, Problem> {
    let (side, finger, slots) = (found.side, found.finger, found.slots);
    let label = match side {
        Some(s) => format!("{} {finger}", s.name()),
        None => finger.to_string(),
    };
    let mut wanted = vec![(Slot::Mcp, Joint::Mcp)];
    wanted.extend(
        Joint::inner(finger)
            .iter()
            .zip([Slot::First, Slot::Second])
            .map(|(&j, s)| (s, j)),
    );
    let missing: Vec<&str> = wanted
        .iter()
        .filter(|(s, _)| !slots.contains_key(s))
        .map(|(_, j)| j.name())
        .collect();
    if !missing.is_empty() {
        if wanted.iter().any(|(s, _)| slots.contains_key(s)) {
            notes.push(format!(
                "{label}: no {} joint found, so this finger is left out",
                missing.join(" or ")
            ));
        }
        return Ok(None);
    }
    let mut tip = slots.get(&Slot::Tip).copied();
    let mut hierarchy = true;
    if let Some(t) = tip {
        let last = slots[&wanted[wanted.len() - 1].0];
        if below(&file.parent, t, last) {
            wanted.push((Slot::Tip, Joint::Tip));
        } else if found.unambiguous {
            wanted.push((Slot::Tip, Joint::Tip));
            hierarchy = false;
        } else {
            notes.push(format!(
                "{label}: tip {} is not below {} in the node hierarchy, so it is not used",
                shown(&names[t]),
                shown(&names[last])
            ));
            tip = None;
        }
    }
    if let Some(w) = wanted
        .windows(2)
        .find(|w| !below(&file.parent, slots[&w[1].0], slots[&w[0].0]))
    {
        if !found.unambiguous {
            notes.push(format!(
                "{label}: {} is not below {} in the node hierarchy, so these are not one finger; left out (give --map to choose)",
                shown(&names[slots[&w[1].0]]),
                shown(&names[slots[&w[0].0]])
            ));
            return Ok(None);
        }
        hierarchy = false;
    }
    Ok(Some(FingerChain {
        side,
        finger,
        joints: rig_joints(file, names, &label, &wanted, slots)?,
        has_tip: tip.is_some(),
        metacarpal: None,
        wrist: None,
        hierarchy,
    }))
}

/// The `wanted` joints of a finger (`label`) at their nodes' world positions;
/// an error when a node's world transform is not finite.
fn rig_joints(
    file: &GltfFile,
    names: &[String],
    label: &str,
    wanted: &[(Slot, Joint)],
    slots: &HashMap<Slot, usize>,
) -> Result<Vec<RigJoint>, Problem> {
    if let Some(&(slot, j)) = wanted
        .iter()
        .find(|(s, _)| !file.world[slots[s]].is_finite())
    {
        return Err(Problem::file(format!(
            "node {} ({label} {}) has a non-finite world transform (a zero rotation quaternion, \
             a zero scale above it, or a huge value); fix its transform or its parents'",
            shown(&names[slots[&slot]]),
            j.name()
        )));
    }
    Ok(wanted
        .iter()
        .map(|&(s, joint)| {
            let node = slots[&s];
            RigJoint {
                joint,
                node: Some(node),
                name: names[node].clone(),
                position: file.world[node].w_axis.truncate(),
                weighted: None,
            }
        })
        .collect())
}

/// The error of a file with no complete finger: the names it has (the first
/// 60), the conventions known, and the notes on fingers left out.
fn no_hand(label: &str, names: &[String], notes: Vec<String>) -> DataError {
    const SHOWN: usize = 60;
    let n = names.len();
    let mut listed: Vec<String> = names.iter().take(SHOWN).map(|s| shown(s)).collect();
    if n > SHOWN {
        listed.push(format!("and {} more", n - SHOWN));
    }
    let seen = if n == 0 {
        "no nodes at all".to_string()
    } else {
        format!("{n} node names: {}", listed.join(", "))
    };
    let mut e = DataError::whole_file(
        label,
        format!(
            "has no recognisable hand: no finger chain (MCP and its inner joints) was found among its {seen}. \
             Known conventions: Mixamo (mixamorig:RightHandIndex1..4), Rigify (f_index.01.R, DEF-f_index.01.R, thumb.01.R), \
             VRM (rightIndexProximal), Unreal (index_01_r), WebXR (index-finger-phalanx-proximal); \
             for other names give --map FILE (columns node,side,finger,joint)"
        ),
    );
    e.problems.extend(notes.into_iter().map(Problem::file));
    e
}

/// How a rig is judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AuditOptions {
    pub judge: judge::JudgeOptions,
    /// A joint further than this from where its skin bends is flagged (rig units).
    pub bend_tolerance: f64,
    /// With skin tips: take the skin's end from the mesh when it reaches
    /// past the tip node (`--tip auto`).
    pub measure_tip: bool,
}

impl Default for AuditOptions {
    fn default() -> AuditOptions {
        AuditOptions {
            judge: judge::JudgeOptions::default(),
            bend_tolerance: bend::BEND_TOLERANCE_MM / 1000.0,
            measure_tip: true,
        }
    }
}

/// A tip node this far (metres) or more inside the skin's end is not at the
/// skin: WebXR's `*-tip` joints, the centres of the fingertips' spheres, lie
/// 10-12 mm inside the generic hand's skin. 2 mm leaves room for a mesh's
/// faceting at a rounded tip.
pub const TIP_INSIDE: f64 = 0.002;

/// The skin's end of a finger, measured on its mesh and used as its tip.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SkinTip {
    /// How far the skin reaches past the tip node, along the last segment.
    pub beyond_node: f64,
    /// The point used as the tip.
    #[schemars(with = "[f64; 3]")]
    pub position: DVec3,
}

/// A rig finger with its judgement.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AuditedFinger {
    #[serde(flatten)]
    pub chain: FingerChain,
    pub audit: judge::FingerAudit,
    /// Where the skin bends at each joint (empty without skin weights).
    pub bends: Vec<bend::Bend>,
    /// The skin's end used as the tip, when the tip node lies inside the skin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skin_tip: Option<SkinTip>,
    /// The MCP judged from the CMC against the metacarpals' dataset, when the
    /// rig has a metacarpal node and the audit was given one
    /// ([`AuditedRig::judge_metacarpals`]). Not `metacarpal`: that key is
    /// the chain's metacarpal node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metacarpal_check: Option<judge::MetacarpalCheck>,
}

/// Every finger of a rig judged against the statistics.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AuditedRig {
    /// The file (or reference rig) the chains come from.
    pub label: String,
    /// How the tips were compared.
    pub tips: judge::JudgeOptions,
    /// The bend tolerance used, in rig units.
    pub bend_tolerance: f64,
    pub fingers: Vec<AuditedFinger>,
    /// Fingers left out and other remarks.
    pub notes: Vec<String>,
    /// Things that make the judgement doubtful (the rig's scale).
    pub warnings: Vec<String>,
}

/// Plausible lengths of an adult finger from MCP to tip, in metres: a
/// fingertip-to-knuckle length is 50-110 mm; half and twice that allow for
/// children and stylised characters.
const PLAUSIBLE_FINGER: (f64, f64) = (0.025, 0.22);

/// A warning when the fingers' median length (MCP to the last point, in file
/// units read as metres) is implausible, naming the unit that would make it
/// plausible (the one nearest a 75 mm finger).
fn scale_warning(lengths: &[f64]) -> Option<String> {
    let mut l: Vec<f64> = lengths
        .iter()
        .copied()
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    if l.is_empty() {
        return None;
    }
    l.sort_by(f64::total_cmp);
    let median = l[l.len() / 2];
    let plausible = |x: f64| (PLAUSIBLE_FINGER.0..=PLAUSIBLE_FINGER.1).contains(&x);
    if plausible(median) {
        return None;
    }
    let units = [
        ("centimetres", 0.01),
        ("millimetres", 0.001),
        ("inches", 0.0254),
        ("decimetres", 0.1),
    ];
    let likely = units
        .iter()
        .filter(|(_, m)| plausible(median * m))
        .min_by(|a, b| {
            let off = |m: f64| (median * m / 0.075).ln().abs();
            off(a.1).total_cmp(&off(b.1))
        });
    let shown = format!(
        "its fingers are {} m long (median, MCP to tip), implausible for a hand in metres",
        crate::format::num(median, 4)
    );
    Some(match likely {
        Some((unit, m)) => format!(
            "{shown}; the file is likely in {unit} ({} mm fingers). glTF units are metres: \
             re-export in metres. The mm figures, the soft tissue and the bend tolerance are off; \
             relative values and ratios are not",
            crate::format::num(median * m * 1000.0, 1)
        ),
        None => format!(
            "{shown} or in any common unit; the mm figures, the soft tissue and the bend \
             tolerance are off; relative values and ratios are not"
        ),
    })
}

/// The note saying how the MCPs were judged from their rays' bases.
fn metacarpal_note(
    atlas: &crate::analysis::Analysis,
    wrist: Option<&judge::WristRatios>,
    from_cmc: usize,
    from_wrist: usize,
) -> String {
    let n = atlas
        .fingers
        .iter()
        .filter_map(|fa| fa.quantity(crate::dataset::Quantity::RatioMcJ))
        .map(|s| s.n)
        .max()
        .unwrap_or(0);
    let mcps = |k: usize| match k {
        1 => "1 MCP is".to_string(),
        k => format!("{k} MCPs are"),
    };
    let judged = match (from_cmc, from_wrist) {
        (c, 0) => format!("{} also judged from their CMC", mcps(c)),
        (0, w) => format!("{} also judged from the wrist", mcps(w)),
        (c, w) => format!(
            "{} also judged from their CMC and {w} from the wrist",
            mcps(c)
        ),
    };
    let mut out = format!(
        "Metacarpals: {judged} against {} ({} with the metacarpal measured), with the same \
         settings. The Digital Hand Atlas (the default) is children's left hands with {}: read \
         this as a guide.",
        atlas.dataset.path,
        crate::format::xrays(n),
        crate::dataset::landmarks::ATLAS_LANDMARKS
    );
    if from_wrist > 0 {
        out.push_str(&format!(
            " The wrist is {}; the rig's wrist-to-MCP distance over the finger's length (w/J) \
             is judged against the same ratio measured on each X-ray of the atlas's landmarks \
             (from {}). The thumb is not judged from the wrist: its distance depends on the \
             thumb's pose.",
            judge::WRIST_DEFINITION,
            wrist.map_or("the atlas's landmarks", |w| w.source.as_str())
        ));
    }
    out
}

impl AuditedRig {
    /// Judges `chains` against the analysis with the default options and no
    /// skin; fingers the data lacks become notes.
    pub fn of(
        label: &str,
        chains: &[FingerChain],
        notes: &[String],
        a: &crate::analysis::Analysis,
    ) -> AuditedRig {
        AuditedRig::with(label, chains, notes, a, &AuditOptions::default(), None)
    }

    /// Judges `chains` against the analysis with `opts`, and finds where the
    /// skin bends when `weights` are given.
    pub fn with(
        label: &str,
        chains: &[FingerChain],
        notes: &[String],
        a: &crate::analysis::Analysis,
        opts: &AuditOptions,
        weights: Option<&weights::SkinWeights>,
    ) -> AuditedRig {
        let mut notes = notes.to_vec();
        let mut fingers = Vec::new();
        let mut lengths = Vec::new();
        for chain in chains {
            let mut input = chain.input();
            let mut skin_tip = None;
            let n = input.points.len();
            if opts.measure_tip
                && opts.judge.rig_tip == judge::TipKind::Skin
                && let Some(w) = weights
                && let Some(reach) = bend::skin_end(chain, w)
                && n >= 2
            {
                let (last, tip) = (input.points[n - 2], input.points[n - 1]);
                let node = last.distance(tip);
                if reach > node + TIP_INSIDE {
                    let position = last + (tip - last).normalize_or_zero() * reach;
                    input.points[n - 1] = position;
                    skin_tip = Some(SkinTip {
                        beyond_node: reach - node,
                        position,
                    });
                }
            }
            lengths.push(
                input
                    .points
                    .windows(2)
                    .map(|w| w[0].distance(w[1]))
                    .sum::<f64>(),
            );
            match judge::audit_with(a, &input, &opts.judge) {
                Some(audit) => {
                    let bends = weights
                        .map(|w| bend::bends(chain, w, opts.bend_tolerance))
                        .unwrap_or_default();
                    fingers.push(AuditedFinger {
                        chain: chain.clone(),
                        audit,
                        bends,
                        skin_tip,
                        metacarpal_check: None,
                    });
                }
                None => notes.push(format!(
                    "{}: {} has no statistics for this finger (or the chain has zero length, or \
                     a last segment no longer than the tip's soft tissue), so it is not judged",
                    chain.label(),
                    a.dataset.path
                )),
            }
        }
        AuditedRig {
            label: label.to_string(),
            tips: opts.judge,
            bend_tolerance: opts.bend_tolerance,
            fingers,
            notes,
            warnings: scale_warning(&lengths).into_iter().collect(),
        }
    }

    /// Fingers with a joint or value outside the prediction interval.
    pub fn outside(&self) -> usize {
        self.fingers
            .iter()
            .filter(|f| !f.audit.is_consistent())
            .count()
    }

    /// Judges the MCP of every finger from the base of its ray against
    /// `atlas`'s metacarpal statistics: from its CMC where the finger has a
    /// metacarpal node ([`judge::metacarpal`]), else from the wrist where the
    /// hand has a wrist bone ([`judge::wrist`]; not the thumb). The fingers'
    /// own standings are unchanged. A finger with a metacarpal that cannot be
    /// judged (no tip, no mc/J in `atlas`) gets a note; without `wrist` (the
    /// atlas's wrist-to-MCP over finger length, read from its landmark file) no MCP is
    /// judged from the wrist, and a rig that has one gets a note.
    pub fn judge_metacarpals(
        &mut self,
        atlas: &crate::analysis::Analysis,
        wrist: Option<&judge::WristRatios>,
    ) {
        let (mut from_cmc, mut from_wrist, mut wrist_skipped) = (0, 0, 0);
        for f in &mut self.fingers {
            let Some(mcp) = f.chain.joints.first() else {
                continue;
            };
            if let Some(node) = &f.chain.metacarpal {
                f.metacarpal_check =
                    judge::metacarpal(atlas, &f.audit, &node.name, node.position, mcp.position);
                match f.metacarpal_check {
                    Some(_) => from_cmc += 1,
                    None => self.notes.push(format!(
                        "{}: its MCP is not judged from the metacarpal {} ({})",
                        f.chain.label(),
                        node.name,
                        if f.audit.length.is_none() {
                            "the rig has no tip, so the finger's length is unknown".to_string()
                        } else {
                            format!("{} has no mc/J for this finger", atlas.dataset.path)
                        }
                    )),
                }
            } else if let Some(node) = &f.chain.wrist {
                match wrist {
                    Some(rho) => {
                        f.metacarpal_check = judge::wrist(
                            atlas,
                            rho,
                            &f.audit,
                            &node.name,
                            node.position,
                            mcp.position,
                        );
                        from_wrist += usize::from(f.metacarpal_check.is_some());
                    }
                    None => wrist_skipped += usize::from(f.audit.finger != Finger::Thumb),
                }
            }
        }
        if from_cmc + from_wrist > 0 {
            self.notes
                .push(metacarpal_note(atlas, wrist, from_cmc, from_wrist));
        }
        if wrist_skipped > 0 {
            self.notes.push(format!(
                "Metacarpals: {wrist_skipped} MCPs are not judged from the wrist: the rig has no \
                 metacarpals, and the atlas's landmark file (landmarks.csv beside {}, which gives \
                 the wrist-to-MCP distance over the finger's length) was not found",
                atlas.dataset.path
            ));
        }
    }

    /// Fingers whose MCP lies outside the prediction interval from its ray's
    /// base (the CMC or the wrist).
    pub fn metacarpals_outside(&self) -> usize {
        self.fingers
            .iter()
            .filter_map(|f| f.metacarpal_check.as_ref())
            .filter(|m| !m.standing.is_consistent())
            .count()
    }

    /// Joints further from their bend than the tolerance.
    pub fn bends_flagged(&self) -> usize {
        self.fingers
            .iter()
            .flat_map(|f| &f.bends)
            .filter(|b| b.flagged)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_implausible_scale_names_the_likely_unit() {
        // 7.5 file units: centimetres (75 mm); 75: millimetres; 3 units: inches
        // (76.2 mm), not centimetres (30 mm is further from 75 mm).
        assert!(scale_warning(&[0.075, 0.08, 0.06]).is_none());
        let w = scale_warning(&[7.5, 8.0, 6.0]).unwrap();
        assert!(w.contains("likely in centimetres (75.0 mm fingers)"), "{w}");
        let w = scale_warning(&[75.0, 80.0]).unwrap();
        assert!(w.contains("likely in millimetres"), "{w}");
        let w = scale_warning(&[3.0]).unwrap();
        assert!(w.contains("likely in inches (76.2 mm"), "{w}");
        let w = scale_warning(&[1e6]).unwrap();
        assert!(w.contains("or in any common unit"), "{w}");
        assert!(scale_warning(&[]).is_none());
    }
}
