//! The terms of a finger's judgement ([`super::finger`], whose module notes
//! the docs here refer to): the options, a chain's points, and where its
//! values and joints stand against the X-ray statistics (range, prediction
//! interval), with the small arithmetic they share.

pub use super::soft_tissue::{FingerSoftTissue, SOFT_TISSUE_TABLE, SoftTissue, data_tip_of};
use crate::analysis::placement::Joint;
use crate::analysis::region::{ShapePrior, ShapePriors};
use crate::analysis::{Analysis, Interval, Quantity, QuantityStats};
pub use crate::dataset::TipKind;
use crate::dataset::{Finger, TipCounts};
use crate::rig::read::FingerChain;
use glam::DVec3;
use schemars::JsonSchema;
use serde::Serialize;

/// How a rig is compared with the data.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct JudgeOptions {
    /// What the rig's tip nodes mark.
    pub rig_tip: TipKind,
    /// What the data's tips mark, from its `tip` column ([`data_tip_of`]): assumed (bone)
    /// when the column does not record one kind for every row (see `data_tips`).
    pub data_tip: TipKind,
    /// Where the data's rows put their tips, as their `tip` column says.
    pub data_tips: TipCounts,
    /// The soft tissue between bone tip and skin tip, used when the two differ.
    pub soft_tissue: SoftTissue,
    /// The prior shape of each finger's joint region (`None`: the X-rays'
    /// own covariance); each finger's region check names what it used.
    #[serde(skip)]
    #[schemars(skip)]
    pub shape: Option<ShapePriors>,
}

impl JudgeOptions {
    /// The options to judge a rig whose tips mark `rig_tip` against the
    /// statistics `a`, their tips read from the data's `tip` column.
    pub fn new(rig_tip: TipKind, soft_tissue: SoftTissue, a: &Analysis) -> JudgeOptions {
        JudgeOptions {
            rig_tip,
            data_tip: data_tip_of(&a.tips),
            data_tips: a.tips,
            soft_tissue,
            shape: None,
        }
    }

    /// These options with the joint regions' prior shape `shape`.
    pub fn with_shape(mut self, shape: Option<ShapePriors>) -> JudgeOptions {
        self.shape = shape;
        self
    }

    /// The prior shape of finger `finger`'s joint region, if any.
    pub fn shape_of(&self, finger: Finger) -> Option<ShapePrior> {
        self.shape.as_ref().and_then(|s| s.of(finger))
    }

    /// Skin tips against `a`'s tips, with no soft tissue figure: what
    /// [`super::audit`] uses.
    pub fn skin(a: &Analysis) -> JudgeOptions {
        JudgeOptions::new(TipKind::Skin, SoftTissue::Unknown, a)
    }

    /// Taken off the last segment of a rig finger `length` long to compare
    /// like with like ([`SoftTissue::correction`]).
    pub fn tip_correction(&self, finger: Finger, length: f64) -> Option<f64> {
        self.soft_tissue
            .correction(self.rig_tip, self.data_tip, finger, length)
    }

    /// The rig finger's length, segments `segments` (MCP to its tip), with its
    /// tip moved to where the tips of data `tips` end (another dataset's, as
    /// the metacarpals'); `None` when that needs a soft tissue figure not known.
    pub fn length_against(
        &self,
        tips: &TipCounts,
        finger: Finger,
        segments: &[f64],
    ) -> Option<f64> {
        let length: f64 = segments.iter().sum();
        let c = self
            .soft_tissue
            .correction(self.rig_tip, data_tip_of(tips), finger, length)?;
        Some(length - c)
    }

    /// True when the data's tip column does not record one kind for every row, so that
    /// [`JudgeOptions::data_tip`] is assumed ([`data_tip_of`]), not read.
    pub fn data_tip_assumed(&self) -> bool {
        self.data_tips.single().is_none()
    }

