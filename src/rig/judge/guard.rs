//! The fix's guards on a finger's judgement: a move held when it would
//! leave the joint's skin bend behind, when its weights cannot follow it, or
//! when it is too short to make; the explanation sought again without it.

use super::bend;
use super::finger;
use super::standing::{
    BEND_GUARD, ChainInput, FingerAudit, Held, HoldReason, JudgeOptions, chain_kinds,
    under_tolerance,
};
use crate::analysis::Analysis;
use crate::analysis::placement::Joint;
use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::DVec3;

/// Per joint, why its skin weights cannot follow a move ([`bend::cannot_carry`]).
pub type Carry = Vec<(Joint, Option<String>)>;

/// The distances from `from` (the joint `joint` as the rig has it) and from
/// `to` (where a move puts it) to where its skin bends, when a bend was found.
fn bend_distances(
    bends: &[bend::Bend],
    joint: Joint,
    from: DVec3,
    to: DVec3,
) -> Option<(f64, f64)> {
    let at = bends.iter().find(|b| b.joint == joint)?.at?;
    Some((from.distance(at), to.distance(at)))
}

/// Why a move of the joint at `from` to `to` is not made, if it is not: it
/// would end more than [`BEND_GUARD`] farther from its bend, or it is
/// shorter than [`MOVE_TOLERANCE`].
pub(super) fn hold_reason(
    bends: &[bend::Bend],
    joint: Joint,
    from: DVec3,
    to: DVec3,
) -> Option<Held> {
    let shift = from.distance(to);
    let bend = bend_distances(bends, joint, from, to);
    if let Some((before, after)) = bend
        && after > before + BEND_GUARD
    {
        return Some(Held::new(HoldReason::Bend, shift, bend));
    }
    (shift > 0.0 && under_tolerance(shift)).then(|| Held::new(HoldReason::Small, shift, bend))
}

/// Why a move of `joint` from `from` to `to` is not made, by the skin's
/// rule: with the weights carried (`carry`), when they cannot follow it
/// ([`HoldReason::Carry`]) or the move is under the tolerance; with the
/// weights as painted, [`hold_reason`] against the bends.
pub(super) fn hold_for(
    carry: Option<&Carry>,
    bends: &[bend::Bend],
    joint: Joint,
    from: DVec3,
    to: DVec3,
) -> Option<Held> {
    let Some(carry) = carry else {
        return hold_reason(bends, joint, from, to);
    };
    let shift = from.distance(to);
    if shift > 0.0
        && let Some(why) = carry
            .iter()
            .find(|(j, _)| *j == joint)
            .and_then(|(_, why)| why.as_deref())
    {
        return Some(Held::carry(shift, why));
    }
    (shift > 0.0 && under_tolerance(shift)).then(|| Held::new(HoldReason::Small, shift, None))
}

/// `audit` (of `input`, judged with `judge` against `a`) with the fix's
/// rules applied to its explanation: an MCP the explanation would move is
/// held unless `pinned` holds it already (the caller places it itself, as
/// `--fix-mcp atlas` does, or the artist pinned it with `--hold`): the guard
/// cannot check it, for where the skin over a knuckle bends is not located
/// reliably ([`super::bend`]). The explanation is not sought again without
/// it: it still names the MCP (a misplaced MCP is not made up for by moving
/// the PIP and DIP), and the fix leaves it; a joint the explanation would
/// move more than [`BEND_GUARD`] farther from where its skin bends (`bends`, from the
/// rig's weights) is held, and the explanation sought again among the other
/// joints (and `pinned`), until no held joint remains to add; then a move
/// shorter than [`MOVE_TOLERANCE`] is marked not made. Each held joint's
/// check says why ([`super::standing::JointCheck::held`]). Without bends only the tolerance
/// applies. At most 4 re-judgements (a finger has 3 movable joints).
pub(super) fn guard(
    a: &Analysis,
    input: &ChainInput,
    judge: &JudgeOptions,
    audit: FingerAudit,
    (bends, carry): (&[bend::Bend], Option<&Carry>),
    pinned: &[Joint],
) -> FingerAudit {
    guard_holding(a, input, judge, audit, (bends, carry), pinned, &[])
}

