//! Which of two rigs deforms better, joint by joint and measure by measure.
//!
//! Each measure is turned into a badness, lower is better: |volume loss|
//! (a bulge is as wrong as a collapse), the count of new self-intersections,
//! the 95th percentile of edge strain, and |crease offset|. A measure calls a
//! rig better when its badness is lower by more than the measure's tolerance
//! ([`Measure::tolerance`]); otherwise, or when both are missing, it calls
//! them the same; when only one rig has the value it cannot tell.
//!
//! **Overall rule**: a rig is better at a joint when at least one measure
//! calls it better and none calls the other better; when measures call
//! different rigs better the joint is `mixed`, and the disagreement is named
//! (never averaged away); no call either way is `same`.

use super::measures::{HandMeasures, JointMeasures};
use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use schemars::JsonSchema;
use serde::Serialize;

/// One of the four measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    VolumeLoss,
    SelfIntersections,
    StrainP95,
    CreaseOffset,
}

impl Measure {
    pub const ALL: [Measure; 4] = [
        Measure::VolumeLoss,
        Measure::SelfIntersections,
        Measure::StrainP95,
        Measure::CreaseOffset,
    ];

    /// The measure's name for people.
    pub fn name(self) -> &'static str {
        match self {
            Measure::VolumeLoss => "volume loss",
            Measure::SelfIntersections => "self-intersections",
            Measure::StrainP95 => "strain p95",
            Measure::CreaseOffset => "crease offset",
        }
    }

    /// Differences of badness up to this are ties: one percentage point of
    /// area; no crossing pair; 0.005 of |ln ratio| (half a percent of length);
    /// 0.5 mm of crease position (glTF units are metres).
    pub fn tolerance(self) -> f64 {
        match self {
            Measure::VolumeLoss => 0.01,
            Measure::SelfIntersections => 0.0,
            Measure::StrainP95 => 0.005,
            Measure::CreaseOffset => 0.0005,
        }
    }

    /// The measure's value at a joint.
    pub fn value(self, j: &JointMeasures) -> Option<f64> {
        match self {
            Measure::VolumeLoss => j.volume_loss,
            Measure::SelfIntersections => Some(j.self_intersections as f64),
            Measure::StrainP95 => j.strain_p95,
            Measure::CreaseOffset => j.crease_offset,
        }
    }

    /// Lower is better.
    fn badness(self, v: f64) -> f64 {
        match self {
            Measure::VolumeLoss | Measure::CreaseOffset => v.abs(),
            _ => v,
        }
    }
}

/// Which rig a measure (or the rule) favours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Better {
    A,
    B,
    Same,
    /// Measures call different rigs better.
    Mixed,
    /// The measure is missing on one side.
    Unknown,
}

/// One measure at one joint, for both rigs.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct MeasureVerdict {
    pub measure: Measure,
    pub a: Option<f64>,
    pub b: Option<f64>,
    pub better: Better,
    /// How much lower the better rig's badness is (0 for a tie).
    pub by: Option<f64>,
}

/// One joint, both rigs.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct JointVerdict {
    pub finger: Finger,
    pub joint: Joint,
    pub measures: Vec<MeasureVerdict>,
    pub overall: Better,
    /// For a mixed joint: which measure favours which rig.
    pub disagreement: Option<String>,
}

fn judge(m: Measure, a: Option<f64>, b: Option<f64>) -> MeasureVerdict {
    let (better, by) = match (a, b) {
        (Some(x), Some(y)) => {
            let d = m.badness(x) - m.badness(y);
            if d.abs() <= m.tolerance() {
                (Better::Same, Some(d.abs()))
            } else if d > 0.0 {
                (Better::B, Some(d))
            } else {
                (Better::A, Some(-d))
            }
        }
        (None, None) => (Better::Same, None),
        _ => (Better::Unknown, None),
    };
    MeasureVerdict {
        measure: m,
        a,
        b,
        better,
        by,
    }
}

