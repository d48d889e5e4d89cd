use super::*;
use crate::rig::read::glb_parts::GlbParts;

const QUAD: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];

/// 90 degrees about z.
fn quarter_turn() -> [f64; 4] {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    [0.0, 0.0, s, s]
}

/// A unit quad (positions and indices) as mesh JSON.
fn quad(parts: &mut GlbParts) -> Value {
    let pos = parts.accessor(
        &QUAD.concat(),
        5126,
        "VEC3",
        Some((vec![0.0; 3], vec![1.0, 1.0, 0.0])),
    );
    let idx = parts.accessor(&[0u16, 1, 2, 0, 2, 3], 5123, "SCALAR", None);
    json!({"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]})
}

/// The file of a document built here: `doc` (nodes, meshes, skins) with
/// `parts`' accessors and a scene of every root.
fn document(parts: GlbParts, mut doc: Value) -> GltfFile {
    let nodes = doc["nodes"].as_array().unwrap();
    let children: BTreeSet<u64> = nodes
        .iter()
        .flat_map(|n| n["children"].as_array().into_iter().flatten())
        .filter_map(Value::as_u64)
        .collect();
    let roots: Vec<usize> = (0..nodes.len())
        .filter(|&i| !children.contains(&(i as u64)))
        .collect();
    doc["asset"] = json!({"version": "2.0"});
    doc["scene"] = json!(0);
    doc["scenes"] = json!([{ "nodes": roots }]);
    doc["accessors"] = json!(parts.accessors);
    doc["bufferViews"] = json!(parts.views);
    doc["buffers"] = json!([{"byteLength": parts.bin.len()}]);
    let bytes = crate::rig::read::gltf::glb(&doc, parts.bin).unwrap();
    GltfFile::from_bytes("test.glb", &bytes).unwrap()
}

/// Finishes an edit as a GLB and reads it back; checks that every
/// accessor and buffer view of it is used.
fn finished(edit: Edit<'_>) -> (GltfFile, Vec<String>) {
    let (bytes, warnings) = edit.finish(true).unwrap();
    let out = GltfFile::from_bytes("out.glb", &bytes).unwrap();
    let named = accessor::references(&out.json);
    for a in 0..out.json["accessors"].as_array().map_or(0, Vec::len) {
        assert!(named.contains_key(&a), "accessor {a} is unused");
    }
    let views = accessor::view_references(&out.json);
    for v in 0..out.json["bufferViews"].as_array().map_or(0, Vec::len) {
        assert!(views.contains_key(&v), "bufferView {v} is unused");
    }
    (out, warnings)
}

fn node(f: &GltfFile, name: &str) -> usize {
    f.node_names().iter().position(|n| n == name).unwrap()
}

/// Where the quad's corners rest in world space, drawn by `node` unskinned.
fn drawn(f: &GltfFile, node: usize) -> Vec<DVec3> {
    QUAD.iter()
        .map(|p| f.world[node].transform_point3(DVec3::from_array(p.map(f64::from))))
        .collect()
}

/// The rest positions of the first skinned primitive, as the readers see them.
fn rest(f: &GltfFile) -> Vec<DVec3> {
    let w = SkinWeights::read(f, &f.buffer_data().unwrap());
    assert!(w.notes.is_empty(), "{:?}", w.notes);
    w.primitives[0].rest.clone()
}

fn close(a: &[DVec3], b: &[DVec3], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!(x.distance(*y) <= tol, "{x} != {y}");
    }
}

#[test]
fn nodes_added_under_rotated_and_scaled_parents_sit_unrotated_at_their_points() {
    let mut parts = GlbParts::default();
    let mesh = quad(&mut parts);
    let f = document(
        parts,
        json!({
            "nodes": [
                {"name": "root", "rotation": quarter_turn(), "scale": [2.0, 2.0, 2.0],
                 "translation": [1.0, 2.0, 3.0], "children": [1]},
                {"name": "sheared", "scale": [1.0, 3.0, 0.5], "rotation": [0.0, 0.0, 0.25881904510252074, 0.9659258262890683]},
                {"name": "stretched", "scale": [1.0, 3.0, 0.5], "translation": [0.0, 1.0, 0.0]},
                {"name": "quad", "mesh": 0}
            ],
            "meshes": [mesh]
        }),
    );
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let points = [
        DVec3::new(0.3, -0.2, 0.9),
        DVec3::new(0.5, 0.1, 1.2),
        DVec3::new(-1.0, 4.0, 0.25),
        DVec3::new(2.0, 2.0, 2.0),
    ];
    let a = edit.add_node("a", Some(0), points[0]).unwrap();
    let b = edit.add_node("b", Some(a), points[1]).unwrap();
    let c = edit.add_node("c", Some(2), points[2]).unwrap();
    let d = edit.add_node("d", None, points[3]).unwrap();
    assert_eq!((a, b, c, d), (4, 5, 6, 7));
    // No node's translation, rotation and scale undo a shear.
    let e = edit.add_node("e", Some(1), points[0]).unwrap_err();
    assert!(e.to_string().contains("shears"), "{e}");
    assert!(edit.add_node("f", Some(99), points[0]).is_err());
    assert!(edit.add_node("g", None, DVec3::NAN).is_err());
    for (n, p) in [a, b, c, d].into_iter().zip(points) {
        let w = edit.world(n).unwrap();
        assert!(w.abs_diff_eq(DMat4::from_translation(p), 1e-6), "{w}");
    }
    let (out, _) = finished(edit);
    for (name, p) in ["a", "b", "c", "d"].into_iter().zip(points) {
        let w = out.world[node(&out, name)];
        assert!(
            w.abs_diff_eq(DMat4::from_translation(p), 1e-6),
            "{name}: {w}"
        );
    }
    assert_eq!(out.parent[node(&out, "b")], Some(node(&out, "a")));
    assert_eq!(out.parent[node(&out, "a")], Some(0));
    assert_eq!(out.json["scenes"][0]["nodes"], json!([0, 2, 3, 7]));
    // Under an unrotated parent only the translation is written.
    assert!(out.json["nodes"][d].get("rotation").is_none());
    assert!(out.json["nodes"][d].get("scale").is_none());
}

/// A quad drawn unskinned by node "quad", placed as `quad` says, under
/// `parent` when given, and a file around it.
fn unskinned(quad_node: Value, parent: Option<Value>) -> GltfFile {
    let mut parts = GlbParts::default();
    let mesh = quad(&mut parts);
    let mut nodes = vec![quad_node];
    if let Some(mut p) = parent {
        p["children"] = json!([0]);
        nodes.push(p);
    }
    document(parts, json!({"nodes": nodes, "meshes": [mesh]}))
}

/// Binds the quad of `f` to a new skin of two new joints (a hand and a
/// finger) with weights that mix them, moves the finger, and returns
/// the file written.
fn skin_the_quad(f: &GltfFile) -> GltfFile {
    let mut edit = Edit::new(f, Path::new(".")).unwrap();
    let hand = edit
        .add_node("hand", None, DVec3::new(0.2, 0.1, -0.3))
        .unwrap();
    let finger = edit
        .add_node("finger", Some(hand), DVec3::new(0.8, 0.6, 0.1))
        .unwrap();
    let quad = node(f, "quad");
    let skin = edit.new_skin(quad, &[hand, finger], Some(hand)).unwrap();
    assert_eq!(skin, 0);
    edit.set_weights(
        0,
        0,
        &[
            vec![(hand, 1.0)],
            vec![(hand, 0.5), (finger, 0.5)],
            vec![(finger, 1.0)],
            vec![(finger, 3.0), (hand, 1.0)],
        ],
    )
    .unwrap();
    edit.move_nodes(&[(finger, DVec3::new(0.9, 0.7, 0.2))])
        .unwrap();
    let (out, warnings) = finished(edit);
    assert!(warnings.is_empty(), "{warnings:?}");
    // The rest shape is where the node drew the quad unskinned.
    close(&rest(&out), &drawn(f, quad), 1e-5);
    // And a skinned mesh is drawn by a root without a transform.
    let drawer = (0..out.parent.len())
        .find(|&n| out.json["nodes"][n]["skin"].as_u64() == Some(0))
        .unwrap();
    assert_eq!(out.parent[drawer], None);
    assert_eq!(out.world[drawer], DMat4::IDENTITY);
    assert!(
        out.json["scenes"][0]["nodes"]
            .as_array()
            .unwrap()
            .contains(&json!(drawer))
    );
    out
}

#[test]
fn a_new_skin_keeps_an_unskinned_quads_rest_shape() {
    let turned = json!({"name": "arm", "rotation": quarter_turn(), "scale": [2.0, 2.0, 2.0],
                        "translation": [1.0, 2.0, 3.0]});
    // A leaf under a transformed parent: it becomes a root without a transform.
    let f = unskinned(
        json!({"name": "quad", "mesh": 0, "translation": [0.0, 0.5, 0.0]}),
        Some(turned.clone()),
    );
    let out = skin_the_quad(&f);
    assert_eq!(out.parent[node(&out, "quad")], None);
    assert!(
        out.json["nodes"][node(&out, "arm")]
            .get("children")
            .is_none()
    );
    // A root without a transform takes the skin as it is.
    let f = unskinned(json!({"name": "quad", "mesh": 0}), None);
    let out = skin_the_quad(&f);
    assert_eq!(out.json["nodes"][0]["skin"], json!(0));
    // A transformed node with a child keeps its place and child; a new
    // root draws the mesh.
    let mut parts = GlbParts::default();
    let mesh = quad(&mut parts);
    let f = document(
        parts,
        json!({
            "nodes": [
                {"name": "quad", "mesh": 0, "translation": [0.0, 0.5, 0.0], "scale": [3.0, 1.0, 1.0], "children": [1]},
                {"name": "child", "translation": [1.0, 0.0, 0.0]},
                {"name": "arm", "rotation": quarter_turn(), "translation": [1.0, 2.0, 3.0], "children": [0]}
            ],
            "meshes": [mesh]
        }),
    );
    let out = skin_the_quad(&f);
    let drawer = node(&out, "quad (skinned)");
    assert_eq!(out.json["nodes"][drawer]["mesh"], json!(0));
    assert!(out.json["nodes"][node(&out, "quad")].get("mesh").is_none());
    assert_eq!(out.world[node(&out, "child")], f.world[1]);
}

#[test]
fn a_new_skin_needs_weights_joints_of_one_root_and_its_own_mesh() {
    let f = unskinned(json!({"name": "quad", "mesh": 0}), None);
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let a = edit.add_node("a", None, DVec3::X).unwrap();
    let b = edit.add_node("b", None, DVec3::Y).unwrap();
    let e = edit.new_skin(0, &[a, b], None).unwrap_err();
    assert!(e.to_string().contains("one root"), "{e}");
    let e = edit.new_skin(0, &[a], Some(b)).unwrap_err();
    assert!(e.to_string().contains("skeleton"), "{e}");
    assert!(
        edit.new_skin(a, &[a], None).is_err(),
        "a node without a mesh"
    );
    // Weights before a skin, then a skin without weights.
    assert!(edit.set_weights(0, 0, &vec![vec![(a, 1.0)]; 4]).is_err());
    edit.new_skin(0, &[a], None).unwrap();
    assert!(edit.new_skin(0, &[a], None).is_err(), "skinned twice");
    let e = edit.finish(true).unwrap_err();
    assert!(e.to_string().contains("no weights"), "{e}");
}

/// A quad skinned to 300 joints (a root and 299 children along x, bound
/// where they are) with two sets of unsigned byte joints and normalised
/// byte weights: set 0 on joints 1 and 2, set 1 empty.
fn three_hundred_joints() -> GltfFile {
    let mut parts = GlbParts::default();
    let mut mesh = quad(&mut parts);
    let mut nodes = vec![json!({"name": "j0", "children": (1..300).collect::<Vec<_>>()})];
    let mut ibm = vec![DMat4::IDENTITY];
    for k in 1..300 {
        let t = DVec3::new(0.01 * k as f64, 0.0, 0.0);
        nodes.push(json!({"name": format!("j{k}"), "translation": t.to_array()}));
        ibm.push(DMat4::from_translation(-t));
    }
    let ibm: Vec<f32> = ibm
        .iter()
        .flat_map(|m| m.as_mat4().to_cols_array())
        .collect();
    let ibm = parts.accessor(&ibm, 5126, "MAT4", None);
    let attrs = &mut mesh["primitives"][0]["attributes"];
    for (set, (j, w)) in [([1u8, 2, 0, 0], [200u8, 55, 0, 0]), ([0; 4], [0; 4])]
        .into_iter()
        .enumerate()
    {
        let js = parts.accessor(&j.repeat(4), 5121, "VEC4", None);
        let ws = parts.accessor(&w.repeat(4), 5121, "VEC4", None);
        parts.accessors[ws]["normalized"] = json!(true);
        attrs[format!("JOINTS_{set}")] = json!(js);
        attrs[format!("WEIGHTS_{set}")] = json!(ws);
    }
    nodes.push(json!({"name": "skinned", "mesh": 0, "skin": 0}));
    document(
        parts,
        json!({
            "nodes": nodes,
            "meshes": [mesh],
            "skins": [{"joints": (0..300).collect::<Vec<_>>(), "inverseBindMatrices": ibm, "skeleton": 0}]
        }),
    )
}

/// The influences the readers see on each vertex of the first skinned primitive.
fn influences(f: &GltfFile) -> Vec<Vec<(usize, f64)>> {
    SkinWeights::read(f, &f.buffer_data().unwrap()).primitives[0]
        .influences
        .clone()
}

fn same(a: &[Vec<(usize, f64)>], b: &[Vec<(usize, f64)>], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.len(), y.len(), "{x:?} != {y:?}");
        for (p, q) in x.iter().zip(y) {
            assert!(p.0 == q.0 && (p.1 - q.1).abs() <= tol, "{x:?} != {y:?}");
        }
    }
}

