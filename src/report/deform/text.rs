//! What `phalanx deform` prints: the measures of one rig, or two side by side with a
//! verdict per joint, the pose in words, and the JSON document.

use super::figures::*;

use crate::error::Error;
use crate::format::{count, num, percent, signed, trimmed};
use crate::report::audit::MM;
use crate::report::layout::{Align, Give, Grid, Hidden, Width, fit_text};
use crate::rig::deform::file::{FileDeformation, HandDeformation};
use crate::rig::deform::measures::{HandMeasures, JointMeasures};
use crate::rig::deform::verdict::{Better, JointVerdict, Measure};
use crate::rig::deform::{Pose, Skinning};
use crate::rig::naming::Side;
use schemars::JsonSchema;
use serde::Serialize;

/// What every deformation comparison carries.
pub(crate) const CAVEATS: [&str; 4] = [
    "The measures compare skins, not anatomy: a rig whose skin folds at its joints and keeps its cross-sections deforms well by these measures even if the joints are far from where the X-rays put them.",
    "Volume loss is the cross-section area lost in planes across each bent joint (the worst across a window of half the shorter bone each side), not the enclosed volume; under linear blend skinning it depends on how the weights blend, not on where the joint is.",
    "Crease offset is the strain-weighted centre of the fold along the finger relative to the joint; it tells where the skin folds, not whether the fold looks right.",
    "Both rigs are posed with the same angles about each rig's own flexion axes; muscles, tendons, collisions with the palm and corrective shapes are not modelled.",
];

/// The deformation of one hand, for the JSON document.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct HandView<'a> {
    pub side: Side,
    /// Index of the skin deformed.
    pub skin: usize,
    pub vertices: usize,
    pub triangles: usize,
    /// Remarks from reading the mesh and skinning it.
    pub notes: Vec<String>,
    pub measures: &'a HandMeasures,
}

/// One rig deformed, for the JSON document.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct RigView<'a> {
    pub label: &'a str,
    pub hands: Vec<HandView<'a>>,
}

impl<'a> RigView<'a> {
    pub(crate) fn of(f: &'a FileDeformation) -> RigView<'a> {
        RigView {
            label: &f.label,
            hands: f
                .hands
                .iter()
                .map(|h| {
                    let mut notes = h.mesh.notes.clone();
                    notes.extend(h.deformation.notes.iter().cloned());
                    HandView {
                        side: h.chains.side,
                        skin: h.mesh.skin,
                        vertices: h.mesh.positions.len(),
                        triangles: h.mesh.triangles.len(),
                        notes,
                        measures: &h.deformation.measures,
                    }
                })
                .collect(),
        }
    }
}

/// The verdicts of one hand.
#[derive(Debug, Serialize, JsonSchema)]
pub(crate) struct HandVerdicts<'a> {
    pub side: Side,
    pub joints: &'a [JointVerdict],
}

/// `phalanx deform --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct DeformDocument<'a> {
    #[schemars(extend("const" = crate::report::json::SCHEMA_VERSION))]
    pub schema_version: u32,
    /// Units of every length: "m" (areas m^2; strain and loss unitless).
    pub units: &'static str,
    pub pose: &'a Pose,
    pub skinning: Skinning,
    /// Remarks on the request: each joint angle beyond its normal active
    /// range (the pose is then not one a hand makes).
    pub notes: Vec<String>,
    /// The rig as given: A.
    pub rig: RigView<'a>,
    /// What it is compared with (B): the --against file, or the fixed copy with --fix.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub against: Option<RigView<'a>>,
    /// With --fix: the joints the fix moves (node name, distance in m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moved: Option<Vec<crate::report::json::MovedView<'a>>>,
    /// Per hand both rigs have: per joint, which deforms better, by which measure, by how much.
    pub verdicts: Vec<HandVerdicts<'a>>,
    /// The figures written with --out.
    pub renders: Vec<RenderView>,
    pub caveats: &'static [&'static str],
}

