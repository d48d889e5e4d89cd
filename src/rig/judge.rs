//! Judging a rig's finger joints against the X-ray statistics.
//!
//! A rig finger is a chain of joint centres P0 (MCP), P1, P2 (PIP, DIP; the
//! thumb has one inner joint, IP) and, when the rig has one, the tip. Its
//! segments are the chords c_k = |P_k - P_(k-1)|.
//!
//! **The tip.** A rig's tip node usually marks the skin at the end of the
//! finger, while an X-ray's J3 ends at the bone tip (the distal phalanx's
//! tuft). So, with a skin tip and bone-tip data, the last segment is
//! compared as c_last - s, s the soft tissue beyond the bone tip
//! ([`DEFAULT_SOFT_TISSUE_MM`], `--tip-soft-tissue`); with `--tip bone` it is
//! compared as it is. In general the correction is s x ([rig tip is skin] -
//! [data tip is skin]); the compared segments s_k are the chords with that
//! correction on the last one, L = sum s_k and J~k = s_k / L (eq. 2).
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
//! joint alone, then pairs, keeping the first size at which every value lies
//! inside its prediction interval. A joint alone is placed where the worst
//! value is best (the smallest largest normalised distance from the mean, 1 at
//! a prediction limit); a pair is placed exactly at the means. Between
//! explanations of the same size the better fit wins, then the smaller total
//! move. Joints move along the rig's own chain (the polyline through its
//! joints), the MCP along the first segment's backward extension (at most one
//! segment back, half a segment forward). See `rig::chain`. No files, no glTF.

use super::chain::{arc_positions, backward_at, on_chain, point_at};
use super::read::FingerChain;
use crate::analysis::placement::{Joint, Placed};
use crate::analysis::{Analysis, Interval, Quantity, QuantityStats};
use crate::dataset::Finger;
use glam::DVec3;
use schemars::JsonSchema;
use serde::Serialize;

/// Soft tissue between the bone tip (the distal phalanx's tuft) and the skin
/// at the end of a finger, in mm, when the rig does not say.
///
/// An assumption, not a measured mean: no study measuring the soft tissue
/// distal to the tuft along the finger's axis was found. The nearest measured
/// figures are thinner tissues over the same bone: the nail bed (dorsal soft
/// tissue between nail and tuft) measures 2.38 +/- 0.27 mm (range 1.75-3.10)
/// on lateral radiographs of 100 normal adults (PubMed 18428986, 2008), and
/// the soft tissue under the nail 1.6 +/- 0.1 mm by ultrasound (Diagnosis of
/// digital clubbing by high-frequency ultrasound imaging); the pulp that caps
/// the tip is thicker than the nail bed. 4 mm is taken, and `--tip-soft-tissue`
/// sets it for a given hand.
pub const DEFAULT_SOFT_TISSUE_MM: f64 = 4.0;

/// What the tip node of a rig (or the end of an X-ray's J3) marks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TipKind {
    /// The skin at the end of the finger (most rigs; WebXR's `*-tip`).
    Skin,
    /// The end of the distal phalanx (an X-ray's bone tip).
    Bone,
}

/// How a rig is compared with the data.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct JudgeOptions {
    /// What the rig's tip nodes mark.
    pub rig_tip: TipKind,
    /// What the data's tips mark. The paper does not say; taken as bone tips.
    pub data_tip: TipKind,
    /// Soft tissue between bone tip and skin tip, in rig units (metres).
    pub soft_tissue: f64,
}

impl Default for JudgeOptions {
    fn default() -> JudgeOptions {
        JudgeOptions {
            rig_tip: TipKind::Skin,
            data_tip: TipKind::Bone,
            soft_tissue: DEFAULT_SOFT_TISSUE_MM / 1000.0,
        }
    }
}

impl JudgeOptions {
    /// Taken off the rig's last segment to compare like with like:
    /// s x ([rig tip is skin] - [data tip is skin]).
    pub fn tip_correction(&self) -> f64 {
        let skin = |t: TipKind| f64::from(u8::from(t == TipKind::Skin));
        self.soft_tissue * (skin(self.rig_tip) - skin(self.data_tip))
    }
}

/// One finger of a rig, as joint centres from the root.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainInput {
    pub finger: Finger,
    /// Root (MCP), the inner joints, then the tip when `has_tip`, in the rig's space.
    pub points: Vec<DVec3>,
    pub has_tip: bool,
}

impl ChainInput {
    /// Number of points a complete chain of `finger` has.
    pub fn expected_points(finger: Finger, has_tip: bool) -> usize {
        1 + Joint::inner(finger).len() + usize::from(has_tip)
    }
}

impl FingerChain {
    /// The chain's geometry, for the analysis.
    pub fn input(&self) -> ChainInput {
        ChainInput {
            finger: self.finger,
            points: self.joints.iter().map(|j| j.position).collect(),
            has_tip: self.has_tip,
        }
    }
}

/// What a finger was judged on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// Relative values J~k: the rig has a tip.
    Relative,
    /// The ratio J2/J1 only: no tip.
    Ratio,
    /// Nothing can be judged (a thumb without a tip).
    None,
}

/// Where a measured value stands against the statistics.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "standing", rename_all = "snake_case")]
pub enum Standing {
    /// Inside the observed range [min, max] of the X-rays.
    InRange,
    /// Outside the observed range, inside the prediction interval for one new hand.
    InPrediction,
    /// Above the prediction interval (above the range when there is none) by `by`.
    Above { by: f64 },
    /// Below it by `by`.
    Below { by: f64 },
}

impl Standing {
    /// Judges `x` against the prediction interval when there is one (else the
    /// range): outside it, by how much; inside it, whether also inside the
    /// observed range. O(1).
    ///
    /// The range is widened by one part in a million of its ends, the precision
    /// a glTF file (f32) keeps: an X-ray's own proportions stored in a rig must
    /// still read as inside the range they set.
    pub fn of(x: f64, range: Interval, pi: Option<Interval>) -> Standing {
        let tol = 1e-6 * range.low.abs().max(range.high.abs());
        let in_range = range.low - tol <= x && x <= range.high + tol;
        let outer = match pi {
            Some(pi) if pi.contains(x) || (in_range && pi.width() >= range.width()) => {
                return if in_range {
                    Standing::InRange
                } else {
                    Standing::InPrediction
                };
            }
            Some(pi) => pi,
            None if in_range => return Standing::InRange,
            None => range,
        };
        if x > outer.high {
            Standing::Above { by: x - outer.high }
        } else {
            Standing::Below { by: outer.low - x }
        }
    }

    /// True when inside the range or the prediction interval.
    pub fn is_consistent(self) -> bool {
        matches!(self, Standing::InRange | Standing::InPrediction)
    }
}

/// One quantity of a rig finger against the X-rays.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ValueCheck {
    pub quantity: Quantity,
    pub measured: f64,
    pub mean: f64,
    pub range: Interval,
    pub pi: Option<Interval>,
    #[serde(flatten)]
    pub standing: Standing,
}

/// One joint of a rig finger against the X-rays, in the rig's units, given
/// the rest of the finger as the rig has it (see the module notes).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct JointCheck {
    pub joint: Joint,
    /// Distance from the rig's MCP along the chain, as the rig has it (0 for the MCP).
    pub measured: f64,
    /// Where the mean puts it, on the same scale (negative: proximal of the rig's MCP).
    pub expected: f64,
    pub range: Interval,
    pub pi: Option<Interval>,
    /// `Above` means the joint sits too far towards the tip.
    #[serde(flatten)]
    pub standing: Standing,
    /// True when the explanation moves this joint.
    pub moves: bool,
    /// Where the explanation puts the joint (the rig's joint when it does not move it).
    #[schemars(with = "[f64; 3]")]
    pub suggested: DVec3,
    /// Distance from the rig's joint to the suggested one.
    pub shift: f64,
    /// How far the suggestion lies along the chain from the rig's joint:
    /// positive towards the tip, negative towards the root.
    pub shift_along: f64,
}

