//! Rigged hands: reading their finger chains from a glTF 2.0 file ([`read`]),
//! judging them against the X-ray statistics ([`judge`]), writing a fixed copy
//! ([`fix`]), and measuring how their skin deforms when curled ([`deform`]);
//! [`session`] does load, judge, fix and read back for a command.
//!
//! The sub-rooms depend one way: `read` <- `judge` <- `fix`; `deform` uses
//! `read` (and may use `judge`); `session` uses them all. Nothing below names
//! anything above it (`tests/architecture.rs` holds them to it). This file
//! only declares them and re-exports the paths the library has always had
//! (`rig::GltfFile`, `rig::AuditedRig`, `rig::naming`, `rig::skin`, ...).

pub mod deform;
pub mod find;
pub mod fix;
pub mod judge;
pub mod make;
pub mod read;
pub mod session;

pub use judge::{AuditOptions, AuditedFinger, AuditedRig, SkinTip, TIP_INSIDE, bend, ray};
pub use read::{
    FingerChain, GltfFile, Rig, RigJoint, RigNode, fbx, map, naming, open, reference, skin, weights,
};
