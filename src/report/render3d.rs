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
/// Height of the colour-ramp strip at the bottom.
const LEGEND: u32 = 18;
/// Margin around each mesh in its panel, pixels.
const MARGIN: f64 = 10.0;

/// A grid of panels: one row per view, one column per mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub width: u32,
    pub height: u32,
    /// `cameras[row][column]`.
    pub cameras: Vec<Vec<Camera>>,
}

impl Figure {
    /// Lays out `meshes` in `views`, each panel `panel_w` x `panel_h` pixels:
    /// one scale per row, the largest at which every mesh of the row fits.
    pub fn layout(meshes: &[MeshView<'_>], views: &[View], panel_w: u32, panel_h: u32) -> Figure {
        let cameras = views
            .iter()
            .enumerate()
            .map(|(row, view)| {
                let bounds: Vec<(DVec2, DVec2)> = meshes
                    .iter()
                    .map(|m| {
                        m.positions.iter().fold(
                            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                            |(lo, hi), p| {
                                let v = DVec2::new(p.dot(view.right), p.dot(view.up));
                                (lo.min(v), hi.max(v))
                            },
                        )
                    })
                    .collect();
                let room = DVec2::new(f64::from(panel_w), f64::from(panel_h)) - 2.0 * MARGIN;
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
                            (col as f64 + 0.5) * f64::from(panel_w),
                            (row as f64 + 0.5) * f64::from(panel_h),
                        ),
                    })
                    .collect()
            })
            .collect();
        Figure {
            width: panel_w * meshes.len().max(1) as u32,
            height: panel_h * views.len().max(1) as u32 + LEGEND,
            cameras,
        }
    }

    /// The pixel where `p` of the mesh in `column` is drawn in view `row`.
    pub fn project(&self, row: usize, column: usize, p: DVec3) -> Option<(f64, f64)> {
        let c = self.cameras.get(row)?.get(column)?;
        let (x, y, _) = c.project(p);
        Some((x, y))
    }

    /// Draws `meshes` (the ones given to [`Figure::layout`]) as PNG bytes.
    pub fn render(&self, meshes: &[MeshView<'_>]) -> Result<Vec<u8>, String> {
        let mut big = Pixmap::new(self.width * SS, self.height * SS).ok_or_else(|| {
            format!(
                "an image of {} x {} pixels cannot be made",
                self.width, self.height
            )
        })?;
        big.fill(tiny_skia::Color::WHITE);
        let to_big = Transform::from_scale(SS as f32, SS as f32);
        let mut paint = Paint {
            anti_alias: false,
            ..Paint::default()
        };
        for row in &self.cameras {
            for (camera, mesh) in row.iter().zip(meshes) {
                draw_mesh(&mut big, &mut paint, camera, mesh, to_big);
            }
        }
        // Panel borders and the ramp.
        let panel_h = (self.height - LEGEND) / self.cameras.len().max(1) as u32;
        let panel_w = self.width / meshes.len().max(1) as u32;
        paint.set_color_rgba8(200, 200, 200, 255);
        for k in 1..meshes.len() as u32 {
            if let Some(r) = Rect::from_xywh(
                (k * panel_w) as f32,
                0.0,
                1.0,
                (self.height - LEGEND) as f32,
            ) {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        for k in 1..=self.cameras.len() as u32 {
            if let Some(r) = Rect::from_xywh(0.0, (k * panel_h) as f32, self.width as f32, 1.0) {
                big.fill_rect(r, &paint, to_big, None);
            }
        }
        let y0 = (self.height - LEGEND + 5) as f32;
        for x in 0..self.width {
            let s = f64::from(x) / f64::from(self.width.max(2) - 1) * RAMP_MAX * 1.2;
            let [r, g, b] = strain_colour(s);
            paint.set_color_rgba8(r, g, b, 255);
            if let Some(rect) = Rect::from_xywh(x as f32, y0, 1.0, (LEGEND - 9) as f32) {
                big.fill_rect(rect, &paint, to_big, None);
            }
        }
        downsample(&big, self.width, self.height)?
            .encode_png()
            .map_err(|e| format!("the PNG could not be encoded ({e})"))
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
        };
        // The same finger twice, the second one strained red everywhere.
        let red = vec![1.0; rig.mesh.positions.len()];
        let hot = MeshView {
            strain: &red,
            ..mesh
        };
        let views = [View::side(&frame), View::above(&frame)];
        let fig = Figure::layout(&[mesh, hot], &views, 240, 200);
        let bytes = fig.render(&[mesh, hot]).unwrap();
        assert_eq!(
            bytes,
            fig.render(&[mesh, hot]).unwrap(),
            "not deterministic"
        );
        let img = Pixmap::decode_png(&bytes).unwrap();
        assert_eq!((img.width(), img.height()), (480, 400 + LEGEND));
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