/// The fewest joints whose moves bring the finger inside the X-rays' prediction intervals.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Explanation {
    /// The joints that move, root first (empty: nothing needs to move).
    pub moved: Vec<Joint>,
    /// True when, with those moved, every value is inside its prediction interval.
    pub consistent: bool,
    /// The largest normalised distance of a value from its mean after the
    /// moves: 0 at the mean, 1 at a prediction limit (`None` when no value
    /// could be judged).
    pub score: Option<f64>,
    /// The values after the moves.
    pub values: Vec<ValueCheck>,
    /// Other sets of as many joints that would also bring the finger inside.
    pub also: Vec<Vec<Joint>>,
}

/// A rig finger judged against the X-ray statistics.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct FingerAudit {
    pub finger: Finger,
    pub has_tip: bool,
    pub basis: Basis,
    /// X-rays behind the statistics.
    pub n: usize,
    /// The rig's segment lengths c_k (J1, J2[, J3]; without a tip one fewer).
    pub segments: Vec<f64>,
    /// Taken off the last segment to compare the rig's tip with the data's (see the module notes).
    pub tip_correction: f64,
    /// The segments compared with the X-rays: `segments` with the last one corrected.
    pub compared: Vec<f64>,
    /// L = sum of the compared segments, with a tip.
    pub length: Option<f64>,
    pub values: Vec<ValueCheck>,
    /// MCP, the inner joints and the tip, each against the rest of the finger.
    pub joints: Vec<JointCheck>,
    /// Inner joints that could not be judged (no tip).
    pub unjudged: Vec<Joint>,
    pub explanation: Explanation,
}

impl FingerAudit {
    /// True when every judged joint and value is inside the range or the prediction interval.
    pub fn is_consistent(&self) -> bool {
        self.joints.iter().all(|j| j.standing.is_consistent())
            && self.values.iter().all(|v| v.standing.is_consistent())
    }

    /// The check of `joint`, when judged.
    pub fn joint(&self, joint: Joint) -> Option<&JointCheck> {
        self.joints.iter().find(|j| j.joint == joint)
    }

    /// The suggested chain: the rig's points with the explanation's joints moved.
    pub fn suggested_chain(&self, chain: &ChainInput) -> Vec<DVec3> {
        let kinds = chain_kinds(chain.finger, chain.has_tip);
        chain
            .points
            .iter()
            .zip(&kinds)
            .map(|(p, k)| match self.joint(*k) {
                Some(j) if j.moves => j.suggested,
                _ => *p,
            })
            .collect()
    }
}

/// The joints of a chain of `finger`, root first.
fn chain_kinds(finger: Finger, has_tip: bool) -> Vec<Joint> {
    let mut k = vec![Joint::Mcp];
    k.extend_from_slice(Joint::inner(finger));
    if has_tip {
        k.push(Joint::Tip);
    }
    k
}

/// The statistics of `quantity` for `finger`, when the data has them.
fn stats(a: &Analysis, finger: Finger, q: Quantity) -> Option<&QuantityStats> {
    a.finger(finger)?.quantity(q)
}

fn value_check(q: Quantity, measured: f64, s: &QuantityStats) -> ValueCheck {
    let range = Interval::new(s.min, s.max);
    ValueCheck {
        quantity: q,
        measured,
        mean: s.mean,
        range,
        pi: s.intervals.pi,
        standing: Standing::of(measured, range, s.intervals.pi),
    }
}

/// The value of `q` for segments `s` (the thumb's two, a finger's three, or
/// the first two without a tip).
fn value_of(q: Quantity, s: &[f64]) -> f64 {
    let total: f64 = s.iter().sum();
    match q {
        Quantity::RelJ1 => s[0] / total,
        Quantity::RelJ2 => s[1] / total,
        Quantity::RelJ3 => s[2] / total,
        Quantity::RatioJ2J1 => s[1] / s[0],
        Quantity::RatioJ3J2 => s[2] / s[1],
        Quantity::Total => total,
        // The metacarpal is not part of the chain: never among the judged quantities.
        Quantity::RatioMcJ | Quantity::RatioJ1Mc => f64::NAN,
    }
}

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

/// How far `x` lies from the mean of `s`, in units of the distance from the
/// mean to the prediction limit on that side (the range's end without an
/// interval): at most 1 inside. O(1).
fn normalised(x: f64, s: &QuantityStats) -> f64 {
    let (lo, hi) = s
        .intervals
        .pi
        .map_or((s.min, s.max), |pi| (pi.low, pi.high));
    let (d, half) = if x >= s.mean {
        (x - s.mean, hi - s.mean)
    } else {
        (s.mean - x, s.mean - lo)
    };
    if half > 0.0 {
        d / half
    } else if d > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

/// Judges one rig finger with the default options (a skin tip, 4 mm soft tissue).
pub fn audit(a: &Analysis, chain: &ChainInput) -> Option<FingerAudit> {
    audit_with(a, chain, &JudgeOptions::default())
}

/// Judges one rig finger. `None` when the data has no such finger or the chain
/// has the wrong number of points, a non-finite point, a zero-length segment
/// or a last segment no longer than the tip correction. Cost: O(1) for the
/// standings, a few thousand evaluations of the proportions for the explanation.
pub fn audit_with(a: &Analysis, chain: &ChainInput, opts: &JudgeOptions) -> Option<FingerAudit> {
    judge_finger(a, chain, opts, false)
}

/// Judges one rig finger as [`audit_with`] with its MCP held where it is: the
/// explanation moves only the inner joints (for an MCP placed from its ray's
/// base, [`metacarpal`] or [`wrist`]).
pub fn audit_holding_mcp(
    a: &Analysis,
    chain: &ChainInput,
    opts: &JudgeOptions,
) -> Option<FingerAudit> {
    judge_finger(a, chain, opts, true)
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
        opts.tip_correction()
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
    hold_mcp: bool,
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
    let axis = Axis::new(chain, &compared, tip_correction);
    let solved = explain(&axis, &quantities, basis, hold_mcp);
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
        explanation,
    })
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
        joints.push(JointCheck {
            joint,
            measured,
            expected,
            range,
            pi,
            standing: Standing::of(measured, range, pi),
            moves,
            suggested,
            shift: chain.points[k].distance(suggested),
            shift_along,
        });
    }
    Some(joints)
}

/// What a ray's MCP is judged from: the base held while the MCP moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RayBase {
    /// The origin of the finger's metacarpal node: the CMC joint, where the
    /// atlas's metacarpal starts.
    Cmc,
    /// The origin of the hand's wrist (hand) bone, for a rig without
    /// metacarpals: see [`WRIST_DEFINITION`].
    Wrist,
}

/// How the wrist is defined when a ray is judged from it (also in the JSON).
pub const WRIST_DEFINITION: &str = "the origin of the rig's hand (wrist) bone, read as the \
     wrist's centre of rotation, which lies in the head of the capitate; in the atlas, landmark \
     10, the one carpal landmark on the middle finger's ray (0.37 metacarpal lengths proximal of \
     its CMC, 0.01 off its axis); the atlas does not name landmarks 0-12, so this reading is \
     inferred from where they lie";

