//! Joint placement for a model finger of known total length (the paper's worked example).
//!
//! Measured from the finger's root joint (MCP), for a model finger of total
//! length L: the second joint (PIP) lies at J~1 L, the third (DIP) at
//! (J~1 + J~2) L = (1 - J~3) L, and the tip at L; for the thumb the IP joint lies
//! at J~1 L. Where the data measure the metacarpal, the MCP lies (mc/J) L from the
//! CMC, the base of the metacarpal: the part of the hand the paper leaves open. Every statistic of a position is the corresponding statistic of a
//! relative value under the affine map x -> a + b x (b = +L or -L). The mean and
//! all four intervals are equivariant under such maps (for b < 0 the ends swap),
//! so no new resampling is needed.

use super::{Analysis, Quantity, QuantityStats};
use crate::dataset::Finger;
use crate::stats::Intervals;
use schemars::JsonSchema;
use serde::Serialize;

/// A joint of a finger, from root to tip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub enum Joint {
    /// Metacarpophalangeal: the finger's root, at 0.
    #[serde(rename = "MCP")]
    Mcp,
    /// Proximal interphalangeal (index to little).
    #[serde(rename = "PIP")]
    Pip,
    /// Distal interphalangeal (index to little).
    #[serde(rename = "DIP")]
    Dip,
    /// Interphalangeal joint of the thumb.
    #[serde(rename = "IP")]
    Ip,
    /// The fingertip, at L.
    #[serde(rename = "tip")]
    Tip,
}

impl Joint {
    /// Short name (MCP, PIP, DIP, IP, tip).
    pub fn name(self) -> &'static str {
        match self {
            Joint::Mcp => "MCP",
            Joint::Pip => "PIP",
            Joint::Dip => "DIP",
            Joint::Ip => "IP",
            Joint::Tip => "tip",
        }
    }

    /// The joints of a finger between root and tip, whose positions are estimated.
    pub fn inner(finger: Finger) -> &'static [Joint] {
        match finger {
            Finger::Thumb => &[Joint::Ip],
            _ => &[Joint::Pip, Joint::Dip],
        }
    }
}

/// A statistic carried into model units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Placed {
    pub mean: f64,
    pub min: f64,
    pub max: f64,
    pub range: f64,
    /// SD in model units; null for n = 1.
    pub sd: Option<f64>,
    /// The four intervals in model units (JSON keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`).
    #[serde(flatten)]
    pub intervals: Intervals,
}

impl Placed {
    /// The statistics of `offset + scale * x`, from those of x. O(1).
    pub(crate) fn affine(s: &QuantityStats, offset: f64, scale: f64) -> Placed {
        let map = |x: f64| offset + scale * x;
        let (a, b) = (map(s.min), map(s.max));
        Placed {
            mean: map(s.mean),
            min: a.min(b),
            max: a.max(b),
            range: (b - a).abs(),
            sd: s.sd.map(|sd| sd * scale.abs()),
            intervals: s.intervals.affine(offset, scale),
        }
    }
}

/// Where one joint lies from the root, in model units.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct JointPosition {
    pub joint: Joint,
    pub position: Placed,
}

/// One segment's length in model units.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SegmentLength {
    /// `j1`, `j2` or `j3`.
    pub segment: &'static str,
    pub length: Placed,
}

/// Joint positions and segment lengths for one model finger.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct FingerPlacement {
    pub finger: Finger,
    /// The model finger's total length L (root joint to tip).
    pub length: f64,
    /// X-rays the statistics come from.
    pub n: usize,
    /// The inner joints, root to tip (PIP, DIP; or IP for the thumb).
    pub joints: Vec<JointPosition>,
    pub segments: Vec<SegmentLength>,
    /// The MCP's distance from the CMC, (mc/J) L, where the data measure the metacarpal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metacarpal: Option<Metacarpal>,
}

/// Where the MCP lies from the CMC, in model units.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct Metacarpal {
    /// X-rays whose metacarpal is measured.
    pub n: usize,
    pub position: Placed,
}

/// Places the joints of `finger` for a model finger of total length `length`.
/// `None` when the data has no such finger.
pub fn place(a: &Analysis, finger: Finger, length: f64) -> Option<FingerPlacement> {
    let fa = a.finger(finger)?;
    let rel = |q| fa.quantity(q);
    let mut joints = Vec::new();
    for &j in Joint::inner(finger) {
        let position = match j {
            Joint::Pip | Joint::Ip => Placed::affine(rel(Quantity::RelJ1)?, 0.0, length),
            // (J~1 + J~2) L = L - J~3 L.
            Joint::Dip => Placed::affine(rel(Quantity::RelJ3)?, length, -length),
            Joint::Mcp | Joint::Tip => continue,
        };
        joints.push(JointPosition { joint: j, position });
    }
    let segments = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
        .iter()
        .zip(["j1", "j2", "j3"])
        .filter_map(|(&q, name)| {
            rel(q).map(|s| SegmentLength {
                segment: name,
                length: Placed::affine(s, 0.0, length),
            })
        })
        .collect();
    let metacarpal = rel(Quantity::RatioMcJ).map(|s| Metacarpal {
        n: s.n,
        position: Placed::affine(s, 0.0, length),
    });
    Some(FingerPlacement {
        finger,
        length,
        n: fa.n,
        joints,
        segments,
        metacarpal,
    })
}