    /// What the audit assumed of the tips of the data (`data`, its path) when their tip
    /// column does not record one kind for every row, and that the verdicts rest on it;
    /// `None` when it records one.
    pub fn assumption(&self, data: &str) -> Option<String> {
        if !self.data_tip_assumed() {
            return None;
        }
        Some(format!(
            "{data}'s fingertips are {}, so the audit takes them all as {kind} tips (the usual \
             landmark on an X-ray), and the verdicts of the fingers with a tip rest on that \
             assumption: a last segment to the skin is longer than one to the bone by the \
             fingertip's soft tissue. Record where the X-rays' tips were measured in {data}'s \
             tip column (bone or skin)",
            self.data_tips.describe(),
            kind = self.data_tip.name(),
        ))
    }

    /// True when the rig's tips and the data's differ and no soft tissue figure is known at all.
    pub fn lacks_soft_tissue(&self) -> bool {
        self.rig_tip != self.data_tip && self.soft_tissue == SoftTissue::Unknown
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
    /// True when the explanation moves this joint (JSON `explains`; whether
    /// the fix moves it is `fix`).
    #[serde(rename = "explains")]
    pub moves: bool,
    /// True when the fix moves this joint: the explanation moves it, it is not
    /// held, and (with `--only-outside`) it lies outside its own interval. Set
    /// when the audit is finished ([`super::AuditedRig::settle_fix`]).
    pub fix: bool,
    /// Where the explanation puts the joint (the rig's joint when it does not move it).
    #[schemars(with = "[f64; 3]")]
    pub suggested: DVec3,
    /// Distance from the rig's joint to the suggested one.
    pub shift: f64,
    /// How far the suggestion lies along the chain from the rig's joint:
    /// positive towards the tip, negative towards the root.
    pub shift_along: f64,
    /// Why a joint the explanation would move is not moved by the fix
    /// (`None`: it moves when `moves`, or no move was asked of it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held: Option<Held>,
}

/// Why a move is given up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum HoldReason {
    /// With the weights left as painted (`--keep-weights`), the move would
    /// take the joint more than [`BEND_GUARD`] farther from where its skin
    /// bends (measured on the rig's weights); the explanation was sought
    /// again with the joint held.
    Bend,
    /// The move is shorter than [`MOVE_TOLERANCE`].
    Small,
    /// The joint is an MCP and the fix was not asked to move MCPs
    /// (`--fix-mcp atlas`): where the skin over a knuckle bends is not
    /// located well enough ([`super::bend`]: the MCP's bend is reported for
    /// information only) for the bend guard to tell whether the move takes
    /// the MCP off it. The explanation still names it.
    Knuckle,
    /// The artist pinned the joint (`audit --hold`): the explanation was
    /// sought among the other joints, and the fix leaves it.
    Pinned,
    /// The joint is an MCP that its ray's base (the CMC, or the wrist) puts
    /// inside the atlas's prediction interval, while the finger alone would
    /// move it: the two kinds of evidence are weighed together, so the
    /// explanation is sought among the other joints, and the fix leaves it
    /// ([`super::AuditedRig::judge_rays`]).
    Base,
    /// The joint is an MCP that the finger alone would move one way while
    /// its ray's base puts it outside the atlas's prediction interval the
    /// other way: no move of it satisfies both, so it is held and the
    /// explanation sought among the other joints
    /// ([`super::AuditedRig::judge_rays`]).
    BaseOpposes,
    /// The explanation's moves, the joints at their best place, would not
    /// bring the finger inside the X-rays' inner region, where a fix puts a
    /// finger ([`crate::analysis::region::FIX_LEVEL`]): a finger moved only
    /// to the edge of the 95% region is out again after a few more X-rays,
    /// so the fix moves none of its joints.
    Short,
    /// The fix moves a finger's skin weights with its joints, and this
    /// joint's cannot follow: too few vertices around it to carry a bend, or
    /// vertices shared with another finger ([`super::bend::cannot_carry`]),
    /// or the carried weights would not bend the skin within
    /// [`super::carry::CARRY_TOLERANCE`] of it; the explanation was sought
    /// again with the joint held.
    Carry,
}

