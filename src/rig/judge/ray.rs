//! The MCP placed from its ray's base: what `audit --fix --fix-mcp atlas` moves.
//!
//! The finger's own statistics say where the MCP lies relative to PIP, DIP
//! and tip; the metacarpal check ([`super::ray_base::metacarpal`], [`super::ray_base::wrist`])
//! says where it lies along the ray, from the CMC (or the wrist) with the tip
//! held. With the atlas chosen, the MCP is the atlas's: a finger whose MCP is
//! outside the prediction interval from its base gets its MCP at the atlas's
//! mean position on the base-MCP line, and the finger is judged again with
//! that MCP held, so only PIP and DIP may move to fit the X-rays' proportions.
//! A finger whose MCP is inside is judged again with its MCP held where it is.
//! A finger without a check keeps its own explanation. A fixed rig's MCP lies
//! at the mean, inside the interval, so a second fix holds it and, when the
//! first fit the proportions, moves nothing. The atlas's MCP and the inner
//! joints' moves are guarded as the finger's own are
//! ([`super::audited`]): a move that would take a joint off its skin bend,
//! or shorter than the move tolerance, is not made, and the joint says so.
//! Joints the artist pins (`--hold`) stay pinned: a pinned MCP keeps the
//! finger's own explanation, and pinned inner joints are held in the new one.

use super::audited::{AuditedFinger, AuditedRig};
use super::finger::audit_holding;
use super::guard::{guard, hold_for};
use super::standing::{HoldReason, JudgeOptions};
use crate::analysis::Analysis;
use crate::analysis::placement::Joint;

/// The fingers of `rig` with the explanation a fix applies when the MCP is
/// placed from its ray's base (see the module notes); `a` the statistics the
/// fingers were judged against, `opts` as they were judged, `hold` the joints
/// the artist pinned. O(fingers) audits.
pub fn mcp_from_base(
    rig: &AuditedRig,
    a: &Analysis,
    opts: &JudgeOptions,
    hold: &[Joint],
) -> Vec<AuditedFinger> {
    rig.fingers
        .iter()
        .map(|f| placed(f, a, opts, hold).unwrap_or_else(|| f.clone()))
        .collect()
}

/// One finger with its MCP from its base and the inner joints re-explained;
/// `None` when it has no check, its MCP is pinned, or it cannot be judged again.
fn placed(
    f: &AuditedFinger,
    a: &Analysis,
    opts: &JudgeOptions,
    hold: &[Joint],
) -> Option<AuditedFinger> {
    if hold.contains(&Joint::Mcp) {
        return None;
    }
    let m = f.metacarpal_check.as_ref()?;
    let mut input = f.judged_input();
    let original = *input.points.first()?;
    // The atlas's MCP is guarded as the finger's own moves are: not made when
    // it would take the MCP off its skin bend, or when it is too short.
    let held = (!m.standing.is_consistent())
        .then(|| {
            hold_for(
                f.carry.as_ref(),
                &f.bends,
                Joint::Mcp,
                original,
                m.suggested,
            )
        })
        .flatten();
    let outside = !m.standing.is_consistent() && held.is_none();
    if outside {
        input.points[0] = m.suggested;
    }
    let pinned: Vec<Joint> = std::iter::once(Joint::Mcp)
        .chain(hold.iter().copied())
        .collect();
    let audit = audit_holding(a, &input, opts, &pinned)?;
    let mut audit = guard(
        a,
        &input,
        opts,
        audit,
        (&f.bends, f.carry.as_ref()),
        &pinned,
    );
    // The artist's pins say what they give up as in the finger's own judgement.
    for j in &mut audit.joints {
        if let Some(h) = f
            .audit
            .joint(j.joint)
            .and_then(|k| k.held.as_ref())
            .filter(|h| h.reason == HoldReason::Pinned && j.held.is_none())
        {
            j.held = Some(h.clone());
        }
    }
    if let (Some(h), Some(mcp)) = (
        held,
        audit.joints.iter_mut().find(|j| j.joint == Joint::Mcp),
    ) {
        mcp.held = Some(h);
        mcp.suggested = m.suggested;
        mcp.shift = original.distance(m.suggested);
        mcp.shift_along = m.expected - m.to_mcp;
    }
    if outside {
        let mcp = audit.joints.iter_mut().find(|j| j.joint == Joint::Mcp)?;
        mcp.moves = true;
        mcp.suggested = m.suggested;
        mcp.shift = original.distance(m.suggested);
        // + towards the tip: the MCP moves away from its base.
        mcp.shift_along = m.expected - m.to_mcp;
        if !audit.explanation.moved.contains(&Joint::Mcp) {
            audit.explanation.moved.insert(0, Joint::Mcp);
        }
    }
    Some(AuditedFinger { audit, ..f.clone() })
}
