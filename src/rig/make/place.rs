//! Placing a hand's finger joints on the axes found on its skin, from the
//! statistics (the paper's rule: the X-rays' mean proportions carried to a
//! finger of known length, eqs. 2 and 5).
//!
//! For each finger (not the thumb), its axis from the tip back into the palm:
//! - **The tip** is the skin's end along the last bone, as the audit reads
//!   it: the finder's tip carried on along the laid DIP -> tip direction to
//!   the farthest reach of the finger's skin ([`crate::rig::find`]).
//! - **The MCP** lies on the axis (continued straight into the palm as far as
//!   needed) where the wrist-to-MCP distance w over the finger's bone length J
//!   is the atlas's mean y = w/J: |wrist - M| = y J, J = (1 - q) L, L the
//!   finger's length to the skin (its three chords) and q the fingertip's
//!   soft tissue as a share of it (Buryanov & Kotiuk's, which bridges the
//!   atlas's bone tips). The same ratio the audit judges a rig's MCP by from
//!   its wrist (`rig::judge::ray_base::wrist`), so the audit finds the made MCP
//!   at the atlas's mean. Solved by bisection on the distance from the tip.
//! - **PIP and DIP** lie on the axis between MCP and tip where the three chords
//!   have the data's mean proportions (J~1 : J~2 : J~3); against data whose
//!   tips are at the bone, the last chord includes the soft tissue (q L), as
//!   the audit corrects it: shares m1 (1 - q), m2 (1 - q), m3 (1 - q) + q.
//!
//! For the thumb the CMC is the point of its axis (continued into the palm)
//! nearest the wrist: the thumb's metacarpal turns about the trapezium,
//! beside the wrist; its MCP is where the atlas's thumb mc/J puts it from the
//! CMC (|CMC - MCP| = x J), and its IP at the data's mean J~1 of MCP to tip.
//!
//! **Depth.** The axis runs through the centres of the finger's sections; a
//! joint's rotation centre lies dorsal of that centre, in the head of the bone
//! before it, under the thin skin and extensor hood of the back of the finger
//! while the flexor tendons and the pulp thicken the palm side. Each joint of
//! the fingers, and the thumb's CMC, is put at [`DEPTH`] of the skin's
//! thickness from the back (along the palm's normal made square to the
//! finger, the thickness found by casting that line through the skin); the
//! thumb's other joints, whose back faces across the palm, stay on its axis. Cost: O(m log) per
//! finger for m axis points.

use crate::analysis::placement::Joint;
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::rig::find::{FoundFinger, FoundHand, HandMesh};
use crate::rig::judge::chain::{arc_positions, on_chain, point_at};
use crate::rig::judge::{SoftTissue, TipKind, WristRatios, data_tip_of};
use crate::rig::read::naming::Side;
use glam::DVec3;

/// Where a finger joint's rotation centre lies in the finger's (or, for the
/// MCP, the palm's) thickness, measured from the back along the palm's
/// normal: 0.4. The head of the bone before the joint lies under the thin
/// skin and extensor hood of the back while the flexor tendons, the pulp
/// and the palm's pad thicken the palm side; the artists of the shared rigs
/// put their MCPs at 0.19-0.59 (median 0.42) and their PIPs and DIPs at
/// 0.24-0.52 (median 0.39).
pub const DEPTH: f64 = 0.4;

