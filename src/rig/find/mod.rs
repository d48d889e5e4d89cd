//! A hand's fingers found on its skin: [`mesh`] reads the hand's skin as one
//! welded triangle mesh in world space, [`search`] finds the fingers on it (the
//! tips, the axes, the webs, the wrist, the palm and the side). Uses `read`
//! only; `make` places joints on what it finds, and the audit asks it for
//! the tips a rig's chains lack.
//!
//! Inside, one way: `geometry` and `graph` (sections, lines, principal axes;
//! the mesh's graph, geodesics, persistence) <- `axis` (a finger traced) and
//! `hand` (what is found, the options, the errors) <- `surface` (the checked
//! mesh and its objects) <- `wrist`, `finger` <- `palm` (the palm, the thumb,
//! the names, the side) <- `search`.

mod axis;
mod finger;
mod geometry;
mod graph;
mod hand;
mod mesh;
mod palm;
mod search;
mod surface;
mod wrist;

pub use hand::{FindError, FindOptions, FoundFinger, FoundHand};
pub use mesh::{HandMesh, MeshSelect, hand_mesh};
pub use search::find_hand;

#[cfg(test)]
mod tests;
