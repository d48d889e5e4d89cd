//! `audit --fix`: a copy of a rig with its fingers' middle joints at the mean.
//!
//! For each finger the judged inner joints move to their suggested points (on
//! the rig's own chain, see [`crate::analysis::audit`]); the root, the tip and
//! any joint that was not judged keep their world positions. Only translations
//! change: a moved node's local translation becomes P'^-1 x (P' its parent's
//! new world matrix, x the target), and every later chain node is re-pinned
//! to where it was, so descendants off the chain follow their parent. World
//! rotations and scales are untouched.
//!
//! The mesh's rest shape is kept exactly: a joint whose world matrix goes from
//! W to W' gets the inverse bind matrix B' = W'^-1 W B, so W' B' = W B and every
//! skinned vertex is where it was (up to the f32 the file stores). New inverse
//! bind matrices are appended as a new accessor; everything else in the file's
//! JSON is kept as it was. The output is one .glb (or a .gltf with its buffer
//! embedded), every buffer merged into one.

use super::{AuditedFinger, GltfFile, world_matrices};
use crate::analysis::audit::Point;
use crate::dataset::DataError;
use base64::Engine;
use glam::{DMat4, DVec3};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::Path;

/// The outcome of a fix: the new file's bytes and what was done.
pub struct Fixed {
    pub bytes: Vec<u8>,
    /// (node name, distance moved), in chain order.
    pub moved: Vec<(String, f64)>,
    /// Remarks for the user (animations that drive moved joints, external images).
    pub warnings: Vec<String>,
}

/// Reads the data of every buffer: the GLB chunk, data URIs, or files beside the input.
fn buffers(file: &GltfFile, dir: &Path) -> Result<Vec<Vec<u8>>, DataError> {
    let fail = |m: String| DataError::whole_file(&file.label, m);
    file.document
        .buffers()
        .map(|b| {
            let mut data = match b.source() {
                gltf::buffer::Source::Bin => file
                    .blob
                    .clone()
                    .ok_or_else(|| fail("refers to a GLB binary chunk it does not have".into()))?,
                gltf::buffer::Source::Uri(uri) => {
                    if let Some(rest) = uri.strip_prefix("data:") {
                        let payload = rest.split_once(";base64,").map(|(_, p)| p).ok_or_else(
                            || fail(format!("buffer {} has a data URI that is not base64", b.index())),
                        )?;
                        base64::engine::general_purpose::STANDARD
                            .decode(payload)
                            .map_err(|e| fail(format!("buffer {} has bad base64 ({e})", b.index())))?
                    } else {
                        let p = dir.join(uri);
                        std::fs::read(&p).map_err(|e| {
                            fail(format!(
                                "buffer {} refers to {} which cannot be read ({e}); keep it beside the .gltf",
                                b.index(),
                                p.display()
                            ))
                        })?
                    }
                }
            };
            if data.len() < b.length() {
                return Err(fail(format!(
                    "buffer {} holds {} bytes but declares {}",
                    b.index(),
                    data.len(),
                    b.length()
                )));
            }
            data.truncate(b.length());
            Ok(data)
        })
        .collect()
}

fn pad4(v: &mut Vec<u8>) {
    while !v.len().is_multiple_of(4) {
        v.push(0);
    }
}