/// What the placement needs of the statistics.
#[derive(Debug, Clone)]
pub struct Proportions {
    /// Per finger, the data's mean relative segment lengths (J~1, J~2[, J~3]),
    /// the centre of its joint region.
    pub means: Vec<(Finger, Vec<f64>)>,
    /// Per finger but the thumb, the atlas's mean wrist-to-MCP distance over
    /// the finger's bone length (w/J).
    pub wrist: Vec<(Finger, f64)>,
    /// The atlas's mean thumb metacarpal over the thumb's bone length (mc/J).
    pub thumb_metacarpal: Option<f64>,
    /// The atlas's mean thumb CMC in the hand's frame (a, b): CMC = W + D (a
    /// d + b r), W the wrist, D and d the distance and direction to the
    /// middle finger's MCP, r square to d in the palm towards the thumb.
    pub thumb_cmc: Option<[f64; 2]>,
    /// The fingertip's soft tissue, as the audit takes it.
    pub soft_tissue: SoftTissue,
    /// What the data's tips mark (its last segment is compared to them).
    pub data_tip: TipKind,
    /// What the atlas's tips mark (its ratios' J ends at them).
    pub atlas_tip: TipKind,
}

impl Proportions {
    /// The proportions of `data` (its mean relative lengths), with the
    /// MCP's ratios from `atlas` (mc/J of the thumb) and `wrist` (w/J of the
    /// others) and the tips' soft tissue `soft_tissue`, as the audit judges
    /// them. O(fingers).
    pub fn new(
        data: &Analysis,
        atlas: Option<&Analysis>,
        wrist: Option<&WristRatios>,
        soft_tissue: SoftTissue,
    ) -> Proportions {
        let rel = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3];
        let means = Finger::ALL
            .iter()
            .filter_map(|&f| {
                let s = data.finger(f)?;
                let k = if f == Finger::Thumb { 2 } else { 3 };
                let m: Option<Vec<f64>> = rel[..k]
                    .iter()
                    .map(|&q| s.quantity(q).map(|x| x.mean))
                    .collect();
                Some((f, m?))
            })
            .collect();
        let thumb_cmc = wrist.and_then(|w| w.thumb_cmc);
        let wrist = wrist
            .map(|w| w.ratios.iter().map(|r| (r.finger, r.mean)).collect())
            .unwrap_or_default();
        let thumb_metacarpal = atlas
            .and_then(|a| a.finger(Finger::Thumb)?.quantity(Quantity::RatioMcJ))
            .map(|x| x.mean);
        Proportions {
            means,
            wrist,
            thumb_metacarpal,
            thumb_cmc,
            soft_tissue,
            data_tip: data_tip_of(&data.tips),
            atlas_tip: atlas.map_or(TipKind::Bone, |a| data_tip_of(&a.tips)),
        }
    }

    fn of<T>(list: &[(Finger, T)], f: Finger) -> Option<&T> {
        list.iter().find(|(g, _)| *g == f).map(|(_, x)| x)
    }

    /// The soft tissue a made finger of `length` (to the skin) has beyond
    /// the tip that data with tips `kind` mark, as a share of `length` (0
    /// for skin tips; `None` when it is not known).
    fn soft_share(&self, kind: TipKind, finger: Finger, length: f64) -> Option<f64> {
        let c = self
            .soft_tissue
            .correction(TipKind::Skin, kind, finger, length)?;
        (length > 0.0).then(|| c / length)
    }
}

/// One finger's made joints, root first: for a finger MCP, PIP, DIP, tip;
/// for the thumb MCP, IP, tip, with its CMC apart.
#[derive(Debug, Clone, PartialEq)]
pub struct MadeFinger {
    pub finger: Finger,
    pub joints: Vec<(Joint, DVec3)>,
    /// The thumb's CMC (the base of its metacarpal).
    pub cmc: Option<DVec3>,
    /// The finger's local radius at each joint (for the weights' blends).
    pub radius: Vec<f64>,
    /// The axis as found, root first (the palm end continued), for the weights.
    pub axis: Vec<DVec3>,
}

/// A hand's made joints.
#[derive(Debug, Clone, PartialEq)]
pub struct MadeHand {
    pub side: Side,
    pub wrist: DVec3,
    pub palm_normal: DVec3,
    pub fingers: Vec<MadeFinger>,
    /// Fingers left out, and why.
    pub notes: Vec<String>,
}

