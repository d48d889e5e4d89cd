//! FBX rigs (binary and ASCII, FBX 6100 to 7700), read with the ufbx loader
//! and handed on as a glTF 2.0 document in memory, so that recognition,
//! judgement, bends, skin tips and deformation read one kind of scene
//! whatever the file was.
//!
//! ufbx (the `ufbx` crate, Rust bindings of the C loader) does the reading:
//! the binary and ASCII syntax, FBX's transform stack (pivots, pre- and
//! post-rotations, offsets) and the conversion to metres and +Y up
//! (`target_unit_meters`, `target_axes`; the conversion is put on the scene's
//! root node, so every other node keeps its transform in the file's own units
//! and axes). What is taken from it:
//!
//! - Nodes: every node of the scene, the root first, with its name and parent.
//! - The bind pose from the skin clusters: a bone's world matrix is its
//!   cluster's `bind_to_world`, not its current transform (a file saved in
//!   another pose keeps its bind pose in the clusters); a node without a
//!   cluster sits at its current local transform below its parent's bind
//!   pose. glTF nodes get local matrices W_parent^-1 W.
//! - Skinned meshes: the mesh's vertices in geometry space, its faces
//!   triangulated by ufbx, and per skin deformer a glTF skin whose joints are
//!   the clusters' bones with inverse bind matrices `geometry_to_bone`, so
//!   W_j B_j v puts every vertex where the file binds it. Clusters with no
//!   bone or no weight keep their slot; meshes without a skin are left out.
//!
//! ufbx cannot write FBX, so an FBX rig is never fixed in place: `audit
//! --moves` lists each moved joint with its new `Lcl Translation`
//! ([`FbxSource::lcl_translation`] plus the change of the node's origin in its
//! parent's frame). Cost: O(file size + vertices x influences).

use super::GltfFile;
use super::glb_parts::{GlbParts, bounds};
use super::naming::shown;
use super::skin::SkinnedMesh;
use super::source::FbxSource;
use crate::dataset::DataError;
use glam::{DMat4, DVec3, DVec4};
use serde_json::{Value, json};
use std::path::Path;

/// How far (metres, and per matrix entry) a bone's current world matrix may
/// be from its cluster's bind matrix and still count as in its bind pose.
const OFF_BIND: f64 = 1e-6;

/// The magic of a binary FBX file.
const BINARY_MAGIC: &[u8] = b"Kaydara FBX Binary";

/// True when the file is FBX: the binary magic, an ASCII FBX header in its
/// first kilobyte, or a `.fbx` name (so that a file renamed `.fbx` is
/// refused as FBX, saying what it is not).
pub fn is_fbx(path: &Path, bytes: &[u8]) -> bool {
    bytes.starts_with(BINARY_MAGIC)
        || ascii_header(bytes)
        || path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("fbx"))
}

/// The last 16 bytes of a whole binary FBX file (the FBX SDK writes them
/// after the footer; ufbx does not need them, so a file cut short can still
/// fail on its data first).
const BINARY_END: [u8; 16] = [
    0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5, 0xd9, 0x7e, 0xec, 0xe9, 0x0c, 0xe3, 0x75, 0x8f, 0x29, 0x0b,
];

