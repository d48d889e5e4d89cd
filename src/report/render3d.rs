//! Flat-shaded pictures of posed meshes, coloured by strain, as PNG.
//!
//! Orthographic views in the hand's own frame ([`View::side`] looks along the
//! flexion axes from the little finger's side, so curled fingers show their
//! profile; [`View::above`] looks at the back of the hand). A left hand's
//! views are the mirror images of a right hand's. A [`Figure`] is a grid: one row per view, one
//! column per mesh (rig A, rig B), every panel of a row at one scale so the
//! rigs compare at sight, each centred on its own mesh; a strain colour ramp
//! runs along the bottom.
//!
//! Drawing: the painter's algorithm (triangles sorted by the depth of their
//! centroid, farthest first, with `total_cmp` and the triangle index breaking
//! ties), each filled with one colour: the strain ramp ([`strain_colour`]) of
//! the mean strain of its three vertices, times Lambert shading
//! 0.35 + 0.65 |n . l| with n the triangle's normal and l a light from the
//! viewer's upper left (two-sided: a mesh's winding is not trusted). tiny-skia
//! fills without anti-aliasing (anti-aliased neighbours leave hairline seams)
//! at twice the size, and the image is averaged down 2 x 2, which smooths the
//! edges. Everything is integer or f32 arithmetic in a fixed order, and the
//! PNG encoder has fixed settings: the same input gives the same bytes.

use crate::rig::deform::PalmFrame;
use glam::{DVec2, DVec3};
use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Rect, Transform};

/// An orthographic view direction: screen right and up in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub name: &'static str,
    pub right: DVec3,
    pub up: DVec3,
}

impl View {
    /// From the little finger's side, looking along the flexion axes (a curled
    /// finger shows its profile), the back of the hand up: a right hand's
    /// fingers point right, a left hand's left (the mirror image).
    pub fn side(frame: &PalmFrame) -> View {
        let up = -frame.normal;
        let toward = -frame.radial;
        View {
            name: "side",
            right: up.cross(toward),
            up,
        }
    }

    /// Looking down at the back of the hand, fingers up.
    pub fn above(frame: &PalmFrame) -> View {
        let up = frame.distal;
        let toward = -frame.normal;
        View {
            name: "above",
            right: up.cross(toward),
            up,
        }
    }

    /// The direction from the scene to the viewer (right x up).
    pub fn toward(&self) -> DVec3 {
        self.right.cross(self.up)
    }
}

/// Where a view puts points on the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub view: View,
    /// Pixels per world unit.
    pub scale: f64,
    /// The world point (in view coordinates right, up) drawn at `at`.
    pub centre: DVec2,
    /// Its pixel position in the image.
    pub at: DVec2,
}

impl Camera {
    /// Projects `p`: (x pixels, y pixels downwards, depth; larger is farther).
    pub fn project(&self, p: DVec3) -> (f64, f64, f64) {
        let v = DVec2::new(p.dot(self.view.right), p.dot(self.view.up)) - self.centre;
        (
            self.at.x + v.x * self.scale,
            self.at.y - v.y * self.scale,
            -p.dot(self.view.toward()),
        )
    }
}

/// A posed mesh to draw, with one strain value per vertex.
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    pub positions: &'a [DVec3],
    pub triangles: &'a [[u32; 3]],
    pub strain: &'a [f64],
    /// The vertices a panel is framed on (a hand's, in a whole body's mesh),
    /// one flag per vertex; empty, or none set: every vertex. The rest of
    /// the mesh is drawn too, cut at the panel's edges.
    pub focus: &'a [bool],
}

impl MeshView<'_> {
    /// The vertices to frame: the focus, or every vertex without one.
    fn framed(&self) -> impl Iterator<Item = &DVec3> + '_ {
        let all = !self.focus.iter().any(|&f| f);
        self.positions
            .iter()
            .enumerate()
            .filter(move |(i, _)| all || self.focus.get(*i).copied().unwrap_or(false))
            .map(|(_, p)| p)
    }
}

/// Strain at and beyond which the ramp is fully red: |ln ratio| 0.25, an edge
/// 28% longer or 22% shorter than at rest.
pub const RAMP_MAX: f64 = 0.25;