/// Places every finger of `hand` (see the module notes); a finger the
/// statistics cannot place (no means, no ratio for its base) is left out
/// with a note.
pub fn place(mesh: &HandMesh, hand: &FoundHand, p: &Proportions) -> MadeHand {
    let mut fingers: Vec<MadeFinger> = Vec::new();
    let mut notes = Vec::new();
    // The fingers first: the thumb's CMC is placed in the frame of their MCPs.
    let (thumbs, others): (Vec<&FoundFinger>, Vec<&FoundFinger>) =
        hand.fingers.iter().partition(|f| f.finger == Finger::Thumb);
    for f in others.into_iter().chain(thumbs) {
        match place_finger(mesh, hand, f, p, &fingers) {
            Ok(made) => fingers.push(made),
            Err(why) => notes.push(format!("{}: not placed ({why})", f.finger.name())),
        }
    }
    fingers.sort_by_key(|f| f.finger.index());
    MadeHand {
        side: hand.side,
        wrist: hand.wrist,
        palm_normal: hand.palm_normal,
        fingers,
        notes,
    }
}

/// The thumb's CMC from the atlas's (a, b) in the frame of the wrist and the
/// middle finger's MCP (else the mean of the other MCPs made), r towards
/// the index's MCP (else the thumb's tip), at its depth in the palm.
fn thumb_cmc(hand: &FoundHand, made: &[MadeFinger], ab: [f64; 2], tip: DVec3) -> Option<DVec3> {
    let mcp = |f: &MadeFinger| f.joints.first().map(|j| j.1);
    let middle = made
        .iter()
        .find(|f| f.finger == Finger::Middle)
        .and_then(mcp)
        .or_else(|| {
            let all: Vec<DVec3> = made.iter().filter_map(mcp).collect();
            (!all.is_empty()).then(|| all.iter().sum::<DVec3>() / all.len() as f64)
        })?;
    let w = hand.wrist;
    let big_d = w.distance(middle);
    let d = (middle - w).normalize_or_zero();
    let mut r = hand.palm_normal.cross(d).normalize_or_zero();
    let towards = made
        .iter()
        .find(|f| f.finger == Finger::Index)
        .and_then(mcp)
        .unwrap_or(tip);
    if (towards - w).dot(r) < 0.0 {
        r = -r;
    }
    (big_d > 0.0 && r != DVec3::ZERO).then(|| w + big_d * (ab[0] * d + ab[1] * r))
}

/// The axis root first, continued straight past its palm end by `extra`.
fn root_first(f: &FoundFinger, extra: f64) -> Vec<DVec3> {
    let mut axis: Vec<DVec3> = f.axis.iter().rev().copied().collect();
    if axis.len() >= 2 {
        let dir = (axis[0] - axis[1]).normalize_or_zero();
        axis.insert(0, axis[0] + dir * extra);
    }
    axis
}

/// The point at distance `t` from the tip along `axis` (root first), and
/// the sub-polyline from it to the tip.
fn from_tip(axis: &[DVec3], arcs: &[f64], t: f64) -> (DVec3, Vec<DVec3>) {
    let total = arcs[arcs.len() - 1];
    let u = (total - t).max(0.0);
    let m = point_at(axis, u);
    let mut sub = vec![m];
    sub.extend(
        axis.iter()
            .zip(arcs)
            .filter(|(_, a)| **a > u + 1e-12)
            .map(|(p, _)| *p),
    );
    (m, sub)
}

