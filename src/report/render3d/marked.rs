//! A skin seen through with joints marked over it: bones as lines, made joints as dots,
//! the artist's as rings, labels placed clear of each other, and a key.

use super::camera::*;
use super::figure::*;
use super::raster::*;
use glam::DVec3;
use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Rect, Transform};

/// The colour of each finger's marks, thumb to little (Okabe and Ito's
/// palette, told apart with any colour vision): vermillion, blue, bluish
/// green, reddish purple, orange.
pub const FINGER_COLOURS: [[u8; 3]; 5] = [
    [213, 94, 0],
    [0, 114, 178],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
];

/// One finger's joints marked on a skin: its points root first, the words
/// written beside each in the labelled view (`""`: none), its colour, and
/// whether they are made joints (filled dots on solid bones) or the
/// artist's (rings on thin bones).
#[derive(Debug, Clone, PartialEq)]
pub struct MarkedChain {
    pub points: Vec<DVec3>,
    pub labels: Vec<String>,
    pub colour: [u8; 3],
    pub made: bool,
}

/// Height of the key under a [`Marked`] figure: two lines.
pub const KEY: u32 = 50;

/// Radius in pixels of a made joint's dot.
pub(super) const DOT: f64 = 4.0;

/// Radius in pixels of an artist's joint's ring.
pub(super) const RING: f64 = 5.5;

/// Size in pixels of a joint's label.
pub(super) const LABEL_PX: f32 = 11.0;

/// How far a skin is faded towards white, so the marks over it read as
/// seen through it.
pub(super) const FADE: f32 = 0.55;

/// A skin at rest seen through, one panel per view side by side, with
/// joints marked over it (bones as lines, made joints as dots, the
/// artist's as rings), the made ones labelled in the first view, a title
/// over each panel and a key below. The skin is drawn as [`Figure`] draws a
/// mesh, then faded towards white; the marks are drawn over it whatever
/// their depth.
#[derive(Debug, Clone, PartialEq)]
pub struct Marked {
    pub width: u32,
    pub height: u32,
    /// Pixels of one panel.
    pub panel: (u32, u32),
    /// One camera per view, left to right.
    pub cameras: Vec<Camera>,
}

impl Marked {
    /// Lays out `views` of `mesh` side by side, each panel `panel_w` x
    /// `panel_h` pixels framed on the mesh as [`Figure::layout`] frames it.
    pub fn layout(mesh: &MeshView<'_>, views: &[View], panel_w: u32, panel_h: u32) -> Marked {
        let cameras: Vec<Camera> = views
            .iter()
            .enumerate()
            .filter_map(|(k, view)| {
                let one = Figure::layout(
                    std::slice::from_ref(mesh),
                    std::slice::from_ref(view),
                    panel_w,
                    panel_h,
                );
                let mut camera = *one.cameras.first()?.first()?;
                camera.at.x += k as f64 * f64::from(panel_w);
                Some(camera)
            })
            .collect();
        Marked {
            width: panel_w * cameras.len().max(1) as u32,
            height: LABELS + panel_h + KEY,
            panel: (panel_w, panel_h),
            cameras,
        }
    }

    /// The pixel where `p` is drawn in view `column`.
    pub fn project(&self, column: usize, p: DVec3) -> Option<(f64, f64)> {
        let (x, y, _) = self.cameras.get(column)?.project(p);
        Some((x, y))
    }