/// The user's message for a file ufbx refuses.
fn describe(e: &ufbx::Error, bytes: &[u8]) -> String {
    use ufbx::ErrorType as E;
    let what: &str = &e.description;
    let cut = bytes.starts_with(BINARY_MAGIC) && !bytes.ends_with(&BINARY_END);
    match e.type_ {
        _ if cut && e.type_ != E::UnsupportedVersion => format!(
            "is cut short: a binary FBX file that does not end with the FBX footer ({} bytes; \
             ufbx: {what}); copy or export the file again",
            bytes.len()
        ),
        E::EmptyFile => "is empty; it is no FBX file".into(),
        E::TruncatedFile => format!(
            "is cut short: the FBX data ends before it should ({} bytes read; ufbx: {what}); \
             copy or export the file again",
            bytes.len()
        ),
        E::UnrecognizedFileFormat => "is not an FBX file: it is neither binary FBX (which starts \
             with \"Kaydara FBX Binary\") nor ASCII FBX; export the rig as FBX, or give its .glb \
             or .gltf"
            .into(),
        E::UnsupportedVersion => {
            format!("is an FBX version that cannot be read ({what}); export it as FBX 7.4 or later")
        }
        E::OutOfMemory | E::MemoryLimit | E::AllocationLimit => format!(
            "needs more memory to read than an FBX file of {} bytes should (ufbx: {what}); it is \
             likely corrupt: export it again",
            bytes.len()
        ),
        _ if !bytes.starts_with(BINARY_MAGIC) && !ascii_header(bytes) => format!(
            "is not an FBX file: it is {}, with neither the binary FBX header (\"Kaydara FBX \
             Binary\") nor an ASCII FBX one; export the rig as FBX, or give its .glb or .gltf",
            what_it_is(bytes)
        ),
        _ => format!("is a broken FBX file ({what}); export it again"),
    }
}

/// True when the first kilobyte reads as an ASCII FBX file's start.
fn ascii_header(bytes: &[u8]) -> bool {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(1024)]);
    head.trim_start().starts_with("; FBX") || head.contains("FBXHeaderExtension:")
}

/// What a file that is no FBX seems to be, for the message.
fn what_it_is(bytes: &[u8]) -> &'static str {
    if bytes.starts_with(b"\x89PNG") {
        "a PNG image"
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        "a JPEG image"
    } else if bytes.starts_with(b"glTF") {
        "a binary glTF (GLB) file: name it .glb"
    } else if bytes.trim_ascii_start().starts_with(b"{") {
        "JSON (a .gltf file? name it .gltf)"
    } else if std::str::from_utf8(bytes).is_ok() {
        "text"
    } else {
        "binary data"
    }
}

/// ufbx's matrix (3 x 4 affine, columns) as a glam matrix.
fn mat(m: &ufbx::Matrix) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(m.m00, m.m10, m.m20, 0.0),
        DVec4::new(m.m01, m.m11, m.m21, 0.0),
        DVec4::new(m.m02, m.m12, m.m22, 0.0),
        DVec4::new(m.m03, m.m13, m.m23, 1.0),
    )
}

/// An axis as `-X`, `+Y`.
fn axis(a: ufbx::CoordinateAxis) -> &'static str {
    use ufbx::CoordinateAxis as A;
    match a {
        A::PositiveX => "+X",
        A::NegativeX => "-X",
        A::PositiveY => "+Y",
        A::NegativeY => "-Y",
        A::PositiveZ => "+Z",
        A::NegativeZ => "-Z",
        A::Unknown => "?",
    }
}

/// The load options: FBX only, metres and +Y up (right-handed, +Z front, as
/// glTF) by a transform on the root, no animation or embedded media, and a
/// memory limit that grows with the file (a corrupt count cannot ask for more).
fn options<'a>(bytes: &[u8]) -> ufbx::LoadOpts<'a> {
    let mut opts = ufbx::LoadOpts {
        file_format: ufbx::FileFormat::Fbx,
        target_axes: ufbx::CoordinateAxes {
            right: ufbx::CoordinateAxis::PositiveX,
            up: ufbx::CoordinateAxis::PositiveY,
            front: ufbx::CoordinateAxis::PositiveZ,
        },
        target_unit_meters: 1.0,
        space_conversion: ufbx::SpaceConversion::TransformRoot,
        ignore_animation: true,
        ignore_embedded: true,
        ..Default::default()
    };
    let limit = (256usize << 20).saturating_add(bytes.len().saturating_mul(64));
    opts.temp_allocator.memory_limit = limit;
    opts.result_allocator.memory_limit = limit;
    opts
}

