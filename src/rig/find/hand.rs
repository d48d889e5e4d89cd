//! What [`super::find`] finds and why it may find nothing: the hand and its
//! fingers, the options, the errors (re-exported from `find`).

use crate::dataset::Finger;
use crate::rig::read::naming::Side;
use glam::DVec3;

/// One finger found on the skin.
#[derive(Debug, Clone)]
pub struct FoundFinger {
    pub finger: Finger,
    /// The skin's end: where the finger's axis leaves the mesh (not the
    /// geodesic maximum, which lies on the pad).
    pub tip: DVec3,
    /// The fingertip's direction (unit, distal): the line through the rings
    /// between half a radius and three radii from the tip end, which the tip
    /// lies on.
    pub tip_direction: DVec3,
    /// The axis from the tip towards the palm: the tip, the centres of the
    /// rings traced from it (`measured` points in all with the tip), then
    /// points continued straight past the web into the palm along the last
    /// rings' direction.
    pub axis: Vec<DVec3>,
    /// How many leading points of `axis` were measured (the tip and the ring
    /// centres); the rest are extrapolated.
    pub measured: usize,
    /// The finger's radius at each point of `axis` (the ring's mean distance
    /// from its centre; the tip and the extrapolated points take the nearest
    /// ring's).
    pub radius: Vec<f64>,
    /// The web: the saddle where this finger's region met the rest of the hand.
    pub web: DVec3,
    /// The web's arc position along `axis` from the tip.
    pub web_arc: f64,
    /// The finger's vertices (welded indices), tip to web (by geodesic
    /// distance from its top).
    pub vertices: Vec<u32>,
    /// Persistence of its geodesic maximum: birth minus death (for the
    /// oldest, which never dies, its birth minus its web's level), in the
    /// mesh's units.
    pub persistence: f64,
}

/// A hand found on the skin.
#[derive(Debug, Clone)]
pub struct FoundHand {
    pub side: Side,
    /// The wrist: the point given ([`FindOptions::wrist`]), else the centre
    /// of the ring the geodesics start from.
    pub wrist: DVec3,
    /// The palm's unit normal, towards the palm side.
    pub palm_normal: DVec3,
    /// The unit direction from the wrist to the fingers, in the palm's plane.
    pub distal: DVec3,
    /// Thumb first, then index, middle, ring, little (those found).
    pub fingers: Vec<FoundFinger>,
    /// How the wrist and the side were found, and what was left out.
    pub notes: Vec<String>,
}

/// What the finder is told.
#[derive(Debug, Clone, PartialEq)]
pub struct FindOptions {
    /// How many fingers the hand has, the thumb included: 5, or 4 for a
    /// thumb and three fingers (2 to 5).
    pub fingers: usize,
    /// The wrist (`--wrist X,Y,Z`, or the hand bone's origin), in the mesh's
    /// units.
    pub wrist: Option<DVec3>,
    /// Which hand, when known (`--side`, or the bones' names).
    pub side: Option<Side>,
    /// What the wrist given is, as the notes name it ("the point given
    /// (--wrist)", "the hand bone's origin (hand_L)"); `None`: "the point given".
    pub wrist_is: Option<String>,
}

impl Default for FindOptions {
    fn default() -> FindOptions {
        FindOptions {
            fingers: 5,
            wrist: None,
            side: None,
            wrist_is: None,
        }
    }
}