#[test]
fn weights_are_written_in_place_when_they_fit_and_widened_when_not() {
    let f = three_hundred_joints();
    let accessors = f.json["accessors"].as_array().unwrap().len();
    let before = rest(&f);
    close(&before, &drawn(&f, 0), 1e-6);
    // Slots under 256 fit the bytes: written over them, set 1 zeroed.
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let given = vec![
        vec![(7, 0.75), (3, 0.25)],
        vec![(255, 1.0)],
        vec![(1, 0.5), (2, 0.3), (3, 0.2)],
        vec![(4, 0.25), (5, 0.25), (6, 0.25), (9, 0.25)],
    ];
    edit.set_weights(0, 0, &given).unwrap();
    let (out, warnings) = finished(edit);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(out.json["meshes"], f.json["meshes"]);
    assert_eq!(out.json["accessors"].as_array().unwrap().len(), accessors);
    same(&influences(&out), &given, 1.0 / 255.0);
    close(&rest(&out), &before, 1e-5);
    // Slot 299 does not: new unsigned short joints and float weights
    // replace both sets, and the old accessors are gone.
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let given = vec![
        vec![(299, 0.6), (298, 0.4)],
        vec![(1, 1.0)],
        vec![(2, 0.5), (150, 0.5)],
        vec![(299, 1.0)],
    ];
    edit.set_weights(0, 0, &given).unwrap();
    let (out, _) = finished(edit);
    let attrs = &out.json["meshes"][0]["primitives"][0]["attributes"];
    assert!(attrs.get("JOINTS_1").is_none() && attrs.get("WEIGHTS_1").is_none());
    let acc = |k: &str| &out.json["accessors"][attrs[k].as_u64().unwrap() as usize];
    assert_eq!(acc("JOINTS_0")["componentType"], json!(5123));
    assert_eq!(acc("WEIGHTS_0")["componentType"], json!(5126));
    assert_eq!(
        out.json["accessors"].as_array().unwrap().len(),
        accessors - 2
    );
    same(&influences(&out), &given, 1e-6);
    close(&rest(&out), &before, 1e-5);
    // Positions, indices and the inverse bind matrices read as before.
    assert_eq!(acc("POSITION")["max"], json!([1.0, 1.0, 0.0]));
}