/// The distance from the wrist (atlas landmark 10, [`WRIST_DEFINITION`]) to
/// each finger's MCP over the finger's length, y = w/J with J = J1 + J2 + J3
/// (MCP to bone tip), per X-ray of the atlas's landmark file, read at run time
/// ([`WristRatios::load`]): mean, SD, count and range of y. The thumb has
/// none: its metacarpal swings about the CMC, far off the wrist, so its
/// wrist-to-MCP distance depends on the thumb's pose.
#[derive(Debug, Clone, PartialEq)]
pub struct WristRatios {
    /// The landmark file the ratios were computed from, as given.
    pub source: String,
    /// Per finger: mean, SD, count and range of y over the X-rays.
    pub ratios: Vec<WristRatio>,
}

/// One finger's wrist-to-MCP over its length y = w/J (see [`WristRatios`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WristRatio {
    pub finger: Finger,
    pub mean: f64,
    /// Sample SD (n - 1); 0 for a single X-ray.
    pub sd: f64,
    pub n: usize,
    /// The observed range [min, max] of y.
    pub range: Interval,
}

impl WristRatio {
    /// The Student-t prediction interval of y for one new hand at `confidence`
    /// (mean +/- t sd sqrt(1 + 1/n), the analysis's `pi`); `None` for n < 2. O(1).
    pub fn pi(&self, confidence: f64) -> Option<Interval> {
        crate::stats::describe::prediction_interval(self.mean, self.sd, self.n, confidence)
    }
}

impl WristRatios {
    /// Reads an atlas37 landmark file (e.g. `data/atlas/landmarks.csv`) and
    /// describes each finger's y = |wrist - MCP| / (J1 + J2 + J3) over its
    /// images. Errors with every problem of the file. O(bytes).
    pub fn load(path: &std::path::Path) -> Result<WristRatios, crate::dataset::DataError> {
        let per_image = crate::dataset::landmarks::wrist_over_length_file(path)?;
        Ok(WristRatios::from_samples(
            &path.display().to_string(),
            &per_image,
        ))
    }

    /// Mean, SD and range of each finger's per-image y; a finger without any is left out.
    pub fn from_samples(source: &str, per_image: &[(Finger, Vec<f64>)]) -> WristRatios {
        use crate::stats::describe;
        let ratios = per_image
            .iter()
            .filter_map(|(finger, ys)| {
                let (min, max) = describe::min_max(ys)?;
                Some(WristRatio {
                    finger: *finger,
                    mean: describe::mean(ys)?,
                    sd: describe::sd(ys).unwrap_or(0.0),
                    n: ys.len(),
                    range: Interval::new(min, max),
                })
            })
            .collect();
        WristRatios {
            source: source.to_string(),
            ratios,
        }
    }

    /// y of `finger` (`None` for the thumb or a finger the file lacks).
    pub fn of(&self, finger: Finger) -> Option<&WristRatio> {
        self.ratios.iter().find(|r| r.finger == finger)
    }
}

/// The rig's wrist-to-MCP distance over its finger's length, y = w/J,
/// against the atlas's (see [`WristRatios`]).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct WristValue {
    /// The rig's y: `to_mcp / length`.
    pub measured: f64,
    /// The atlas's mean of y.
    pub mean: f64,
    /// The atlas's sample SD of y (n - 1).
    pub sd: f64,
    /// The number of the atlas's X-rays y is measured on.
    pub n: usize,
    /// The atlas's observed range of y.
    pub range: Interval,
    /// The t prediction interval of y for one new hand, at the audit's confidence.
    pub pi: Option<Interval>,
    #[serde(flatten)]
    pub standing: Standing,
}

/// The MCP judged from its ray's base (the CMC, or the wrist where the rig
/// has no metacarpals) against a dataset's metacarpals (the Digital Hand
/// Atlas's by default): a guide beside the finger's own judgement, which it
/// does not change.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct MetacarpalCheck {
    /// The node the base is read from: the metacarpal (its origin is the
    /// CMC) or the hand bone (its origin is the wrist).
    pub node: String,
    /// Which base the MCP is judged from.
    pub base: RayBase,
    /// What the base is, in words (the wrist's definition for a wrist base).
    pub base_definition: String,
    /// Distance from the base to the MCP, in rig units (mc from a CMC, w from
    /// the wrist).
    pub to_mcp: f64,
    /// The rig's metacarpal mc: CMC to MCP, in rig units; null from the
    /// wrist (the rig has no metacarpal, and none is estimated).
    pub mc: Option<f64>,
    /// The finger's length J as compared (MCP to tip, the tip's soft tissue taken off).
    pub length: f64,
    /// From a CMC: mc/J and J1/mc against the dataset; empty from the wrist.
    pub values: Vec<ValueCheck>,
    /// From the wrist: y = w/J against the atlas's landmarks, the quantity
    /// the MCP is judged on; null from a CMC.
    pub wrist_over_length: Option<WristValue>,
    /// Where the dataset puts the MCP, in rig units from the base along the
    /// base-MCP line, the base and the tip held: see [`metacarpal`] and [`wrist`].
    pub expected: f64,
    /// The observed range of x = mc/J (from a CMC) or y = w/J (from the wrist)
    /// mapped onto positions from the base.
    pub range: Interval,
    /// Their prediction interval for one new hand mapped the same way.
    pub pi: Option<Interval>,
    /// The rig's MCP (at `to_mcp` from the base) against `expected`: above = too distal.
    #[serde(flatten)]
    pub standing: Standing,
    /// The MCP where the dataset puts it (at `expected` from the base).
    #[schemars(with = "[f64; 3]")]
    pub suggested: DVec3,
}

/// Judges a finger's MCP from its CMC (`cmc`, the metacarpal node's origin)
/// against the metacarpal statistics of `a`, given the finger as judged and
/// its MCP `mcp`.
///
/// With S = mc + J (CMC to the compared tip through the MCP, held) and x = mc/J,
/// the MCP belongs at S x / (1 + x) from the CMC, increasing in x, so the
/// range and prediction interval of x map onto positions end to end. Moving
/// the MCP along the line lengthens mc as much as it shortens J; holding J
/// instead would read a 10 mm shift as about 10 (1 + x) mm. `None` without a
/// tip (J unknown), without the dataset's mc/J for the finger, or for a CMC on
/// the MCP. O(1).
pub fn metacarpal(
    a: &Analysis,
    audit: &FingerAudit,
    node: &str,
    cmc: DVec3,
    mcp: DVec3,
) -> Option<MetacarpalCheck> {
    let (length, mc) = ray_lengths(audit, cmc, mcp)?;
    let x = stats(a, audit.finger, Quantity::RatioMcJ)?;
    let values: Vec<ValueCheck> = [
        (Quantity::RatioMcJ, mc / length),
        (Quantity::RatioJ1Mc, audit.compared.first()? / mc),
    ]
    .into_iter()
    .filter_map(|(q, v)| stats(a, audit.finger, q).map(|s| value_check(q, v, s)))
    .collect();
    let share = (x.mean, Interval::new(x.min, x.max), x.intervals.pi);
    Some(MetacarpalCheck {
        mc: Some(mc),
        values,
        wrist_over_length: None,
        ..ray_check((RayBase::Cmc, node), (cmc, mcp, length), share)
    })
}