/// The strain colour ramp: 0 a cool grey (190, 200, 215), 0.1 amber
/// (250, 200, 60), [`RAMP_MAX`] and above red (210, 35, 35), linear between
/// the stops; a non-finite strain is drawn red.
pub fn strain_colour(s: f64) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 3] = [
        (0.0, [190.0, 200.0, 215.0]),
        (0.1, [250.0, 200.0, 60.0]),
        (RAMP_MAX, [210.0, 35.0, 35.0]),
    ];
    let s = if s.is_finite() { s.max(0.0) } else { RAMP_MAX };
    let mut c = STOPS[2].1;
    for w in STOPS.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if s <= b {
            let t = (s - a) / (b - a);
            c = [0, 1, 2].map(|k| ca[k] + (cb[k] - ca[k]) * t);
            break;
        }
    }
    c.map(|x| x.round().clamp(0.0, 255.0) as u8)
}

/// Supersampling factor: drawn at this many times the size, then averaged down.
const SS: u32 = 2;
/// Height of the band above the panels that names each column's rig.
pub const LABELS: u32 = 22;
/// Height of the colour scale at the bottom: its caption, the ramp, the ticks
/// and their numbers.
pub const LEGEND: u32 = 52;
/// Margin around the framed vertices in their panel, as a share of the
/// panel's width and height on each side.
const MARGIN: f64 = 0.06;
/// The strain at the right end of the drawn ramp (the ramp is red from
/// [`RAMP_MAX`] on).
const SCALE_END: f64 = 0.3;
/// The strains the scale marks with a tick and its number: the ends, the
/// middle (0.15), the amber stop (0.1) and the red one ([`RAMP_MAX`]).
pub const SCALE_TICKS: [f64; 7] = [0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3];
/// What the colour measures, in the caption above the ramp: the first of
/// these that fits the figure's width (the shorter for one column).
pub const SCALE_CAPTION: [&str; 3] = [
    "colour: edge strain |ln(posed / rest edge length)|, no unit (0.1: about 10% longer or shorter)",
    "colour: edge strain |ln(posed / rest edge length)|, no unit",
    "edge strain |ln(posed/rest length)|",
];

/// The font of the labels and the scale's numbers, from the working directory:
/// Liberation Sans Regular (SIL Open Font License 1.1), vendored with its
/// licence and source in `data/fonts/liberation-sans/`. Read at run time, as
/// all data from elsewhere is, never compiled in.
pub const FONT_FILE: &str = "data/fonts/liberation-sans/LiberationSans-Regular.ttf";

/// A grid of panels: one row per view, one column per mesh, under a band
/// of column labels and above the colour scale.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub width: u32,
    pub height: u32,
    /// Pixels of one panel.
    pub panel: (u32, u32),
    /// `cameras[row][column]`.
    pub cameras: Vec<Vec<Camera>>,
}

