//! What a rig file was before it was read as glTF: the facts of an FBX file
//! ([`super::fbx`]) that its glTF document in memory does not keep, and that
//! the moves for a DCC (`rig::fix::moves`) and the audit's header need.
//! Its own file so that the glTF file ([`super::gltf`]) can carry it without
//! depending on the FBX reader, which depends on it.

use glam::DVec3;

/// What an FBX file was, beside the glTF document it is read as.
#[derive(Debug, Clone, PartialEq)]
pub struct FbxSource {
    /// The FBX version (7500 for 7.5).
    pub version: u32,
    pub ascii: bool,
    /// Metres per file unit (`UnitScaleFactor` / 100).
    pub unit_meters: f64,
    /// The file's axes, as `-X right, +Y up, -Z front`.
    pub axes: String,
    /// Per node (the same index as the glTF's): the FBX node's
    /// `Lcl Translation` in the file's units and its parent's axes; `None`
    /// for the scene root that ufbx adds.
    pub lcl_translation: Vec<Option<DVec3>>,
    /// Per node: true when it inherits its parent's transform in full (FBX
    /// `InheritType` RrSs, the default); a moved node that does not gets a
    /// warning, its `Lcl Translation` being read in a scaled frame.
    pub inherits_normally: Vec<bool>,
    /// Per node: true when the file is saved with the node out of its bind
    /// pose (its skin cluster's bind matrix is not its current world
    /// matrix): its stored `Lcl Translation` is then not its bind pose's.
    pub off_bind: Vec<bool>,
}
