//! What `phalanx deform` shows: the measures table (one rig, or two side by
//! side with a verdict per joint), the figures (PNG, both rigs posed, from the
//! side and from above, coloured by strain) and the JSON document.
//!
//! Rig coordinates are metres (the glTF unit), shown in millimetres; volume
//! loss as a percentage of the rest cross-section; strain as |ln(posed / rest
//! edge length)|, unitless.

use super::audit::MM;
use super::layout::{Align, Give, Grid, Hidden, Width, fit_text};
use super::render3d::{Figure, MeshView, View};
use super::sections::deform::{
    DeformAuditRow, DeformFigureView, DeformHandView, DeformRowView, DeformSection, DeformView,
    MetacarpalView,
};
use super::writer::OutputFile;
use crate::error::Error;
use crate::format::{count, num, percent, signed, trimmed};
use crate::rig::AuditedRig;
use crate::rig::deform::file::{FileDeformation, HandDeformation};
use crate::rig::deform::measures::{HandMeasures, JointMeasures};
use crate::rig::deform::verdict::{Better, JointVerdict, Measure};
use crate::rig::deform::{Pose, Skinning};
use crate::rig::judge::{MetacarpalCheck, RayBase};
use crate::rig::naming::Side;
use schemars::JsonSchema;
use serde::Serialize;
use std::path::Path;

/// What every deformation comparison carries.
pub(crate) const CAVEATS: [&str; 4] = [
    "The measures compare skins, not anatomy: a rig whose skin folds at its joints and keeps its cross-sections deforms well by these measures even if the joints are far from where the X-rays put them.",
    "Volume loss is the cross-section area lost in planes across each bent joint (the worst across a window of half the shorter bone each side), not the enclosed volume; under linear blend skinning it depends on how the weights blend, not on where the joint is.",
    "Crease offset is the strain-weighted centre of the fold along the finger relative to the joint; it tells where the skin folds, not whether the fold looks right.",
    "Both rigs are posed with the same angles about each rig's own flexion axes; muscles, tendons, collisions with the palm and corrective shapes are not modelled.",
];

/// One panel of a figure: where each fingertip (or the last joint) of a rig is drawn.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub(crate) struct PanelView {
    /// "side" or "above".
    pub view: &'static str,
    /// "a" (the rig) or "b" (--against or the fixed copy).
    pub rig: &'static str,
    /// Pixel position (x right, y down) of each finger's posed tip.
    pub tips: Vec<TipPixel>,
}

/// A fingertip's pixel in a figure.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub(crate) struct TipPixel {
    pub finger: crate::dataset::Finger,
    pub x: f64,
    pub y: f64,
}

/// A figure written by `--out`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub(crate) struct RenderView {
    /// File name inside the --out directory.
    pub file: String,
    pub side: Side,
    pub width: u32,
    pub height: u32,
    /// Row by row (side, then above), column by column (a, then b).
    pub panels: Vec<PanelView>,
}

/// Pixels per panel of a figure.
const PANEL: (u32, u32) = (420, 300);

/// The name of the `side` hand's figure, as `deform --out DIR` writes it.
pub(crate) fn figure_file(side: Side) -> String {
    format!("deform-{}.png", side.name())
}