/// Writes the fixed copy. `dir` resolves external buffers; `glb` picks the container.
pub fn fix(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    dir: &Path,
    glb: bool,
) -> Result<Fixed, DataError> {
    let mut locals: Vec<DMat4> = file
        .document
        .nodes()
        .map(|nd| super::local_matrix(&nd))
        .collect();
    // Targets: moved joints to their suggestions, later chain joints pinned in place.
    let mut targets: Vec<(usize, Point)> = Vec::new();
    let mut moved = Vec::new();
    for f in fingers {
        let (chain, audit) = (&f.chain, &f.audit);
        let judged: Vec<_> = audit.joints.iter().filter(|j| j.shift > 0.0).collect();
        if judged.is_empty() {
            continue;
        }
        for (k, rj) in chain.joints.iter().enumerate().skip(1) {
            let target = match audit.joints.get(k - 1) {
                Some(j) if j.joint == rj.joint => {
                    moved.push((rj.name.clone(), j.shift));
                    j.suggested
                }
                _ => rj.position,
            };
            if let Some(node) = rj.node {
                targets.push((node, target));
            }
        }
    }
    let depth = |mut i: usize| {
        let mut d = 0;
        while let Some(p) = file.parent[i] {
            d += 1;
            i = p;
        }
        d
    };
    targets.sort_by_key(|&(node, _)| depth(node));
    let mut world = file.world.clone();
    for &(node, target) in &targets {
        let up = file.parent[node].map_or(DMat4::IDENTITY, |p| world[p]);
        let t = up.inverse().transform_point3(DVec3::from_array(target));
        locals[node].w_axis = t.extend(1.0);
        world = world_matrices(&file.parent, &locals).unwrap_or(world);
    }
    let mut json = file.json.clone();
    let mut touched: BTreeMap<usize, DVec3> = BTreeMap::new();
    for &(node, _) in &targets {
        touched.insert(node, locals[node].w_axis.truncate());
    }
    for (&node, t) in &touched {
        let nd = &mut json["nodes"][node];
        if let Some(m) = nd.get_mut("matrix").and_then(Value::as_array_mut) {
            for (k, v) in t.to_array().into_iter().enumerate() {
                m[12 + k] = json!(v);
            }
        } else {
            nd["translation"] = json!(t.to_array());
        }
    }
    // Merge all buffers into one, then append the new inverse bind matrices.
    let data = buffers(file, dir)?;
    let mut bin = Vec::new();
    let mut starts = Vec::new();
    for d in &data {
        pad4(&mut bin);
        starts.push(bin.len());
        bin.extend_from_slice(d);
    }
    if let Some(views) = json["bufferViews"].as_array_mut() {
        for v in views {
            let b = v["buffer"].as_u64().unwrap_or(0) as usize;
            let off = v["byteOffset"].as_u64().unwrap_or(0) as usize;
            v["buffer"] = json!(0);
            v["byteOffset"] = json!(starts.get(b).copied().unwrap_or(0) + off);
        }
    }
    for skin in file.document.skins() {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        if !joints.iter().any(|&j| world[j] != file.world[j]) {
            continue;
        }
        let reader = skin.reader(|b| data.get(b.index()).map(Vec::as_slice));
        let ibm: Vec<DMat4> = match reader.read_inverse_bind_matrices() {
            Some(it) => it
                .map(|m| DMat4::from_cols_array_2d(&m.map(|c| c.map(f64::from))))
                .collect(),
            None => vec![DMat4::IDENTITY; joints.len()],
        };
        if ibm.len() != joints.len() {
            return Err(DataError::whole_file(
                &file.label,
                format!(
                    "skin {} has {} inverse bind matrices for {} joints",
                    skin.index(),
                    ibm.len(),
                    joints.len()
                ),
            ));
        }
        pad4(&mut bin);
        let offset = bin.len();
        for (&j, b) in joints.iter().zip(&ibm) {
            let new = world[j].inverse() * file.world[j] * *b;
            for v in new.to_cols_array() {
                bin.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        let view = push(
            &mut json,
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": 64 * joints.len()}),
        );
        let accessor = push(
            &mut json,
            "accessors",
            json!({"bufferView": view, "componentType": 5126, "count": joints.len(), "type": "MAT4"}),
        );
        json["skins"][skin.index()]["inverseBindMatrices"] = json!(accessor);
    }
    let mut buffer = json!({"byteLength": bin.len()});
    if !glb {
        buffer["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bin)
        ));
    }
    if !bin.is_empty() {
        json["buffers"] = json!([buffer]);
    }
    let mut warnings = Vec::new();
    let moved_nodes: Vec<usize> = touched.keys().copied().collect();
    for anim in file.document.animations() {
        for ch in anim.channels() {
            let t = ch.target();
            if t.property() == gltf::animation::Property::Translation
                && moved_nodes.contains(&t.node().index())
            {
                warnings.push(format!(
                    "animation {} drives the translation of {}; its keyframes are unchanged and will undo the fix during playback",
                    anim.name().map_or_else(|| format!("#{}", anim.index()), |s| format!("'{s}'")),
                    t.node().name().unwrap_or("a moved joint"),
                ));
            }
        }
    }
    if file.document.images().any(
        |i| matches!(i.source(), gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:")),
    ) {
        warnings.push(
            "images referenced by file name stay external: copy them beside the output".into(),
        );
    }
    let text =
        serde_json::to_vec(&json).map_err(|e| DataError::whole_file(&file.label, e.to_string()))?;
    let bytes = if glb {
        gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: 0,
            },
            json: text.into(),
            bin: (!bin.is_empty()).then_some(bin.into()),
        }
        .to_vec()
        .map_err(|e| {
            DataError::whole_file(&file.label, format!("cannot be written as GLB ({e})"))
        })?
    } else {
        text
    };
    Ok(Fixed {
        bytes,
        moved,
        warnings,
    })
}

/// Appends `value` to the array `json[key]` (created when absent); returns its index.
fn push(json: &mut Value, key: &str, value: Value) -> usize {
    if !json[key].is_array() {
        json[key] = json!([]);
    }
    let arr = json[key].as_array_mut().expect("just made an array");
    arr.push(value);
    arr.len() - 1
}