    /// Draws the figure as PNG bytes: `titles[k]` over panel k, `chains`
    /// marked (the artist's first, the made over them), the made ones'
    /// labels in the first panel, each where it covers no mark and no other
    /// label when such a place is near ([`place_label`]), and the key:
    /// `key` (each name in its colour) on its first line, `kinds` (the made
    /// mark's words, then the artist's) on its second. `font` as
    /// [`Figure::render`] takes it: without one, no words are drawn.
    pub fn render(
        &self,
        mesh: &MeshView<'_>,
        chains: &[MarkedChain],
        titles: &[&str],
        key: &[(String, [u8; 3])],
        kinds: [&str; 2],
        font: Option<&[u8]>,
    ) -> Result<Vec<u8>, String> {
        let (mut big, mut paint) = canvas(self.width, self.height)?;
        let (panel_w, panel_h) = self.panel;
        for (col, camera) in self.cameras.iter().enumerate() {
            let x = col as u32 * panel_w;
            let mut panel =
                Pixmap::new(panel_w * SS, panel_h * SS).ok_or("an empty panel cannot be made")?;
            panel.fill(tiny_skia::Color::WHITE);
            let to_panel = Transform::from_scale(SS as f32, SS as f32)
                .pre_translate(-(x as f32), -(LABELS as f32));
            let still = vec![0.0; mesh.positions.len()];
            let skin = MeshView {
                strain: &still,
                ..*mesh
            };
            draw_mesh(&mut panel, &mut paint, camera, &skin, to_panel);
            fade(&mut panel, FADE);
            big.draw_pixmap(
                (x * SS) as i32,
                (LABELS * SS) as i32,
                panel.as_ref(),
                &tiny_skia::PixmapPaint::default(),
                Transform::identity(),
                None,
            );
        }
        let to_big = Transform::from_scale(SS as f32, SS as f32);
        paint.set_color_rgba8(200, 200, 200, 255);
        for k in 1..self.cameras.len() as u32 {
            if let Some(r) =
                Rect::from_xywh((k * panel_w) as f32, 0.0, 1.0, (LABELS + panel_h) as f32)
            {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        for y in [LABELS, LABELS + panel_h] {
            if let Some(r) = Rect::from_xywh(0.0, y as f32, self.width as f32, 1.0) {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        paint.anti_alias = true;
        let order = chains
            .iter()
            .filter(|c| !c.made)
            .chain(chains.iter().filter(|c| c.made));
        for chain in order {
            for camera in &self.cameras {
                let points: Vec<(f32, f32)> = chain
                    .points
                    .iter()
                    .map(|p| camera.project(*p))
                    .filter(|(x, y, _)| x.is_finite() && y.is_finite())
                    .map(|(x, y, _)| (x as f32, y as f32))
                    .collect();
                draw_chain(&mut big, &mut paint, &points, chain, to_big);
            }
        }
        let mut img = downsample(&big, self.width, self.height)?;
        let Some(font) = font.and_then(|f| ab_glyph::FontRef::try_from_slice(f).ok()) else {
            return img
                .encode_png()
                .map_err(|e| format!("the PNG could not be encoded ({e})"));
        };
        let dark = [40, 40, 40];
        for (col, title) in titles.iter().enumerate().take(self.cameras.len()) {
            let centre = (col as f64 + 0.5) * f64::from(panel_w);
            let fit = f64::from(panel_w) - 8.0;
            draw_text(&mut img, &font, title, centre, 16.0, 13.0, fit, dark);
        }
        if let Some(camera) = self.cameras.first() {
            self.label(&mut img, &font, camera, chains);
        }
        self.key(&mut img, &font, key, kinds)?;
        img.encode_png()
            .map_err(|e| format!("the PNG could not be encoded ({e})"))
    }

    /// Writes the made chains' labels in the panel of `camera`, each placed
    /// by [`place_label`] among the marks and the labels placed before it.
    pub(super) fn label(
        &self,
        img: &mut Pixmap,
        font: &ab_glyph::FontRef<'_>,
        camera: &Camera,
        chains: &[MarkedChain],
    ) {
        let marks: Vec<(f64, f64, f64)> = chains
            .iter()
            .flat_map(|c| {
                let r = if c.made { DOT + 1.0 } else { RING + 0.5 };
                c.points.iter().map(move |p| {
                    let (x, y, _) = camera.project(*p);
                    (x, y, r)
                })
            })
            .filter(|(x, y, _)| x.is_finite() && y.is_finite())
            .collect();
        let left = camera.at.x - 0.5 * f64::from(self.panel.0);
        let panel = [
            left,
            f64::from(LABELS),
            left + f64::from(self.panel.0),
            f64::from(LABELS + self.panel.1),
        ];
        let mut placed: Vec<[f64; 4]> = Vec::new();
        for chain in chains.iter().filter(|c| c.made) {
            let ink = chain.colour.map(|c| (f32::from(c) * 0.7).round() as u8);
            for (p, words) in chain.points.iter().zip(&chain.labels) {
                if words.is_empty() {
                    continue;
                }
                let (x, y, _) = camera.project(*p);
                if !(x.is_finite() && y.is_finite()) {
                    continue;
                }
                let w = text_width(font, words, LABEL_PX);
                let at = place_label((x, y), w, &marks, &placed, panel);
                placed.push(label_box(at, w));
                draw_text_halo(img, font, words, at.0 + w / 2.0, at.1, LABEL_PX, ink);
            }
        }
    }

    /// The key under the panels: the names in their colours on the first
    /// line, the two kinds of mark on the second.
    pub(super) fn key(
        &self,
        img: &mut Pixmap,
        font: &ab_glyph::FontRef<'_>,
        key: &[(String, [u8; 3])],
        kinds: [&str; 2],
    ) -> Result<(), String> {
        let dark = [40, 40, 40];
        let grey = [90, 90, 90];
        let px = 12.0;
        let top = f64::from(LABELS + self.panel.1);
        let mut x = 12.0;
        let y = top + 20.0;
        for (name, colour) in key {
            dot(img, x + DOT, y - 4.0, DOT, *colour)?;
            x += 2.0 * DOT + 5.0;
            let w = text_width(font, name, px);
            draw_text(img, font, name, x + w / 2.0, y, px, 1e9, dark);
            x += w + 16.0;
        }
        let y = top + 40.0;
        let mut x = 12.0;
        for (k, words) in kinds.iter().enumerate() {
            if k == 0 {
                dot(img, x + RING, y - 4.0, DOT, grey)?;
            } else {
                ring(img, x + RING, y - 4.0, RING, grey)?;
            }
            x += 2.0 * RING + 5.0;
            let w = text_width(font, words, px);
            draw_text(img, font, words, x + w / 2.0, y, px, 1e9, dark);
            x += w + 22.0;
        }
        Ok(())
    }
}

/// A label's box (left, top, right, bottom) from its baseline's left end
/// `at` and its width `w`, at [`LABEL_PX`], with a pixel of room.
pub(super) fn label_box(at: (f64, f64), w: f64) -> [f64; 4] {
    [at.0 - 1.0, at.1 - 9.0, at.0 + w + 1.0, at.1 + 3.0]
}

/// Where a label `w` pixels wide goes beside the mark at `mark`: the first
/// of the places around it (right, left, above, below, then the corners
/// and a step farther out) whose box lies in `panel` and covers no mark
/// (`marks`: centre and radius) and no label placed before (`placed`);
/// when none is free, the one covering fewest. The baseline's left end.
pub(super) fn place_label(
    mark: (f64, f64),
    w: f64,
    marks: &[(f64, f64, f64)],
    placed: &[[f64; 4]],
    panel: [f64; 4],
) -> (f64, f64) {
    let (cx, cy) = mark;
    let candidates = [
        (cx + 8.0, cy + 4.0),
        (cx - 8.0 - w, cy + 4.0),
        (cx - w / 2.0, cy - 9.0),
        (cx - w / 2.0, cy + 17.0),
        (cx + 7.0, cy - 7.0),
        (cx + 7.0, cy + 15.0),
        (cx - 7.0 - w, cy - 7.0),
        (cx - 7.0 - w, cy + 15.0),
        (cx + 18.0, cy + 4.0),
        (cx - 18.0 - w, cy + 4.0),
    ];
    let covers = |at: (f64, f64)| -> usize {
        let b = label_box(at, w);
        let out = b[0] < panel[0] || b[1] < panel[1] || b[2] > panel[2] || b[3] > panel[3];
        let hits_mark = marks
            .iter()
            .filter(|(x, y, r)| {
                let nx = x.clamp(b[0], b[2]);
                let ny = y.clamp(b[1], b[3]);
                (nx - x).hypot(ny - y) < *r
            })
            .count();
        let hits_label = placed
            .iter()
            .filter(|o| b[0] < o[2] && o[0] < b[2] && b[1] < o[3] && o[1] < b[3])
            .count();
        hits_mark + hits_label + if out { 100 } else { 0 }
    };
    let mut best = candidates[0];
    let mut fewest = usize::MAX;
    for at in candidates {
        let n = covers(at);
        if n < fewest {
            best = at;
            fewest = n;
        }
        if n == 0 {
            break;
        }
    }
    best
}

/// A chain's bones and marks, in pixels of the final image (drawn at
/// `to_big`): made bones solid and dots filled with a white edge, the
/// artist's bones thin and marks as rings.
pub(super) fn draw_chain(
    big: &mut Pixmap,
    paint: &mut Paint<'_>,
    points: &[(f32, f32)],
    chain: &MarkedChain,
    to_big: Transform,
) {
    let [r, g, b] = chain.colour;
    let mut pb = PathBuilder::new();
    for (k, (x, y)) in points.iter().enumerate() {
        if k == 0 {
            pb.move_to(*x, *y);
        } else {
            pb.line_to(*x, *y);
        }
    }
    let bones = tiny_skia::Stroke {
        width: if chain.made { 2.0 } else { 1.2 },
        ..tiny_skia::Stroke::default()
    };
    paint.set_color_rgba8(r, g, b, if chain.made { 255 } else { 200 });
    if let Some(path) = pb.finish() {
        big.stroke_path(&path, paint, &bones, to_big, None);
    }
    for (x, y) in points {
        if chain.made {
            if let Some(c) = PathBuilder::from_circle(*x, *y, DOT as f32) {
                paint.set_color_rgba8(r, g, b, 255);
                big.fill_path(&c, paint, FillRule::Winding, to_big, None);
                paint.set_color_rgba8(255, 255, 255, 255);
                let edge = tiny_skia::Stroke {
                    width: 1.0,
                    ..tiny_skia::Stroke::default()
                };
                big.stroke_path(&c, paint, &edge, to_big, None);
            }
        } else if let Some(c) = PathBuilder::from_circle(*x, *y, RING as f32) {
            paint.set_color_rgba8(r, g, b, 255);
            let edge = tiny_skia::Stroke {
                width: 1.6,
                ..tiny_skia::Stroke::default()
            };
            big.stroke_path(&c, paint, &edge, to_big, None);
        }
    }
}

/// A filled dot of radius `r` at (`x`, `y`) on the final image.
pub(super) fn dot(img: &mut Pixmap, x: f64, y: f64, r: f64, rgb: [u8; 3]) -> Result<(), String> {
    let c =
        PathBuilder::from_circle(x as f32, y as f32, r as f32).ok_or("a dot cannot be drawn")?;
    let mut paint = Paint::default();
    paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    img.fill_path(&c, &paint, FillRule::Winding, Transform::identity(), None);
    Ok(())
}

/// A ring of radius `r` at (`x`, `y`) on the final image.
pub(super) fn ring(img: &mut Pixmap, x: f64, y: f64, r: f64, rgb: [u8; 3]) -> Result<(), String> {
    let c =
        PathBuilder::from_circle(x as f32, y as f32, r as f32).ok_or("a ring cannot be drawn")?;
    let mut paint = Paint::default();
    paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    let edge = tiny_skia::Stroke {
        width: 1.6,
        ..tiny_skia::Stroke::default()
    };
    img.stroke_path(&c, &paint, &edge, Transform::identity(), None);
    Ok(())
}

/// Fades an opaque pixmap towards white by `t` (0: as it is, 1: white).
pub(super) fn fade(img: &mut Pixmap, t: f32) {
    for c in img.data_mut().chunks_exact_mut(4) {
        for v in &mut c[..3] {
            *v = (f32::from(*v) + (255.0 - f32::from(*v)) * t)
                .round()
                .clamp(0.0, 255.0) as u8;
        }
    }
}