/// The figure of one hand: rig A (and B) posed, from the side and from above
/// in A's palm frame, each panel framed on the hand (the vertices its bones
/// skin, [`HandDeformation::hand_vertices`]), its columns headed by `labels`
/// (A's, then B's); PNG bytes and where the fingertips are drawn.
pub(crate) fn figure(
    a: &HandDeformation,
    b: Option<&HandDeformation>,
    labels: &[&str],
    font: Option<&[u8]>,
) -> Result<(OutputFile, RenderView), Error> {
    let rigs: Vec<&HandDeformation> = std::iter::once(a).chain(b).collect();
    let focus: Vec<Vec<bool>> = rigs.iter().map(|h| h.hand_vertices()).collect();
    let meshes: Vec<MeshView<'_>> = rigs
        .iter()
        .zip(&focus)
        .map(|(h, focus)| MeshView {
            positions: &h.deformation.posed,
            triangles: &h.mesh.triangles,
            strain: &h.deformation.vertex_strain,
            focus,
        })
        .collect();
    let views = [View::side(&a.posed.frame), View::above(&a.posed.frame)];
    let fig = Figure::layout(&meshes, &views, PANEL.0, PANEL.1);
    let png = fig
        .render(&meshes, labels, font)
        .map_err(|e| Error::render("cannot draw the deformation figure", e))?;
    let mut panels = Vec::new();
    for (row, view) in views.iter().enumerate() {
        for (col, h) in rigs.iter().enumerate() {
            let tips = h
                .posed
                .fingers
                .iter()
                .filter_map(|f| {
                    let last = f.joints.last()?;
                    let p = last.after.transform_point3(f.tip.unwrap_or(last.rest));
                    let (x, y) = fig.project(row, col, p)?;
                    Some(TipPixel {
                        finger: f.finger,
                        x,
                        y,
                    })
                })
                .collect();
            panels.push(PanelView {
                view: view.name,
                rig: if col == 0 { "a" } else { "b" },
                tips,
            });
        }
    }
    let side = a.chains.side;
    let file = figure_file(side);
    Ok((
        OutputFile::new(&file, png),
        RenderView {
            file,
            side,
            width: fig.width,
            height: fig.height,
            panels,
        },
    ))
}

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
    #[schemars(extend("const" = super::json::SCHEMA_VERSION))]
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
    pub moved: Option<Vec<super::json::MovedView<'a>>>,
    /// Per hand both rigs have: per joint, which deforms better, by which measure, by how much.
    pub verdicts: Vec<HandVerdicts<'a>>,
    /// The figures written with --out.
    pub renders: Vec<RenderView>,
    pub caveats: &'static [&'static str],
}

/// The words over each column of a figure: the rig and its file name, and
/// B's: "the fixed rig" when `fixed` (B is what `audit --fix` would write),
/// else its file name.
pub(crate) fn column_labels(
    a: &FileDeformation,
    b: Option<&FileDeformation>,
    fixed: bool,
) -> Vec<String> {
    let name = |label: &str| {
        Path::new(label)
            .file_name()
            .map_or_else(|| label.to_string(), |n| n.to_string_lossy().into_owned())
    };
    match b {
        None => vec![format!("the rig, {}", name(&a.label))],
        Some(_) if fixed => vec![
            format!("A: the rig, {}", name(&a.label)),
            "B: the fixed rig (as audit --fix writes it)".to_string(),
        ],
        Some(b) => vec![
            format!("A: the rig, {}", name(&a.label)),
            format!("B: {}", name(&b.label)),
        ],
    }
}

/// The figure of each hand of `a`, beside the same side of `b`: the PNG files
/// (`deform-<side>.png`) and where they draw the fingertips. `fixed`: B is
/// the fixed copy (see [`column_labels`]).
pub(crate) fn figures(
    a: &FileDeformation,
    b: Option<&FileDeformation>,
    fixed: bool,
) -> Result<(Vec<OutputFile>, Vec<RenderView>), Error> {
    let mut files = Vec::new();
    let mut renders = Vec::new();
    let labels = column_labels(a, b, fixed);
    let labels: Vec<&str> = labels.iter().map(String::as_str).collect();
    let font = label_font();
    for ha in &a.hands {
        let hb = b.and_then(|b| b.hands.iter().find(|h| h.chains.side == ha.chains.side));
        let (f, r) = figure(ha, hb, &labels, font.as_deref())?;
        files.push(f);
        renders.push(r);
    }
    Ok((files, renders))
}

/// The labels' font, read from the working directory
/// ([`super::render3d::FONT_FILE`]); without it the figures are drawn
/// without their labels and scale numbers, and a note says so and what to do.
pub(crate) fn label_font() -> Option<Vec<u8>> {
    let path = super::render3d::FONT_FILE;
    match std::fs::read(path) {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            eprintln!(
                "note: the figures are drawn without their labels and scale numbers: \
                 {path}: {e}; run phalanx from its checkout, where data/fonts/ is"
            );
            None
        }
    }
}

/// The JSON bytes of `doc`.
pub(crate) fn json(doc: &DeformDocument<'_>) -> Result<Vec<u8>, Error> {
    let mut out =
        serde_json::to_vec_pretty(doc).map_err(|e| Error::render("cannot serialise JSON", e))?;
    out.push(b'\n');
    Ok(out)
}

/// A loss as a percentage, "n/a" when absent.
fn loss(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), percent)
}

/// A length in mm with its sign, "n/a" when absent.
fn mm(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), |v| signed(v * MM, 1))
}

/// A strain, 3 decimals.
fn strain(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), |v| num(v, 3))
}

fn better(b: Better) -> &'static str {
    match b {
        Better::A => "A",
        Better::B => "B",
        Better::Same => "same",
        Better::Mixed => "mixed",
        Better::Unknown => "?",
    }
}

