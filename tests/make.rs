//! The fingers found on the skin alone (`rig::find`), on every shared rig with
//! a mesh (../shared/rigs, skipped with the reason when absent), against what
//! the artist rigged: the labels and the side the joint names say, the skin's
//! end the audit measures (`bend::skin_end` past a tip node inside the skin,
//! else the tip node; `bend::mesh_end` past the last joint of a tipless
//! finger), and the artist's joints against the axis found. The finder reads
//! no bone but the hand bone's origin, given as the wrist.
//!
//! Independent of the finder: each PIP's and DIP's own section, the plane
//! through the joint across the artist's chain cutting the mesh (a slicer
//! written here), whose centre tells whether the joint sits at the middle
//! of the finger's skin.

use crate::common::{glb, shared_rig_files, unglb};
use glam::DVec3;
use phalanx::dataset::Finger;
use phalanx::rig::find::{FindOptions, FoundFinger, FoundHand, find_hand};
use phalanx::rig::find::{HandMesh, MeshSelect, hand_mesh};
use phalanx::rig::naming::{Side, side_from_label};
use phalanx::rig::{FingerChain, Rig, TIP_INSIDE, bend};
use std::fmt::Write;

/// The nearest point of a polyline to `q`, and the polyline's direction there.
fn nearest(points: &[DVec3], q: DVec3) -> (DVec3, DVec3) {
    let mut best = (points[0], points[1] - points[0], f64::INFINITY);
    for w in points.windows(2) {
        let ab = w[1] - w[0];
        let t = ((q - w[0]).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        let x = w[0] + t * ab;
        if x.distance(q) < best.2 {
            best = (x, ab, x.distance(q));
        }
    }
    (best.0, best.1.normalize())
}

/// A joint's offset from the axis: (distance, across the palm (lateral),
/// towards the palm (palmar, + palmar, - dorsal)), in mm. Lateral is along
/// the axis's direction x the palm normal; palmar, perpendicular to both.
fn offset(axis: &[DVec3], palm_normal: DVec3, q: DVec3) -> (f64, f64, f64) {
    let (x, t) = nearest(axis, q);
    let d = q - x;
    let lateral = t.cross(palm_normal).normalize();
    let palmar = lateral.cross(t).normalize();
    let palmar = if palmar.dot(palm_normal) < 0.0 {
        -palmar
    } else {
        palmar
    };
    (
        d.length() * 1000.0,
        d.dot(lateral).abs() * 1000.0,
        d.dot(palmar) * 1000.0,
    )
}

/// The centre of the section of `mesh` by the plane through `at` across
/// `normal`: the loop of crossed triangles (joined by shared edges) whose
/// length-weighted centre is nearest `at`.
fn section_centre(mesh: &HandMesh, at: DVec3, normal: DVec3) -> Option<DVec3> {
    let side = |i: u32| (mesh.positions[i as usize] - at).dot(normal);
    type Segment = (DVec3, DVec3, [(u32, u32); 2]);
    let mut segs: Vec<Segment> = Vec::new();
    for t in &mesh.triangles {
        let s = t.map(side);
        let mut ends = Vec::new();
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            if (s[a] < 0.0) != (s[b] < 0.0) {
                let u = s[a] / (s[a] - s[b]);
                let (pa, pb) = (mesh.positions[t[a] as usize], mesh.positions[t[b] as usize]);
                ends.push((pa + u * (pb - pa), (t[a].min(t[b]), t[a].max(t[b]))));
            }
        }
        if let [(p, k), (q, l)] = ends[..] {
            segs.push((p, q, [k, l]));
        }
    }
    // Loops: segments sharing an edge, by repeated relabelling.
    let mut label: Vec<usize> = (0..segs.len()).collect();
    let mut by_edge: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
    for (i, s) in segs.iter().enumerate() {
        for k in s.2 {
            by_edge.entry(k).or_default().push(i);
        }
    }
    loop {
        let mut changed = false;
        for list in by_edge.values() {
            let m = list.iter().map(|&i| label[i]).min().unwrap_or(0);
            for &i in list {
                if label[i] != m {
                    label[i] = m;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    let mut loops: std::collections::HashMap<usize, (f64, DVec3)> = Default::default();
    for (i, (p, q, _)) in segs.iter().enumerate() {
        let e = loops.entry(label[i]).or_insert((0.0, DVec3::ZERO));
        let l = p.distance(*q);
        e.0 += l;
        e.1 += l * (*p + *q) / 2.0;
    }
    loops
        .values()
        .filter(|(l, _)| *l > 0.0)
        .map(|(l, s)| *s / *l)
        .min_by(|a, b| a.distance(at).total_cmp(&b.distance(at)))
}

/// The skin's end the audit takes for a chain: past the tip node when it
/// lies inside the skin (`skin_end` more than `TIP_INSIDE` past it), else the
/// tip node; for a tipless chain, `mesh_end` past its last joint.
fn skin_end(chain: &FingerChain, rig: &Rig) -> Option<(DVec3, &'static str)> {
    let w = rig.weights.as_ref()?;
    let j: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let n = j.len();
    let dir = (j[n - 1] - j[n - 2]).normalize();
    if chain.has_tip {
        let node = j[n - 2].distance(j[n - 1]);
        match bend::skin_end(chain, w) {
            Some(reach) if reach > node + TIP_INSIDE => Some((j[n - 2] + dir * reach, "skin end")),
            _ => Some((j[n - 1], "tip node")),
        }
    } else {
        let reach = bend::mesh_end(chain, w).ok()?;
        Some((j[n - 1] + dir * reach, "mesh end"))
    }
}

/// One finger's comparison.
struct Row {
    rig: String,
    finger: Finger,
    /// Distance from the found tip to the audit's skin end, and its part
    /// along the fingertip's direction (+ past it), mm.
    tip: f64,
    along: f64,
    reference: &'static str,
    /// The artist's last segment's angle to the fingertip's direction, degrees.
    angle: f64,
    /// PIP and DIP (the thumb's IP): (distance, lateral, palmar) from the axis,
    /// and from their own section's centre (mm).
    inner: Vec<((f64, f64, f64), f64)>,
    /// The found axis's distance from each inner joint's section centre (mm).
    to_centre: Vec<f64>,
    mcp: (f64, f64, f64),
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// The hands of a shared rig found on their skin, each with its chains:
/// the whole file for a one-hand file, else the vertices under each hand bone.
fn hands(rig: &Rig, label: &str) -> Vec<(Side, Vec<FingerChain>, HandMesh, FoundHand)> {
    let mut sides: Vec<Option<Side>> = rig.chains.iter().map(|c| c.side).collect();
    sides.sort();
    sides.dedup();
    let mut out = Vec::new();
    for side in &sides {
        let chains: Vec<FingerChain> = rig
            .chains
            .iter()
            .filter(|c| c.side == *side)
            .cloned()
            .collect();
        let wrist = chains.iter().find_map(|c| c.wrist.clone());
        let select = match (&wrist, sides.len()) {
            (Some(w), 2..) => MeshSelect::UnderNode { node: w.node },
            _ => MeshSelect::Whole,
        };
        let mesh = hand_mesh(&rig.file, &select).unwrap_or_else(|e| panic!("{label}: {e}"));
        let opts = FindOptions {
            fingers: chains.len(),
            wrist: wrist.as_ref().map(|w| w.position),
            side: None,
            ..FindOptions::default()
        };
        let found = find_hand(&mesh, &opts).unwrap_or_else(|e| panic!("{label} {side:?}: {e}"));
        let named = side
            .or_else(|| side_from_label(label))
            .unwrap_or_else(|| panic!("{label}: no side in its names or file name"));
        out.push((named, chains, mesh, found));
    }
    out
}

fn compare(
    label: &str,
    f: &FoundFinger,
    chain: &FingerChain,
    rig: &Rig,
    hand: &FoundHand,
    mesh: &HandMesh,
) -> Row {
    let (reference, kind) = skin_end(chain, rig).unwrap_or_else(|| panic!("{label}: no skin end"));
    let e = f.tip - reference;
    let j: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
    let n = j.len();
    let last = (j[n - 1] - j[n - 2]).normalize();
    let inner_end = if chain.has_tip { n - 1 } else { n };
    let mut inner = Vec::new();
    let mut to_centre = Vec::new();
    for k in 1..inner_end {
        let across = (j[(k + 1).min(n - 1)] - j[k - 1]).normalize();
        let centre = section_centre(mesh, j[k], across).expect("a section");
        inner.push((
            offset(&f.axis, hand.palm_normal, j[k]),
            centre.distance(j[k]) * 1000.0,
        ));
        to_centre.push(nearest(&f.axis, centre).0.distance(centre) * 1000.0);
    }
    Row {
        rig: label.to_string(),
        finger: f.finger,
        tip: e.length() * 1000.0,
        along: e.dot(f.tip_direction) * 1000.0,
        reference: kind,
        angle: last
            .dot(f.tip_direction)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees(),
        inner,
        to_centre,
        mcp: offset(&f.axis, hand.palm_normal, j[0]),
    }
}

/// On every shared rig: each hand's fingers found on its skin, given only
/// the hand bone's origin (and the finger count: 4 for the mannequin), get
/// the labels and the side the artist's names give; each tip lies within
/// 2.5 mm of the audit's skin end along the fingertip's direction; the axis
/// passes within 1.5 mm of the centre of each PIP's and DIP's own section
/// (the middle of the finger's skin there); the artist's PIP and DIP lie
/// within 2 mm of the axis across the palm on the median rig, and within 2 mm
/// in all on WebXR's generic hands, whose joints are at the middle of their
/// fingers (within 2 mm of their own sections' centres). How long a finding
/// takes is measured by `cargo bench --bench kernels` (find_hand).
#[test]
fn the_fingers_found_on_every_shared_rig_against_the_artists_joints() {
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    assert!(!rigs.is_empty(), "no rigs in ../shared/rigs");
    let mut rows: Vec<Row> = Vec::new();
    let mut table = String::new();
    let mut per_hand_lateral = Vec::new();
    let mut per_hand_total = Vec::new();
    for path in &rigs {
        let label = path.file_name().unwrap().to_string_lossy().to_string();
        let rig = Rig::load(path, None).unwrap_or_else(|e| panic!("{label}: {e}"));
        for (side, chains, mesh, hand) in hands(&rig, &path.display().to_string()) {
            assert_eq!(hand.side, side, "{label}: {:?}", hand.notes);
            let found: Vec<Finger> = hand.fingers.iter().map(|f| f.finger).collect();
            let rigged: Vec<Finger> = Finger::ALL
                .into_iter()
                .filter(|g| chains.iter().any(|c| c.finger == *g))
                .collect();
            assert_eq!(found, rigged, "{label}");
            let name = format!("{label} {}", side.name());
            let start = rows.len();
            for f in &hand.fingers {
                let chain = chains.iter().find(|c| c.finger == f.finger).unwrap();
                rows.push(compare(&name, f, chain, &rig, &hand, &mesh));
            }
            let hand_rows = &rows[start..];
            per_hand_lateral.push(median(
                hand_rows
                    .iter()
                    .flat_map(|r| r.inner.iter().map(|x| x.0.1))
                    .collect(),
            ));
            per_hand_total.push(median(
                hand_rows
                    .iter()
                    .flat_map(|r| r.inner.iter().map(|x| x.0.0))
                    .collect(),
            ));
            let _ = writeln!(table, "{name}: {} vertices", mesh.positions.len());
        }
    }
    let _ = writeln!(
        table,
        "\n{:<36} {:<7} {:>5} {:>6} {:<9} {:>5}  {:<40} {:<18} MCP",
        "rig",
        "finger",
        "tip",
        "along",
        "vs",
        "angle",
        "PIP, DIP (IP): mm off the axis [lateral, palmar]",
        "centre: joint/axis"
    );
    for r in &rows {
        let inner: Vec<String> = r
            .inner
            .iter()
            .map(|((d, l, p), _)| format!("{d:.1} [{l:.1}, {p:+.1}]"))
            .collect();
        let own: Vec<String> = r
            .inner
            .iter()
            .zip(&r.to_centre)
            .map(|(x, c)| format!("{:.1}/{c:.1}", x.1))
            .collect();
        let _ = writeln!(
            table,
            "{:<36} {:<7} {:>5.2} {:>+6.2} {:<9} {:>5.1}  {:<40} {:<18} {:.1} [{:.1}, {:+.1}]",
            r.rig,
            r.finger.name(),
            r.tip,
            r.along,
            r.reference,
            r.angle,
            inner.join("; "),
            own.join(", "),
            r.mcp.0,
            r.mcp.1,
            r.mcp.2
        );
    }
    let _ = writeln!(
        table,
        "\nper hand, the median PIP/DIP distance across the palm from the axis: {:.2?} mm (median {:.2}); in all: {:.2?} mm (median {:.2})",
        per_hand_lateral,
        median(per_hand_lateral.clone()),
        per_hand_total,
        median(per_hand_total.clone())
    );
    println!("{table}");
    for r in &rows {
        assert!(
            r.along.abs() <= 2.5,
            "{} {}: tip {:.2} mm along\n{table}",
            r.rig,
            r.finger,
            r.along
        );
        for c in &r.to_centre {
            assert!(
                *c <= 1.5,
                "{} {}: the axis passes {c:.2} mm from a section's centre\n{table}",
                r.rig,
                r.finger
            );
        }
        if r.rig.starts_with("left.glb") || r.rig.starts_with("right.glb") {
            for ((d, _, _), own) in &r.inner {
                assert!(
                    *own <= 2.0 && *d <= 2.0,
                    "{} {}: {d:.2} mm ({own:.2} from its centre)\n{table}",
                    r.rig,
                    r.finger
                );
            }
        }
    }
    assert!(median(per_hand_lateral) <= 2.0, "{table}");
}

/// The finder reads the skin alone: WebXR's hands with their skins taken
/// away (no skin on the mesh node, no joints or weights, no bones but the
/// nodes) give the same fingers, with the wrist given and without.
#[test]
fn the_fingers_found_do_not_depend_on_the_bones() {
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    let webxr: Vec<_> = rigs
        .iter()
        .filter(|p| {
            p.parent()
                .is_some_and(|d| d.ends_with("webxr-generic-hand"))
        })
        .collect();
    assert_eq!(webxr.len(), 2, "{rigs:?}");
    for path in webxr {
        let bytes = std::fs::read(path).unwrap();
        let label = path.display().to_string();
        let skinned = phalanx::rig::GltfFile::from_bytes(&label, &bytes).unwrap();
        let (mut json, bin) = unglb(&bytes);
        for node in json["nodes"].as_array_mut().unwrap() {
            node.as_object_mut().unwrap().remove("skin");
        }
        json.as_object_mut().unwrap().remove("skins");
        for mesh in json["meshes"].as_array_mut().unwrap() {
            for prim in mesh["primitives"].as_array_mut().unwrap() {
                let attrs = prim["attributes"].as_object_mut().unwrap();
                attrs.remove("JOINTS_0");
                attrs.remove("WEIGHTS_0");
            }
        }
        let bare = phalanx::rig::GltfFile::from_bytes(&label, &glb(&json, &bin)).unwrap();
        let rig = Rig::from_file(
            phalanx::rig::GltfFile::from_bytes(&label, &bytes).unwrap(),
            None,
        )
        .unwrap();
        let wrist = rig.chains.iter().find_map(|c| c.wrist.clone()).unwrap();
        for given in [Some(wrist.position), None] {
            let opts = FindOptions {
                wrist: given,
                ..FindOptions::default()
            };
            let a = find_hand(&hand_mesh(&skinned, &MeshSelect::Whole).unwrap(), &opts).unwrap();
            let b = find_hand(&hand_mesh(&bare, &MeshSelect::Whole).unwrap(), &opts).unwrap();
            assert_eq!(a.side, b.side);
            for (f, g) in a.fingers.iter().zip(&b.fingers) {
                assert_eq!(f.finger, g.finger);
                assert!(
                    f.tip.distance(g.tip) < 1e-5,
                    "{label} {}: {} {}",
                    f.finger,
                    f.tip,
                    g.tip
                );
                assert_eq!(f.axis.len(), g.axis.len(), "{label} {}", f.finger);
            }
        }
    }
}