/// The JSON bytes of `doc`.
pub(crate) fn json(doc: &DeformDocument<'_>) -> Result<Vec<u8>, Error> {
    let mut out =
        serde_json::to_vec_pretty(doc).map_err(|e| Error::render("cannot serialise JSON", e))?;
    out.push(b'\n');
    Ok(out)
}

/// A loss as a percentage, "n/a" when absent.
pub(super) fn loss(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), percent)
}

/// A length in mm with its sign, "n/a" when absent.
pub(super) fn mm(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), |v| signed(v * MM, 1))
}

/// A strain, 3 decimals.
pub(super) fn strain(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), |v| num(v, 3))
}

pub(super) fn better(b: Better) -> &'static str {
    match b {
        Better::A => "A",
        Better::B => "B",
        Better::Same => "same",
        Better::Mixed => "mixed",
        Better::Unknown => "?",
    }
}

/// The heading of the tables: pose and skinning.
pub(super) fn heading(pose: &Pose, method: Skinning) -> String {
    let mut out = pose_line(pose, method);
    for n in pose.anatomy_notes() {
        out.push_str(&format!("note: {n}\n"));
    }
    out
}

/// Pose and skinning in one line; fingers bent alike share one group:
/// "fingers MCP 60, PIP 90, DIP 60 degrees" when all four are, else each
/// group named ("index MCP 0, PIP 0, DIP 0; middle, ring and little MCP 60,
/// ...").
pub(crate) fn pose_line(pose: &Pose, method: Skinning) -> String {
    let t = &pose.fingers[0];
    let mut groups: Vec<(crate::rig::deform::pose::Angles, Vec<&str>)> = Vec::new();
    for (k, a) in pose.fingers.iter().enumerate().skip(1) {
        let name = crate::dataset::Finger::ALL[k].name();
        match groups.iter_mut().find(|(g, _)| g == a) {
            Some((_, names)) => names.push(name),
            None => groups.push((*a, vec![name])),
        }
    }
    let fingers: Vec<String> = groups
        .iter()
        .map(|(a, names)| {
            let who = match names.len() {
                4 => "fingers".to_string(),
                1 => names[0].to_string(),
                n => format!("{} and {}", names[..n - 1].join(", "), names[n - 1]),
            };
            format!(
                "{who} MCP {}, PIP {}, DIP {}",
                trimmed(a.mcp, 1),
                trimmed(a.pip, 1),
                trimmed(a.dip, 1)
            )
        })
        .collect();
    format!(
        "Pose {}: {} degrees; thumb MCP {}, IP {}{}. Skinning: {}.\n",
        pose.name,
        fingers.join("; "),
        trimmed(t.mcp, 1),
        trimmed(t.pip, 1),
        thumb_words(pose),
        match method {
            Skinning::Lbs => "linear blend (LBS)",
            Skinning::Dqs => "dual quaternion (DQS)",
        }
    )
}

/// Where the pose folds the thumb, as words after its angles ("" when it
/// only bends).
pub(super) fn thumb_words(pose: &Pose) -> String {
    pose.thumb_across.map_or_else(String::new, |f| {
        format!(", turned at its CMC to lie across the {f} finger's middle phalanx")
    })
}

pub(super) const LEGEND_ONE: &str = "loss: cross-section area lost across the joint (worst section, `at` mm from the joint, + distal); \
x: new self-intersecting triangle pairs; p95, max: |ln(posed/rest edge length)|; \
fold: where the skin folds, mm from the joint (+ distal).";

pub(super) const LEGEND_TWO: &str = "A is the rig, B what it is compared with. loss: cross-section area lost across the joint; \
x: new self-intersecting triangle pairs; p95: 95th percentile of |ln(posed/rest edge length)|; \
fold: where the skin folds, mm from the joint (+ distal); better: lower |loss|, fewer crossings, \
lower p95 and |fold| (ties within 1 point, 0, 0.005, 0.5 mm).";