/// The heading of the tables: pose and skinning.
fn heading(pose: &Pose, method: Skinning) -> String {
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
fn thumb_words(pose: &Pose) -> String {
    pose.thumb_across.map_or_else(String::new, |f| {
        format!(", turned at its CMC to lie across the {f} finger's middle phalanx")
    })
}

const LEGEND_ONE: &str = "loss: cross-section area lost across the joint (worst section, `at` mm from the joint, + distal); \
x: new self-intersecting triangle pairs; p95, max: |ln(posed/rest edge length)|; \
fold: where the skin folds, mm from the joint (+ distal).";

const LEGEND_TWO: &str = "A is the rig, B what it is compared with. loss: cross-section area lost across the joint; \
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

fn notes(h: &HandDeformation) -> String {
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

fn find<'a>(h: &'a HandDeformation, v: &JointVerdict) -> Option<&'a JointMeasures> {
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
fn by_how_much(v: &JointVerdict, side: Better) -> String {
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

/// What the deformation measures can and cannot tell, for the report.
pub(crate) const CAN_TELL: &str = "What the measures can tell: where the skin collapses (loss; linear blend \
skinning loses 1 - cos(theta/2) of a joint's section, 29% at 90 degrees, wherever the weights blend), where \
it folds relative to the joint (fold), how much it stretches (p95) and whether it passes through itself (x). \
What they cannot tell: whether a joint is anatomically right. The fix moves the skin weights with the joints \
but does not remodel the mesh, so a joint moved away from the edge loops it was modelled at can deform worse \
even where it matches the bones: read a worse score as \"check the topology around the moved joint\", not as \
\"the statistics are wrong\".";

/// A real rig deformed as it is (A) and as `audit --fix` writes it (B), with
/// its audit: what [`section`] turns into the report's part.
pub(crate) struct SectionInputs<'a> {
    pub a: &'a FileDeformation,
    pub b: &'a FileDeformation,
    pub verdicts: &'a [(Side, Vec<JointVerdict>)],
    pub pose: &'a Pose,
    pub method: Skinning,
    /// The joints the fix moves (node, distance in m).
    pub moved: &'a [(String, f64)],
    /// The rig as given, judged (its metacarpals too, when an atlas was given).
    pub audit: &'a AuditedRig,
    /// Whether an atlas was given to judge the metacarpals against.
    pub atlas: bool,
    pub confidence: f64,
    /// The figures of [`figure`], one per hand, in `a`'s hand order.
    pub figures: Vec<(OutputFile, RenderView)>,
    /// File name stem under `plots/`, e.g. `deform-webxr-generic-hand`.
    pub stem: &'a str,
}

/// The report's part on a real rig: the view, and the figures under `plots/`
/// (the HTML embeds them as data URIs, so it stays one self-contained file).
pub(crate) fn section(s: SectionInputs<'_>) -> DeformSection {
    use base64::Engine;
    let mut files = Vec::new();
    let mut hands = Vec::new();
    for (side, joints) in s.verdicts {
        let (Some(ha), Some(hb)) = (
            s.a.hands.iter().find(|h| h.chains.side == *side),
            s.b.hands.iter().find(|h| h.chains.side == *side),
        ) else {
            continue;
        };
        let Some((png, render)) = s.figures.iter().find(|(_, r)| r.side == *side) else {
            continue;
        };
        let name = format!("{}-{}", s.stem, side.name());
        let file = format!("plots/{name}.png");
        let data_uri = format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&png.bytes)
        );
        files.push(OutputFile::new(&file, png.bytes.clone()));
        hands.push(DeformHandView {
            side: side.name().to_string(),
            rows: joint_rows(ha, hb, joints),
            summary: verdict_summary(joints),
            reasons: reasons(joints),
            figure: DeformFigureView {
                id: name,
                file,
                data_uri,
                width: render.width.to_string(),
                height: render.height.to_string(),
                alt: format!(
                    "The {} hand in the pose as it is (left) and as audit --fix writes it (right), \
                     from the side (top) and from above (bottom), coloured by strain",
                    side.name()
                ),
                caption: format!(
                    "The {} hand posed, as it is (A, left) and as audit --fix writes it (B, right), \
                     from the side (top row) and from above (bottom row). Colour: edge strain \
                     |ln(posed/rest edge length)|, grey 0, amber 0.1, red 0.25 and more. {CAN_TELL}",
                    side.name()
                ),
            },
        });
    }
    DeformSection {
        view: DeformView {
            rig: s.a.label.clone(),
            pose: pose_line(s.pose, s.method).trim_end().to_string(),
            moved: moved_words(s.moved),
            audit: audit_rows(s.audit, s.atlas, s.confidence),
            audit_notes: s
                .audit
                .notes
                .iter()
                .chain(&s.audit.warnings)
                .cloned()
                .collect(),
            hands,
            can_tell: CAN_TELL.to_string(),
            caveats: CAVEATS.iter().map(|c| c.to_string()).collect(),
        },
        figures: files,
    }
}