/// Loads FBX bytes with the options the reader uses (for tests that read the
/// file independently of the glTF it becomes).
pub fn load(label: &str, bytes: &[u8]) -> Result<ufbx::SceneRoot, DataError> {
    ufbx::load_memory(bytes, options(bytes))
        .map_err(|e| DataError::whole_file(label, describe(&e, bytes)))
}

/// Reads an FBX file's bytes as a glTF document in memory (see the module
/// doc); `label` names the file in errors.
pub fn read(label: &str, bytes: &[u8]) -> Result<GltfFile, DataError> {
    let fail = |what: String| DataError::whole_file(label, what);
    let scene = load(label, bytes)?;
    let n = scene.nodes.len();
    let index = |node: &ufbx::Node| {
        let i = node.element.typed_id as usize;
        (i < n).then_some(i)
    };
    let mut parent = vec![None; n];
    for nd in scene.nodes.iter() {
        let i = index(nd).ok_or_else(|| fail("has a node outside its node list".into()))?;
        parent[i] = nd.parent.as_ref().and_then(|p| index(p));
    }
    // The bind pose: each bone's first cluster, then the current local
    // transforms below, parents first.
    let mut bind: Vec<Option<DMat4>> = vec![None; n];
    for d in scene.skin_deformers.iter() {
        for c in d.clusters.iter() {
            if let Some(i) = c.bone_node.as_ref().and_then(|b| index(b))
                && bind[i].is_none()
            {
                bind[i] = Some(mat(&c.bind_to_world));
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| scene.nodes[i].node_depth);
    let mut world = vec![DMat4::IDENTITY; n];
    for &i in &order {
        let nd = &scene.nodes[i];
        world[i] = match (bind[i], parent[i]) {
            (Some(b), _) => b,
            (None, Some(p)) => world[p] * mat(&nd.node_to_parent),
            (None, None) => mat(&nd.node_to_world),
        };
    }
    let name = |i: usize| -> String { scene.nodes[i].element.name.to_string() };
    if let Some(i) = (0..n).find(|&i| !world[i].is_finite()) {
        return Err(fail(format!(
            "node {} has a non-finite transform (a zero scale above it, or a huge value); fix \
             its transform or its parents'",
            shown(&name(i))
        )));
    }
    let mut nodes: Vec<Value> = Vec::with_capacity(n);
    for i in 0..n {
        let local = match parent[i] {
            Some(p) => world[p].inverse() * world[i],
            None => world[i],
        };
        if !local.is_finite() {
            return Err(fail(format!(
                "node {} sits below a node with a singular transform (a zero scale); fix the \
                 scale of its parent",
                shown(&name(i))
            )));
        }
        let mut node = json!({ "matrix": local.to_cols_array() });
        let nm = name(i);
        if !nm.is_empty() {
            node["name"] = json!(nm);
        }
        let children: Vec<usize> = (0..n).filter(|&c| parent[c] == Some(i)).collect();
        if !children.is_empty() {
            node["children"] = json!(children);
        }
        nodes.push(node);
    }
    let (parts, skins, meshes) = skinned_meshes(&scene, &index, &mut nodes);
    let roots: Vec<usize> = (0..n).filter(|&i| parent[i].is_none()).collect();
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": format!("phalanx, read from FBX {}", scene.metadata.version)},
        "scene": 0,
        "scenes": [{"nodes": roots}],
        "nodes": nodes,
    });
    if !skins.is_empty() {
        doc["skins"] = json!(skins);
        doc["meshes"] = json!(meshes);
        doc["accessors"] = json!(parts.accessors);
        doc["bufferViews"] = json!(parts.views);
        doc["buffers"] = json!([{"byteLength": parts.bin.len()}]);
    }
    let glb = super::gltf::glb(&doc, parts.bin).map_err(fail)?;
    let mut file = GltfFile::from_bytes(label, &glb)?;
    // The glTF document holds its matrices in f32: a transform finite in f64
    // can overflow there (found by the fuzz target), so check again.
    if let Some(i) = (0..n.min(file.world.len())).find(|&i| !file.world[i].is_finite()) {
        return Err(fail(format!(
            "node {} has a transform too large to hold (beyond 32-bit floats, as glTF keeps \
             them, in metres); fix its transform or its parents'",
            shown(&name(i))
        )));
    }
    file.fbx = Some(fbx_source(&scene, &bind));
    Ok(file)
}

