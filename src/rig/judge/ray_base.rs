//! The MCP judged from its ray's base: from the CMC (the finger's metacarpal
//! node) against a dataset's metacarpals, or from the wrist (the hand bone)
//! against the atlas's wrist-to-MCP distance over the finger's length. A
//! guide beside the finger's own judgement ([`super::finger`]), which it does
//! not change.

use super::standing::{FingerAudit, Standing, ValueCheck, stats, value_check};
use crate::analysis::{Analysis, Interval, Quantity};
use crate::dataset::Finger;
use glam::DVec3;
use schemars::JsonSchema;
use serde::Serialize;

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
    /// The thumb's CMC in the frame of the wrist and the middle finger's MCP,
    /// (a, b) averaged over the X-rays (`landmarks::thumb_cmc_in_hand_file`):
    /// where `rig` puts a thumb's CMC; the audit does not judge it.
    pub thumb_cmc: Option<[f64; 2]>,
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
        let cmc = crate::dataset::landmarks::thumb_cmc_in_hand_file(path)?;
        let mut ratios = WristRatios::from_samples(&path.display().to_string(), &per_image);
        let n = cmc.len() as f64;
        ratios.thumb_cmc = (n > 0.0).then(|| {
            let sum = cmc
                .iter()
                .fold([0.0, 0.0], |s, c| [s[0] + c[0], s[1] + c[1]]);
            [sum[0] / n, sum[1] / n]
        });
        Ok(ratios)
    }

    /// Mean, SD and range of each finger's per-image y; a finger without any is left out.
    pub fn from_samples(source: &str, per_image: &[(Finger, Vec<f64>)]) -> WristRatios {
        use crate::stats::describe;
        let describe = |(finger, ys): &(Finger, Vec<f64>)| {
            let (min, max) = describe::min_max(ys)?;
            Some(WristRatio {
                finger: *finger,
                mean: describe::mean(ys)?,
                sd: describe::sd(ys).unwrap_or(0.0),
                n: ys.len(),
                range: Interval::new(min, max),
            })
        };
        let ratios = per_image.iter().filter_map(describe).collect();
        WristRatios {
            source: source.to_string(),
            ratios,
            thumb_cmc: None,
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
    /// The finger's length J, MCP to the tip as the metacarpals' dataset
    /// measures it (the atlas's: at the bone, the rig's soft tissue taken off).
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
/// its MCP `mcp`, and the finger's length `length` to the dataset's tips
/// ([`super::JudgeOptions::length_against`]).
///
/// With S = mc + J (CMC to the compared tip through the MCP, held) and x = mc/J,
/// the MCP belongs at S x / (1 + x) from the CMC, increasing in x, so the
/// range and prediction interval of x map onto positions end to end. Moving
/// the MCP along the line lengthens mc as much as it shortens J; holding J
/// instead would read a 10 mm shift as about 10 (1 + x) mm. `None` without a
/// tip (J unknown), for a `length` not finite, without the dataset's mc/J
/// for the finger, or for a CMC on the MCP. O(1).
pub fn metacarpal(
    a: &Analysis,
    audit: &FingerAudit,
    length: f64,
    node: &str,
    cmc: DVec3,
    mcp: DVec3,
) -> Option<MetacarpalCheck> {
    let (length, mc) = ray_lengths(audit, length, cmc, mcp)?;
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
/// With w the wrist-to-MCP distance, J the finger's `length` to the atlas's
/// tips ([`super::JudgeOptions::length_against`]) and y = w/J, the
/// MCP belongs at S y / (1 + y) from the wrist, S = w + J held (wrist and
/// compared tip fixed), as [`metacarpal`] with x = mc/J. The atlas's y is
/// measured per X-ray (`ratios`, [`WristRatios`]): its mean, range and t
/// prediction interval at the audit's confidence map onto positions end to end.
/// `None` for the thumb, for a finger `ratios` lacks, and as [`metacarpal`]. O(1).
pub fn wrist(
    a: &Analysis,
    ratios: &WristRatios,
    audit: &FingerAudit,
    length: f64,
    node: &str,
    wrist: DVec3,
    mcp: DVec3,
) -> Option<MetacarpalCheck> {
    let y = ratios.of(audit.finger)?;
    let (length, w) = ray_lengths(audit, length, wrist, mcp)?;
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

/// The length J of a judged finger and the distance from `origin` to `mcp`;
/// `None` without a tip, for a length not finite and positive, or for an
/// origin on the MCP.
fn ray_lengths(audit: &FingerAudit, length: f64, origin: DVec3, mcp: DVec3) -> Option<(f64, f64)> {
    audit.length?;
    let to_mcp = origin.distance(mcp);
    (origin.is_finite() && mcp.is_finite() && to_mcp > 0.0 && length.is_finite() && length > 0.0)
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