/// The table of one rig.
pub(crate) fn text_one(
    rig: &FileDeformation,
    pose: &Pose,
    method: Skinning,
    width: Width,
) -> String {
    let mut hidden = Hidden::new();
    let mut out = format!("{}\n{}", rig.label, heading(pose, method));
    for h in &rig.hands {
        out.push_str(&format!(
            "\n{} hand: {}, {}\n",
            h.chains.side.name(),
            count(h.mesh.positions.len(), "vertex", "vertices"),
            count(h.mesh.triangles.len(), "triangle", "triangles")
        ));
        let mut t = Grid::new()
            .col("finger", Align::Left, Give::Keep)
            .col("joint", Align::Left, Give::Keep)
            .col("deg", Align::Right, Give::Keep)
            .col("loss", Align::Right, Give::Keep)
            .col("at", Align::Right, Give::Drop(2))
            .col("x", Align::Right, Give::Keep)
            .col("p95", Align::Right, Give::Keep)
            .col("max", Align::Right, Give::Drop(1))
            .col("fold", Align::Right, Give::Keep);
        for f in &h.deformation.measures.fingers {
            for j in &f.joints {
                t.row(vec![
                    f.finger.name().to_string(),
                    j.joint.name().to_string(),
                    trimmed(j.angle, 1),
                    loss(j.volume_loss),
                    mm(j.volume_loss_at),
                    j.self_intersections.to_string(),
                    strain(j.strain_p95),
                    strain(j.strain_max),
                    mm(j.crease_offset),
                ]);
            }
        }
        out.push_str(&t.render(width, 0, &mut hidden));
        out.push_str(&notes(h));
    }
    out.push('\n');
    out.push_str(LEGEND_ONE);
    out.push('\n');
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

pub(super) fn notes(h: &HandDeformation) -> String {
    let mut out = String::new();
    let all = h
        .mesh
        .notes
        .iter()
        .chain(&h.deformation.notes)
        .chain(h.deformation.measures.fingers.iter().flat_map(|f| &f.notes));
    for n in all {
        out.push_str(&format!("note: {n}\n"));
    }
    out
}

pub(super) fn find<'a>(h: &'a HandDeformation, v: &JointVerdict) -> Option<&'a JointMeasures> {
    h.deformation
        .measures
        .fingers
        .iter()
        .find(|f| f.finger == v.finger)?
        .joints
        .iter()
        .find(|j| j.joint == v.joint)
}