impl HoldReason {
    /// The reason in a few words, for the audit's one line per finger.
    pub fn short(self) -> String {
        match self {
            HoldReason::Bend => "would leave its skin bend".into(),
            HoldReason::Small => format!(
                "under the {} mm tolerance",
                crate::format::num(MOVE_TOLERANCE * 1000.0, 1)
            ),
            HoldReason::Knuckle => "a knuckle".into(),
            HoldReason::Pinned => "pinned by --hold".into(),
            HoldReason::Base => "in range from its base".into(),
            HoldReason::BaseOpposes => "its base puts it the other way".into(),
            HoldReason::Carry => "its skin cannot follow it".into(),
            HoldReason::Short => format!(
                "the finger would stay outside the {} region",
                crate::format::level(crate::analysis::region::FIX_LEVEL)
            ),
        }
    }
}

/// A move a fix gives up, and why, with the words every output gives for it.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Held {
    pub reason: HoldReason,
    /// The joint's distance to where its skin bends as the rig has it (rig
    /// units), when a bend was found.
    pub before: Option<f64>,
    /// Its distance to that bend were it moved, when a bend was found.
    pub after: Option<f64>,
    /// The length of the move not made.
    pub shift: f64,
    /// What the audit says of it, in its text and here alike (mm, for a rig in metres).
    pub words: String,
}

impl Held {
    /// A move of `shift` not made because the joint's skin weights cannot
    /// follow it, for the reason `why` ([`HoldReason::Carry`]).
    pub fn carry(shift: f64, why: &str) -> Held {
        Held {
            reason: HoldReason::Carry,
            before: None,
            after: None,
            shift,
            words: format!(
                "held: its skin cannot follow it, {why}, so it is not moved (it would be moved {} \
                 mm; --keep-weights moves it and leaves the weights)",
                crate::format::num(shift * 1000.0, 1)
            ),
        }
    }

    /// A move of `shift` not made: for `reason`, with the distances to the bend `bend` (before, after).
    pub fn new(reason: HoldReason, shift: f64, bend: Option<(f64, f64)>) -> Held {
        let mm = |x: f64| crate::format::num(x * 1000.0, 1);
        let words = match (reason, bend) {
            (HoldReason::Bend, Some((before, after)))
                if before <= super::bend::BEND_TOLERANCE_MM / 1000.0 =>
            {
                format!(
                    "held: it sits where its skin bends, {} mm (moved {} mm it would be {} mm \
                     from it)",
                    mm(before),
                    mm(shift),
                    mm(after)
                )
            }
            (HoldReason::Bend, Some((before, after))) => format!(
                "held: moved {} mm it would be {} mm from where its skin bends, farther than the \
                 {} mm it is",
                mm(shift),
                mm(after),
                mm(before)
            ),
            (HoldReason::Knuckle, _) => format!(
                "held: where the skin over a knuckle bends cannot be located, so it is not moved \
                 (it would be moved {} mm; --fix-mcp atlas moves MCPs)",
                mm(shift)
            ),
            (HoldReason::Pinned, _) if shift > 0.0 => format!(
                "held: pinned by --hold (the explanation would move it {} mm)",
                mm(shift)
            ),
            (HoldReason::Pinned, _) => "held: pinned by --hold".to_string(),
            (HoldReason::Base, _) => base_words(GENERIC_BASE, None, shift),
            (HoldReason::BaseOpposes, _) => base_words(GENERIC_BASE, Some(None), shift),
            (HoldReason::Short, _) => format!(
                "held: the moves the fix could make (this one {} mm) would leave the finger \
                 outside the X-rays' {} joint region, where the fix puts a finger, so none is made",
                mm(shift),
                crate::format::level(crate::analysis::region::FIX_LEVEL)
            ),
            _ => format!(
                "held: the move, {} mm, is under the {} mm tolerance",
                mm(shift),
                mm(MOVE_TOLERANCE)
            ),
        };
        Held {
            reason,
            before: bend.map(|b| b.0),
            after: bend.map(|b| b.1),
            shift,
            words,
        }
    }

