//! Tests of the figures: where things are drawn, and that the bytes hold.

use super::camera::*;
use super::figure::*;
use super::marked::*;
use super::raster::*;
use crate::dataset::Finger;
use crate::rig::deform::PalmFrame;
use crate::rig::deform::synthetic::{HandSpec, tube_hand};
use crate::rig::naming::Side;
use glam::DVec3;
use tiny_skia::Pixmap;

/// The vendored label font, read as `phalanx` reads it (from the checkout).
fn font() -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(super::FONT_FILE);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

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
    let img =
        Pixmap::decode_png(&fig.render(&[framed], &["the rig"], Some(&font())).unwrap()).unwrap();
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
