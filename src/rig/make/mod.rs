//! Making a rig's fingers from its skin: [`mesh`] reads the hand's skin as one
//! welded triangle mesh in world space, [`find`] finds the fingers on it (the
//! tips, the axes, the webs, the wrist, the palm and the side). Uses `read`
//! only; nothing in `judge` or `fix` uses it.
//!
//! Inside, one way: `geometry` and `graph` (sections, lines, principal axes;
//! the mesh's graph, geodesics, persistence) <- `axis` (a finger traced) and
//! `hand` (what is found, the options, the errors) <- `surface` (the checked
//! mesh and its objects) <- `wrist`, `finger` <- `palm` (the palm, the thumb,
//! the names, the side) <- `find`.

mod axis;
pub mod find;
mod finger;
mod geometry;
mod graph;
mod hand;
pub mod mesh;
mod palm;
mod surface;
mod wrist;

#[cfg(test)]
mod tests;
