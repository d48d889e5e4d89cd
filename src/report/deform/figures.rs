//! The figures of a deformation: both rigs posed, from the side and from above, coloured
//! by strain, as PNG; where the tips fall, for the JSON.

use crate::error::Error;
use crate::report::render3d::{Figure, MeshView, View};
use crate::report::writer::OutputFile;
use crate::rig::deform::file::{FileDeformation, HandDeformation};
use crate::rig::naming::Side;
use schemars::JsonSchema;
use serde::Serialize;
use std::path::Path;

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
pub(super) const PANEL: (u32, u32) = (420, 300);

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
/// ([`crate::report::render3d::FONT_FILE`]); without it the figures are drawn
/// without their labels and scale numbers, and a note says so and what to do.
pub(crate) fn label_font() -> Option<Vec<u8>> {
    let path = crate::report::render3d::FONT_FILE;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::deform::file::{DeformRequest, deform_file};
    use crate::rig::deform::{Pose, Skinning};
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
