//! The strain figure: a grid of panels, one row per view and one column per mesh, under
//! the rigs' names and above the colour scale.

use super::camera::*;
use super::raster::*;
use glam::{DVec2, DVec3};
use tiny_skia::{Paint, Pixmap, Rect, Transform};

/// Height of the band above the panels that names each column's rig.
pub const LABELS: u32 = 22;

/// Height of the colour scale at the bottom: its caption, the ramp, the ticks
/// and their numbers.
pub const LEGEND: u32 = 52;

/// Margin around the framed vertices in their panel, as a share of the
/// panel's width and height on each side.
pub(super) const MARGIN: f64 = 0.06;

/// The strain at the right end of the drawn ramp (the ramp is red from
/// [`RAMP_MAX`] on).
pub(super) const SCALE_END: f64 = 0.3;

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
        let (mut big, mut paint) = canvas(self.width, self.height)?;
        self.draw_panels(&mut big, &mut paint, meshes)?;
        let ramp_y = self.draw_scale(&mut big, &mut paint, meshes.len());
        let mut img = downsample(&big, self.width, self.height)?;
        if let Some(font) = font.and_then(|f| ab_glyph::FontRef::try_from_slice(f).ok()) {
            self.draw_words(&mut img, &font, labels, meshes.len(), ramp_y);
        }
        img.encode_png()
            .map_err(|e| format!("the PNG could not be encoded ({e})"))
    }

    /// Draws each mesh in its panel on `big` (at [`SS`] times the size), each panel on
    /// its own pixmap so that a mesh framed on its hand is cut at the panel's edges.
    fn draw_panels(
        &self,
        big: &mut Pixmap,
        paint: &mut Paint<'_>,
        meshes: &[MeshView<'_>],
    ) -> Result<(), String> {
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
                draw_mesh(&mut panel, paint, camera, mesh, to_panel);
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
        Ok(())
    }

    /// Draws the panels' borders and the colour ramp with its ticks on `big`, for
    /// `columns` meshes; returns the ramp's top row (in figure pixels).
    fn draw_scale(&self, big: &mut Pixmap, paint: &mut Paint<'_>, columns: usize) -> f32 {
        let to_big = Transform::from_scale(SS as f32, SS as f32);
        // Panel borders.
        let (panel_w, panel_h) = self.panel;
        let panels_h = panel_h * self.cameras.len() as u32;
        paint.set_color_rgba8(200, 200, 200, 255);
        for k in 1..columns as u32 {
            if let Some(r) =
                Rect::from_xywh((k * panel_w) as f32, 0.0, 1.0, (LABELS + panels_h) as f32)
            {
                big.fill_rect(r, paint, to_big, None);
            }
        }
        for k in 0..=self.cameras.len() as u32 {
            if let Some(r) =
                Rect::from_xywh(0.0, (LABELS + k * panel_h) as f32, self.width as f32, 1.0)
            {
                big.fill_rect(r, paint, to_big, None);
            }
        }
        // The ramp, from 0 to SCALE_END, between the scale's side margins.
        let (x0, x1) = self.scale_span();
        let ramp_y = (LABELS + panels_h + 20) as f32;
        for x in x0..x1 {
            let [r, g, b] = strain_colour(self.strain_at(f64::from(x) + 0.5));
            paint.set_color_rgba8(r, g, b, 255);
            if let Some(rect) = Rect::from_xywh(x as f32, ramp_y, 1.0, 10.0) {
                big.fill_rect(rect, paint, to_big, None);
            }
        }
        paint.set_color_rgba8(60, 60, 60, 255);
        for t in SCALE_TICKS {
            let x = self.scale_x(t).round() as f32;
            if let Some(rect) = Rect::from_xywh(x - 0.5, ramp_y + 10.0, 1.0, 4.0) {
                big.fill_rect(rect, paint, to_big, None);
            }
        }
        ramp_y
    }

    /// Writes the words on the downsampled `img`: each column's label over it, each view's
    /// name in its panels' corner, the scale's caption and its numbers under the ramp
    /// (whose top row is `ramp_y`).
    fn draw_words(
        &self,
        img: &mut Pixmap,
        font: &ab_glyph::FontRef<'_>,
        labels: &[&str],
        columns: usize,
        ramp_y: f32,
    ) {
        let (panel_w, panel_h) = self.panel;
        let panels_h = panel_h * self.cameras.len() as u32;
        let dark = [40, 40, 40];
        let grey = [110, 110, 110];
        for (col, label) in labels.iter().enumerate().take(columns) {
            let centre = (col as f64 + 0.5) * f64::from(panel_w);
            let fit = f64::from(panel_w) - 8.0;
            draw_text(img, font, label, centre, 16.0, 14.0, fit, dark);
        }
        for (row, cams) in self.cameras.iter().enumerate() {
            let name = match cams.first().map(|c| c.view.name) {
                Some("side") => "from the side",
                Some("above") => "from above (the back of the hand)",
                Some(other) => other,
                None => continue,
            };
            let y = f64::from(LABELS + row as u32 * panel_h) + 14.0;
            for col in 0..columns {
                let left = f64::from(col as u32 * panel_w) + 6.0;
                let w = text_width(font, name, 11.0);
                draw_text(img, font, name, left + w / 2.0, y, 11.0, 1e9, grey);
            }
        }
        let caption_y = f64::from(LABELS + panels_h) + 15.0;
        let fit = f64::from(self.width) - 8.0;
        let caption = SCALE_CAPTION
            .iter()
            .find(|c| text_width(font, c, 11.5) <= fit)
            .unwrap_or(&SCALE_CAPTION[2]);
        draw_text(
            img,
            font,
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
            draw_text(img, font, &words, self.scale_x(t), y, 11.0, 1e9, dark);
        }
    }

    /// The scale's ramp runs from x0 to x1 pixels (left and right margins of
    /// a twelfth of the width, at least 30 px).
    pub(super) fn scale_span(&self) -> (u32, u32) {
        let m = (self.width / 12).max(30).min(self.width / 3);
        (m, self.width.saturating_sub(m).max(m + 1))
    }

    /// The pixel x of strain `s` on the ramp.
    pub fn scale_x(&self, s: f64) -> f64 {
        let (x0, x1) = self.scale_span();
        f64::from(x0) + s / SCALE_END * f64::from(x1 - x0)
    }

    /// The strain drawn at pixel x of the ramp.
    pub(super) fn strain_at(&self, x: f64) -> f64 {
        let (x0, x1) = self.scale_span();
        (x - f64::from(x0)) / f64::from(x1 - x0) * SCALE_END
    }

    /// The pixel row through the middle of the ramp.
    pub fn scale_y(&self) -> f64 {
        f64::from(LABELS + self.panel.1 * self.cameras.len() as u32 + 20) + 5.0
    }
}