/// Both rigs' measures per joint, with the verdict.
fn joint_rows(
    ha: &HandDeformation,
    hb: &HandDeformation,
    joints: &[JointVerdict],
) -> Vec<DeformRowView> {
    joints
        .iter()
        .filter_map(|v| {
            let (ja, jb) = (find(ha, v)?, find(hb, v)?);
            Some(DeformRowView {
                finger: v.finger.name().to_string(),
                joint: v.joint.name().to_string(),
                angle: trimmed(ja.angle, 1),
                loss_a: loss(ja.volume_loss),
                loss_b: loss(jb.volume_loss),
                x_a: ja.self_intersections.to_string(),
                x_b: jb.self_intersections.to_string(),
                p95_a: strain(ja.strain_p95),
                p95_b: strain(jb.strain_p95),
                fold_a: mm(ja.crease_offset),
                fold_b: mm(jb.crease_offset),
                better: better(v.overall).to_string(),
            })
        })
        .collect()
}

/// "B deforms better at 4 joints, A at 1, ...".
fn verdict_summary(joints: &[JointVerdict]) -> String {
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
fn reasons(joints: &[JointVerdict]) -> Vec<String> {
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

/// What the fix moves, in one sentence.
fn moved_words(moved: &[(String, f64)]) -> String {
    if moved.is_empty() {
        return "The fix moves no joint: A and B are the same rig.".into();
    }
    let parts: Vec<String> = moved
        .iter()
        .map(|(node, d)| format!("{node} by {} mm", num(d * MM, 2)))
        .collect();
    format!(
        "The fix moves {} {}, taking the skin weights with {}: {}.",
        moved.len(),
        if moved.len() == 1 { "joint" } else { "joints" },
        if moved.len() == 1 { "it" } else { "them" },
        parts.join(", ")
    )
}

/// The audit of the rig, one row per finger, its metacarpal included.
fn audit_rows(audit: &AuditedRig, atlas: bool, confidence: f64) -> Vec<DeformAuditRow> {
    use super::audit::{finger_summary, value_of};
    use crate::analysis::Quantity;
    let c = crate::format::level(confidence);
    audit
        .fingers
        .iter()
        .map(|f| {
            let rel: Vec<String> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
                .iter()
                .filter_map(|&q| value_of(&f.audit, q).map(|v| num(v, 4)))
                .collect();
            let metacarpal = match (&f.metacarpal_check, &f.chain.metacarpal) {
                (Some(m), _) => metacarpal_view(m, &c),
                (None, None) => unjudged("no metacarpal in the rig"),
                (None, Some(_)) if !atlas => unjudged("not judged: no atlas was given"),
                (None, Some(_)) => unjudged("not judged (see the notes)"),
            };
            DeformAuditRow {
                finger: f.chain.finger.name().to_string(),
                relative: if rel.is_empty() {
                    "n/a (no tip)".into()
                } else {
                    rel.join(" / ")
                },
                standing: finger_summary(&f.audit),
                metacarpal,
            }
        })
        .collect()
}

fn unjudged(why: &str) -> MetacarpalView {
    MetacarpalView {
        node: why.to_string(),
        lengths: String::new(),
        values: Vec::new(),
        mcp: String::new(),
    }
}

/// What a [`MetacarpalCheck`] holds, as strings (lengths in mm).
fn metacarpal_view(m: &MetacarpalCheck, c: &str) -> MetacarpalView {
    use super::audit::{joint_standing, metacarpal_values};
    let values = metacarpal_values(m, c);
    let mm2 = |x: f64| num(x * MM, 2);
    MetacarpalView {
        node: m.node.clone(),
        lengths: match m.mc {
            Some(mc) => format!("mc {} mm, J {} mm", mm2(mc), mm2(m.length)),
            None => format!("wrist to MCP {} mm, J {} mm", mm2(m.to_mcp), mm2(m.length)),
        },
        values,
        mcp: format!(
            "{}; the atlas puts it {} mm from the {} ({c} prediction {})",
            joint_standing(m.standing, MM),
            mm2(m.expected),
            match m.base {
                RayBase::Cmc => "CMC",
                RayBase::Wrist => "wrist",
            },
            m.pi.map_or("n/a".into(), |p| format!(
                "[{}, {}] mm",
                mm2(p.low),
                mm2(p.high)
            ))
        ),
    }
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

#[cfg(test)]
mod figure_tests {
    use super::*;
    use crate::rig::deform::file::{DeformRequest, deform_file};
    use std::path::Path;

    /// The Mannequiny (`../shared/rigs/gdquest-mannequiny`, CC0): a whole
    /// T-posed body; skipped, saying so, when it is not there.
    fn mannequiny() -> Option<FileDeformation> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/rigs/gdquest-mannequiny/mannequiny.glb");
        if !path.is_file() {
            eprintln!("skipped: {} is not there", path.display());
            return None;
        }
        let file = crate::rig::read::open(&path).unwrap();
        let pose = Pose::fist();
        let req = DeformRequest {
            map: None,
            side: None,
            pose: &pose,
            method: Skinning::Lbs,
        };
        Some(deform_file(&file, path.parent().unwrap(), &req).unwrap())
    }

    #[test]
    fn a_whole_body_figure_frames_the_hand() {
        let Some(rig) = mannequiny() else { return };
        let file = crate::rig::read::open(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../shared/rigs/gdquest-mannequiny/mannequiny.glb"),
        )
        .unwrap();
        let names = file.node_names();
        for h in &rig.hands {
            // The hand's vertices by the file's own names, not by the code's
            // chains: those whose largest weight is on hand.l (or .r) or one of
            // its finger bones (thumb_, index_, middle_, ring_ 01-03).
            let suffix = match h.chains.side {
                Side::Left => ".l",
                Side::Right => ".r",
            };
            let is_hand = |node: usize| {
                let n = &names[node];
                n.ends_with(suffix)
                    && ["hand", "thumb_", "index_", "middle_", "ring_"]
                        .iter()
                        .any(|p| n.starts_with(p))
            };
            let hand: Vec<usize> = (0..h.mesh.positions.len())
                .filter(|&v| {
                    h.mesh
                        .dominant(v)
                        .is_some_and(|s| is_hand(h.mesh.joints[usize::from(s)]))
                })
                .collect();
            assert!(hand.len() > 50, "{} hand vertices", hand.len());
            assert!(
                hand.len() * 5 < h.mesh.positions.len(),
                "the body is more than its hand"
            );
            let (_, render) = figure(h, Some(h), &["A", "B"], None).unwrap();
            let fig = {
                // The same layout as the figure's, to project with.
                let focus = h.hand_vertices();
                let m = MeshView {
                    positions: &h.deformation.posed,
                    triangles: &h.mesh.triangles,
                    strain: &h.deformation.vertex_strain,
                    focus: &focus,
                };
                let views = [View::side(&h.posed.frame), View::above(&h.posed.frame)];
                Figure::layout(&[m, m], &views, PANEL.0, PANEL.1)
            };
            assert_eq!((render.width, render.height), (fig.width, fig.height));
            for row in 0..2 {
                let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
                for &v in &hand {
                    let (x, y) = fig.project(row, 0, h.deformation.posed[v]).unwrap();
                    lo = (lo.0.min(x), lo.1.min(y));
                    hi = (hi.0.max(x), hi.1.max(y));
                }
                let (px, py, pw, ph) = fig.panel_rect(row, 0);
                let share_x = (hi.0 - lo.0) / f64::from(pw);
                let share_y = (hi.1 - lo.1) / f64::from(ph);
                // The whole body put each hand at about 15 px of a 420 x 300 panel
                // (a share under 0.05); framed on the hand, its larger share is the
                // panel less its margins (0.88), and the hand lies inside the panel.
                assert!(
                    share_x.max(share_y) > 0.8,
                    "{} row {row}: the hand covers {share_x:.2} x {share_y:.2} of its panel",
                    h.chains.side.name()
                );
                assert!(
                    lo.0 >= f64::from(px) - 1.0
                        && hi.0 <= f64::from(px + pw) + 1.0
                        && lo.1 >= f64::from(py) - 1.0
                        && hi.1 <= f64::from(py + ph) + 1.0,
                    "row {row}: the hand leaves its panel: {lo:?} {hi:?}"
                );
            }
        }
    }
}
