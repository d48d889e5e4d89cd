//! Pixels: the strain colour ramp, meshes filled with the painter's algorithm, text, and
//! the 2 x 2 average that smooths the supersampled image.

use super::camera::*;
use glam::DVec3;
use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Transform};

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
pub(super) const SS: u32 = 2;

/// [`draw_text`] over a white halo a pixel wide, so the words read over
/// marks and skin alike.
pub(super) fn draw_text_halo(
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
pub(super) fn text_width(font: &ab_glyph::FontRef<'_>, text: &str, px: f32) -> f64 {
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
pub(super) fn draw_text(
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
pub(super) fn draw_mesh(
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

/// A white canvas `SS` times the figure's size, and the paint every figure draws with
/// (no anti-aliasing: the supersampling smooths it when downsampled).
pub(super) fn canvas(width: u32, height: u32) -> Result<(Pixmap, Paint<'static>), String> {
    let mut big = Pixmap::new(width * SS, height * SS)
        .ok_or_else(|| format!("an image of {width} x {height} pixels cannot be made"))?;
    big.fill(tiny_skia::Color::WHITE);
    let paint = Paint {
        anti_alias: false,
        ..Paint::default()
    };
    Ok((big, paint))
}

/// Averages `SS` x `SS` blocks of an opaque pixmap into one pixel each.
pub(super) fn downsample(big: &Pixmap, width: u32, height: u32) -> Result<Pixmap, String> {
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