#[test]
fn weights_are_merged_cut_to_the_largest_four_and_renormalised() {
    let f = three_hundred_joints();
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    edit.set_weights(
        0,
        0,
        &[
            vec![(1, 2.0), (2, 2.0)],
            vec![(3, 1.0), (3, 1.0), (4, 1.0), (5, 0.0)],
            vec![(1, 5.0), (2, 4.0), (3, 3.0), (4, 2.0), (5, 1.0), (6, 0.5)],
            vec![(9, 0.1)],
        ],
    )
    .unwrap();
    let (out, _) = finished(edit);
    let want = vec![
        vec![(1, 0.5), (2, 0.5)],
        vec![(3, 2.0 / 3.0), (4, 1.0 / 3.0)],
        vec![
            (1, 5.0 / 14.0),
            (2, 4.0 / 14.0),
            (3, 3.0 / 14.0),
            (4, 2.0 / 14.0),
        ],
        vec![(9, 1.0)],
    ];
    same(&influences(&out), &want, 1.0 / 255.0);
}

#[test]
fn bad_influences_are_errors_not_panics() {
    let f = three_hundred_joints();
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let ok = vec![vec![(1, 1.0)]; 4];
    let with = |v: usize, infl: Vec<(usize, f64)>| {
        let mut all = ok.clone();
        all[v] = infl;
        all
    };
    type Influences = Vec<Vec<(usize, f64)>>;
    let cases: Vec<(Influences, &str)> = vec![
        (with(2, vec![(300, 1.0)]), "not a joint"),
        (with(2, vec![(100_000, 1.0)]), "not a joint"),
        (with(0, vec![(1, -0.5), (2, 1.0)]), "not negative"),
        (with(1, vec![(1, f64::NAN)]), "not negative"),
        (with(3, vec![]), "no weight"),
        (with(3, vec![(1, 0.0)]), "no weight"),
        (ok[..3].to_vec(), "4 vertices"),
    ];
    for (infl, words) in cases {
        let e = edit.set_weights(0, 0, &infl).unwrap_err().to_string();
        assert!(e.contains(words), "{e}");
    }
    assert!(edit.set_weights(0, 1, &ok).is_err());
    assert!(edit.set_weights(1, 0, &ok).is_err());
    // A joint under another root, and an unknown node or skin.
    let other = edit.add_node("other", None, DVec3::ONE).unwrap();
    let e = edit.add_joints(0, &[other]).unwrap_err().to_string();
    assert!(e.contains("one root"), "{e}");
    assert!(edit.add_joints(0, &[100_000]).is_err());
    assert!(edit.add_joints(1, &[other]).is_err());
    assert!(edit.move_nodes(&[(100_000, DVec3::ZERO)]).is_err());
}