/// Places every finger of the data at the same model length.
pub fn place_all(a: &Analysis, length: f64) -> Vec<FingerPlacement> {
    a.fingers
        .iter()
        .filter_map(|f| place(a, f.finger, length))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;
    use std::path::Path;

    fn paper() -> Analysis {
        let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        analyse(&d, &Settings::default())
    }

    #[test]
    fn worked_example_with_the_corrected_mean() {
        // The paper: mean 494.6 (misprint; 0.4846 x 1000 = 484.6), max 504.7, min 472.8, range 31.9
        // (from rounded values; unrounded 31.96).
        let p = place(&paper(), Finger::Index, 1000.0).unwrap();
        let pip = &p.joints[0];
        assert_eq!(pip.joint, Joint::Pip);
        assert_eq!(format!("{:.1}", pip.position.mean), "484.6");
        assert_eq!(format!("{:.1}", pip.position.max), "504.7");
        assert_eq!(format!("{:.1}", pip.position.min), "472.8");
        assert_eq!(format!("{:.1}", pip.position.range), "32.0");
        assert_eq!(p.segments.len(), 3);
        assert!(p.metacarpal.is_none(), "the paper measures no metacarpal");
    }

    #[test]
    fn the_mcp_from_the_cmc_where_the_metacarpal_is_measured() {
        // mc/J by hand: 60/85, 66/90, 58/80; at L = 10 the MCP lies 10 mc/J from the CMC.
        let text = "xray,finger,j1,j2,j3,mc\na,index,40,25,20,60\nb,index,45,25,20,66\nc,index,40,22,18,58\n";
        let d = Dataset::from_bytes("t.csv", text.as_bytes()).unwrap();
        let p = place(&analyse(&d, &Settings::default()), Finger::Index, 10.0).unwrap();
        let m = p.metacarpal.unwrap();
        let want = [60.0 / 85.0, 66.0 / 90.0, 58.0 / 80.0].map(|r| 10.0 * r);
        assert_eq!(m.n, 3);
        assert!((m.position.mean - want.iter().sum::<f64>() / 3.0).abs() < 1e-12);
        assert!((m.position.min - want[0]).abs() < 1e-12);
        assert!((m.position.max - want[1]).abs() < 1e-12);
    }

    #[test]
    fn dip_is_one_minus_j3_and_intervals_flip() {
        let a = paper();
        let p = place(&a, Finger::Middle, 100.0).unwrap();
        let j3 = a
            .finger(Finger::Middle)
            .unwrap()
            .quantity(Quantity::RelJ3)
            .unwrap();
        let dip = &p.joints[1].position;
        assert!((dip.mean - 100.0 * (1.0 - j3.mean)).abs() < 1e-9);
        assert!((dip.max - 100.0 * (1.0 - j3.min)).abs() < 1e-9);
        let ci = dip.intervals.ci_bca.unwrap();
        let src = j3.intervals.ci_bca.unwrap();
        assert!((ci.low - 100.0 * (1.0 - src.high)).abs() < 1e-9);
        assert!(ci.low < dip.mean && dip.mean < ci.high);
        // The mean DIP equals the sum of the mean J~1 and J~2 positions.
        let s: f64 = p.segments[..2].iter().map(|s| s.length.mean).sum();
        assert!((dip.mean - s).abs() < 1e-9);
    }

    #[test]
    fn thumb_has_one_inner_joint() {
        let p = place(&paper(), Finger::Thumb, 50.0).unwrap();
        assert_eq!(p.joints.len(), 1);
        assert_eq!(p.joints[0].joint, Joint::Ip);
        assert_eq!(p.segments.len(), 2);
        assert_eq!(place_all(&paper(), 1.0).len(), 5);
    }
}

/// A position or length placed from a summary table's ratio of means, in model units.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct TablePlaced {
    pub mean: f64,
    /// The t interval of the ratio of the table's means (delta-method SE), in model units.
    pub ci: Option<crate::stats::Interval>,
    /// The prediction interval for one hand (the first-order SD of one hand's ratio).
    pub pi: Option<crate::stats::Interval>,
}