/// Compares every joint that both rigs have (see the module doc).
pub fn compare(a: &HandMeasures, b: &HandMeasures) -> Vec<JointVerdict> {
    let mut out = Vec::new();
    for fa in &a.fingers {
        let Some(fb) = b.fingers.iter().find(|f| f.finger == fa.finger) else {
            continue;
        };
        for ja in &fa.joints {
            let Some(jb) = fb.joints.iter().find(|j| j.joint == ja.joint) else {
                continue;
            };
            let measures: Vec<MeasureVerdict> = Measure::ALL
                .iter()
                .map(|&m| judge(m, m.value(ja), m.value(jb)))
                .collect();
            let names = |side: Better| -> Vec<&str> {
                measures
                    .iter()
                    .filter(|v| v.better == side)
                    .map(|v| v.measure.name())
                    .collect()
            };
            let (for_a, for_b) = (names(Better::A), names(Better::B));
            let (overall, disagreement) = match (for_a.is_empty(), for_b.is_empty()) {
                (false, true) => (Better::A, None),
                (true, false) => (Better::B, None),
                (false, false) => (
                    Better::Mixed,
                    Some(format!(
                        "A is better by {}; B is better by {}",
                        for_a.join(", "),
                        for_b.join(", ")
                    )),
                ),
                (true, true) if measures.iter().all(|v| v.better == Better::Unknown) => {
                    (Better::Unknown, None)
                }
                (true, true) => (Better::Same, None),
            };
            out.push(JointVerdict {
                finger: fa.finger,
                joint: ja.joint,
                measures,
                overall,
                disagreement,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::deform::measures::FingerMeasures;

    fn joint(loss: f64, crossings: usize, p95: f64, crease: f64) -> JointMeasures {
        JointMeasures {
            joint: Joint::Pip,
            angle: 90.0,
            rest_area: Some(1.0),
            posed_area: Some(1.0 - loss),
            volume_loss: Some(loss),
            volume_loss_at: Some(0.0),
            self_intersections: crossings,
            strain_p95: Some(p95),
            strain_max: Some(p95 * 2.0),
            crease_offset: Some(crease),
        }
    }

    fn hand(j: JointMeasures) -> HandMeasures {
        HandMeasures {
            fingers: vec![FingerMeasures {
                finger: Finger::Index,
                vertices: 1,
                triangles: 1,
                self_intersections: j.self_intersections,
                strain_p95: j.strain_p95,
                strain_max: j.strain_max,
                joints: vec![j],
                notes: Vec::new(),
            }],
        }
    }

    #[test]
    fn the_rule_names_disagreements() {
        // B better on every measure.
        let v = compare(
            &hand(joint(0.3, 4, 0.2, 0.005)),
            &hand(joint(0.1, 0, 0.1, 0.001)),
        );
        assert_eq!(v[0].overall, Better::B);
        assert!((v[0].measures[0].by.unwrap() - 0.2).abs() < 1e-12);
        // A bulge of 0.1 and a loss of 0.1 are equally bad: a tie.
        let v = compare(
            &hand(joint(-0.1, 0, 0.1, 0.0)),
            &hand(joint(0.1, 0, 0.1, 0.0)),
        );
        assert_eq!(v[0].overall, Better::Same);
        // Volume favours A, strain favours B: mixed, and said so.
        let v = compare(
            &hand(joint(0.05, 0, 0.3, 0.0)),
            &hand(joint(0.2, 0, 0.1, 0.0)),
        );
        assert_eq!(v[0].overall, Better::Mixed);
        let d = v[0].disagreement.as_deref().unwrap();
        assert!(
            d.contains("A is better by volume loss") && d.contains("B is better by strain p95"),
            "{d}"
        );
        // Within tolerance: the same.
        let v = compare(
            &hand(joint(0.100, 1, 0.100, 0.0010)),
            &hand(joint(0.105, 1, 0.103, 0.0013)),
        );
        assert_eq!(v[0].overall, Better::Same);
    }
}