#[test]
fn joints_added_to_a_skin_and_moved_keep_its_rest_shape() {
    let f = three_hundred_joints();
    let before = rest(&f);
    let accessors = f.json["accessors"].as_array().unwrap().len();
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let tip = edit
        .add_node("tip", Some(2), DVec3::new(0.5, 0.5, 0.0))
        .unwrap();
    edit.add_joints(0, &[tip, 2]).unwrap();
    edit.move_nodes(&[
        (2, DVec3::new(0.3, 0.2, 0.1)),
        (1, DVec3::new(-0.1, 0.0, 0.0)),
    ])
    .unwrap();
    edit.set_weights(
        0,
        0,
        &[
            vec![(tip, 1.0)],
            vec![(tip, 0.5), (2, 0.5)],
            vec![(1, 0.2), (tip, 0.8)],
            vec![(299, 1.0)],
        ],
    )
    .unwrap();
    let (out, warnings) = finished(edit);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(
        out.json["skins"][0]["joints"].as_array().unwrap().len(),
        301
    );
    assert_eq!(out.json["skins"][0]["joints"][300], json!(tip));
    // The old inverse bind matrices went with their accessor, and both
    // weight sets with theirs (slot 300 needs short joints); the new
    // matrices serve 301 joints.
    assert_eq!(
        out.json["accessors"].as_array().unwrap().len(),
        accessors - 2
    );
    let acc = &out.json["accessors"][out.json["skins"][0]["inverseBindMatrices"]
        .as_u64()
        .unwrap() as usize];
    assert_eq!(acc["count"], json!(301));
    close(&rest(&out), &before, 1e-5);
}

