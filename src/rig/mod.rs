//! Rigged hands: reading their finger chains from a glTF 2.0 file, judging
//! them against the X-ray statistics ([`judge`], on the chain geometry of
//! `chain`) and writing a fixed copy ([`fix`]).

pub mod deform;
pub mod fix;
pub mod judge;
pub mod read;
pub mod session;

pub use judge::{AuditOptions, AuditedFinger, AuditedRig, SkinTip, TIP_INSIDE, bend, ray};
pub use read::{
    FingerChain, GltfFile, Rig, RigJoint, RigNode, map, naming, reference, skin, weights,
};
