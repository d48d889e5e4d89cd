use super::*;
use serde_json::json;

/// A glTF with one skinned quad (two triangles, four vertices), joints and
/// weights in two sets of the given component types, returned as GLB bytes.
fn quad(joint_type: u32, weight_type: u32, extra: impl Fn(&mut serde_json::Value)) -> Vec<u8> {
    let pos: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    let mut bin = Bin::default();
    let p = bin.push(pos.iter().flatten().flat_map(|x| x.to_le_bytes()).collect());
    let idx = bin.push(
        [0u16, 1, 2, 0, 2, 3]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect(),
    );
    // Set 0: joints (0, 1), weights (3, 1) -> 0.375/0.125 of the eight parts.
    // Set 1: joint 1 again and joint 2, weights (2, 2) -> 0.25 each.
    let sets = [
        ([0u16, 1, 0, 0], [3.0f32, 1.0, 0.0, 0.0]),
        ([1, 2, 0, 0], [2.0, 2.0, 0.0, 0.0]),
    ];
    let mut accessors = vec![
        json!({"bufferView": p, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}),
        json!({"bufferView": idx, "componentType": 5123, "count": 6, "type": "SCALAR"}),
    ];
    let mut attrs = json!({"POSITION": 0});
    for (s, (j, w)) in sets.iter().enumerate() {
        let jv = bin.push(joint_bytes(j, joint_type));
        let wv = bin.push(weight_bytes(w, weight_type));
        accessors.push(
            json!({"bufferView": jv, "componentType": joint_type, "count": 4, "type": "VEC4"}),
        );
        let mut wa =
            json!({"bufferView": wv, "componentType": weight_type, "count": 4, "type": "VEC4"});
        if weight_type != 5126 {
            wa["normalized"] = json!(true);
        }
        accessors.push(wa);
        attrs[format!("JOINTS_{s}")] = json!(accessors.len() - 2);
        attrs[format!("WEIGHTS_{s}")] = json!(accessors.len() - 1);
    }
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "nodes": [
            {"name": "a", "children": [1]}, {"name": "b", "translation": [0.0, 1.0, 0.0]},
            {"name": "c", "translation": [2.0, 0.0, 0.0]},
            {"name": "skinned", "mesh": 0, "skin": 0}
        ],
        "meshes": [{"primitives": [{"attributes": attrs, "indices": 1}]}],
        "skins": [{"joints": [0, 1, 2]}],
        "accessors": accessors,
        "bufferViews": bin.views,
        "buffers": [{"byteLength": bin.bytes.len()}]
    });
    extra(&mut doc);
    glb(&doc, bin.bytes)
}

/// A GLB's binary chunk and its buffer views, as [`quad`] writes them.
#[derive(Default)]
struct Bin {
    bytes: Vec<u8>,
    views: Vec<serde_json::Value>,
}

impl Bin {
    /// Appends `bytes` 4-byte aligned as a buffer view; returns the view's index.
    fn push(&mut self, bytes: Vec<u8>) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": bytes.len()}));
        self.bytes.extend(bytes);
        self.views.len() - 1
    }
}

/// One joint set for all four vertices of the quad, as `joint_type` (5121 bytes, else shorts).
fn joint_bytes(j: &[u16; 4], joint_type: u32) -> Vec<u8> {
    (0..4)
        .flat_map(|_| {
            j.iter().flat_map(|&x| {
                if joint_type == 5121 {
                    vec![x as u8]
                } else {
                    x.to_le_bytes().to_vec()
                }
            })
        })
        .collect()
}

/// One weight set for all four vertices, in eighths scaled by 1/8 (so each set sums
/// to 1/2 before normalising), as `weight_type` (5121, 5123 normalised, else float).
fn weight_bytes(w: &[f32; 4], weight_type: u32) -> Vec<u8> {
    (0..4)
        .flat_map(|_| {
            w.iter().flat_map(|&x| {
                let f = x / 8.0;
                match weight_type {
                    5121 => vec![(f * 255.0).round() as u8],
                    5123 => ((f * 65535.0).round() as u16).to_le_bytes().to_vec(),
                    _ => f.to_le_bytes().to_vec(),
                }
            })
        })
        .collect()
}

/// `doc` and `bin` as GLB bytes.
fn glb(doc: &serde_json::Value, bin: Vec<u8>) -> Vec<u8> {
    crate::rig::read::gltf::glb(doc, bin).unwrap()
}

fn read(bytes: &[u8]) -> Result<SkinnedMesh, DataError> {
    let file = GltfFile::from_bytes("quad.glb", bytes).unwrap();
    SkinnedMesh::read(&file, Path::new("."), 0)
}