/// Judges a finger's MCP from the wrist (`wrist`, the hand bone's origin; see
/// [`WRIST_DEFINITION`]) where the rig has no metacarpal.
///
/// With w the wrist-to-MCP distance, J the compared length and y = w/J, the
/// MCP belongs at S y / (1 + y) from the wrist, S = w + J held (wrist and
/// compared tip fixed), as [`metacarpal`] with x = mc/J. The atlas's y is
/// measured per X-ray (`ratios`, [`WristRatios`]): its mean, range and t
/// prediction interval at the audit's confidence map onto positions end to end.
/// `None` for the thumb, for a finger `ratios` lacks, and as [`metacarpal`]. O(1).
pub fn wrist(
    a: &Analysis,
    ratios: &WristRatios,
    audit: &FingerAudit,
    node: &str,
    wrist: DVec3,
    mcp: DVec3,
) -> Option<MetacarpalCheck> {
    let y = ratios.of(audit.finger)?;
    let (length, w) = ray_lengths(audit, wrist, mcp)?;
    let pi = y.pi(a.settings.confidence);
    let measured = w / length;
    Some(MetacarpalCheck {
        mc: None,
        values: Vec::new(),
        wrist_over_length: Some(WristValue {
            measured,
            mean: y.mean,
            sd: y.sd,
            n: y.n,
            range: y.range,
            pi,
            standing: Standing::of(measured, y.range, pi),
        }),
        ..ray_check(
            (RayBase::Wrist, node),
            (wrist, mcp, length),
            (y.mean, y.range, pi),
        )
    })
}

/// The compared length J of a judged finger and the distance from `origin` to
/// `mcp`; `None` without a tip or for an origin on the MCP.
fn ray_lengths(audit: &FingerAudit, origin: DVec3, mcp: DVec3) -> Option<(f64, f64)> {
    let length = audit.length?;
    let to_mcp = origin.distance(mcp);
    (origin.is_finite() && mcp.is_finite() && to_mcp > 0.0 && length > 0.0)
        .then_some((length, to_mcp))
}

/// The MCP judged from `origin`, the base of its ray, on a share q of the
/// base-to-MCP distance over J (x = mc/J or y = w/J: `(mean, range, pi)`):
/// it belongs at S q / (1 + q), S = to_mcp + J. O(1).
fn ray_check(
    (base, node): (RayBase, &str),
    (origin, mcp, length): (DVec3, DVec3, f64),
    (mean, q_range, q_pi): (f64, Interval, Option<Interval>),
) -> MetacarpalCheck {
    let base_definition = match base {
        RayBase::Cmc => "the origin of the finger's metacarpal node: the CMC joint".to_string(),
        RayBase::Wrist => WRIST_DEFINITION.to_string(),
    };
    let to_mcp = origin.distance(mcp);
    let span = to_mcp + length;
    // Increasing in q: intervals map end to end; a share is never negative.
    let at = |q: f64| {
        let q = q.max(0.0);
        span * q / (1.0 + q)
    };
    let expected = at(mean);
    let range = Interval::new(at(q_range.low), at(q_range.high));
    let pi = q_pi.map(|i| Interval::new(at(i.low), at(i.high)));
    MetacarpalCheck {
        node: node.to_string(),
        base,
        base_definition,
        to_mcp,
        mc: None,
        length,
        values: Vec::new(),
        wrist_over_length: None,
        expected,
        range,
        pi,
        standing: Standing::of(to_mcp, range, pi),
        suggested: origin + (mcp - origin).normalize_or_zero() * expected,
    }
}

/// A joint's standing inputs: (joint, measured, expected, range, prediction interval).
type StandingInput = (Joint, f64, f64, Interval, Option<Interval>);

/// x -> base x / (1 - x), the length a relative value x gives one segment
/// when the others sum to `base`; `None` at x >= 1.
fn share_to_length(base: f64, x: f64) -> Option<f64> {
    (x < 1.0).then(|| base * x / (1.0 - x))
}

/// The MCP and tip standings of a finger with a tip, and the inner joints'.
fn relative_standings(
    a: &Analysis,
    finger: Finger,
    segments: &[f64],
    compared: &[f64],
    correction: f64,
) -> Option<Vec<StandingInput>> {
    let length: f64 = compared.iter().sum();
    let m = compared.len();
    let last = match m {
        2 => Quantity::RelJ2,
        _ => Quantity::RelJ3,
    };
    let rel1 = stats(a, finger, Quantity::RelJ1)?;
    let rel_last = stats(a, finger, last)?;
    // A monotone increasing map of a relative value's statistics onto positions.
    let mapped = |s: &QuantityStats,
                  f: &dyn Fn(f64) -> Option<f64>|
     -> Option<(f64, Interval, Option<Interval>)> {
        let mean = f(s.mean)?;
        let range = Interval::new(f(s.min)?, f(s.max)?);
        let pi = match s.intervals.pi {
            Some(pi) => Some(Interval::new(f(pi.low.max(0.0))?, f(pi.high.min(0.999))?)),
            None => None,
        };
        Some((mean, range, pi))
    };
    let flip = |i: Interval| Interval::new(i.high, i.low);
    let mut out = Vec::new();
    // MCP: at s_1 - J1, J1 = (L - s_1) x / (1 - x), decreasing in x.
    let rest = length - compared[0];
    let (mean, range, pi) = mapped(rel1, &|x| {
        share_to_length(rest, x).map(|j1| compared[0] - j1)
    })?;
    out.push((Joint::Mcp, 0.0, mean, flip(range), pi.map(flip)));
    let mut measured = 0.0;
    for (k, &joint) in Joint::inner(finger).iter().enumerate() {
        measured += segments[k];
        // PIP/IP at J~1 L; DIP at (1 - J~3) L (see placement).
        let placed = if k == 0 {
            Placed::affine(rel1, 0.0, length)
        } else {
            Placed::affine(stats(a, finger, Quantity::RelJ3)?, length, -length)
        };
        out.push((
            joint,
            measured,
            placed.mean,
            Interval::new(placed.min, placed.max),
            placed.intervals.pi,
        ));
    }
    // Tip: at (L - s_last) + J_last + correction, increasing in x.
    let base = length - compared[m - 1];
    let (mean, range, pi) = mapped(rel_last, &|x| {
        share_to_length(base, x).map(|j| base + j + correction)
    })?;
    out.push((Joint::Tip, segments.iter().sum(), mean, range, pi));
    Some(out)
}

/// The MCP and PIP standings of a finger without a tip, on J2/J1.
fn ratio_standings(a: &Analysis, finger: Finger, s: &[f64]) -> Option<Vec<StandingInput>> {
    let st = stats(a, finger, Quantity::RatioJ2J1)?;
    // A ratio is never negative, even where an interval's formula says so.
    let r = |x: f64| x.max(1e-9);
    let span = s[0] + s[1];
    let pip = |x: f64| span / (1.0 + r(x));
    let mcp = |x: f64| s[0] - s[1] / r(x);
    // The PIP's position falls with r, the MCP's rises.
    let flip = |f: &dyn Fn(f64) -> f64, i: Interval| Interval::new(f(i.high), f(i.low));
    let keep = |f: &dyn Fn(f64) -> f64, i: Interval| Interval::new(f(i.low), f(i.high));
    let range = Interval::new(st.min, st.max);
    Some(vec![
        (
            Joint::Mcp,
            0.0,
            mcp(st.mean),
            keep(&mcp, range),
            st.intervals.pi.map(|i| keep(&mcp, i)),
        ),
        (
            Joint::Pip,
            s[0],
            pip(st.mean),
            flip(&pip, range),
            st.intervals.pi.map(|i| flip(&pip, i)),
        ),
    ])
}

/// The line the joints move along: the first segment's backward extension,
/// then the rig's joints, ending at the compared tip (the bone tip for a skin
/// tip) or, without a tip, at the last joint.
struct Axis {
    points: Vec<DVec3>,
    arcs: Vec<f64>,
    /// Arc position of each chain joint (MCP, inner joints, compared tip).
    joint_arcs: Vec<f64>,
    /// How far the MCP may move: (towards the root, towards the tip).
    mcp_reach: (f64, f64),
}

