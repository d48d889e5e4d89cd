//! Judging a rig's finger joints against the X-ray statistics: each joint's
//! standing and the explanation that moves the fewest joints.
//!
//! A rig finger is a chain of joint centres P0 (MCP), P1, P2 (PIP, DIP; the
//! thumb has one inner joint, IP) and, when the rig has one, the tip. Its
//! segments are the chords c_k = |P_k - P_(k-1)|.
//!
//! **The tip.** A rig's tip node usually marks the skin at the end of the
//! finger; a dataset's J3 ends where its `tip` column says: at the skin (the
//! paper's X-rays) or at the bone tip, the distal phalanx's tuft (the atlas).
//! Where the two agree the last segment is compared as it is. Where they
//! differ it is compared as c_last - s, s the soft tissue beyond the bone tip
//! ([`SoftTissue::correction`](super::SoftTissue::correction)): the measured
//! share of the finger from a published table (Buryanov and Kotiuk 2010),
//! times the rig's finger length, or one length given by `--tip-soft-tissue`;
//! s > 0 for a skin tip against bone tips, s < 0 for a bone tip against skin
//! tips. s is computed once per finger, from the chain as given, and held
//! while the explanation moves joints. The compared segments s_k are the
//! chords with that correction on the last one, L = sum s_k and J~k = s_k / L
//! (eq. 2).
//!
//! **Each joint against the others.** Every joint gets a standing: where the
//! X-rays put it given the rest of the finger as the rig has it, in distances
//! from the rig's MCP along the chain (+ towards the tip):
//! - PIP (IP) at J~1 L and DIP at (1 - J~3) L (MCP and tip held);
//! - MCP at s_1 - J1 with J1 = R x/(1 - x), x = J~1 and R = L - s_1 the rest
//!   of the finger (PIP and tip held): J1/R = J~1/(1 - J~1);
//! - tip at (L - s_last) + J_last + correction, J_last = R' x/(1 - x), x the
//!   last J~ and R' = L - s_last (MCP and DIP held).
//!
//! x/(1 - x) is increasing, so the range and prediction interval of x map
//! onto positions end to end (a monotone map keeps the coverage of an
//! interval).
//!
//! Without a tip (VRM, Unreal) L is unknown; a finger is then judged on
//! r = J2/J1 alone: the PIP belongs at (c_1 + c_2) / (1 + r) with MCP and DIP
//! fixed (decreasing in r, so intervals swap ends), and the MCP at
//! c_1 - c_2 / r with PIP and DIP fixed (increasing in r). The DIP and the whole thumb cannot be
//! judged without a tip.
//!
//! **The fewest joints.** A misfit of the proportions can come from any joint:
//! rigs often put the MCP at the finger's visible base (the web), distal of
//! the knuckle, and the tip at the skin. So the judgement looks for the
//! explanation that moves the fewest joints (MCP, PIP, DIP; the tip node is
//! never moved: its soft tissue is modelled above): first none, then each
//! joint alone, then pairs, keeping the first size at which the finger is
//! inside the X-rays' joint prediction region (with a tip: its relative joint
//! positions u = (J~1, J~1 + J~2) as one vector with their covariance,
//! T^2 <= bound, [`crate::analysis::region`]; without a tip J2/J1 inside its
//! prediction interval). Explanations of one size are told apart by how well
//! they can fit: a joint alone at its best place (the smallest sqrt(T^2 /
//! bound), 1 at the region's edge; without a tip the normalised distance of
//! J2/J1, 1 at a prediction limit), a pair exactly at the means; the better
//! fit wins, then the smaller move. The chosen joints are then moved only as
//! far as that takes: from the rig's place straight towards the best place,
//! just inside the edge (0.999), so the fix is the smallest change of those
//! joints that makes the finger a plausible hand. Joints move along the rig's
//! own chain (the polyline through its joints), the MCP along the first
//! segment's backward extension (at most one segment back, half a segment
//! forward). See `rig::chain`. No files, no glTF.

use super::chain::point_at;
use super::expected::{StandingInput, ratio_standings, relative_standings};
use super::explain::{Axis, Judge, Solved, explain};
use super::standing::{
    Basis, ChainInput, Explanation, FingerAudit, Held, HoldReason, JointCheck, JudgeOptions,
    OwnRegion, RegionCheck, RegionShape, Standing, chain_kinds, stats, value_check, value_of,
};
use crate::analysis::placement::Joint;
use crate::analysis::{Analysis, Quantity, QuantityStats};
use crate::dataset::Finger;

