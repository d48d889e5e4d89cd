//! The WebXR generic hands (MIT; vendored in `data/rigs/webxr-generic-hand/`
//! with their licence and source): read, curled, measured and drawn.
//! Skipped, saying why, when the files are not there.
//!
//! Their 25 joints are siblings under `Armature`, so the chains are built
//! here from the WebXR joint names, not from the hierarchy.

use super::measures::HandMeasures;
use super::*;
use crate::dataset::Finger;
use crate::report::render3d::{Figure, MeshView, View};
use crate::rig::read::GltfFile;
use crate::rig::read::naming::Side;
use crate::rig::read::skin::{SkinnedMesh, pick_skin};
use std::path::{Path, PathBuf};

fn rig_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/rigs/webxr-generic-hand");
    (dir.join("left.glb").is_file() && dir.join("right.glb").is_file()).then_some(dir)
}

/// The chains of a WebXR hand, by joint name.
fn chains(file: &GltfFile, side: Side) -> HandChains {
    let names = file.node_names();
    let node = |n: &str| names.iter().position(|x| x == n);
    let fingers = [
        (Finger::Thumb, "thumb"),
        (Finger::Index, "index-finger"),
        (Finger::Middle, "middle-finger"),
        (Finger::Ring, "ring-finger"),
        (Finger::Little, "pinky-finger"),
    ]
    .into_iter()
    .map(|(finger, p)| {
        let parts: &[&str] = if finger == Finger::Thumb {
            &["phalanx-proximal", "phalanx-distal"]
        } else {
            &["phalanx-proximal", "phalanx-intermediate", "phalanx-distal"]
        };
        FingerNodes {
            finger,
            metacarpal: node(&format!("{p}-metacarpal")),
            joints: parts
                .iter()
                .map(|x| node(&format!("{p}-{x}")).expect("WebXR joint"))
                .collect(),
            tip: node(&format!("{p}-tip")),
        }
    })
    .collect();
    HandChains {
        side,
        wrist: node("wrist"),
        fingers,
    }
}

fn table(label: &str, m: &HandMeasures) {
    eprintln!("{label}");
    eprintln!("finger  joint  angle  loss(%)  at(mm)  crossings  p95    max    crease(mm)");
    for f in &m.fingers {
        for j in &f.joints {
            let opt =
                |x: Option<f64>, k: f64| x.map_or("n/a".to_string(), |v| format!("{:.1}", v * k));
            eprintln!(
                "{:7} {:5} {:5.0}  {:>7}  {:>6}  {:9}  {:.3}  {:.3}  {:>6}",
                f.finger.name(),
                j.joint.name(),
                j.angle,
                opt(j.volume_loss, 100.0),
                opt(j.volume_loss_at, 1000.0),
                j.self_intersections,
                j.strain_p95.unwrap_or(f64::NAN),
                j.strain_max.unwrap_or(f64::NAN),
                opt(j.crease_offset, 1000.0),
            );
        }
        eprintln!(
            "{:7} whole  {} vertices, {} triangles, {} crossings, strain p95 {:.3} max {:.3}{}",
            f.finger.name(),
            f.vertices,
            f.triangles,
            f.self_intersections,
            f.strain_p95.unwrap_or(f64::NAN),
            f.strain_max.unwrap_or(f64::NAN),
            if f.notes.is_empty() {
                String::new()
            } else {
                format!("; {}", f.notes.join("; "))
            }
        );
    }
}