    /// An MCP move of `shift` the finger alone asks for, given up for the
    /// evidence of its ray's base `base` ("its CMC (Index_Metacarpal_R)"),
    /// where that base puts the MCP (`standing`): in range ([`HoldReason::Base`])
    /// or outside the other way ([`HoldReason::BaseOpposes`]).
    pub fn from_base(shift: f64, base: &str, standing: Standing) -> Held {
        let (reason, outside) = match standing {
            Standing::InRange | Standing::InPrediction => (HoldReason::Base, None),
            Standing::Above { by } => (HoldReason::BaseOpposes, Some(Some((by, "distal")))),
            Standing::Below { by } => (HoldReason::BaseOpposes, Some(Some((by, "proximal")))),
        };
        Held {
            reason,
            before: None,
            after: None,
            shift,
            words: base_words(base, outside, shift),
        }
    }
}

/// How [`Held::new`] names a ray's base it was not told.
const GENERIC_BASE: &str = "its ray's base (the CMC or the wrist)";

/// The words of an MCP held for its ray's base `base`: in range (`outside`
/// `None`), or outside the other way, by how much and which way when known.
fn base_words(base: &str, outside: Option<Option<(f64, &str)>>, shift: f64) -> String {
    let mm = |x: f64| crate::format::num(x * 1000.0, 1);
    let where_ = match outside {
        None => "the atlas puts it in range".to_string(),
        Some(Some((by, way))) => {
            format!("the atlas puts it {} mm too {way}, the other way", mm(by))
        }
        Some(None) => {
            "the atlas puts it outside its prediction interval, the other way".to_string()
        }
    };
    format!(
        "held: from {base} {where_}, so the explanation moves the other joints (the finger alone \
         would move it {} mm)",
        mm(shift)
    )
}

/// With the skin weights left as painted (`--keep-weights`), a fix never
/// takes a joint more than this farther from where its skin bends than it
/// was (metres): the mesh was modelled to fold there, so a joint moved off
/// its bend rotates skin that is not built to bend. (With the weights
/// carried, the guard asks instead whether the skin would bend at the new
/// joint: [`super::carry::CARRY_TOLERANCE`].) 1 mm: a third of the bend tolerance
/// ([`super::bend::BEND_TOLERANCE_MM`]) and below a ring of a finger mesh's
/// vertices (2-4 mm apart), so a move within it leaves the fold on the same
/// edge loop.
pub const BEND_GUARD: f64 = 0.001;

/// A fix makes no move shorter than this (metres). 1 mm: with the paper's
/// 5 X-rays the mean position of a joint along a finger is itself uncertain
/// by about this much (the index PIP of a 90 mm finger: SD of the position
/// about 1.2 mm, so a standard error of the mean of 1.2 / sqrt(5) = 0.5 mm and
/// a 95% confidence half-width of t(0.975, 4) x 0.5 = 1.5 mm); a shorter move
/// is below what the data can tell apart. For the same reason the audit
/// prints millimetres to 0.1 mm.
pub const MOVE_TOLERANCE: f64 = 0.001;

/// True when a move of `shift` (metres) is under [`MOVE_TOLERANCE`] as the
/// audit prints it, to 0.1 mm: mirror-image joints whose moves print alike are
/// decided alike (0.95 mm prints as 1.0 mm and is made).
pub fn under_tolerance(shift: f64) -> bool {
    (shift * 1e4).round() < (MOVE_TOLERANCE * 1e4).round()
}

impl JointCheck {
    /// True when a fix moves this joint: the explanation moves it and it is not held.
    pub fn fix_moves(&self) -> bool {
        self.moves && self.held.is_none() && self.shift > 0.0
    }
}