/// The statistics a finger is judged on: every unitless quantity with a tip,
/// J2/J1 without one (none for a thumb without a tip).
fn judged_quantities<'a>(
    a: &'a Analysis,
    chain: &ChainInput,
) -> Option<Vec<(Quantity, &'a QuantityStats)>> {
    let qs: Vec<Quantity> = match (chain.has_tip, chain.finger) {
        (true, f) => Quantity::of(f)
            .iter()
            .copied()
            .filter(|q| q.is_unitless())
            .collect(),
        (false, Finger::Thumb) => Vec::new(),
        (false, _) => vec![Quantity::RatioJ2J1],
    };
    qs.into_iter()
        .map(|q| stats(a, chain.finger, q).map(|s| (q, s)))
        .collect()
}

/// Judges one rig finger with a skin tip and no soft tissue figure
/// ([`JudgeOptions::skin`]): against data with bone tips it is not judged.
pub fn audit(a: &Analysis, chain: &ChainInput) -> Option<FingerAudit> {
    audit_with(a, chain, &JudgeOptions::skin(a))
}

/// Judges one rig finger. `None` when the data has no such finger or the chain
/// has the wrong number of points, a non-finite point, a zero-length segment,
/// tips unlike the data's with no soft tissue figure for the finger, or a last
/// segment no longer than the tip correction. Cost: O(1) for the
/// standings, a few thousand evaluations of the proportions for the explanation.
pub fn audit_with(a: &Analysis, chain: &ChainInput, opts: &JudgeOptions) -> Option<FingerAudit> {
    judge_finger(a, chain, opts, &[])
}

/// Judges one rig finger as [`audit_with`] with its MCP held where it is: the
/// explanation moves only the inner joints (for an MCP placed from its ray's
/// base, [`super::ray_base::metacarpal`] or [`super::ray_base::wrist`]).
pub fn audit_holding_mcp(
    a: &Analysis,
    chain: &ChainInput,
    opts: &JudgeOptions,
) -> Option<FingerAudit> {
    judge_finger(a, chain, opts, &[Joint::Mcp])
}

/// Judges one rig finger as [`audit_with`] with the joints `hold` held where
/// they are: the explanation moves only the others (for joints that sit where
/// their skin bends, [`super::audited`]). The standings are those of
/// [`audit_with`]: they do not depend on the explanation.
pub fn audit_holding(
    a: &Analysis,
    chain: &ChainInput,
    opts: &JudgeOptions,
    hold: &[Joint],
) -> Option<FingerAudit> {
    judge_finger(a, chain, opts, hold)
}

/// The segments c_k of a chain, the tip correction and the compared segments;
/// `None` for a chain [`audit_with`] refuses.
fn compared_segments(chain: &ChainInput, opts: &JudgeOptions) -> Option<(Vec<f64>, f64, Vec<f64>)> {
    if chain.points.len() != ChainInput::expected_points(chain.finger, chain.has_tip)
        || chain.points.iter().any(|p| !p.is_finite())
    {
        return None;
    }
    let segments: Vec<f64> = chain
        .points
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .collect();
    if segments.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
        return None;
    }
    let tip_correction = if chain.has_tip {
        opts.tip_correction(chain.finger, segments.iter().sum())?
    } else {
        0.0
    };
    let mut compared = segments.clone();
    if let Some(last) = compared.last_mut() {
        *last -= tip_correction;
    }
    if compared.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
        return None;
    }
    Some((segments, tip_correction, compared))
}