/// [`guard`] with the joints `pre` held from the start, each with its reason.
fn guard_holding(
    a: &Analysis,
    input: &ChainInput,
    judge: &JudgeOptions,
    mut audit: FingerAudit,
    (bends, carry): (&[bend::Bend], Option<&Carry>),
    pinned: &[Joint],
    pre: &[(Joint, Held)],
) -> FingerAudit {
    let kinds = chain_kinds(input.finger, input.has_tip);
    let at = |joint: Joint| {
        kinds
            .iter()
            .position(|&k| k == joint)
            .and_then(|k| input.points.get(k).copied())
    };
    let mut held: Vec<(Joint, Held)> = pre.to_vec();
    if !held.is_empty() {
        let hold: Vec<Joint> = pinned
            .iter()
            .copied()
            .chain(held.iter().map(|h| h.0))
            .collect();
        if let Some(again) = finger::audit_holding(a, input, judge, &hold) {
            audit = again;
        }
    }
    for _ in 0..4 {
        let new: Vec<(Joint, Held)> = audit
            .joints
            .iter()
            .filter(|j| j.moves)
            .filter_map(|j| {
                let from = at(j.joint)?;
                if j.joint == Joint::Mcp && !pinned.contains(&Joint::Mcp) {
                    return None;
                }
                let h = hold_for(carry, bends, j.joint, from, j.suggested)?;
                matches!(h.reason, HoldReason::Bend | HoldReason::Carry).then_some((j.joint, h))
            })
            .filter(|(joint, _)| !held.iter().any(|(k, _)| k == joint))
            .collect();
        if new.is_empty() {
            break;
        }
        held.extend(new);
        let hold: Vec<Joint> = pinned
            .iter()
            .copied()
            .chain(held.iter().map(|h| h.0))
            .collect();
        match finger::audit_holding(a, input, judge, &hold) {
            Some(again) => audit = again,
            None => break,
        }
    }
    for j in &mut audit.joints {
        if let Some((_, h)) = held.iter().find(|(k, _)| *k == j.joint) {
            j.held = Some(h.clone());
        } else if j.joint == Joint::Mcp
            && j.moves
            && !pinned.contains(&Joint::Mcp)
            && let Some(from) = at(j.joint)
        {
            j.held = Some(Held::new(
                HoldReason::Knuckle,
                from.distance(j.suggested),
                None,
            ));
        } else if j.moves
            && j.held.is_none()
            && let Some(from) = at(j.joint)
        {
            j.held = hold_for(carry, bends, j.joint, from, j.suggested);
        }
    }
    // The moves the fix makes must land the finger inside the inner region
    // on their own: a move whose companions are held (a knuckle, a short
    // move) is judged as it would be made, and not made when it falls short.
    if !finger::lands_inside(a, input, judge, &audit) {
        for j in audit.joints.iter_mut().filter(|j| j.fix_moves()) {
            j.held = Some(Held::new(HoldReason::Short, j.shift, None));
        }
    }
    audit
}

/// The joints of `hold` that `audit`'s explanation (sought with none held)
/// moves, each held as pinned by the artist with the move it gives up.
fn pins(audit: &FingerAudit, hold: &[Joint]) -> Vec<(Joint, Held)> {
    audit
        .joints
        .iter()
        .filter(|j| hold.contains(&j.joint) && j.moves)
        .map(|j| (j.joint, Held::new(HoldReason::Pinned, j.shift, None)))
        .collect()
}