/// A finger's relative joint positions against the X-rays' joint prediction
/// region ([`crate::analysis::region::JointRegion`]), as the rig is: the
/// verdict on the model's shape, and beside it the X-rays' own.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RegionCheck {
    /// Hotelling's T^2 of the positions u = (J~1, J~1 + J~2) (the thumb's
    /// J~1) under the model's covariance S* (the verdict's).
    pub t2: f64,
    /// The region's bound on T^2: p (n - 1) / (n - p) F(confidence; p, n - p).
    pub bound: f64,
    pub confidence: f64,
    /// X-rays behind the region.
    pub n: usize,
    /// T^2 at most the bound: the finger's verdict.
    pub inside: bool,
    /// The shape the verdict used and the X-rays' own (a finger with two
    /// positions; the thumb's one position has no shape).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<RegionShape>,
}

/// The shape of a finger's joint region: the model's correlation, the
/// X-rays' own, the prior's, and the verdict under the X-rays' own S.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RegionShape {
    /// S*'s correlation of the two positions (the verdict's).
    pub correlation: f64,
    /// The prior's correlation r0 and weight in hands, when one was used.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prior: Option<ShapePrior>,
    /// Where the prior came from (the prior cohort's path).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prior_source: Option<String>,
    /// The verdict on the X-rays' own covariance S.
    pub own: OwnRegion,
}

/// The finger against the region on the X-rays' own covariance S.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct OwnRegion {
    /// S's correlation of the two positions.
    pub correlation: f64,
    /// T^2 under S (1 + 1/n).
    pub t2: f64,
    /// T^2 at most the same bound.
    pub inside: bool,
}

/// The fewest joints whose moves bring the finger inside the X-rays' joint
/// prediction region (with a tip; without one, inside the prediction
/// interval of J2/J1).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Explanation {
    /// The joints that move, root first (empty: nothing needs to move).
    pub moved: Vec<Joint>,
    /// True when, with those moved, the finger is inside the joint region
    /// (without a tip: J2/J1 inside its prediction interval or range).
    pub consistent: bool,
    /// The normalised distance from the X-rays after the moves: 0 at their
    /// mean, 1 at the region's edge, sqrt(T^2 / bound) (without a tip, J2/J1's
    /// distance from its mean over the distance to its prediction limit)
    /// (`None` when nothing could be judged).
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
    /// The relative joint positions against the joint region, as the rig is
    /// (`None` without a tip or without a region: too few X-rays).
    pub region: Option<RegionCheck>,
    pub explanation: Explanation,
}

impl FingerAudit {
    /// True when the finger fits the X-rays as the rig is: inside the joint
    /// region when there is one (its joints' and values' own intervals are
    /// then read against it, not alone), else every judged joint and value
    /// inside its range or prediction interval.
    pub fn is_consistent(&self) -> bool {
        match &self.region {
            Some(r) => r.inside,
            None => {
                self.joints.iter().all(|j| j.standing.is_consistent())
                    && self.values.iter().all(|v| v.standing.is_consistent())
            }
        }
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
pub(super) fn chain_kinds(finger: Finger, has_tip: bool) -> Vec<Joint> {
    let mut k = vec![Joint::Mcp];
    k.extend_from_slice(Joint::inner(finger));
    if has_tip {
        k.push(Joint::Tip);
    }
    k
}

/// The statistics of `quantity` for `finger`, when the data has them.
pub(super) fn stats(a: &Analysis, finger: Finger, q: Quantity) -> Option<&QuantityStats> {
    a.finger(finger)?.quantity(q)
}

pub(super) fn value_check(q: Quantity, measured: f64, s: &QuantityStats) -> ValueCheck {
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
pub(super) fn value_of(q: Quantity, s: &[f64]) -> f64 {
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

/// How far `x` lies from the mean of `s`, in units of the distance from the
/// mean to the prediction limit on that side (the range's end without an
/// interval): at most 1 inside. O(1).
pub(super) fn normalised(x: f64, s: &QuantityStats) -> f64 {
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