fn judge_finger(
    a: &Analysis,
    chain: &ChainInput,
    opts: &JudgeOptions,
    hold: &[Joint],
) -> Option<FingerAudit> {
    let finger = chain.finger;
    let fa = a.finger(finger)?;
    let (segments, tip_correction, compared) = compared_segments(chain, opts)?;
    let quantities = judged_quantities(a, chain)?;
    let basis = match (chain.has_tip, finger) {
        (true, _) => Basis::Relative,
        (false, Finger::Thumb) => Basis::None,
        (false, _) => Basis::Ratio,
    };
    let values = quantities
        .iter()
        .map(|&(q, s)| value_check(q, value_of(q, &compared), s))
        .collect();
    let unjudged = match basis {
        Basis::Relative => Vec::new(),
        Basis::Ratio => vec![Joint::Dip],
        Basis::None => vec![Joint::Ip],
    };
    let standings = match basis {
        Basis::Relative => relative_standings(a, finger, &segments, &compared, tip_correction)?,
        Basis::Ratio => ratio_standings(a, finger, &compared)?,
        Basis::None => Vec::new(),
    };
    // The proportions as one vector with their covariance, for a finger with a
    // tip: the joint region of the X-rays' relative joint positions.
    let region = match basis {
        Basis::Relative => fa.joint_region(a.settings.confidence, opts.shape_of(finger)),
        _ => None,
    };
    let judge = Judge::new(&quantities, region.as_ref(), fa.n, a.settings.confidence);
    let region_check = region.as_ref().map(|r| {
        let t2 = r.distance_of_segments(&compared);
        let shape = match (r.correlation, r.own_correlation) {
            (Some(correlation), Some(own)) => {
                let own_t2 = r.own_distance_of_segments(&compared);
                Some(RegionShape {
                    correlation,
                    prior: r.prior,
                    prior_source: r.prior.and(opts.shape.as_ref()).map(|s| s.source.clone()),
                    own: OwnRegion {
                        correlation: own,
                        t2: own_t2,
                        inside: own_t2 <= r.bound,
                    },
                })
            }
            _ => None,
        };
        RegionCheck {
            t2,
            bound: r.bound,
            confidence: r.confidence,
            n: r.n,
            inside: t2 <= r.bound,
            shape,
        }
    });
    let axis = Axis::new(chain, &compared, tip_correction);
    let solved = explain(&axis, judge, basis, hold);
    let joints = joint_checks(chain, &axis, &solved, standings)?;
    let explanation = Explanation {
        moved: solved.moved,
        consistent: solved.consistent,
        score: solved.score.is_finite().then_some(solved.score),
        values: solved
            .segments
            .map(|s| {
                quantities
                    .iter()
                    .map(|&(q, st)| value_check(q, value_of(q, &s), st))
                    .collect()
            })
            .unwrap_or_default(),
        also: solved.also,
    };
    Some(FingerAudit {
        finger,
        has_tip: chain.has_tip,
        basis,
        n: fa.n,
        length: (basis == Basis::Relative).then(|| compared.iter().sum()),
        segments,
        tip_correction,
        compared,
        values,
        joints,
        unjudged,
        region: region_check,
        explanation,
    })
}

/// True when the fix's moves of `audit` (its joints that [`JointCheck::fix_moves`],
/// at their suggested places; the others where `chain` has them) land the
/// finger inside the inner region a fix aims at
/// ([`crate::analysis::region::FIX_LEVEL`]), judged as `audit` was (`a`,
/// `opts`, its tip correction held); also true when it moves nothing. For a
/// move made without the rest of its explanation (a companion held at a
/// knuckle or a bend). O(p^2) after the region is built.
pub(super) fn lands_inside(
    a: &Analysis,
    chain: &ChainInput,
    opts: &JudgeOptions,
    audit: &FingerAudit,
) -> bool {
    if !audit.joints.iter().any(|j| j.fix_moves()) {
        return true;
    }
    let kinds = chain_kinds(chain.finger, chain.has_tip);
    let mut points = chain.points.clone();
    for j in audit.joints.iter().filter(|j| j.fix_moves()) {
        if let Some(k) = kinds.iter().position(|&x| x == j.joint)
            && let Some(p) = points.get_mut(k)
        {
            *p = j.suggested;
        }
    }
    let mut compared: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    if let Some(last) = compared.last_mut() {
        *last -= audit.tip_correction;
    }
    let (Some(fa), Some(quantities)) = (a.finger(chain.finger), judged_quantities(a, chain)) else {
        return false;
    };
    let region = match audit.basis {
        Basis::Relative => fa.joint_region(a.settings.confidence, opts.shape_of(chain.finger)),
        _ => None,
    };
    let judge = Judge::new(&quantities, region.as_ref(), fa.n, a.settings.confidence);
    judge.fit(&compared).0 <= judge.inner
}

/// Each judged joint's check, with where the explanation puts it.
fn joint_checks(
    chain: &ChainInput,
    axis: &Axis,
    solved: &Solved,
    standings: Vec<StandingInput>,
) -> Option<Vec<JointCheck>> {
    let kinds = chain_kinds(chain.finger, chain.has_tip);
    let mut joints = Vec::new();
    for (joint, measured, expected, range, pi) in standings {
        let k = kinds.iter().position(|&j| j == joint)?;
        let moves = solved.moved.contains(&joint);
        let (suggested, shift_along) = match (&solved.arcs, moves) {
            (Some(arcs), true) => (
                point_at(&axis.points, arcs[k]),
                arcs[k] - axis.joint_arcs[k],
            ),
            _ => (chain.points[k], 0.0),
        };
        let shift = chain.points[k].distance(suggested);
        joints.push(JointCheck {
            joint,
            measured,
            expected,
            range,
            pi,
            standing: Standing::of(measured, range, pi),
            moves,
            fix: false,
            suggested,
            shift,
            shift_along,
            // Moves that leave the finger outside the inner region are not made.
            held: (moves && !solved.consistent).then(|| Held::new(HoldReason::Short, shift, None)),
        });
    }
    Some(joints)
}