#[test]
fn two_sets_of_every_storage_are_merged_and_normalised() {
    // By hand: set 0 gives joint 0: 3/8, joint 1: 1/8; set 1 gives joint 1: 2/8,
    // joint 2: 2/8; merged: 0: 0.375, 1: 0.375, 2: 0.25 (sum 1 after dividing by the 1 they sum to).
    for jt in [5121, 5123] {
        for wt in [5126, 5121, 5123] {
            let m = read(&quad(jt, wt, |_| {})).unwrap();
            assert_eq!(m.positions.len(), 4);
            assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
            assert_eq!(m.joints, vec![0, 1, 2]);
            for v in 0..4 {
                let infl = m.influences_of(v);
                let sum: f64 = infl.iter().map(|x| x.1).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{jt} {wt}: {infl:?}");
                let w = |j: u16| infl.iter().find(|x| x.0 == j).map_or(0.0, |x| x.1);
                let tol = if wt == 5121 { 3e-3 } else { 1e-4 };
                assert!(
                    (w(0) - 0.375).abs() < tol && (w(1) - 0.375).abs() < tol,
                    "{infl:?}"
                );
                assert!((w(2) - 0.25).abs() < tol, "{infl:?}");
                // Largest first, ties by slot.
                assert!(infl.windows(2).all(|p| p[0].1 >= p[1].1));
            }
            // No inverse bind matrices: identity; M_j = W_j.
            let file = GltfFile::from_bytes("q", &quad(jt, wt, |_| {})).unwrap();
            let s = m.skin_matrices(&file.world);
            assert_eq!(s[1].w_axis.truncate(), DVec3::new(0.0, 1.0, 0.0));
        }
    }
}

#[test]
fn malformed_accessors_are_named_not_panicked_on() {
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|d| d["accessors"][0]["componentType"] = json!(5123)),
            "/accessors/0 (POSITION of /meshes/0/primitives/0)",
        ),
        (
            // Past its buffer view: refused at the door (gltf::precheck).
            Box::new(|d| d["accessors"][0]["count"] = json!(400)),
            "/accessors/0: 400 VEC3 elements need 4800 bytes",
        ),
        (
            Box::new(|d| d["accessors"][2]["type"] = json!("VEC3")),
            "JOINTS_0",
        ),
        (
            Box::new(|d| d["accessors"][3]["componentType"] = json!(5125)),
            "WEIGHTS_0",
        ),
        (
            Box::new(|d| d["bufferViews"][2]["byteStride"] = json!(4)),
            "shorter than one element",
        ),
        (
            // Past its buffer view: refused at the door too.
            Box::new(|d| d["accessors"][1]["byteOffset"] = json!(8)),
            "/accessors/1: 6 SCALAR elements need 12 bytes from byteOffset 8",
        ),
        (
            Box::new(|d| d["skins"][0]["joints"] = json!([0])),
            "names joint",
        ),
        (
            Box::new(
                |d| d["accessors"][0]["sparse"] = json!({"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}}),
            ),
            "sparse",
        ),
        (
            Box::new(|d| {
                d["meshes"][0]["primitives"][0]["attributes"]
                    .as_object_mut()
                    .unwrap()
                    .remove("WEIGHTS_1")
                    .map(|_| ())
                    .unwrap_or(())
            }),
            "JOINTS_1 but no WEIGHTS_1",
        ),
    ];
    for (edit, expect) in cases {
        let bytes = quad(5123, 5126, &*edit);
        match GltfFile::from_bytes("quad.glb", &bytes) {
            // What the door refuses is named there, by the same JSON path.
            Err(e) => {
                let e = e.to_string();
                assert!(e.contains(expect), "{expect}: {e}");
                assert!(e.contains("quad.glb"), "{e}");
            }
            Ok(file) => {
                let e = SkinnedMesh::read(&file, Path::new("."), 0)
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(expect), "{expect}: {e}");
                assert!(e.contains("quad.glb"), "{e}");
            }
        }
    }
}

#[test]
fn non_triangle_primitives_become_notes() {
    // The only primitive skipped: nothing is left to deform, and the reason is given.
    let e = read(&quad(5123, 5126, |d| {
        d["meshes"][0]["primitives"][0]["mode"] = json!(1)
    }))
    .unwrap_err()
    .to_string();
    assert!(e.contains("no triangles") && e.contains("Lines"), "{e}");
    let file = GltfFile::from_bytes(
        "q",
        &quad(5123, 5126, |d| {
            let p = d["meshes"][0]["primitives"][0].clone();
            let mut lines = p.clone();
            lines["mode"] = json!(1);
            d["meshes"][0]["primitives"] = json!([p, lines]);
        }),
    )
    .unwrap();
    let m = SkinnedMesh::read(&file, Path::new("."), 0).unwrap();
    assert_eq!(m.triangles.len(), 2);
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("/meshes/0/primitives/1") && n.contains("Lines")),
        "{:?}",
        m.notes
    );
}

#[test]
fn welding_joins_split_seams_only() {
    let p = [
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(-0.0, 0.0, 0.0),
        DVec3::X * 1.000_000_1,
    ];
    assert_eq!(weld(&p), vec![0, 1, 0, 3]);
}
