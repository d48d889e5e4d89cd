//! Reading rigs: a file becomes finger chains, with the skin beside them.
//!
//! Joint positions are the world translations of the joint nodes in the
//! file's node pose (the bind pose of an exported rig), in the file's units
//! (metres by the glTF specification). Candidate nodes are the joints of any
//! skin and their descendants (tip nodes are often unskinned leaves); a file
//! without skins is read as a bare skeleton, every node a candidate. Names are
//! read by [`naming`], VRM's humanoid bone tables when present, and a
//! `--map` file ([`map`]) first of all ([`recognise`]).
//!
//! What is glTF's own lives in [`gltf`] (the file, its node transforms and
//! buffers, the GLB container), [`skin`] and [`weights`] (the skinned mesh and
//! its weights, read from glTF accessors) and `anim` (animation channels).
//! The types here, [`RigJoint`], [`RigNode`], [`FingerChain`] and [`Rig`], are
//! what the rest of `rig` reads: positions and node indices, no format.
//! [`sniff`] names what a file that is not glTF really is.
//! [`reference`](mod@reference) reads another format into the same chains: the reference
//! rigs of `data/rigs`. Nothing here judges, and nothing writes but
//! [`gltf`]'s GLB container, shared by the fix and the synthetic hands.

pub(crate) mod anim;
pub mod gltf;
pub mod map;
pub mod naming;
pub mod recognise;
pub mod reference;
pub mod skin;
pub mod sniff;
pub mod weights;

pub use gltf::GltfFile;

use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use glam::DVec3;
use naming::Side;
use schemars::JsonSchema;
use serde::Serialize;

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
    /// "right index", "left thumb", or "index" when the side is unknown.
    pub fn label(&self) -> String {
        match self.side {
            Some(s) => format!("{} {}", s.name(), self.finger),
            None => self.finger.to_string(),
        }
    }
}

/// A rig's fingers, as found in a glTF file (its `file`).
pub struct Rig {
    pub file: GltfFile,
    pub chains: Vec<FingerChain>,
    /// Fingers seen but incomplete, and other remarks.
    pub notes: Vec<String>,
    /// The skin weights, when the file has skins whose weights could be read.
    pub weights: Option<weights::SkinWeights>,
}