#[test]
fn the_webxr_hands_curl_into_a_fist() {
    let Some(dir) = rig_dir() else {
        eprintln!("skipped: the WebXR generic hands are not in data/rigs/webxr-generic-hand");
        return;
    };
    let out = std::env::var_os("PHALANX_RENDER_DIR").map(PathBuf::from);
    let tmp = tempfile::tempdir().unwrap();
    let out = out.unwrap_or_else(|| tmp.path().to_path_buf());
    for (name, side) in [("left", Side::Left), ("right", Side::Right)] {
        let file = GltfFile::load(&dir.join(format!("{name}.glb"))).unwrap();
        let hand = chains(&file, side);
        // The audit's reading of the rig gives the same chains (its names carry
        // no side: the caller gives it).
        let rig = crate::rig::read::Rig::load(&dir.join(format!("{name}.glb")), None).unwrap();
        assert_eq!(rig.hand_chains(Some(side)), vec![hand.clone()]);
        assert!(rig.hand_chains(None).is_empty());
        let nodes: Vec<usize> = hand.fingers.iter().flat_map(|f| f.joints.clone()).collect();
        let skin = pick_skin(&file, &nodes).unwrap();
        let mesh = SkinnedMesh::read(&file, &dir, skin).unwrap();
        // The file's own counts (accessors 0 and 5 of the JSON: 1360 vertices, 6942 indices).
        assert_eq!(mesh.positions.len(), 1360);
        assert_eq!(mesh.triangles.len(), 6942 / 3);
        assert_eq!(mesh.joints.len(), 25);
        assert!(mesh.notes.is_empty(), "{:?}", mesh.notes);
        for v in 0..mesh.positions.len() {
            let sum: f64 = mesh.influences_of(v).iter().map(|x| x.1).sum();
            assert!((sum - 1.0).abs() < 1e-9, "vertex {v}: {sum}");
        }
        let skeleton = Skeleton::of(&file);
        // The bind pose reproduces the stored mesh (the file's inverse bind matrices
        // are its joints' inverse world matrices, up to f32).
        let (rest, _) = skinning::skin(Skinning::Lbs, &mesh, &mesh.skin_matrices(&skeleton.world));
        let off = rest
            .iter()
            .zip(&mesh.positions)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(off < 1e-5, "{off}");
        let posed = pose::pose_hand(&skeleton, &hand, &Pose::fist()).unwrap();
        {
            let bent = Pose {
                thumb_across: None,
                ..Pose::fist()
            };
            let bent = pose::pose_hand(&skeleton, &hand, &bent).unwrap();
            // The fist's thumb lies across the index's middle phalanx (its tip
            // within 15 mm of that bone's axis: the index's skin is about 9 mm
            // off it here) and no deeper below the palm than the curled index's
            // DIP plus 10 mm. Bent at its MCP and IP alone, it stuck straight
            // out of the palm: 27 mm from the index, 17 mm below its DIP.
            let (height, to_index, depth) = pose::tests::thumb_tip_place(&posed, Finger::Index);
            assert!(to_index < 0.015, "{name}: {to_index} m from the index");
            assert!(
                height > 0.0 && height < depth + 0.01,
                "{name}: {height} m below the palm, the fist {depth}"
            );
            let (height, to_index, depth) = pose::tests::thumb_tip_place(&bent, Finger::Index);
            assert!(
                to_index > 0.02 && height > depth + 0.015,
                "{name}: {to_index} {height}"
            );
        }
        let mut results = Vec::new();
        for method in [Skinning::Lbs, Skinning::Dqs] {
            let d = deform(&mesh, &skeleton, &posed, method);
            table(
                &format!("{name} hand, fist, {}", method.name()),
                &d.measures,
            );
            // The wrist's skin stays. Each fingertip's skin moves about as the tip
            // node does, which is at least half the finger's length: a point p
            // carried rigidly with the tip moves |u(tip) + (R - I)(p - tip)|,
            // within 2 |p - tip| of the tip's own displacement.
            let wrist = mesh.slot_of(hand.wrist.unwrap()).unwrap();
            let moved = |v: usize| d.posed[v].distance(d.rest[v]);
            for v in 0..mesh.positions.len() {
                if mesh.influences_of(v).iter().all(|x| x.0 == wrist) {
                    assert!(moved(v) < 1e-12, "wrist vertex {v} moved {}", moved(v));
                }
            }
            for (f, p) in hand.fingers.iter().zip(&posed.fingers) {
                let tip_slot = mesh.slot_of(*f.joints.last().unwrap()).unwrap();
                let tips: Vec<usize> = (0..mesh.positions.len())
                    .filter(|&v| mesh.dominant(v) == Some(tip_slot))
                    .collect();
                let far = tips.iter().map(|&v| moved(v)).fold(0.0, f64::max);
                let tip = p.tip.unwrap();
                let reach = tips
                    .iter()
                    .map(|&v| d.rest[v].distance(tip))
                    .fold(0.0, f64::max);
                let node_moved = p
                    .joints
                    .last()
                    .unwrap()
                    .after
                    .transform_point3(tip)
                    .distance(tip);
                let axis = p.rest_axis();
                let length: f64 = axis.windows(2).map(|w| w[0].distance(w[1])).sum();
                assert!(
                    node_moved > 0.5 * length,
                    "{name} {}: {node_moved} of {length}",
                    f.finger
                );
                assert!(
                    (far - node_moved).abs() <= 2.0 * reach,
                    "{name} {}: skin {far} m, tip {node_moved} m, skin within {reach} m of the tip",
                    f.finger
                );
            }
            // Every finger curls to the palm side.
            for f in &posed.fingers {
                let tip = f.tip.unwrap();
                let t = f.joints.last().unwrap().after.transform_point3(tip);
                assert!(
                    (t - tip).dot(posed.frame.normal) > 0.0,
                    "{name} {}",
                    f.finger
                );
            }
            results.push(d);
        }
        // The mirror images: the left hand's palm normal is the right's mirrored in
        // x (the two files are mirror images of each other in x).
        if side == Side::Left {
            assert!(posed.frame.normal.x > 0.9, "{:?}", posed.frame);
        } else {
            assert!(posed.frame.normal.x < -0.9, "{:?}", posed.frame);
        }
        // Draw LBS against DQS, from the side and from above.
        let views = [View::side(&posed.frame), View::above(&posed.frame)];
        let meshes: Vec<MeshView<'_>> = results
            .iter()
            .map(|d| MeshView {
                positions: &d.posed,
                triangles: &mesh.triangles,
                strain: &d.vertex_strain,
                focus: &[],
            })
            .collect();
        let fig = Figure::layout(&meshes, &views, 360, 300);
        let png = fig.render(&meshes, &["LBS", "DQS"], Some(&font())).unwrap();
        let path = out.join(format!("webxr-{name}-fist-lbs-dqs.png"));
        std::fs::write(&path, &png).unwrap();
        eprintln!("drawn: {}", path.display());
        let img = tiny_skia::Pixmap::decode_png(&png).unwrap();
        let background = img
            .pixels()
            .iter()
            .filter(|p| p.red() == 255 && p.green() == 255 && p.blue() == 255)
            .count();
        let share = background as f64 / img.pixels().len() as f64;
        assert!(
            (0.2..0.95).contains(&share),
            "{share} of the image is background"
        );
    }
}

/// The vendored label font, read as `phalanx` reads it (from the checkout).
fn font() -> Vec<u8> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(crate::report::render3d::FONT_FILE);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}