/// The skinned meshes of `scene` as glTF: their accessors' bytes, skins and
/// meshes; each mesh and its skin set on the `nodes` that draw it (a node's
/// first). Meshes without a skin, triangles or joints are left out.
fn skinned_meshes(
    scene: &ufbx::Scene,
    index: &impl Fn(&ufbx::Node) -> Option<usize>,
    nodes: &mut [Value],
) -> (GlbParts, Vec<Value>, Vec<Value>) {
    let mut parts = GlbParts::default();
    let mut skins = Vec::new();
    let mut meshes = Vec::new();
    for mesh in scene.meshes.iter() {
        let Some(d) = mesh.skin_deformers.first() else {
            continue;
        };
        let Some(m) = skinned_mesh(mesh, d, index) else {
            continue;
        };
        if m.triangles.is_empty() || m.joints.is_empty() {
            continue;
        }
        let positions: Vec<[f32; 3]> = m.positions.iter().map(|p| p.as_vec3().to_array()).collect();
        let (lo, hi) = bounds(&positions);
        let pos = parts.accessor(
            &positions.concat(),
            5126,
            "VEC3",
            Some((lo.to_vec(), hi.to_vec())),
        );
        let tris: Vec<u32> = m.triangles.iter().flatten().copied().collect();
        let idx = parts.accessor(&tris, 5125, "SCALAR", None);
        let mut attributes = serde_json::Map::new();
        attributes.insert("POSITION".into(), pos.into());
        parts.weight_sets(&m, &mut attributes);
        let ibm: Vec<f32> = m
            .inverse_bind
            .iter()
            .flat_map(|b| b.as_mat4().to_cols_array())
            .collect();
        let ibm = parts.accessor(&ibm, 5126, "MAT4", None);
        let (s, k) = (skins.len(), meshes.len());
        skins.push(json!({"joints": m.joints, "inverseBindMatrices": ibm}));
        let mut mesh_json =
            json!({"primitives": [{"attributes": attributes, "indices": idx, "mode": 4}]});
        // A mesh without a name of its own goes by the node that draws it
        // (a DCC lists the object), which the moves' weights file names.
        let mut nm = mesh.element.name.to_string();
        if nm.is_empty()
            && let Some(inst) = mesh.element.instances.iter().next()
        {
            nm = inst.element.name.to_string();
        }
        if !nm.is_empty() {
            mesh_json["name"] = json!(nm);
        }
        meshes.push(mesh_json);
        for inst in mesh.element.instances.iter() {
            if let Some(i) = index(inst)
                && nodes[i].get("mesh").is_none()
            {
                nodes[i]["mesh"] = json!(k);
                nodes[i]["skin"] = json!(s);
            }
        }
    }
    (parts, skins, meshes)
}

