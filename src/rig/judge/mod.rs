//! Judging a rig: each finger against the X-ray statistics ([`finger`]: the
//! joints' standings, `expected`, and the explanation that moves the fewest
//! joints, `explain`, in the terms of [`standing`], on the chain geometry of
//! `chain`); its MCP from its ray's base, the CMC or the wrist
//! ([`ray_base`]); where its skin bends ([`bend`]); whether its bones match its
//! mesh (`sanity`: joints far outside it, a rest pose not the bind pose); a whole
//! rig at once ([`audited`]); and `--fix-mcp atlas`, the MCP placed from its ray's base
//! ([`ray`]).
//!
//! It reads the chains and skin weights of [`super::read`] and writes
//! nothing. No glTF here: positions, node indices and weights only.

pub mod audited;
pub mod bend;
pub mod carry;
pub(crate) mod chain;
mod expected;
mod explain;
pub mod finger;
mod guard;
pub mod ray;
pub mod ray_base;
pub(crate) mod sanity;
pub mod soft_tissue;
pub mod standing;
#[cfg(test)]
mod tests;

pub use audited::{AuditOptions, AuditedFinger, AuditedRig, SkinTip, TIP_INSIDE};
pub use finger::{audit, audit_holding, audit_holding_mcp, audit_with};
pub use ray_base::{
    MetacarpalCheck, RayBase, WRIST_DEFINITION, WristRatio, WristRatios, WristValue, metacarpal,
    wrist,
};
pub use standing::{
    BEND_GUARD, Basis, ChainInput, Explanation, FingerAudit, FingerSoftTissue, Held, HoldReason,
    JointCheck, JudgeOptions, MOVE_TOLERANCE, OwnRegion, RegionCheck, RegionShape,
    SOFT_TISSUE_TABLE, SoftTissue, Standing, TipKind, ValueCheck, data_tip_of, under_tolerance,
};
