//! The file around an edit: its buffers merged into one, a node's JSON
//! from its matrix, the remarks on what is left alone, and the container written.

use crate::dataset::DataError;
use crate::rig::fix::accessor;
use crate::rig::read::anim as channels;
use crate::rig::read::gltf::{GltfFile, buffers};
use glam::{DMat4, DQuat, DVec3};
use serde_json::{Value, json};
use std::path::Path;

/// A node named `name` whose translation, rotation and scale (at f32
/// precision, defaults left out) make `local`, and the local matrix they
/// make as a reader computes it; `None` when `local` shears.
pub(super) fn trs_node(name: &str, local: &DMat4) -> Option<(Value, DMat4)> {
    let (s, r, t) = local.to_scale_rotation_translation();
    let snap = |x: f64| if x.abs() < 1e-12 { 0.0 } else { x };
    let f32s = |v: [f64; 3]| v.map(|x| f64::from(snap(x) as f32));
    let t = f32s(t.to_array());
    let s = f32s(s.to_array()).map(|x| if (x - 1.0).abs() < 1e-12 { 1.0 } else { x });
    let r = r.to_array().map(|x| f64::from(snap(x) as f32));
    let stored = DMat4::from_scale_rotation_translation(
        DVec3::from_array(s),
        DQuat::from_array(r).normalize(),
        DVec3::from_array(t),
    );
    // A rotation and scale reproduce the upper 3x3 up to f32 rounding; a shear they cannot.
    let size = (0..3)
        .map(|c| local.col(c).truncate().abs().max_element())
        .fold(0.0, f64::max);
    let off = (0..3)
        .map(|c| {
            (stored.col(c) - local.col(c))
                .truncate()
                .abs()
                .max_element()
        })
        .fold(0.0, f64::max);
    if off.is_nan() || off > 1e-5 * size {
        return None;
    }
    let mut node = json!({"name": name, "translation": t});
    if r != [0.0, 0.0, 0.0, 1.0] && r != [0.0, 0.0, 0.0, -1.0] {
        node["rotation"] = json!(r);
    }
    if s != [1.0; 3] {
        node["scale"] = json!(s);
    }
    Some((node, stored))
}

/// Writes a node's new local translation into its JSON (into `matrix` when it has one).
pub(super) fn write_translation(node: &mut Value, t: DVec3) {
    if let Some(m) = node.get_mut("matrix").and_then(Value::as_array_mut) {
        for (k, v) in t.to_array().into_iter().enumerate() {
            m[12 + k] = json!(v);
        }
    } else {
        node["translation"] = json!(t.to_array());
    }
}

/// Merges every buffer into one (each start 4-byte aligned) and points the
/// buffer views into it; returns the buffers as read and the merged bytes.
pub(super) fn merge_buffers(
    file: &GltfFile,
    json: &mut Value,
    dir: &Path,
) -> Result<(Vec<Vec<u8>>, Vec<u8>), DataError> {
    if let Some(k) = json["bufferViews"]
        .as_array()
        .and_then(|v| v.iter().position(|v| v.get("extensions").is_some()))
    {
        return Err(DataError::whole_file(
            &file.label,
            format!(
                "bufferView {k} carries an extension (EXT_meshopt_compression?) that points into buffers; \
                 --fix cannot rewrite it: decompress the file first (e.g. gltf-transform)"
            ),
        ));
    }
    let data = buffers(file, dir)?;
    let mut bin = Vec::new();
    let mut starts = Vec::new();
    for d in &data {
        accessor::pad4(&mut bin);
        starts.push(bin.len());
        bin.extend_from_slice(d);
    }
    if let Some(views) = json.get_mut("bufferViews").and_then(Value::as_array_mut) {
        for (k, v) in views.iter_mut().enumerate() {
            let b = v["buffer"].as_u64().unwrap_or(0) as usize;
            let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
            let moved = starts
                .get(b)
                .and_then(|s| s.checked_add(off))
                .ok_or_else(|| {
                    DataError::whole_file(
                        &file.label,
                        format!("bufferView {k} has an impossible byteOffset"),
                    )
                })?;
            v["buffer"] = json!(0);
            v["byteOffset"] = json!(moved);
        }
    }
    Ok((data, bin))
}

/// Remarks on what an edit leaves alone: animation channels with paths glTF
/// does not define, and images left as external files.
pub(super) fn other_warnings(file: &GltfFile) -> Vec<String> {
    let mut warnings = channels::unknown_paths(&file.json);
    if file.document.images().any(
        |i| matches!(i.source(), gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:")),
    ) {
        warnings.push(
            "images referenced by file name stay external: copy them beside the output".into(),
        );
    }
    warnings
}

/// The output file: the JSON alone (`.gltf`, buffer embedded), or a GLB with the bytes.
pub(super) fn container(
    file: &GltfFile,
    json: &Value,
    bin: Vec<u8>,
    glb: bool,
) -> Result<Vec<u8>, DataError> {
    let bytes = if glb {
        crate::rig::read::gltf::glb(json, bin)
    } else {
        serde_json::to_vec(json).map_err(|e| e.to_string())
    };
    bytes.map_err(|e| DataError::whole_file(&file.label, e))
}