impl TablePlaced {
    fn affine(e: &super::literature::Estimate, offset: f64, scale: f64) -> TablePlaced {
        let map = |i: crate::stats::Interval| {
            let (a, b) = (offset + scale * i.low, offset + scale * i.high);
            crate::stats::Interval::new(a.min(b), a.max(b))
        };
        TablePlaced {
            mean: offset + scale * e.mean,
            ci: e.ci.map(map),
            pi: e.pi.map(map),
        }
    }
}

/// Where one joint lies from the root, placed from a table.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct TableJoint {
    pub joint: Joint,
    pub position: TablePlaced,
}

/// Joint positions for one model finger from a summary table.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct TablePlacement {
    pub finger: Finger,
    pub length: f64,
    /// Hands of the table (its smallest n among the segments used).
    pub n: Option<usize>,
    /// Where the table's finger ends: at the skin when it gives the soft tissue (a model
    /// finger ends at its skin), else at the bone.
    pub tip: crate::dataset::TipKind,
    /// The correlation between segments the intervals rest on.
    pub rho: f64,
    pub joints: Vec<TableJoint>,
    /// `j1`, `j2`, `j3` in model units.
    pub segments: Vec<(String, TablePlaced)>,
    /// The MCP's distance from the CMC, (mc/J) L, where the table gives the metacarpal.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metacarpal: Option<TablePlaced>,
    /// Why an interval is missing, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

/// Places the joints of `finger` for a model finger of total length `length` from a
/// summary table's ratios of means, their intervals under correlation `rho` between the
/// table's segments ([`super::literature::table_estimate`]). Err says what the table lacks.
pub fn place_from_table(
    table: &crate::dataset::SummaryTable,
    finger: Finger,
    length: f64,
    rho: f64,
    confidence: f64,
) -> Result<TablePlacement, String> {
    use crate::dataset::{Segment, TipKind};
    let tip = if table.get(finger, Segment::TipSoftTissue).is_some() {
        TipKind::Skin
    } else {
        TipKind::Bone
    };
    let est = |q| super::literature::table_estimate(table, finger, q, tip, rho, confidence);
    let rel = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3];
    let k = finger.segments();
    let mut segments = Vec::new();
    let mut why = None;
    for (i, &q) in rel[..k].iter().enumerate() {
        let e = est(q)?;
        why = why.or(e.why.clone());
        segments.push((format!("j{}", i + 1), TablePlaced::affine(&e, 0.0, length)));
    }
    let last = if finger == Finger::Thumb {
        Quantity::RelJ2
    } else {
        Quantity::RelJ3
    };
    let mut joints = vec![TableJoint {
        joint: if finger == Finger::Thumb {
            Joint::Ip
        } else {
            Joint::Pip
        },
        position: TablePlaced::affine(&est(Quantity::RelJ1)?, 0.0, length),
    }];
    if finger != Finger::Thumb {
        joints.push(TableJoint {
            joint: Joint::Dip,
            position: TablePlaced::affine(&est(last)?, length, -length),
        });
    }
    let metacarpal = est(Quantity::RatioMcJ)
        .ok()
        .map(|e| TablePlaced::affine(&e, 0.0, length));
    Ok(TablePlacement {
        finger,
        length,
        n: est(Quantity::RelJ1)?.n,
        tip,
        rho,
        joints,
        segments,
        metacarpal,
        why,
    })
}

#[cfg(test)]
mod table_tests {
    use super::*;
    use crate::dataset::SummaryTable;

    #[test]
    fn placed_from_bk_by_hand() {
        let t = SummaryTable::load(std::path::Path::new(
            "data/literature/buryanov-kotiuk-2010.csv",
        ))
        .unwrap();
        let p = place_from_table(&t, Finger::Index, 100.0, 0.5, 0.95).unwrap();
        // Tip at the skin: finger 39.78 + 22.38 + 15.82 + 3.84 = 81.82; PIP at 39.78 / 81.82,
        // DIP at (39.78 + 22.38) / 81.82 of the length.
        assert!((p.joints[0].position.mean - 100.0 * 39.78 / 81.82).abs() < 1e-12);
        assert!((p.joints[1].position.mean - 100.0 * 62.16 / 81.82).abs() < 1e-12);
        let ci = p.joints[1].position.ci.unwrap();
        assert!(ci.low < p.joints[1].position.mean && p.joints[1].position.mean < ci.high);
        assert_eq!(p.tip, crate::dataset::TipKind::Skin);
        // mc/J: 68.12 / 81.82.
        assert!((p.metacarpal.unwrap().mean - 100.0 * 68.12 / 81.82).abs() < 1e-12);
        let th = place_from_table(&t, Finger::Thumb, 10.0, 0.5, 0.95).unwrap();
        assert_eq!((th.joints.len(), th.segments.len()), (1, 2));
        assert!((th.joints[0].position.mean - 10.0 * 31.57 / 58.91).abs() < 1e-12);
    }
}