fn place_finger(
    mesh: &HandMesh,
    hand: &FoundHand,
    f: &FoundFinger,
    p: &Proportions,
    made_so_far: &[MadeFinger],
) -> Result<MadeFinger, String> {
    let means = Proportions::of(&p.means, f.finger)
        .cloned()
        .ok_or("the data has no such finger")?;
    let reach = 4.0 * hand.wrist.distance(f.tip);
    let mut axis = root_first(f, reach);
    // The tip is the skin's end along the last bone, as the audit reads it
    // (the farthest reach of the finger's skin along DIP -> tip): the axis
    // is carried on to it, then laid again until the reach along the laid
    // last bone is under 0.05 mm (two or three rounds).
    let mut towards = f.tip_direction;
    let mut chain = None;
    for _ in 0..4 {
        let end = axis[axis.len() - 1];
        let past = skin_past(mesh, f, end, towards);
        if past > 5e-5 || chain.is_none() {
            if past > 1e-9 {
                axis.push(end + towards * past);
            }
        } else {
            break;
        }
        let laid = lay_finger(mesh, hand, f, p, made_so_far, &means, &axis)?;
        let n = laid.joints.len();
        if n >= 2 {
            towards = (laid.joints[n - 1] - laid.joints[n - 2]).normalize_or(towards);
        }
        chain = Some(laid);
    }
    let chain = chain.ok_or("its joints cannot be laid on its axis")?;
    finish_finger(f, chain, axis)
}

/// How far the finger's skin (its region's vertices) reaches past `end`
/// along `dir`; 0 when it does not. O(region).
fn skin_past(mesh: &HandMesh, f: &FoundFinger, end: DVec3, dir: DVec3) -> f64 {
    f.vertices
        .iter()
        .filter_map(|&v| mesh.positions.get(v as usize))
        .map(|&q| (q - end).dot(dir))
        .fold(0.0, f64::max)
}

/// One finger's chain laid on `axis` (root first, ending at the tip).
fn lay_finger(
    mesh: &HandMesh,
    hand: &FoundHand,
    f: &FoundFinger,
    p: &Proportions,
    made_so_far: &[MadeFinger],
    means: &[f64],
    axis: &[DVec3],
) -> Result<Chain, String> {
    let arcs = arc_positions(axis);
    let total = arcs[arcs.len() - 1];
    if !(total.is_finite() && total > 0.0) {
        return Err("its axis has no length".into());
    }
    // The soft tissue's shares are taken at the finger's length: first the
    // tip-to-web arc, then the made finger's (exact at once for a table's
    // shares, which do not depend on the length).
    let mut length = f.web_arc.max(f.tip.distance(f.web));
    let mut made = None;
    for _ in 0..2 {
        let unknown = "the fingertip's soft tissue is not known, so the data's bone tips cannot \
                       be carried to the skin (give --tip-soft-tissue MM)";
        let q = p.soft_share(p.data_tip, f.finger, length).ok_or(unknown)?;
        let q_atlas = p.soft_share(p.atlas_tip, f.finger, length).ok_or(unknown)?;
        // The chords' shares of the finger to the skin (see the module notes).
        let k = means.len();
        let shares: Vec<f64> = means
            .iter()
            .enumerate()
            .map(|(i, m)| m * (1.0 - q) + if i + 1 == k { q } else { 0.0 })
            .collect();
        let laid = Laying {
            mesh,
            hand,
            axis,
            arcs: &arcs,
            shares: &shares,
        };
        let chain = if f.finger == Finger::Thumb {
            let x = p
                .thumb_metacarpal
                .ok_or("the atlas gives no thumb metacarpal ratio (mc/J)")?;
            let ab = p
                .thumb_cmc
                .ok_or("the atlas gives no place for the thumb's CMC")?;
            let cmc = thumb_cmc(hand, made_so_far, ab, f.tip)
                .ok_or("no other finger's MCP was made to place its CMC from")?;
            let cmc = cmc + laid.depth_at(cmc, f.tip - cmc);
            laid.thumb(x * (1.0 - q_atlas), cmc)?
        } else {
            let y = *Proportions::of(&p.wrist, f.finger)
                .ok_or("the atlas gives no wrist ratio (w/J) for it")?;
            laid.finger(y * (1.0 - q_atlas))?
        };
        length = chain.joints.windows(2).map(|w| w[0].distance(w[1])).sum();
        made = Some(chain);
    }
    made.ok_or_else(|| "its joints cannot be laid on its axis".to_string())
}