impl Figure {
    /// Lays out `meshes` in `views`, each panel `panel_w` x `panel_h` pixels:
    /// one scale per row, the largest at which the framed vertices
    /// ([`MeshView::focus`]) of every mesh of the row fit within the margin.
    pub fn layout(meshes: &[MeshView<'_>], views: &[View], panel_w: u32, panel_h: u32) -> Figure {
        let cameras = views
            .iter()
            .enumerate()
            .map(|(row, view)| {
                let bounds: Vec<(DVec2, DVec2)> = meshes
                    .iter()
                    .map(|m| {
                        m.framed().fold(
                            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                            |(lo, hi), p| {
                                let v = DVec2::new(p.dot(view.right), p.dot(view.up));
                                (lo.min(v), hi.max(v))
                            },
                        )
                    })
                    .collect();
                let panel = DVec2::new(f64::from(panel_w), f64::from(panel_h));
                let room = panel * (1.0 - 2.0 * MARGIN);
                let scale = bounds
                    .iter()
                    .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
                    .map(|(lo, hi)| {
                        let size = (*hi - *lo).max(DVec2::splat(1e-12));
                        (room.x / size.x).min(room.y / size.y)
                    })
                    .fold(f64::INFINITY, f64::min);
                let scale = if scale.is_finite() { scale } else { 1.0 };
                bounds
                    .iter()
                    .enumerate()
                    .map(|(col, (lo, hi))| Camera {
                        view: *view,
                        scale,
                        centre: if lo.is_finite() && hi.is_finite() {
                            (*lo + *hi) / 2.0
                        } else {
                            DVec2::ZERO
                        },
                        at: DVec2::new(
                            (col as f64 + 0.5) * panel.x,
                            f64::from(LABELS) + (row as f64 + 0.5) * panel.y,
                        ),
                    })
                    .collect()
            })
            .collect();
        Figure {
            width: panel_w * meshes.len().max(1) as u32,
            height: LABELS + panel_h * views.len().max(1) as u32 + LEGEND,
            panel: (panel_w, panel_h),
            cameras,
        }
    }

    /// The pixel where `p` of the mesh in `column` is drawn in view `row`.
    pub fn project(&self, row: usize, column: usize, p: DVec3) -> Option<(f64, f64)> {
        let c = self.cameras.get(row)?.get(column)?;
        let (x, y, _) = c.project(p);
        Some((x, y))
    }

    /// The rectangle of panel (`row`, `column`): x, y, width, height in pixels.
    pub fn panel_rect(&self, row: usize, column: usize) -> (u32, u32, u32, u32) {
        let (w, h) = self.panel;
        (column as u32 * w, LABELS + row as u32 * h, w, h)
    }

    /// Draws `meshes` (the ones given to [`Figure::layout`]) as PNG bytes,
    /// `labels[k]` over column k, each view's name in its panel's corner,
    /// and the colour scale with its numbers at the bottom.
    /// `font`: the bytes of a TrueType font for the labels and the scale's
    /// numbers (the caller reads `data/fonts/`, see [`FONT_FILE`]); without
    /// one, or with bytes that are no font, the figure is drawn without text.
    pub fn render(
        &self,
        meshes: &[MeshView<'_>],
        labels: &[&str],
        font: Option<&[u8]>,
    ) -> Result<Vec<u8>, String> {
        let mut big = Pixmap::new(self.width * SS, self.height * SS).ok_or_else(|| {
            format!(
                "an image of {} x {} pixels cannot be made",
                self.width, self.height
            )
        })?;
        big.fill(tiny_skia::Color::WHITE);
        let mut paint = Paint {
            anti_alias: false,
            ..Paint::default()
        };
        // Each panel drawn on its own pixmap, so a mesh framed on its hand is
        // cut at the panel's edges.
        for (row, cams) in self.cameras.iter().enumerate() {
            for (col, (camera, mesh)) in cams.iter().zip(meshes).enumerate() {
                let (x, y, w, h) = self.panel_rect(row, col);
                let mut panel =
                    Pixmap::new(w * SS, h * SS).ok_or("an empty panel cannot be made")?;
                panel.fill(tiny_skia::Color::WHITE);
                let to_panel = Transform::from_scale(SS as f32, SS as f32)
                    .pre_translate(-(x as f32), -(y as f32));
                draw_mesh(&mut panel, &mut paint, camera, mesh, to_panel);
                big.draw_pixmap(
                    (x * SS) as i32,
                    (y * SS) as i32,
                    panel.as_ref(),
                    &tiny_skia::PixmapPaint::default(),
                    Transform::identity(),
                    None,
                );
            }
        }
        let to_big = Transform::from_scale(SS as f32, SS as f32);
        // Panel borders.
        let (panel_w, panel_h) = self.panel;
        let panels_h = panel_h * self.cameras.len() as u32;
        paint.set_color_rgba8(200, 200, 200, 255);
        for k in 1..meshes.len() as u32 {
            if let Some(r) =
                Rect::from_xywh((k * panel_w) as f32, 0.0, 1.0, (LABELS + panels_h) as f32)
            {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        for k in 0..=self.cameras.len() as u32 {
            if let Some(r) =
                Rect::from_xywh(0.0, (LABELS + k * panel_h) as f32, self.width as f32, 1.0)
            {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        // The ramp, from 0 to SCALE_END, between the scale's side margins.
        let (x0, x1) = self.scale_span();
        let ramp_y = (LABELS + panels_h + 20) as f32;
        for x in x0..x1 {
            let [r, g, b] = strain_colour(self.strain_at(f64::from(x) + 0.5));
            paint.set_color_rgba8(r, g, b, 255);
            if let Some(rect) = Rect::from_xywh(x as f32, ramp_y, 1.0, 10.0) {
                big.fill_rect(rect, &paint, to_big, None);
            }
        }
        paint.set_color_rgba8(60, 60, 60, 255);
        for t in SCALE_TICKS {
            let x = self.scale_x(t).round() as f32;
            if let Some(rect) = Rect::from_xywh(x - 0.5, ramp_y + 10.0, 1.0, 4.0) {
                big.fill_rect(rect, &paint, to_big, None);
            }
        }
        let mut img = downsample(&big, self.width, self.height)?;
        if let Some(font) = font.and_then(|f| ab_glyph::FontRef::try_from_slice(f).ok()) {
            let dark = [40, 40, 40];
            let grey = [110, 110, 110];
            for (col, label) in labels.iter().enumerate().take(meshes.len()) {
                let centre = (col as f64 + 0.5) * f64::from(panel_w);
                let fit = f64::from(panel_w) - 8.0;
                draw_text(&mut img, &font, label, centre, 16.0, 14.0, fit, dark);
            }
            for (row, cams) in self.cameras.iter().enumerate() {
                let name = match cams.first().map(|c| c.view.name) {
                    Some("side") => "from the side",
                    Some("above") => "from above (the back of the hand)",
                    Some(other) => other,
                    None => continue,
                };
                let y = f64::from(LABELS + row as u32 * panel_h) + 14.0;
                for col in 0..meshes.len() {
                    let left = f64::from(col as u32 * panel_w) + 6.0;
                    let w = text_width(&font, name, 11.0);
                    draw_text(&mut img, &font, name, left + w / 2.0, y, 11.0, 1e9, grey);
                }
            }
            let caption_y = f64::from(LABELS + panels_h) + 15.0;
            let fit = f64::from(self.width) - 8.0;
            let caption = SCALE_CAPTION
                .iter()
                .find(|c| text_width(&font, c, 11.5) <= fit)
                .unwrap_or(&SCALE_CAPTION[2]);
            draw_text(
                &mut img,
                &font,
                caption,
                f64::from(self.width) / 2.0,
                caption_y,
                11.5,
                fit,
                dark,
            );
            for t in SCALE_TICKS {
                let words = if t == RAMP_MAX {
                    "0.25 red".to_string()
                } else if t == SCALE_END {
                    "0.3+".to_string()
                } else {
                    crate::format::trimmed(t, 2)
                };
                let y = f64::from(ramp_y) + 26.0;
                draw_text(&mut img, &font, &words, self.scale_x(t), y, 11.0, 1e9, dark);
            }
        }
        img.encode_png()
            .map_err(|e| format!("the PNG could not be encoded ({e})"))
    }

    /// The scale's ramp runs from x0 to x1 pixels (left and right margins of
    /// a twelfth of the width, at least 30 px).
    fn scale_span(&self) -> (u32, u32) {
        let m = (self.width / 12).max(30).min(self.width / 3);
        (m, self.width.saturating_sub(m).max(m + 1))
    }

    /// The pixel x of strain `s` on the ramp.
    pub fn scale_x(&self, s: f64) -> f64 {
        let (x0, x1) = self.scale_span();
        f64::from(x0) + s / SCALE_END * f64::from(x1 - x0)
    }

    /// The strain drawn at pixel x of the ramp.
    fn strain_at(&self, x: f64) -> f64 {
        let (x0, x1) = self.scale_span();
        (x - f64::from(x0)) / f64::from(x1 - x0) * SCALE_END
    }

    /// The pixel row through the middle of the ramp.
    pub fn scale_y(&self) -> f64 {
        f64::from(LABELS + self.panel.1 * self.cameras.len() as u32 + 20) + 5.0
    }
}

/// The width of `text` at `px` pixels.
fn text_width(font: &ab_glyph::FontRef<'_>, text: &str, px: f32) -> f64 {
    use ab_glyph::{Font, ScaleFont};
    let f = font.as_scaled(px);
    let mut w = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    f64::from(w)
}

/// Writes `text` centred on `cx` with its baseline at `y`, at `px` pixels
/// (smaller when it would be wider than `fit`), blending the glyphs'
/// coverage into the opaque image.
#[allow(clippy::too_many_arguments)]
fn draw_text(
    img: &mut Pixmap,
    font: &ab_glyph::FontRef<'_>,
    text: &str,
    cx: f64,
    y: f64,
    px: f32,
    fit: f64,
    rgb: [u8; 3],
) {
    use ab_glyph::{Font, ScaleFont, point};
    let wide = text_width(font, text, px);
    let px = if wide > fit && wide > 0.0 {
        (f64::from(px) * fit / wide).max(6.0) as f32
    } else {
        px
    };
    let f = font.as_scaled(px);
    let mut x = (cx - text_width(font, text, px) / 2.0) as f32;
    let (w, h) = (img.width() as i32, img.height() as i32);
    let data = img.data_mut();
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            x += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(px, point(x, y as f32));
        x += f.h_advance(id);
        prev = Some(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, cov| {
            let (px_x, px_y) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
            if px_x < 0 || px_y < 0 || px_x >= w || px_y >= h {
                return;
            }
            let at = (px_y as usize * w as usize + px_x as usize) * 4;
            let a = cov.clamp(0.0, 1.0);
            for k in 0..3 {
                let old = f32::from(data[at + k]);
                data[at + k] = (old + (f32::from(rgb[k]) - old) * a)
                    .round()
                    .clamp(0.0, 255.0) as u8;
            }
        });
    }
}

/// Fills the triangles of `mesh` far to near (see the module doc).
fn draw_mesh(
    big: &mut Pixmap,
    paint: &mut Paint<'_>,
    cam: &Camera,
    mesh: &MeshView<'_>,
    to_big: Transform,
) {
    let n = mesh.positions.len();
    let light = (cam.view.toward() + cam.view.up * 0.6 - cam.view.right * 0.4).normalize();
    let mut order: Vec<(f64, usize)> = mesh
        .triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| t.iter().all(|&v| (v as usize) < n))
        .map(|(i, t)| {
            let c = t.iter().map(|&v| mesh.positions[v as usize]).sum::<DVec3>() / 3.0;
            (cam.project(c).2, i)
        })
        .filter(|(d, _)| d.is_finite())
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for (_, i) in order {
        let t = mesh.triangles[i];
        let p = t.map(|v| mesh.positions[v as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let shade = 0.35 + 0.65 * normal.dot(light).abs();
        let strain = t
            .iter()
            .map(|&v| mesh.strain.get(v as usize).copied().unwrap_or(0.0))
            .sum::<f64>()
            / 3.0;
        let [r, g, b] =
            strain_colour(strain).map(|c| (f64::from(c) * shade).round().clamp(0.0, 255.0) as u8);
        paint.set_color_rgba8(r, g, b, 255);
        let mut pb = PathBuilder::new();
        for (k, q) in p.iter().enumerate() {
            let (x, y, _) = cam.project(*q);
            if k == 0 {
                pb.move_to(x as f32, y as f32);
            } else {
                pb.line_to(x as f32, y as f32);
            }
        }
        pb.close();
        if let Some(path) = pb.finish() {
            big.fill_path(&path, paint, FillRule::Winding, to_big, None);
        }
    }
}

/// Averages `SS` x `SS` blocks of an opaque pixmap into one pixel each.
fn downsample(big: &Pixmap, width: u32, height: u32) -> Result<Pixmap, String> {
    let mut out = Pixmap::new(width, height).ok_or("an empty image cannot be made")?;
    let src = big.data();
    let bw = (width * SS) as usize;
    let dst = out.data_mut();
    for y in 0..height as usize {
        for x in 0..width as usize {
            for ch in 0..4 {
                let mut sum = 0u32;
                for dy in 0..SS as usize {
                    for dx in 0..SS as usize {
                        sum += u32::from(
                            src[((y * SS as usize + dy) * bw + x * SS as usize + dx) * 4 + ch],
                        );
                    }
                }
                dst[(y * width as usize + x) * 4 + ch] = ((sum + SS * SS / 2) / (SS * SS)) as u8;
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    /// The vendored label font, read as `phalanx` reads it (from the checkout).
    fn font() -> Vec<u8> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(super::FONT_FILE);
        std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    use super::*;
    use crate::dataset::Finger;
    use crate::rig::deform::synthetic::{HandSpec, tube_hand};
    use crate::rig::naming::Side;

    fn pixel(png: &Pixmap, x: f64, y: f64) -> [u8; 3] {
        let p = png.pixel(x.round() as u32, y.round() as u32).unwrap();
        [p.red(), p.green(), p.blue()]
    }

    #[test]
    fn a_straight_finger_is_drawn_where_it_projects() {
        let rig = tube_hand(&HandSpec {
            fingers: vec![Finger::Middle],
            ..HandSpec::default()
        });
        let frame = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        let strain = vec![0.0; rig.mesh.positions.len()];
        let mesh = MeshView {
            positions: &rig.mesh.positions,
            triangles: &rig.mesh.triangles,
            strain: &strain,
            focus: &[],
        };
        // The same finger twice, the second one strained red everywhere.
        let red = vec![1.0; rig.mesh.positions.len()];
        let hot = MeshView {
            strain: &red,
            ..mesh
        };
        let views = [View::side(&frame), View::above(&frame)];
        let fig = Figure::layout(&[mesh, hot], &views, 240, 200);
        let bytes = fig
            .render(&[mesh, hot], &["A", "B"], Some(&font()))
            .unwrap();
        assert_eq!(
            bytes,
            fig.render(&[mesh, hot], &["A", "B"], Some(&font()))
                .unwrap(),
            "not deterministic"
        );
        let img = Pixmap::decode_png(&bytes).unwrap();
        assert_eq!((img.width(), img.height()), (480, LABELS + 400 + LEGEND));
        // The middle finger runs along +y from (-5, 31, 0) mm to the tip at (-5, 157, 0) mm.
        let tip = rig
            .skeleton
            .position(*rig.chains.fingers[0].tip.as_ref().unwrap());
        let dir = DVec3::Y;
        for (row, v) in views.iter().enumerate() {
            for col in 0..2 {
                let (x, y) = fig.project(row, col, tip - dir * 0.003).unwrap();
                let inside = pixel(&img, x, y);
                assert_ne!(
                    inside,
                    [255, 255, 255],
                    "row {row} col {col}: no finger at ({x}, {y})"
                );
                let (x, y) = fig.project(row, col, tip + dir * 0.004).unwrap();
                assert_eq!(
                    pixel(&img, x, y),
                    [255, 255, 255],
                    "row {row} col {col}: drawn past the tip"
                );
                // Beside the finger, beyond its radius: background.
                let across = if v.right.dot(dir).abs() < 0.5 {
                    v.right
                } else {
                    v.up
                };
                let (x, y) = fig
                    .project(row, col, tip - dir * 0.02 + across * 0.012)
                    .unwrap();
                assert_eq!(
                    pixel(&img, x, y),
                    [255, 255, 255],
                    "row {row} col {col}: drawn beside the finger"
                );
                // Its colour is the ramp's: grey-blue unstrained, red strained.
                let c = pixel(
                    &img,
                    fig.project(row, col, tip - dir * 0.03).unwrap().0,
                    fig.project(row, col, tip - dir * 0.03).unwrap().1,
                );
                if col == 0 {
                    assert!(c[2] > c[0], "{c:?}");
                } else {
                    assert!(c[0] > 2 * c[2], "{c:?}");
                }
            }
        }
        // Not a constant image: the shading varies across the tube.
        let mut colours: Vec<[u8; 4]> = img
            .pixels()
            .iter()
            .map(|p| [p.red(), p.green(), p.blue(), p.alpha()])
            .collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 20, "{} colours", colours.len());
    }

    /// A finger framed inside a big body: its panel is framed on the finger,
    /// and the labels and the scale's numbers are drawn where they belong.
    #[test]
    fn a_focus_frames_its_vertices_and_the_figure_carries_its_words() {
        let rig = tube_hand(&HandSpec {
            fingers: vec![Finger::Middle],
            ..HandSpec::default()
        });
        let frame = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        // The finger, and a "body": one triangle 2 m across, 1 m from it.
        let mut positions = rig.mesh.positions.clone();
        let n = positions.len() as u32;
        positions.extend([
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(3.0, -1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
        ]);
        let mut triangles = rig.mesh.triangles.clone();
        triangles.push([n, n + 1, n + 2]);
        let strain = vec![0.0; positions.len()];
        let mut focus = vec![true; rig.mesh.positions.len()];
        focus.extend([false; 3]);
        let framed = MeshView {
            positions: &positions,
            triangles: &triangles,
            strain: &strain,
            focus: &focus,
        };
        let whole = MeshView {
            focus: &[],
            ..framed
        };
        let views = [View::above(&frame)];
        // The finger's rest extent from above, by hand: x from -5 - r to -5 + r mm
        // (r = its radius), y from its root to the tip at 157 mm.
        let xs = |m: &MeshView<'_>, fig: &Figure| {
            let mut lo = f64::MAX;
            let mut hi = f64::MIN;
            for p in &m.positions[..n as usize] {
                let (_, y) = fig.project(0, 0, *p).unwrap();
                lo = lo.min(y);
                hi = hi.max(y);
            }
            (hi - lo) / f64::from(fig.panel.1)
        };
        let fig = Figure::layout(&[framed], &views, 300, 300);
        let share = xs(&framed, &fig);
        assert!((0.85..=0.8801).contains(&share), "framed: {share}");
        let fig_whole = Figure::layout(&[whole], &views, 300, 300);
        let share = xs(&whole, &fig_whole);
        assert!(share < 0.1, "whole: {share}");
        // The words: dark pixels in the label band over the column, on the
        // ramp's row the ramp's colours, and numbers under the ticks.
        let img = Pixmap::decode_png(&fig.render(&[framed], &["the rig"], Some(&font())).unwrap())
            .unwrap();
        let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| {
                    let p = img.pixel(x, y).unwrap();
                    u32::from(p.red()) + u32::from(p.green()) + u32::from(p.blue()) < 300
                })
                .count()
        };
        assert!(dark(120, 180, 0, LABELS) > 20, "no label over the column");
        assert_eq!(dark(0, 100, 0, LABELS), 0, "the label is not centred");
        let ramp_y = fig.scale_y();
        for t in [0.0, 0.1, RAMP_MAX] {
            let x = fig.scale_x(t + 0.004);
            let c = pixel(&img, x, ramp_y);
            let want = strain_colour(t + 0.004);
            assert!(
                c.iter().zip(want).all(|(a, b)| a.abs_diff(b) <= 6),
                "ramp at {t}: {c:?} against {want:?}"
            );
            let x = fig.scale_x(t).round() as u32;
            let below = ramp_y as u32 + 12;
            assert!(
                dark(x - 8, x + 8, below, fig.height) > 5,
                "no number under {t}"
            );
        }
        assert!(
            dark(0, fig.width, fig.height - LEGEND, ramp_y as u32 - 6) > 100,
            "no caption"
        );
    }

    #[test]
    fn the_ramp_runs_grey_amber_red() {
        assert_eq!(strain_colour(0.0), [190, 200, 215]);
        assert_eq!(strain_colour(0.1), [250, 200, 60]);
        assert_eq!(strain_colour(RAMP_MAX), [210, 35, 35]);
        assert_eq!(strain_colour(9.0), [210, 35, 35]);
        assert_eq!(strain_colour(f64::NAN), [210, 35, 35]);
        assert_eq!(strain_colour(0.05), [220, 200, 138]);
    }

    #[test]
    fn views_are_right_handed_and_mirror_with_the_hand() {
        let r = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        for v in [View::side(&r), View::above(&r)] {
            assert!((v.right.cross(v.up) - v.toward()).length() < 1e-15);
            assert!(v.right.dot(v.up).abs() < 1e-15);
        }
        // From above, a right hand seen from its back has its thumb (-x here) on
        // the left; from the side its fingers point right, its back up.
        let above = View::above(&r);
        assert!(r.radial.dot(above.right) < 0.0);
        let side = View::side(&r);
        assert!(side.right.dot(r.distal) > 0.99 && side.up.dot(r.normal) < -0.99);
        // A left hand (the mirror image in x) is seen in the mirror image: the
        // projected x of a mirrored point is the negated projected x (side) or
        // the same (above, whose right is the mirror axis).
        let l = PalmFrame::new(Side::Left, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        let p = DVec3::new(0.3, 0.5, -0.7);
        let m = p * DVec3::new(-1.0, 1.0, 1.0);
        for (vr, vl) in [
            (View::side(&r), View::side(&l)),
            (View::above(&r), View::above(&l)),
        ] {
            assert!((p.dot(vr.up) - m.dot(vl.up)).abs() < 1e-15);
            assert!((p.dot(vr.right) + m.dot(vl.right)).abs() < 1e-15);
        }
    }
}