/// How much better, in words: "volume loss 12.3 points, strain p95 0.021".
pub(super) fn by_how_much(v: &JointVerdict, side: Better) -> String {
    v.measures
        .iter()
        .filter(|m| m.better == side)
        .map(|m| {
            let by = m.by.unwrap_or(0.0);
            let amount = match m.measure {
                Measure::VolumeLoss => format!("{} points", num(by * 100.0, 1)),
                Measure::SelfIntersections => {
                    let n = by.round();
                    let n = if n.is_finite() && n >= 0.0 {
                        n as usize
                    } else {
                        0
                    };
                    count(n, "pair", "pairs")
                }
                Measure::StrainP95 => num(by, 3),
                Measure::CreaseOffset => format!("{} mm", num(by * MM, 1)),
            };
            format!("{} {amount}", m.measure.name())
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The table of two rigs with the verdicts.
pub(crate) fn text_two(
    a: &FileDeformation,
    b: &FileDeformation,
    verdicts: &[(Side, Vec<JointVerdict>)],
    pose: &Pose,
    method: Skinning,
    width: Width,
) -> String {
    let mut hidden = Hidden::new();
    let mut out = format!("A: {}\nB: {}\n{}", a.label, b.label, heading(pose, method));
    for (side, joints) in verdicts {
        let (Some(ha), Some(hb)) = (
            a.hands.iter().find(|h| h.chains.side == *side),
            b.hands.iter().find(|h| h.chains.side == *side),
        ) else {
            continue;
        };
        out.push_str(&format!("\n{} hand\n", side.name()));
        let mut t = Grid::new()
            .col("finger", Align::Left, Give::Keep)
            .col("joint", Align::Left, Give::Keep)
            .col("deg", Align::Right, Give::Keep)
            .col("loss A", Align::Right, Give::Keep)
            .col("loss B", Align::Right, Give::Keep)
            .col("x A", Align::Right, Give::Drop(1))
            .col("x B", Align::Right, Give::Drop(1))
            .col("p95 A", Align::Right, Give::Keep)
            .col("p95 B", Align::Right, Give::Keep)
            .col("fold A", Align::Right, Give::Drop(2))
            .col("fold B", Align::Right, Give::Drop(2))
            .col("better", Align::Left, Give::Keep);
        for v in joints {
            let (Some(ja), Some(jb)) = (find(ha, v), find(hb, v)) else {
                continue;
            };
            t.row(vec![
                v.finger.name().to_string(),
                v.joint.name().to_string(),
                trimmed(ja.angle, 1),
                loss(ja.volume_loss),
                loss(jb.volume_loss),
                ja.self_intersections.to_string(),
                jb.self_intersections.to_string(),
                strain(ja.strain_p95),
                strain(jb.strain_p95),
                mm(ja.crease_offset),
                mm(jb.crease_offset),
                better(v.overall).to_string(),
            ]);
        }
        out.push_str(&t.render(width, 0, &mut hidden));
        out.push_str(&format!("Verdict: {}\n", verdict_summary(joints)));
        for line in reasons(joints) {
            out.push_str(&format!("  {line}\n"));
        }
        for (label, h) in [("A", ha), ("B", hb)] {
            let n = notes(h);
            if !n.is_empty() {
                out.push_str(&format!("{label}:\n{n}"));
            }
        }
    }
    out.push('\n');
    out.push_str(LEGEND_TWO);
    out.push('\n');
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// "B deforms better at 4 joints, A at 1, ...".
pub(super) fn verdict_summary(joints: &[JointVerdict]) -> String {
    let n = |b: Better| joints.iter().filter(|v| v.overall == b).count();
    format!(
        "B deforms better at {}, A at {}, mixed at {}, the same at {} (of {}).",
        count(n(Better::B), "joint", "joints"),
        n(Better::A),
        n(Better::Mixed),
        n(Better::Same),
        joints.len()
    )
}

/// Per joint where a rig is better: by which measures and by how much.
pub(super) fn reasons(joints: &[JointVerdict]) -> Vec<String> {
    joints
        .iter()
        .filter_map(|v| match v.overall {
            Better::A | Better::B => Some(format!(
                "{} {}: {} better by {}",
                v.finger,
                v.joint.name(),
                better(v.overall),
                by_how_much(v, v.overall)
            )),
            Better::Mixed => Some(format!(
                "{} {}: mixed; A better by {}; B better by {}",
                v.finger,
                v.joint.name(),
                by_how_much(v, Better::A),
                by_how_much(v, Better::B)
            )),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pose_line_names_each_group_of_fingers_at_its_own_angles() {
        // The fist bends the four fingers alike (MCP 60, PIP 90, DIP 60; thumb 30, 45).
        let fist = pose_line(&Pose::fist(), Skinning::Lbs);
        assert!(
            fist.starts_with(
                "Pose fist: fingers MCP 60, PIP 90, DIP 60 degrees; thumb MCP 30, IP 45"
            ),
            "{fist}"
        );
        // Pointing: the index straight, the other three in the fist.
        let point = pose_line(&Pose::point(), Skinning::Dqs);
        assert!(
            point.starts_with(
                "Pose point: index MCP 0, PIP 0, DIP 0; middle, ring and little MCP 60, PIP 90, \
                 DIP 60 degrees; thumb MCP 30, IP 45"
            ),
            "{point}"
        );
        assert!(!point.contains("fingers MCP 0"), "{point}");
        assert!(
            fist.contains(
                "IP 45, turned at its CMC to lie across the index finger's middle phalanx."
            ) && point.contains("across the middle finger's middle phalanx."),
            "{fist}{point}"
        );
        // Two fingers bent one way, two another.
        let mut p = Pose::fist();
        p.fingers[2].mcp = 10.0;
        p.fingers[4].mcp = 10.0;
        let two = pose_line(&p, Skinning::Lbs);
        assert!(
            two.contains("index and ring MCP 60, PIP 90, DIP 60; middle and little MCP 10, PIP 90, DIP 60 degrees"),
            "{two}"
        );
    }
}