/// Why no hand was found; each prints as one line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FindError {
    /// An option out of range (the finger count, a wrist that is not finite).
    #[error("{0}")]
    Options(String),
    /// No triangles at all.
    #[error("the mesh has no triangles, so there is no hand to find")]
    Empty,
    /// A position that is NaN or infinite.
    #[error("vertex {0} of the mesh is not a finite position (NaN or infinite)")]
    NotFinite(usize),
    /// A triangle naming a vertex the mesh does not have.
    #[error("triangle {triangle} names vertex {vertex}, but the mesh has {vertices}")]
    BadTriangle {
        triangle: usize,
        vertex: u32,
        vertices: usize,
    },
    /// No volume: a point, a line, a plane.
    #[error("the mesh has no extent (its vertices coincide or lie on a line or a plane)")]
    Flat,
    /// Fewer extremities beyond the wrist than the hand has fingers.
    #[error("found {found} extremit{} beyond the wrist; a hand has {wanted}{hint}",
        if *found == 1 { "y" } else { "ies" })]
    TooFew {
        found: usize,
        wanted: usize,
        hint: String,
    },
    /// Two separate hands and no side given to choose.
    #[error(
        "found two hands, separate pieces of the mesh with {found} fingers in all: give --side to take one, or rig each alone"
    )]
    TwoHands { found: usize },
    /// Two hands in one piece of skin.
    #[error(
        "found {found} extremities in two clusters, as two hands joined in one skin have: rig each hand alone (its own file, or the region under its hand bone)"
    )]
    TwoHandsJoined { found: usize },
    /// Two hands, neither or both of the side given.
    #[error("found two hands, {0}; rig each alone (its own file, or its hand bone)")]
    TwoHandsSide(String),
    /// A finger much wider than the others: two fused.
    #[error(
        "the {} is {} mm wide, {} times the other fingers: two fingers fused in one, as in a mitten",
        finger_words(*finger),
        crate::format::num(*width, 0),
        crate::format::num(*ratio, 1)
    )]
    Fused {
        finger: Finger,
        width: f64,
        ratio: f64,
    },
    /// Fingers curled back towards the palm.
    #[error(
        "the hand is posed in a fist, not at rest: {0}; rig a hand at rest (fingers straight or slightly bent)"
    )]
    Fist(String),
    /// No wrist given, no open end, and both ends alike.
    #[error("no clear wrist: {0}; name it with --wrist X,Y,Z")]
    NoWrist(String),
    /// The wrist given is far from the mesh.
    #[error(
        "the wrist given lies {} mm from the mesh, farther than a quarter of its length; give a point at the wrist",
        crate::format::num(*distance, 0)
    )]
    WristOff { distance: f64 },
    /// An extremity whose rings never close around an axis.
    #[error(
        "could not trace a finger from the extremity at ({}, {}, {}) mm: its rings do not close around an axis",
        crate::format::num(*x, 1),
        crate::format::num(*y, 1),
        crate::format::num(*z, 1)
    )]
    NoAxis { x: f64, y: f64, z: f64 },
    /// The palm side, and so the side, cannot be told, and none was given.
    #[error(
        "the palm side is unclear (the thumb and the fingertips lie in the palm's plane), so a left hand cannot be told from a right: give --side"
    )]
    NoSide,
}

impl FindError {
    /// The error as a problem of the file `label` the mesh was read from
    /// (bad input: exit status 2).
    pub fn in_file(&self, label: &str) -> crate::dataset::DataError {
        crate::dataset::DataError::whole_file(label, self.to_string())
    }
}

/// "thumb", "index finger", ...: a finger in a sentence.
pub(super) fn finger_words(f: Finger) -> String {
    match f {
        Finger::Thumb => "thumb".to_string(),
        _ => format!("{f} finger"),
    }
}

/// Millimetres of a length in metres, for messages.
pub(super) fn mm(x: f64) -> f64 {
    x * 1000.0
}

/// The error for too few extremities, with a hint at why.
pub(super) fn too_few(found: usize, wanted: usize) -> FindError {
    let hint = match found {
        0 => ": the mesh has no fingers (is it a hand?)".to_string(),
        1 | 2 if wanted >= 4 => {
            ": are its fingers fused (a mitten), curled into a fist, or is it not a hand?"
                .to_string()
        }
        _ => format!(": are two fingers fused, or does the hand have {found} (give the count)?"),
    };
    FindError::TooFew {
        found,
        wanted,
        hint,
    }
}
