//! Skin deformation of a curled hand: the paper's Section 3 (its Figures 2-3,
//! judged there by eye) made a measurement.
//!
//! A rig's fingers are curled to a pose ([`pose`]), its mesh is skinned by
//! linear blend or dual-quaternion skinning ([`skinning`]), and each finger's
//! skin is measured against the rest pose ([`measures`]): volume loss at each
//! bent joint, new self-intersections, edge strain and crease offset. Two rigs
//! (as they are, and fixed) are compared joint by joint in [`verdict`].
//!
//! No file is read or written here: the mesh comes from [`super::read::skin`], the
//! finger chains from the caller (a list of joint nodes per finger, so rigs
//! whose joints are siblings, such as WebXR's, are posed as well as
//! parent-child chains).
//!
//! Numbers are f64 (glam's `D` types) throughout: the rest of `rig` holds
//! world matrices in f64, the identity checks of skinning hold to 1e-9
//! relative only in f64 (f32 keeps about 6e-8), and a 30,000-triangle finger
//! set costs milliseconds either way. Units are the file's (metres in glTF).

pub mod chains;
pub mod file;
pub mod hand;
pub mod measures;
pub mod pose;
pub mod skinning;
pub mod synthetic;
pub mod verdict;

mod intersect;
mod section;
#[cfg(test)]
mod webxr_tests;

use glam::DVec3;

pub use chains::{FingerNodes, HandChains, Skeleton};
pub use measures::{FingerMeasures, HandMeasures, JointMeasures};
pub use pose::{PalmFrame, Pose, PosedHand};
pub use skinning::Skinning;

/// One rig deformed and measured.
#[derive(Debug, Clone)]
pub struct Deformation {
    pub method: Skinning,
    /// The skinned mesh in the rest (node) pose.
    pub rest: Vec<DVec3>,
    /// The skinned mesh in the pose.
    pub posed: Vec<DVec3>,
    /// Per vertex: mean |log(posed / rest length)| of its edges (for drawing).
    pub vertex_strain: Vec<f64>,
    pub measures: HandMeasures,
    /// Remarks from skinning (e.g. scale ignored by DQS).
    pub notes: Vec<String>,
}

/// Skins `mesh` at rest and in `posed`, and measures every finger. Cost: the
/// skinning O(vertices x influences), then [`measures::measure`].
pub fn deform(
    mesh: &crate::rig::read::skin::SkinnedMesh,
    skeleton: &Skeleton,
    posed: &PosedHand,
    method: Skinning,
) -> Deformation {
    let (rest, mut notes) = skinning::skin(method, mesh, &mesh.skin_matrices(&skeleton.world));
    let (pose, more) = skinning::skin(method, mesh, &mesh.skin_matrices(&posed.world));
    for n in more {
        if !notes.contains(&n) {
            notes.push(n);
        }
    }
    let measures = measures::measure(mesh, &rest, &pose, posed);
    let vertex_strain = measures::vertex_strain(mesh, &rest, &pose);
    Deformation {
        method,
        rest,
        posed: pose,
        vertex_strain,
        measures,
        notes,
    }
}
