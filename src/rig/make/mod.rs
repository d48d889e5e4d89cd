//! Making a rig's fingers from its skin: [`mesh`] reads the hand's skin as one
//! welded triangle mesh in world space. Uses `read` only; nothing in `judge`
//! or `fix` uses it.

pub mod mesh;