#[test]
fn new_weights_that_move_the_rest_shape_say_so() {
    // Joint 1 is bound as if at the origin, while it sits at x = 1: its
    // rest skin matrix is not joint 0's.
    let mut parts = GlbParts::default();
    let mut mesh = quad(&mut parts);
    let j = parts.accessor(&[0u16, 0, 0, 0].repeat(4), 5123, "VEC4", None);
    let w = parts.accessor(&[1.0f32, 0.0, 0.0, 0.0].repeat(4), 5126, "VEC4", None);
    mesh["primitives"][0]["attributes"]["JOINTS_0"] = json!(j);
    mesh["primitives"][0]["attributes"]["WEIGHTS_0"] = json!(w);
    let f = document(
        parts,
        json!({
            "nodes": [
                {"name": "a", "children": [1]}, {"name": "b", "translation": [1.0, 0.0, 0.0]},
                {"name": "skinned", "mesh": 0, "skin": 0}
            ],
            "meshes": [mesh],
            "skins": [{"joints": [0, 1]}]
        }),
    );
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    edit.set_weights(
        0,
        0,
        &[
            vec![(0, 1.0)],
            vec![(1, 1.0)],
            vec![(0, 1.0)],
            vec![(1, 0.5), (0, 0.5)],
        ],
    )
    .unwrap();
    let (_, warnings) = finished(edit);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("2 vertices rest up to 1.000000"),
        "{warnings:?}"
    );
}
