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
const DOT: f64 = 4.0;
/// Radius in pixels of an artist's joint's ring.
const RING: f64 = 5.5;
/// Size in pixels of a joint's label.
const LABEL_PX: f32 = 11.0;
/// How far a skin is faded towards white, so the marks over it read as
/// seen through it.
const FADE: f32 = 0.55;

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
    fn label(
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
    fn key(
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
fn label_box(at: (f64, f64), w: f64) -> [f64; 4] {
    [at.0 - 1.0, at.1 - 9.0, at.0 + w + 1.0, at.1 + 3.0]
}

/// Where a label `w` pixels wide goes beside the mark at `mark`: the first
/// of the places around it (right, left, above, below, then the corners
/// and a step farther out) whose box lies in `panel` and covers no mark
/// (`marks`: centre and radius) and no label placed before (`placed`);
/// when none is free, the one covering fewest. The baseline's left end.
fn place_label(
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
fn draw_chain(
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
fn dot(img: &mut Pixmap, x: f64, y: f64, r: f64, rgb: [u8; 3]) -> Result<(), String> {
    let c =
        PathBuilder::from_circle(x as f32, y as f32, r as f32).ok_or("a dot cannot be drawn")?;
    let mut paint = Paint::default();
    paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
    img.fill_path(&c, &paint, FillRule::Winding, Transform::identity(), None);
    Ok(())
}

/// A ring of radius `r` at (`x`, `y`) on the final image.
fn ring(img: &mut Pixmap, x: f64, y: f64, r: f64, rgb: [u8; 3]) -> Result<(), String> {
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
fn fade(img: &mut Pixmap, t: f32) {
    for c in img.data_mut().chunks_exact_mut(4) {
        for v in &mut c[..3] {
            *v = (f32::from(*v) + (255.0 - f32::from(*v)) * t)
                .round()
                .clamp(0.0, 255.0) as u8;
        }
    }
}

/// [`draw_text`] over a white halo a pixel wide, so the words read over
/// marks and skin alike.
fn draw_text_halo(
    img: &mut Pixmap,
    font: &ab_glyph::FontRef<'_>,
    text: &str,
    cx: f64,
    y: f64,
    px: f32,
    rgb: [u8; 3],
) {
    for (dx, dy) in [
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (-1.0, 0.0),
        (1.0, 0.0),
        (-1.0, 1.0),
        (0.0, 1.0),
        (1.0, 1.0),
    ] {
        draw_text(img, font, text, cx + dx, y + dy, px, 1e9, [255, 255, 255]);
    }
    draw_text(img, font, text, cx, y, px, 1e9, rgb);
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

    /// A finger with its made joints and an artist's a little off: each mark
    /// is drawn where it projects in both views, in its colour, over the
    /// faded skin, and each label lies clear of every mark.
    #[test]
    fn marks_are_drawn_where_they_project_and_labels_clear_them() {
        let rig = tube_hand(&HandSpec {
            fingers: vec![Finger::Middle],
            ..HandSpec::default()
        });
        let frame = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        let mesh = MeshView {
            positions: &rig.mesh.positions,
            triangles: &rig.mesh.triangles,
            strain: &[],
            focus: &[],
        };
        let tip = rig
            .skeleton
            .position(*rig.chains.fingers[0].tip.as_ref().unwrap());
        let made: Vec<DVec3> = [0.1, 0.5, 0.75, 1.0]
            .iter()
            .map(|t| DVec3::new(tip.x, 0.031 + (tip.y - 0.031) * t, 0.0))
            .collect();
        let theirs: Vec<DVec3> = made.iter().map(|p| *p - DVec3::Y * 0.006).collect();
        let colour = FINGER_COLOURS[2];
        let chains = vec![
            MarkedChain {
                labels: vec![String::new(); 4],
                points: theirs.clone(),
                colour,
                made: false,
            },
            MarkedChain {
                labels: ["MCP", "PIP", "DIP", "middle"].map(String::from).to_vec(),
                points: made.clone(),
                colour,
                made: true,
            },
        ];
        let views = [View::above(&frame), View::side(&frame)];
        let fig = Marked::layout(&mesh, &views, 240, 320);
        let key = [("middle".to_string(), colour)];
        let draw = || {
            fig.render(
                &mesh,
                &chains,
                &["above", "side"],
                &key,
                ["made", "artist's"],
                Some(&font()),
            )
            .unwrap()
        };
        let bytes = draw();
        assert_eq!(bytes, draw(), "not deterministic");
        let img = Pixmap::decode_png(&bytes).unwrap();
        assert_eq!((img.width(), img.height()), (480, LABELS + 320 + KEY));
        let near = |c: [u8; 3], want: [u8; 3]| c.iter().zip(want).all(|(a, b)| a.abs_diff(b) <= 12);
        for (col, v) in views.iter().enumerate() {
            for p in &made {
                let (x, y) = fig.project(col, *p).unwrap();
                assert!(
                    near(pixel(&img, x, y), colour),
                    "col {col}: no dot at ({x}, {y})"
                );
            }
            // A ring is hollow: its colour on its edge, not at its centre (which
            // lies between the made dots, on the bone or the skin).
            let (x, y) = fig.project(col, theirs[1]).unwrap();
            assert!(
                near(pixel(&img, x + RING, y), colour)
                    || near(pixel(&img, x - RING, y), colour)
                    || near(pixel(&img, x, y + RING), colour)
                    || near(pixel(&img, x, y - RING), colour),
                "col {col}: no ring at ({x}, {y})"
            );
            // The skin, faded: paler than the mesh drawn darkest (its grey at
            // the least light, 0.35, faded 0.55: about 180), not white.
            let across = if v.right.dot(DVec3::Y).abs() < 0.5 {
                v.right
            } else {
                v.up
            };
            let (x, y) = fig
                .project(col, tip - DVec3::Y * 0.02 + across * 0.004)
                .unwrap();
            let c = pixel(&img, x, y);
            assert!(
                c.iter().all(|&v| v >= 170) && c != [255, 255, 255],
                "col {col}: skin {c:?}"
            );
        }
        // The labels' places keep clear of the marks they are placed among.
        let font = font();
        let font = ab_glyph::FontRef::try_from_slice(&font).unwrap();
        let marks: Vec<(f64, f64, f64)> = made
            .iter()
            .chain(&theirs)
            .map(|p| {
                let (x, y) = fig.project(0, *p).unwrap();
                (x, y, RING)
            })
            .collect();
        let panel = [0.0, f64::from(LABELS), 240.0, f64::from(LABELS + 320)];
        let mut placed = Vec::new();
        for (p, words) in made.iter().zip(["MCP", "PIP", "DIP", "middle"]) {
            let w = text_width(&font, words, LABEL_PX);
            let at = place_label(fig.project(0, *p).unwrap(), w, &marks, &placed, panel);
            let b = label_box(at, w);
            for (x, y, r) in &marks {
                let d = (x.clamp(b[0], b[2]) - x).hypot(y.clamp(b[1], b[3]) - y);
                assert!(d >= *r, "{words} covers the mark at ({x}, {y})");
            }
            assert!(b[0] >= panel[0] && b[2] <= panel[2] && b[1] >= panel[1] && b[3] <= panel[3]);
            placed.push(b);
        }
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