/// What the FBX file was: its version, units and axes, and per node its
/// Lcl Translation, inheritance and whether its bind pose (`bind`) is off
/// its current pose.
fn fbx_source(scene: &ufbx::Scene, bind: &[Option<DMat4>]) -> FbxSource {
    let n = scene.nodes.len();
    let s = &scene.settings;
    FbxSource {
        version: scene.metadata.version,
        ascii: scene.metadata.ascii,
        unit_meters: s.unit_meters,
        axes: format!(
            "{} right, {} up, {} front",
            axis(s.axes.right),
            axis(s.axes.up),
            axis(s.axes.front)
        ),
        lcl_translation: (0..n)
            .map(|i| {
                let nd = &scene.nodes[i];
                (!nd.is_root).then(|| {
                    ufbx::find_prop(&nd.element.props, "Lcl Translation").map_or(DVec3::ZERO, |p| {
                        DVec3::new(p.value_vec4.x, p.value_vec4.y, p.value_vec4.z)
                    })
                })
            })
            .collect(),
        inherits_normally: (0..n)
            .map(|i| scene.nodes[i].inherit_mode == ufbx::InheritMode::Normal)
            .collect(),
        off_bind: (0..n)
            .map(|i| {
                bind[i]
                    .is_some_and(|b| !b.abs_diff_eq(mat(&scene.nodes[i].node_to_world), OFF_BIND))
            })
            .collect(),
    }
}

/// One ufbx mesh with its skin deformer as a skinned mesh: vertices in
/// geometry space, faces triangulated, influences per vertex by joint slot
/// (largest first, positive weights only, normalised by the skin reader);
/// `None` when the deformer's vertex count is not the mesh's.
fn skinned_mesh(
    mesh: &ufbx::Mesh,
    d: &ufbx::SkinDeformer,
    index: &impl Fn(&ufbx::Node) -> Option<usize>,
) -> Option<SkinnedMesh> {
    let nv = mesh.vertices.len();
    if d.vertices.len() != nv || nv > u32::MAX as usize {
        return None;
    }
    let mut slot_of = vec![None; d.clusters.len()];
    let mut joints = Vec::new();
    let mut inverse_bind = Vec::new();
    for (ci, c) in d.clusters.iter().enumerate() {
        if let Some(i) = c.bone_node.as_ref().and_then(|b| index(b))
            && joints.len() < usize::from(u16::MAX)
        {
            slot_of[ci] = u16::try_from(joints.len()).ok();
            joints.push(i);
            inverse_bind.push(mat(&c.geometry_to_bone));
        }
    }
    let positions: Vec<DVec3> = mesh
        .vertices
        .iter()
        .map(|p| DVec3::new(p.x, p.y, p.z))
        .collect();
    let mut triangles = Vec::new();
    let mut scratch = vec![0u32; mesh.max_face_triangles.saturating_mul(3)];
    for &face in mesh.faces.iter() {
        if face.num_indices < 3 {
            continue;
        }
        let k = ufbx::triangulate_face(&mut scratch, mesh, face) as usize;
        for t in scratch.chunks_exact(3).take(k) {
            let v = |x: u32| {
                mesh.vertex_indices
                    .get(x as usize)
                    .copied()
                    .filter(|&v| (v as usize) < nv)
            };
            if let (Some(a), Some(b), Some(c)) = (v(t[0]), v(t[1]), v(t[2])) {
                triangles.push([a, b, c]);
            }
        }
    }
    let mut influences = Vec::new();
    let mut influence_start = Vec::with_capacity(nv + 1);
    for sv in d.vertices.iter() {
        influence_start.push(influences.len());
        let begin = sv.weight_begin as usize;
        let end = begin
            .saturating_add(sv.num_weights as usize)
            .min(d.weights.len());
        let mut list: Vec<(u16, f64)> = d.weights.as_ref()[begin.min(end)..end]
            .iter()
            .filter(|w| w.weight.is_finite() && w.weight > 0.0)
            .filter_map(|w| Some((slot_of.get(w.cluster_index as usize).copied()??, w.weight)))
            .collect();
        let sum: f64 = list.iter().map(|x| x.1).sum();
        if sum > 0.0 {
            for x in &mut list {
                x.1 /= sum;
            }
        }
        list.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        influences.extend(list);
    }
    influence_start.push(influences.len());
    let welded = super::skin::weld(&positions);
    Some(SkinnedMesh {
        skin: 0,
        positions,
        triangles,
        influences,
        influence_start,
        joints,
        inverse_bind,
        welded,
        notes: Vec::new(),
    })
}