/// [`guard`] (the joints `hold` pinned, those of them `first` moves held
/// as pinned, [`pins`]) checked on the skin as the fix leaves it:
/// the bends of `chain` with the guarded explanation's moves made, found
/// again on the skin's weights (with the bend tolerance) as the re-audit of the written copy finds them (the
/// fix keeps the weights and the mesh's rest shape, so only the joints
/// move). Moving a joint moves the axis its bend is measured along, so a
/// move [`guard`] passes against the rig's bend may still end more than
/// [`BEND_GUARD`] farther from the bend the fixed copy has (allowing for the
/// bends' resolution, a bin of [`bend::BIN`] of the finger's length); such a
/// joint is held too, with those two distances, and the explanation sought again.
/// At most 3 rounds of at most 5 re-judgements and one bend search each.
#[allow(clippy::too_many_arguments)]
pub(super) fn guard_on_weights(
    a: &Analysis,
    input: &ChainInput,
    judge: &JudgeOptions,
    first: FingerAudit,
    (bends, carry): (&[bend::Bend], Option<&Carry>),
    chain: &FingerChain,
    skin: Option<(&SkinWeights, f64)>,
    hold: &[Joint],
) -> FingerAudit {
    let pinned = pins(&first, hold);
    let mut audit = guard_holding(
        a,
        input,
        judge,
        first.clone(),
        (bends, carry),
        hold,
        &pinned,
    );
    let mut held = pinned;
    let Some((w, tolerance)) = skin else {
        return audit;
    };
    if carry.is_some() {
        // Carried weights: the question is whether the skin would bend at
        // the moved joint, not whether the joint leaves its painted bend.
        for _ in 0..3 {
            let new = carried_short(&audit, bends, chain, w, tolerance);
            if new.is_empty() {
                break;
            }
            held.extend(new);
            audit = guard_holding(a, input, judge, first.clone(), (bends, carry), hold, &held);
        }
        return audit;
    }
    for _ in 0..3 {
        let mut moved = chain.clone();
        for rj in &mut moved.joints {
            if let Some(j) = audit.joint(rj.joint).filter(|j| j.fix_moves()) {
                rj.position = j.suggested;
            }
        }
        let after = bend::bends(&moved, w, tolerance);
        // Each bend is found to within half a bin either way (the shares are
        // averaged in bins `bend::BIN` of the finger's length wide), so
        // before and after together may be off by a bin: a move is held
        // when it may end more than BEND_GUARD farther, not only when the
        // estimates say it does.
        let bin = bend::BIN
            * chain
                .joints
                .windows(2)
                .map(|p| p[0].position.distance(p[1].position))
                .sum::<f64>();
        let at = |list: &[bend::Bend], joint: Joint| {
            list.iter().find(|b| b.joint == joint).and_then(|b| b.at)
        };
        let new: Vec<(Joint, Held)> = chain
            .joints
            .iter()
            .filter_map(|rj| {
                let j = audit.joint(rj.joint).filter(|j| j.fix_moves())?;
                let (b0, b1) = (at(bends, rj.joint)?, at(&after, rj.joint)?);
                let (d0, d1) = (rj.position.distance(b0), j.suggested.distance(b1));
                (d1 > d0 + BEND_GUARD - bin).then(|| {
                    (
                        rj.joint,
                        Held::new(HoldReason::Bend, j.shift, Some((d0, d1))),
                    )
                })
            })
            .collect();
        if new.is_empty() {
            break;
        }
        held.extend(new);
        audit = guard_holding(a, input, judge, first.clone(), (bends, carry), hold, &held);
    }
    audit
}

/// For each joint of `chain`, why its skin weights cannot follow a move
/// ([`bend::cannot_carry`], against the other `chains`' nodes); every joint
/// can when the rig has no weights (nothing to carry).
pub(super) fn carry_of(
    chain: &FingerChain,
    chains: &[FingerChain],
    weights: Option<&SkinWeights>,
) -> Carry {
    let others: Vec<usize> = chains
        .iter()
        .filter(|c| !std::ptr::eq(*c, chain))
        .flat_map(|c| c.joints.iter().filter_map(|j| j.node))
        .collect();
    chain
        .joints
        .iter()
        .map(|j| {
            let why = weights.and_then(|w| bend::cannot_carry(chain, w, &others, j.joint));
            (j.joint, why)
        })
        .collect()
}

/// The fix's moves of `audit`, their weights carried
/// ([`super::carry::carry_finger`]): each moved joint whose skin would then
/// bend more than [`super::carry::CARRY_TOLERANCE`] from it (or nowhere near
/// it), held with that distance. A mesh bends only where it has vertices.
fn carried_short(
    audit: &FingerAudit,
    bends: &[bend::Bend],
    chain: &FingerChain,
    weights: &SkinWeights,
    tolerance: f64,
) -> Vec<(Joint, Held)> {
    let moving: Vec<&super::standing::JointCheck> =
        audit.joints.iter().filter(|j| j.fix_moves()).collect();
    if moving.is_empty() {
        return Vec::new();
    }
    let carried = super::carry::FingerMove::of(chain, bends, |joint| {
        moving
            .iter()
            .find(|j| j.joint == joint)
            .map(|j| j.suggested)
    });
    let (_, offsets, _) = super::carry::carry_finger(weights, &carried, tolerance);
    offsets
        .into_iter()
        .filter_map(|(k, offset)| {
            let j = moving.iter().find(|j| j.joint == chain.joints[k].joint)?;
            let why = match offset {
                Some(o) if o.abs() <= super::carry::CARRY_TOLERANCE => return None,
                Some(o) => format!(
                    "its skin would bend {} mm {} of it",
                    crate::format::num(o.abs() * 1000.0, 1),
                    if o < 0.0 { "proximal" } else { "distal" }
                ),
                None => "no bend of its skin would be found near it".to_string(),
            };
            Some((j.joint, Held::carry(j.shift, &why)))
        })
        .collect()
}