impl Axis {
    fn new(chain: &ChainInput, compared: &[f64], correction: f64) -> Axis {
        let p = &chain.points;
        let c1 = p[0].distance(p[1]);
        let back = (p[0] - p[1]).normalize_or_zero();
        let mut points = vec![p[0] + 1.5 * c1 * back];
        points.extend_from_slice(p);
        let n = p.len();
        if chain.has_tip && correction != 0.0 {
            // The compared tip lies on the last segment's line, `correction`
            // nearer the DIP (beyond the tip when negative).
            let dir = (p[n - 1] - p[n - 2]).normalize_or_zero();
            points[n] = p[n - 1] - correction * dir;
        }
        debug_assert_eq!(compared.len(), n - 1);
        let arcs = arc_positions(&points);
        let joint_arcs = arcs[1..].to_vec();
        Axis {
            points,
            arcs,
            joint_arcs,
            mcp_reach: (c1, 0.5 * c1),
        }
    }

    /// The compared segments for joints at arc positions `u`.
    fn segments(&self, u: &[f64]) -> Vec<f64> {
        let q: Vec<DVec3> = u.iter().map(|&x| point_at(&self.points, x)).collect();
        q.windows(2).map(|w| w[0].distance(w[1])).collect()
    }
}

/// An explanation as solved, with the joints' arc positions.
struct Solved {
    moved: Vec<Joint>,
    consistent: bool,
    score: f64,
    /// Arc positions of the chain's joints after the moves (`None`: nothing solved).
    arcs: Option<Vec<f64>>,
    segments: Option<Vec<f64>>,
    also: Vec<Vec<Joint>>,
}

/// The largest normalised distance of the judged values of `segments`, and
/// whether every value is inside its prediction interval (or range).
fn fit(quantities: &[(Quantity, &QuantityStats)], segments: &[f64]) -> (f64, bool) {
    if segments.iter().any(|&c| !(c.is_finite() && c > 0.0)) {
        return (f64::INFINITY, false);
    }
    let mut worst: f64 = 0.0;
    let mut inside = true;
    for &(q, s) in quantities {
        let x = value_of(q, segments);
        worst = worst.max(normalised(x, s));
        let range = Interval::new(s.min, s.max);
        inside &= Standing::of(x, range, s.intervals.pi).is_consistent();
    }
    (worst, inside)
}

/// The explanation with the fewest moved joints (see the module notes); with
/// `hold_mcp`, among moves of the inner joints only.
fn explain(
    axis: &Axis,
    quantities: &[(Quantity, &QuantityStats)],
    basis: Basis,
    hold_mcp: bool,
) -> Solved {
    if basis == Basis::None || quantities.is_empty() {
        return none_like();
    }
    let u0 = axis.joint_arcs.clone();
    let n = u0.len();
    // Movable joints: MCP and the inner joints (the last point stays).
    let kinds: Vec<Joint> = std::iter::once(Joint::Mcp)
        .chain(match n {
            3 if basis == Basis::Ratio => vec![Joint::Pip],
            3 => vec![Joint::Ip],
            _ => vec![Joint::Pip, Joint::Dip],
        })
        .collect();
    let first = usize::from(hold_mcp);
    let solved = |moved: Vec<Joint>, u: Vec<f64>| {
        let s = axis.segments(&u);
        let (score, inside) = fit(quantities, &s);
        Solved {
            moved,
            consistent: inside,
            score,
            arcs: Some(u),
            segments: Some(s),
            also: Vec::new(),
        }
    };
    let mut tried: Vec<Vec<Solved>> = vec![vec![solved(Vec::new(), u0.clone())]];
    tried.push(
        (first..kinds.len())
            .filter_map(|k| solve_one(axis, quantities, &u0, k).map(|u| solved(vec![kinds[k]], u)))
            .collect(),
    );
    if n == 4 {
        tried.push(
            [[1, 2], [0, 1], [0, 2]]
                .into_iter()
                .filter(|pair| pair[0] >= first)
                .filter_map(|pair| {
                    solve_pair(axis, quantities, &u0, pair)
                        .map(|u| solved(pair.iter().map(|&k| kinds[k]).collect(), u))
                })
                .collect(),
        );
    }
    choose(tried, &u0)
}

/// The first size at which an explanation fits, its best (the better fit,
/// then the smaller total move), with the others of that size as `also`;
/// when none fits, the best fit of all, fewer joints first on a tie.
fn choose(mut tried: Vec<Vec<Solved>>, u0: &[f64]) -> Solved {
    let movement = |s: &Solved| -> f64 {
        s.arcs.as_ref().map_or(f64::INFINITY, |a| {
            a.iter().zip(u0).map(|(x, y)| (x - y).abs()).sum()
        })
    };
    let better = |a: &Solved, b: &Solved| -> bool {
        if (a.score - b.score).abs() > 1e-6 {
            a.score < b.score
        } else {
            movement(a) < movement(b)
        }
    };
    for size in tried.iter_mut() {
        if !size.iter().any(|s| s.consistent) {
            continue;
        }
        let mut fits: Vec<Solved> = size.drain(..).filter(|s| s.consistent).collect();
        let mut best = 0;
        for i in 1..fits.len() {
            if better(&fits[i], &fits[best]) {
                best = i;
            }
        }
        let mut chosen = fits.swap_remove(best);
        chosen.also = fits.into_iter().map(|s| s.moved).collect();
        return chosen;
    }
    let mut best: Option<Solved> = None;
    for s in tried.into_iter().flatten() {
        if best.as_ref().is_none_or(|b| s.score < b.score - 1e-6) {
            best = Some(s);
        }
    }
    best.unwrap_or_else(none_like)
}

fn none_like() -> Solved {
    Solved {
        moved: Vec::new(),
        consistent: false,
        score: f64::INFINITY,
        arcs: None,
        segments: None,
        also: Vec::new(),
    }
}

/// The arc positions with joint `k` alone moved to where the worst value is
/// best: a scan of 200 points over its span, then golden-section search
/// around the best (the worst value is a maximum of functions each monotone
/// in the joint's position, so it falls then rises). `None` for an empty span.
fn solve_one(
    axis: &Axis,
    quantities: &[(Quantity, &QuantityStats)],
    u0: &[f64],
    k: usize,
) -> Option<Vec<f64>> {
    let n = u0.len();
    let gap = 1e-4 * (u0[n - 1] - u0[0]);
    let (lo, hi) = if k == 0 {
        (
            (u0[0] - axis.mcp_reach.0).max(axis.arcs[0]),
            (u0[0] + axis.mcp_reach.1).min(u0[1] - gap),
        )
    } else {
        (u0[k - 1] + gap, u0[k + 1] - gap)
    };
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let mut u = u0.to_vec();
    let mut eval = |x: f64| {
        u[k] = x;
        fit(quantities, &axis.segments(&u)).0
    };
    const STEPS: usize = 200;
    let step = (hi - lo) / STEPS as f64;
    let mut best = (f64::INFINITY, lo);
    for i in 0..=STEPS {
        let x = lo + step * i as f64;
        let f = eval(x);
        if f < best.0 {
            best = (f, x);
        }
    }
    let (mut a, mut b) = ((best.1 - step).max(lo), (best.1 + step).min(hi));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (eval(c), eval(d));
    for _ in 0..100 {
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = eval(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = eval(d);
        }
    }
    let x = if fc <= fd { c } else { d };
    let x = if eval(x) <= best.0 { x } else { best.1 };
    let mut out = u0.to_vec();
    out[k] = x;
    Some(out)
}