/// The made finger from its laid chain: the joints named, each one's local
/// radius.
fn finish_finger(f: &FoundFinger, chain: Chain, axis: Vec<DVec3>) -> Result<MadeFinger, String> {
    let kinds: &[Joint] = if f.finger == Finger::Thumb {
        &[Joint::Mcp, Joint::Ip, Joint::Tip]
    } else {
        &[Joint::Mcp, Joint::Pip, Joint::Dip, Joint::Tip]
    };
    if chain.joints.len() != kinds.len() {
        return Err("its joints cannot be laid on its axis".into());
    }
    // The local radius at each joint: the axis point nearest it.
    let radius_at = |q: DVec3| -> f64 {
        f.axis
            .iter()
            .zip(&f.radius)
            .min_by(|a, b| a.0.distance(q).total_cmp(&b.0.distance(q)))
            .map_or(0.0, |(_, r)| *r)
    };
    let radius: Vec<f64> = chain.joints.iter().map(|&q| radius_at(q)).collect();
    Ok(MadeFinger {
        finger: f.finger,
        joints: kinds.iter().copied().zip(chain.joints).collect(),
        cmc: chain.cmc,
        radius,
        axis,
    })
}

/// A finger's chain as laid: MCP to tip, and the thumb's CMC.
struct Chain {
    joints: Vec<DVec3>,
    cmc: Option<DVec3>,
}

/// What laying one finger's joints on its axis needs.
struct Laying<'a> {
    mesh: &'a HandMesh,
    hand: &'a FoundHand,
    /// The axis root first, continued into the palm.
    axis: &'a [DVec3],
    arcs: &'a [f64],
    /// The chords' shares of the finger, MCP to the skin's tip.
    shares: &'a [f64],
}