/// The arc positions with the joints `pair` (of MCP 0, PIP 1, DIP 2; a finger
/// with a tip) moved so the compared segments have the mean relative values
/// exactly; the other joint and the tip stay. `None` when no such placement
/// exists on the chain or the MCP would leave its reach.
fn solve_pair(
    axis: &Axis,
    quantities: &[(Quantity, &QuantityStats)],
    u0: &[f64],
    pair: [usize; 2],
) -> Option<Vec<f64>> {
    let mean = |q: Quantity| {
        quantities
            .iter()
            .find(|(x, _)| *x == q)
            .map(|(_, s)| s.mean)
    };
    let m = [
        mean(Quantity::RelJ1)?,
        mean(Quantity::RelJ2)?,
        mean(Quantity::RelJ3)?,
    ];
    let (pts, arcs) = (&axis.points, &axis.arcs);
    let p = |x: f64| point_at(pts, x);
    let mut u = u0.to_vec();
    match pair {
        [1, 2] => {
            let sub: Vec<DVec3> = u0.iter().map(|&x| p(x)).collect();
            let (_, at) = on_chain(&sub, &m)?;
            u[1] = u0[0] + at[0];
            u[2] = u0[0] + at[1];
        }
        [0, 1] => {
            let l = p(u0[2]).distance(p(u0[3])) / m[2];
            u[1] = backward_at(pts, arcs, u0[2], p(u0[2]), m[1] * l)?;
            u[0] = backward_at(pts, arcs, u[1], p(u[1]), m[0] * l)?;
        }
        [0, 2] => {
            let sub = [p(u0[1]), p(u0[2]), p(u0[3])];
            let share = m[1] / (m[1] + m[2]);
            let (q, at) = on_chain(&sub, &[share, 1.0 - share])?;
            u[2] = u0[1] + at[0];
            let l = (q[0].distance(q[1]) + q[1].distance(q[2])) / (m[1] + m[2]);
            u[0] = backward_at(pts, arcs, u0[1], p(u0[1]), m[0] * l)?;
        }
        _ => return None,
    }
    let within = u[0] >= u0[0] - axis.mcp_reach.0 - 1e-12 && u[0] <= u0[0] + axis.mcp_reach.1;
    (within && u.windows(2).all(|w| w[0] < w[1])).then_some(u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use crate::rig::chain::on_chain;
    use std::path::Path;

    fn paper() -> Analysis {
        let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        analyse(&d, &Settings::default())
    }

    /// Tips compared as they are (bone tips on both sides).
    fn bone() -> JudgeOptions {
        JudgeOptions {
            rig_tip: TipKind::Bone,
            ..JudgeOptions::default()
        }
    }

    /// A straight finger along x with the given segment lengths (and a tip).
    fn straight(finger: Finger, segs: &[f64]) -> ChainInput {
        let mut points = vec![DVec3::ZERO];
        let mut x = 0.0;
        for s in segs {
            x += s;
            points.push(DVec3::new(x, 0.0, 0.0));
        }
        ChainInput {
            finger,
            points,
            has_tip: true,
        }
    }

    /// The mean of mc / (J1 + J2 + J3) over the atlas's rows of `finger` that
    /// measure the metacarpal, read from the CSV by hand (not by the dataset reader).
    fn atlas_mean_mc_over_j(finger: &str) -> f64 {
        let text = std::fs::read_to_string("data/atlas/measurements.csv").unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let (f, mc, js) = (col("finger"), col("mc"), [col("j1"), col("j2"), col("j3")]);
        let ratios: Vec<f64> = lines
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|r| r[f] == finger && !r[mc].is_empty())
            .map(|r| {
                let j: f64 = js.iter().filter_map(|&k| r[k].parse::<f64>().ok()).sum();
                r[mc].parse::<f64>().unwrap() / j
            })
            .collect();
        assert!(
            ratios.len() > 100,
            "{} atlas rows for {finger}",
            ratios.len()
        );
        ratios.iter().sum::<f64>() / ratios.len() as f64
    }

    #[test]
    fn an_mcp_10_mm_towards_the_web_is_out_too_distal_on_the_metacarpal_line() {
        let d = Dataset::load(Path::new("data/atlas/measurements.csv")).unwrap();
        let atlas = analyse(&d, &Settings::default());
        let x = atlas_mean_mc_over_j("index");
        // A straight index finger along x: CMC at the origin, the metacarpal
        // at the atlas's mean mc/J of an 80 mm finger (J~ at the paper's
        // means), the skin tip 4 mm past the bone tip (the default).
        let length = 0.080;
        let mc = x * length;
        let segs = [0.4846 * length, 0.2726 * length, 0.2428 * length + 0.004];
        let finger = |mcp: f64| {
            let mut c = straight(Finger::Index, &segs);
            c.points[0].x = mcp;
            for (k, p) in c.points.iter_mut().enumerate().skip(1) {
                p.x = mc + segs[..k].iter().sum::<f64>();
            }
            c
        };
        let judge = |c: &ChainInput| {
            let audit = audit_with(&atlas, c, &JudgeOptions::default()).unwrap();
            metacarpal(
                &atlas,
                &audit,
                "index_metacarpal_r",
                DVec3::ZERO,
                c.points[0],
            )
            .unwrap()
        };
        let at_mean = judge(&finger(mc));
        assert!((at_mean.length - length).abs() < 1e-12);
        assert!((at_mean.values[0].measured - x).abs() < 1e-9);
        assert!(
            (at_mean.values[0].mean - x).abs() < 1e-9,
            "the atlas mean, by hand"
        );
        assert_eq!(at_mean.standing, Standing::InRange);
        let moved = judge(&finger(mc + 0.010));
        // CMC and tip held, the atlas still puts the MCP where it was.
        assert!(
            (moved.expected - mc).abs() < 1e-9,
            "{} vs {mc}",
            moved.expected
        );
        assert!((moved.suggested.x - mc).abs() < 1e-9);
        let pi = moved.pi.unwrap();
        match moved.standing {
            Standing::Above { by } => {
                assert!((by - (mc + 0.010 - pi.high)).abs() < 1e-12);
                assert!(by > 0.0 && by < 0.010, "{by}");
            }
            s => panic!("expected too distal, got {s:?}"),
        }
        assert!(matches!(moved.values[0].standing, Standing::Above { .. }));
    }

    /// [`WristRatios::load`] against an independent reading of the atlas's
    /// landmarks (split by hand here, not by the dataset reader): y = |landmark
    /// 10 - MCP| / (J1 + J2 + J3) per X-ray, J along MCP, PIP, DIP, tip
    /// (data/atlas/README.md). The published values were computed from the same
    /// file with Python (statistics.mean / stdev, math.dist; scipy.stats.t.ppf
    /// for the 95 % prediction interval, mean -/+ t sd sqrt(1 + 1/n)).
    #[test]
    fn wrist_ratios_are_the_atlas_means() {
        let path = std::path::Path::new("data/atlas/landmarks.csv");
        let Ok(text) = std::fs::read_to_string(path) else {
            eprintln!("skipped: data/atlas/landmarks.csv is not readable");
            return;
        };
        // (finger, MCP, PIP, DIP, tip, Python's mean, SD, 95 % prediction interval)
        let rays = [
            (
                Finger::Index,
                [21, 22, 23, 24],
                1.16467,
                0.04963,
                [1.0672, 1.2621],
            ),
            (
                Finger::Middle,
                [25, 26, 27, 28],
                0.98944,
                0.04095,
                [0.9090, 1.0698],
            ),
            (
                Finger::Ring,
                [29, 30, 31, 32],
                0.96133,
                0.03966,
                [0.8835, 1.0392],
            ),
            (
                Finger::Little,
                [33, 34, 35, 36],
                1.18625,
                0.05998,
                [1.0685, 1.3040],
            ),
        ];
        let mut samples: [Vec<f64>; 4] = Default::default();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let v: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap()).collect();
            let p = |i: usize| DVec3::new(v[1 + 2 * i], v[2 + 2 * i], 0.0);
            for (k, &(_, m, ..)) in rays.iter().enumerate() {
                let j = p(m[0]).distance(p(m[1]))
                    + p(m[1]).distance(p(m[2]))
                    + p(m[2]).distance(p(m[3]));
                samples[k].push(p(10).distance(p(m[0])) / j);
            }
        }
        let read = WristRatios::load(path).unwrap();
        assert_eq!(read.ratios.len(), 4);
        for (k, &(finger, _, published, published_sd, published_pi)) in rays.iter().enumerate() {
            let ys = &samples[k];
            let n = ys.len() as f64;
            assert_eq!(ys.len(), 910);
            let mean = ys.iter().sum::<f64>() / n;
            let sd = (ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let r = read.of(finger).unwrap();
            assert_eq!(r.n, 910);
            assert!(
                (r.mean - mean).abs() < 1e-12,
                "{finger:?}: {} vs {mean}",
                r.mean
            );
            assert!((r.sd - sd).abs() < 1e-12, "{finger:?}: {} vs {sd}", r.sd);
            assert_eq!((r.range.low, r.range.high), (lo, hi), "{finger:?}");
            assert!((mean - published).abs() < 5e-6, "{finger:?}: {mean}");
            assert!((sd - published_sd).abs() < 5e-6, "{finger:?}: {sd}");
            let pi = r.pi(0.95).unwrap();
            assert!(
                (pi.low - published_pi[0]).abs() < 5e-5 && (pi.high - published_pi[1]).abs() < 5e-5,
                "{finger:?}: {pi:?}"
            );
        }
        assert!(read.of(Finger::Thumb).is_none());
    }

    #[test]
    fn standing_orders_range_then_prediction_then_outside() {
        let range = Interval::new(0.4, 0.5);
        let pi = Some(Interval::new(0.3, 0.6));
        assert_eq!(Standing::of(0.45, range, pi), Standing::InRange);
        assert_eq!(Standing::of(0.55, range, pi), Standing::InPrediction);
        match Standing::of(0.7, range, pi) {
            Standing::Above { by } => assert!((by - 0.1).abs() < 1e-12),
            s => panic!("{s:?}"),
        }
        match Standing::of(0.35, range, None) {
            Standing::Below { by } => assert!((by - 0.05).abs() < 1e-12),
            s => panic!("{s:?}"),
        }
    }

    #[test]
    fn a_finger_with_the_paper_means_is_in_range_and_needs_no_move() {
        let a = paper();
        let f = a.finger(Finger::Index).unwrap();
        let m: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
            .iter()
            .map(|&q| f.quantity(q).unwrap().mean * 80.0)
            .collect();
        let r = audit_with(&a, &straight(Finger::Index, &m), &bone()).unwrap();
        assert_eq!(r.basis, Basis::Relative);
        assert!(r.is_consistent());
        let kinds: Vec<Joint> = r.joints.iter().map(|j| j.joint).collect();
        assert_eq!(kinds, [Joint::Mcp, Joint::Pip, Joint::Dip, Joint::Tip]);
        for j in &r.joints {
            assert_eq!(j.standing, Standing::InRange);
            assert!(j.shift < 1e-9, "{j:?}");
            // MCP and tip: the mean's x / (1 - x) of the rest is the mean's own segment.
            assert!((j.measured - j.expected).abs() < 1e-9, "{j:?}");
        }
        assert!(r.explanation.consistent && r.explanation.moved.is_empty());
        // PIP at J~1 L = 0.4846 x 80 (the corrected eq. 6 mean).
        let pip = r.joint(Joint::Pip).unwrap();
        assert!((pip.expected - 0.4846 * 80.0).abs() < 0.01);
    }

    #[test]
    fn a_pip_far_towards_the_tip_is_flagged_above_with_its_distance() {
        let a = paper();
        // J~1 = 0.6 of 100 units: the paper's index max is 0.5047.
        let r = audit_with(&a, &straight(Finger::Index, &[60.0, 22.0, 18.0]), &bone()).unwrap();
        let pip = r.joint(Joint::Pip).unwrap();
        let pi = pip.pi.unwrap();
        match pip.standing {
            Standing::Above { by } => assert!((by - (60.0 - pi.high)).abs() < 1e-9),
            s => panic!("{s:?}"),
        }
        assert!(!r.is_consistent());
        // One joint explains it: the PIP alone cannot (moved back to fit J~1 it
        // leaves J2 too long), the MCP moved towards the tip can, on the
        // (straight) chain.
        assert!(r.explanation.consistent, "{:?}", r.explanation);
        assert_eq!(r.explanation.moved, vec![Joint::Mcp], "{:?}", r.explanation);
        let mcp = r.joint(Joint::Mcp).unwrap();
        assert!(mcp.moves && mcp.shift_along > 0.0 && !pip.moves);
        assert!((mcp.suggested[0] - mcp.shift_along).abs() < 1e-9);
        assert!(
            r.explanation
                .values
                .iter()
                .all(|v| v.standing.is_consistent())
        );
    }

    #[test]
    fn sharp_bends_keep_the_joints_in_order_or_decline() {
        // 120 degrees at each joint, segments 20, 40, 40 (a case a per-point
        // correction got out of order).
        let turn = |a: f64| DVec3::new(a.cos(), a.sin(), 0.0);
        let mut pts = vec![DVec3::ZERO];
        let mut dir = 0.0f64;
        for len in [20.0, 40.0, 40.0] {
            let p = *pts.last().unwrap();
            pts.push(p + len * turn(dir));
            dir += 120f64.to_radians();
        }
        let shares = [0.48, 0.29, 0.23];
        // A finger curled 60 degrees at each joint is solved exactly, in order.
        let mut bent = vec![DVec3::ZERO];
        let mut dir = 0.0f64;
        for len in [45.0, 28.0, 22.0] {
            let p = *bent.last().unwrap();
            bent.push(p + len * turn(dir));
            dir += 60f64.to_radians();
        }
        let (q, u) = on_chain(&bent, &shares).expect("a 60-degree curl is solvable");
        assert!(u[0] < u[1]);
        let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = c.iter().sum();
        for (ck, s) in c.iter().zip(shares) {
            assert!((ck / total - s).abs() < 1e-9, "{c:?}");
        }
        if let Some((q, u)) = on_chain(&pts, &shares) {
            assert!(u.windows(2).all(|w| w[0] <= w[1]), "{u:?}");
            let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
            let total: f64 = c.iter().sum();
            for (ck, s) in c.iter().zip(shares) {
                assert!((ck / total - s).abs() < 1e-9, "{c:?}");
            }
        }
        // Degenerate chains are declined, never a panic.
        assert!(on_chain(&[DVec3::ZERO; 4], &shares).is_none());
        assert!(
            on_chain(
                &[
                    DVec3::new(f64::NAN, 0.0, 0.0),
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(2.0, 0.0, 0.0),
                    DVec3::new(3.0, 0.0, 0.0)
                ],
                &shares
            )
            .is_none()
        );
        let a = paper();
        let nan = ChainInput {
            finger: Finger::Index,
            points: vec![
                DVec3::ZERO,
                DVec3::new(f64::INFINITY, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(3.0, 0.0, 0.0),
            ],
            has_tip: true,
        };
        assert!(audit(&a, &nan).is_none());
        let zero = ChainInput {
            points: vec![
                DVec3::ZERO,
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(3.0, 0.0, 0.0),
            ],
            ..nan
        };
        assert!(audit(&a, &zero).is_none());
    }

    #[test]
    fn with_many_xrays_the_prediction_interval_decides() {
        // Range wider than the interval (large n): inside the range but outside the interval is outside.
        let range = Interval::new(0.3, 0.7);
        let pi = Some(Interval::new(0.45, 0.55));
        assert!(matches!(
            Standing::of(0.65, range, pi),
            Standing::Above { .. }
        ));
        assert_eq!(Standing::of(0.5, range, pi), Standing::InRange);
    }

    #[test]
    fn without_a_tip_a_finger_is_judged_on_its_ratio_and_the_thumb_not_at_all() {
        let a = paper();
        let s = a
            .finger(Finger::Middle)
            .unwrap()
            .quantity(Quantity::RatioJ2J1)
            .unwrap();
        let chain = ChainInput {
            finger: Finger::Middle,
            points: vec![
                DVec3::ZERO,
                DVec3::new(0.0, 50.0, 0.0),
                DVec3::new(0.0, 50.0 + 50.0 * s.mean, 0.0),
            ],
            has_tip: false,
        };
        let r = audit(&a, &chain).unwrap();
        assert_eq!(r.basis, Basis::Ratio);
        assert_eq!(r.unjudged, vec![Joint::Dip]);
        assert!((r.values[0].measured - s.mean).abs() < 1e-12);
        assert!(r.joints.iter().all(|j| j.shift < 1e-9));
        // MCP at c1 - c2 / r: at the mean ratio exactly where it is.
        let mcp = r.joint(Joint::Mcp).unwrap();
        assert!(mcp.expected.abs() < 1e-9, "{mcp:?}");
        // A PIP too close to the root makes J2/J1 too large: flagged below.
        let close = ChainInput {
            points: vec![
                DVec3::ZERO,
                DVec3::new(0.0, 20.0, 0.0),
                DVec3::new(0.0, 80.0, 0.0),
            ],
            ..chain
        };
        let r = audit(&a, &close).unwrap();
        let pip = r.joint(Joint::Pip).unwrap();
        assert!(matches!(pip.standing, Standing::Below { .. }));
        assert!(matches!(r.values[0].standing, Standing::Above { .. }));
        assert!(pip.range.low < pip.range.high);
        // J2/J1 = 3: the X-rays put the MCP 60/0.64 = 94 back, so the rig's is far
        // towards the tip; but it may move at most one segment (20) back, so the
        // PIP alone explains it.
        let mcp = r.joint(Joint::Mcp).unwrap();
        assert!(matches!(mcp.standing, Standing::Above { .. }), "{mcp:?}");
        assert!(mcp.range.low < mcp.range.high);
        assert!((mcp.expected - (20.0 - 60.0 / s.mean)).abs() < 1e-9);
        assert_eq!(r.explanation.moved, vec![Joint::Pip]);
        assert!(r.explanation.also.is_empty());
        let thumb = ChainInput {
            finger: Finger::Thumb,
            points: vec![DVec3::ZERO, DVec3::new(1.0, 0.0, 0.0)],
            has_tip: false,
        };
        let r = audit(&a, &thumb).unwrap();
        assert_eq!(r.basis, Basis::None);
        assert!(r.joints.is_empty() && r.values.is_empty());
    }

    #[test]
    fn a_skin_tip_is_compared_without_its_soft_tissue() {
        let a = paper();
        let f = a.finger(Finger::Index).unwrap();
        let m: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
            .iter()
            .map(|&q| f.quantity(q).unwrap().mean * 80.0)
            .collect();
        // The X-ray mean finger with 4 units of soft tissue past the bone tip.
        let skin = [m[0], m[1], m[2] + 4.0];
        let opts = JudgeOptions {
            soft_tissue: 4.0,
            ..JudgeOptions::default()
        };
        let r = audit_with(&a, &straight(Finger::Index, &skin), &opts).unwrap();
        assert_eq!(r.tip_correction, 4.0);
        assert!((r.compared[2] - m[2]).abs() < 1e-12);
        assert!((r.length.unwrap() - 80.0).abs() < 1e-9);
        assert!(r.is_consistent() && r.explanation.moved.is_empty());
        // The tip stands where the X-rays put the bone tip plus the soft tissue: 84.
        let tip = r.joint(Joint::Tip).unwrap();
        assert!((tip.measured - 84.0).abs() < 1e-9 && (tip.expected - 84.0).abs() < 1e-9);
        // Read as a bone tip, the same rig's J~3 is too long.
        let r = audit_with(&a, &straight(Finger::Index, &skin), &bone()).unwrap();
        assert_eq!(r.tip_correction, 0.0);
        assert!((r.values[2].measured - (m[2] + 4.0) / 84.0).abs() < 1e-12);
        // Data with skin tips and a skin tip: nothing to correct; a bone tip gains it.
        let both = JudgeOptions {
            data_tip: TipKind::Skin,
            ..opts
        };
        assert_eq!(both.tip_correction(), 0.0);
        let rig_bone = JudgeOptions {
            rig_tip: TipKind::Bone,
            ..both
        };
        assert_eq!(rig_bone.tip_correction(), -4.0);
    }

    #[test]
    fn an_mcp_at_the_web_is_named_not_the_pip() {
        // X-ray 1b's index (Table 1, image units x 0.1 = mm-like units), with
        // its MCP 10 units towards the tip: J1 shrinks by 10, nothing else moves.
        let a = paper();
        let segs = [34.247 - 10.0, 19.524, 18.670];
        let r = audit_with(&a, &straight(Finger::Index, &segs), &bone()).unwrap();
        assert!(!r.is_consistent());
        assert_eq!(r.explanation.moved, vec![Joint::Mcp], "{:?}", r.explanation);
        let mcp = r.joint(Joint::Mcp).unwrap();
        assert!(matches!(mcp.standing, Standing::Above { .. }), "{mcp:?}");
        // Moved back towards the root by about the 10 units it was pushed.
        assert!(mcp.moves && (mcp.shift_along + 10.0).abs() < 3.0, "{mcp:?}");
        assert!(!r.joint(Joint::Pip).unwrap().moves);
        assert!(
            r.explanation
                .values
                .iter()
                .all(|v| v.standing.is_consistent())
        );
        // Its X-rays' own proportions restored would be inside the range: the
        // solution lies inside every prediction interval.
        assert!(r.explanation.score.is_some_and(|s| s <= 1.0));
    }

    #[test]
    fn pairs_land_exactly_on_the_means() {
        // PIP and DIP both far off: no single joint fits; the pair moved fits exactly.
        let a = paper();
        let r = audit_with(&a, &straight(Finger::Middle, &[60.0, 10.0, 30.0]), &bone()).unwrap();
        assert_eq!(r.explanation.moved.len(), 2, "{:?}", r.explanation);
        // The ratios of the means are not the means of the ratios: close, not 0.
        assert!(
            r.explanation.score.is_some_and(|s| s < 0.05),
            "{:?}",
            r.explanation
        );
        let f = a.finger(Finger::Middle).unwrap();
        for v in &r.explanation.values {
            if v.quantity.is_relative() {
                let mean = f.quantity(v.quantity).unwrap().mean;
                assert!((v.measured - mean).abs() < 1e-9, "{v:?}");
            }
        }
    }
}