impl Laying<'_> {
    /// The chain from the axis point `t` from the tip, its root moved by
    /// `depth` (the MCP's offset from the axis to its depth): root, inner
    /// joints at the shares on the axis, the tip.
    fn chain(&self, t: f64, depth: DVec3) -> Option<Vec<DVec3>> {
        let (m, mut sub) = from_tip(self.axis, self.arcs, t);
        sub[0] = m + depth;
        let (points, _) = on_chain(&sub, self.shares)?;
        Some(points)
    }

    /// The offset that puts `at` at [`DEPTH`] of the skin's thickness from
    /// the back, along the palm's normal made square to the chain's
    /// direction `along`; zero where the line finds no skin on both sides.
    fn depth_at(&self, at: DVec3, along: DVec3) -> DVec3 {
        let n = self.hand.palm_normal;
        let u = along.normalize_or_zero();
        let towards_palm = (n - n.dot(u) * u).normalize_or_zero();
        match self.mesh.inside_along(at, towards_palm) {
            Some((back, palm)) => towards_palm * (back + DEPTH * (palm - back)),
            None => DVec3::ZERO,
        }
    }

    /// Each inner joint of `chain` moved to its depth, then the inner joints
    /// laid again on the moved chain at the shares exactly (ends fixed).
    fn deepen(&self, chain: &[DVec3]) -> Option<Vec<DVec3>> {
        let n = chain.len();
        let mut moved = chain.to_vec();
        for k in 1..n - 1 {
            moved[k] = chain[k] + self.depth_at(chain[k], chain[k + 1] - chain[k - 1]);
        }
        on_chain(&moved, self.shares).map(|(p, _)| p)
    }

    /// A finger (not the thumb): the MCP where |wrist - MCP| = y J, J the
    /// chain's length (y the atlas's w/J carried to the skin's length), at
    /// its depth (found by three rounds: the depth's offset held while the
    /// distance is solved, then measured again at the new MCP).
    fn finger(&self, y: f64) -> Result<Chain, String> {
        let wrist = self.hand.wrist;
        let total = self.arcs[self.arcs.len() - 1];
        let mut depth = DVec3::ZERO;
        let mut found = None;
        for _ in 0..3 {
            let g = |t: f64| {
                self.chain(t, depth).map(|c| {
                    let length: f64 = c.windows(2).map(|w| w[0].distance(w[1])).sum();
                    wrist.distance(c[0]) - y * length
                })
            };
            let t = first_root(g, 1e-6 * total, total)
                .ok_or("no MCP on its axis fits the atlas's wrist-to-MCP ratio")?;
            let c = self
                .chain(t, depth)
                .ok_or("its joints cannot be laid on its axis")?;
            let root = c[0] - depth;
            depth = self.depth_at(root, c[1] - c[0]);
            found = Some(t);
        }
        let t = found.ok_or("no MCP fits")?;
        let c = self
            .chain(t, depth)
            .ok_or("its joints cannot be laid on its axis")?;
        let joints = self
            .deepen(&c)
            .ok_or("its joints cannot be laid on its axis")?;
        Ok(Chain { joints, cmc: None })
    }

    /// The thumb from its CMC `cmc`: the MCP on the axis where |CMC - MCP|
    /// = x J (x the atlas's mc/J carried to the skin's length, J the chain's
    /// length), as the audit judges a metacarpal; the thumb's joints stay on
    /// its axis (its back faces across the palm).
    fn thumb(&self, x: f64, cmc: DVec3) -> Result<Chain, String> {
        let total = self.arcs[self.arcs.len() - 1];
        let g = |t: f64| {
            self.chain(t, DVec3::ZERO).map(|c| {
                let length: f64 = c.windows(2).map(|w| w[0].distance(w[1])).sum();
                cmc.distance(c[0]) - x * length
            })
        };
        // Where no MCP lies x J from the CMC, the one that comes nearest.
        let t = first_root(g, 1e-6 * total, total)
            .or_else(|| nearest_zero(g, 1e-6 * total, total))
            .ok_or("its joints cannot be laid on its axis")?;
        let joints = self
            .chain(t, DVec3::ZERO)
            .ok_or("its joints cannot be laid on its axis")?;
        Ok(Chain {
            joints,
            cmc: Some(cmc),
        })
    }
}

/// Where |g| is least on [lo, hi], over 256 even steps; `None` when `g`
/// cannot be evaluated anywhere.
fn nearest_zero(g: impl Fn(f64) -> Option<f64>, lo: f64, hi: f64) -> Option<f64> {
    (0..=256)
        .map(|k| lo + (hi - lo) * k as f64 / 256.0)
        .filter_map(|t| g(t).map(|v| (t, v.abs())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(t, _)| t)
}

/// The first root of `g` on [lo, hi] where it falls through 0: the first of
/// 64 even steps where it goes from above 0 to at most 0, then 60 steps of
/// bisection; `None` when it never does (steps where `g` cannot be evaluated
/// are passed over).
fn first_root(g: impl Fn(f64) -> Option<f64>, lo: f64, hi: f64) -> Option<f64> {
    const STEPS: usize = 64;
    let at = |k: usize| lo + (hi - lo) * k as f64 / STEPS as f64;
    let mut prev: Option<(f64, f64)> = None;
    for k in 0..=STEPS {
        let t = at(k);
        let Some(v) = g(t) else {
            prev = None;
            continue;
        };
        if let Some((a, va)) = prev
            && va > 0.0
            && v <= 0.0
        {
            let (mut a, mut b) = (a, t);
            for _ in 0..60 {
                let mid = 0.5 * (a + b);
                match g(mid) {
                    Some(x) if x > 0.0 => a = mid,
                    Some(_) => b = mid,
                    None => return None,
                }
            }
            return Some(0.5 * (a + b));
        }
        prev = Some((t, v));
    }
    None
}
