//! `audit --fix`: a copy of a rig with its fingers' middle joints at the mean.
//!
//! For each finger the judged inner joints move to their suggested points (on
//! the rig's own chain, see [`super::judge`]); the root, the tip and
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

/// Decodes `%xx` escapes of a URI path; `None` on a bad escape or non-UTF-8 result.
fn percent_decode(uri: &str) -> Option<String> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Reads the data of every buffer: the GLB chunk (buffer 0 only, as the
/// specification says), data URIs, or files beside the input. A file URI must
/// be a relative path that stays beside the input (no `..`, no scheme), and
/// only the declared byte length is read.
pub(crate) fn buffers(file: &GltfFile, dir: &Path) -> Result<Vec<Vec<u8>>, DataError> {
    let fail = |m: String| DataError::whole_file(&file.label, m);
    file.document
        .buffers()
        .map(|b| {
            let i = b.index();
            let mut data = match b.source() {
                gltf::buffer::Source::Bin if i == 0 => file
                    .blob
                    .clone()
                    .ok_or_else(|| fail("refers to a GLB binary chunk it does not have".into()))?,
                gltf::buffer::Source::Bin => {
                    return Err(fail(format!(
                        "buffer {i} has no data of its own (a compression fallback buffer?); --fix cannot copy it"
                    )));
                }
                gltf::buffer::Source::Uri(uri) => {
                    if let Some(rest) = uri.strip_prefix("data:") {
                        let payload = rest
                            .split_once(";base64,")
                            .map(|(_, p)| p)
                            .ok_or_else(|| fail(format!("buffer {i} has a data URI that is not base64")))?;
                        base64::engine::general_purpose::STANDARD
                            .decode(payload)
                            .map_err(|e| fail(format!("buffer {i} has bad base64 ({e})")))?
                    } else {
                        let rel = percent_decode(uri)
                            .filter(|r| {
                                let p = Path::new(r);
                                !r.contains(':')
                                    && p.is_relative()
                                    && p.components().all(|c| matches!(c, std::path::Component::Normal(_)))
                            })
                            .ok_or_else(|| {
                                fail(format!(
                                    "buffer {i} refers to '{uri}', which is not a plain relative path beside the file; \
                                     --fix reads only files next to the input"
                                ))
                            })?;
                        let p = dir.join(rel);
                        let read = || -> std::io::Result<Vec<u8>> {
                            let mut data = Vec::new();
                            std::io::Read::read_to_end(
                                &mut std::io::Read::take(std::fs::File::open(&p)?, (b.length() as u64).saturating_add(1)),
                                &mut data,
                            )?;
                            Ok(data)
                        };
                        read().map_err(|e| {
                            fail(format!(
                                "buffer {i} refers to {} which cannot be read ({e}); keep it beside the .gltf",
                                p.display()
                            ))
                        })?
                    }
                }
            };
            if data.len() < b.length() {
                return Err(fail(format!(
                    "buffer {i} holds {} bytes but declares {}",
                    data.len(),
                    b.length()
                )));
            }
            data.truncate(b.length());
            Ok(data)
        })
        .collect()
}

/// The inverse bind matrices of a skin, read with every offset checked
/// (identity matrices when the skin has none).
pub(crate) fn inverse_binds(
    data: &[Vec<u8>],
    skin: &gltf::Skin<'_>,
    joints: usize,
) -> Result<Vec<DMat4>, String> {
    let Some(acc) = skin.inverse_bind_matrices() else {
        return Ok(vec![DMat4::IDENTITY; joints]);
    };
    let what = format!(
        "skin {}'s inverse bind matrices (accessor {})",
        skin.index(),
        acc.index()
    );
    if acc.data_type() != gltf::accessor::DataType::F32
        || acc.dimensions() != gltf::accessor::Dimensions::Mat4
        || acc.sparse().is_some()
        || acc.count() != joints
    {
        return Err(format!(
            "{what} are not {joints} plain float MAT4 values, as glTF requires"
        ));
    }
    let view = acc
        .view()
        .ok_or_else(|| format!("{what} have no buffer view"))?;
    let stride = view.stride().unwrap_or(64);
    let buf = data
        .get(view.buffer().index())
        .ok_or_else(|| format!("{what} name a missing buffer"))?;
    let start = view.offset().checked_add(acc.offset());
    let need = stride
        .checked_mul(joints.saturating_sub(1))
        .and_then(|x| x.checked_add(64));
    let in_view = need.and_then(|n| acc.offset().checked_add(n));
    let view_end = view.offset().checked_add(view.length());
    let (Some(start), Some(in_view), Some(view_end)) = (start, in_view, view_end) else {
        return Err(format!("{what} have impossible offsets"));
    };
    if stride < 64 || in_view > view.length() || view_end > buf.len() {
        return Err(format!("{what} do not fit their buffer view"));
    }
    Ok((0..joints)
        .map(|k| {
            let at = start + k * stride;
            let cols: Vec<f64> = buf[at..at + 64]
                .chunks_exact(4)
                .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect();
            DMat4::from_cols_slice(&cols)
        })
        .collect())
}

fn pad4(v: &mut Vec<u8>) {
    while !v.len().is_multiple_of(4) {
        v.push(0);
    }
}

/// Writes the fixed copy. `dir` resolves external buffers; `glb` picks the container.
///
/// In steps: the target of every chain node, the nodes moved there (parents
/// first), their new translations written into the JSON, every buffer merged
/// into one, new inverse bind matrices for the skins whose joints moved, then
/// the output container.
pub fn fix(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    dir: &Path,
    glb: bool,
) -> Result<Fixed, DataError> {
    let (targets, moved) = targets(fingers);
    let (locals, world) = move_nodes(file, &targets)?;
    let mut json = file.json.clone();
    let mut touched: BTreeMap<usize, DVec3> = BTreeMap::new();
    for &(node, _) in &targets {
        touched.insert(node, locals[node].w_axis.truncate());
    }
    write_translations(&mut json, &touched);
    let (data, mut bin) = merge_buffers(file, &mut json, dir)?;
    rebind_skins(file, &mut json, &data, &mut bin, &world)?;
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
    let moved_nodes: Vec<usize> = touched.keys().copied().collect();
    let warnings = warnings(file, &moved_nodes);
    let bytes = container(file, &json, bin, glb)?;
    Ok(Fixed {
        bytes,
        moved,
        warnings,
    })
}

/// A node and the world position it goes to.
type Target = (usize, DVec3);

/// Where each chain node goes: moved joints to their suggestions, later chain
/// joints pinned where they are (node, world position); and the moved joints'
/// (name, distance).
fn targets(fingers: &[AuditedFinger]) -> (Vec<Target>, Vec<(String, f64)>) {
    let mut targets: Vec<Target> = Vec::new();
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
    (targets, moved)
}

/// Moves each node to its target (world position), parents first, by changing
/// its local translation only; returns the new local and world matrices.
/// Fails when the transform above a node is singular.
fn move_nodes(file: &GltfFile, targets: &[Target]) -> Result<(Vec<DMat4>, Vec<DMat4>), DataError> {
    let mut locals: Vec<DMat4> = file
        .document
        .nodes()
        .map(|nd| super::local_matrix(&nd))
        .collect();
    let depth = |mut i: usize| {
        let mut d = 0;
        while let Some(p) = file.parent[i] {
            d += 1;
            i = p;
        }
        d
    };
    let mut order = targets.to_vec();
    order.sort_by_key(|&(node, _)| depth(node));
    let mut world = file.world.clone();
    for &(node, target) in &order {
        let up = file.parent[node].map_or(DMat4::IDENTITY, |p| world[p]);
        let det = up.determinant();
        let t = up.inverse().transform_point3(target);
        if !(det.is_finite() && det.abs() > 1e-300 && t.is_finite()) {
            return Err(DataError::whole_file(
                &file.label,
                format!(
                    "cannot move node {node} ('{}'): the transform above it is singular (a zero scale?); fix that first",
                    file.document
                        .nodes()
                        .nth(node)
                        .and_then(|n| n.name())
                        .unwrap_or("unnamed")
                ),
            ));
        }
        locals[node].w_axis = t.extend(1.0);
        world = world_matrices(&file.parent, &locals).unwrap_or(world);
    }
    Ok((locals, world))
}

/// Writes new translations into the nodes' JSON (into `matrix` when a node has one).
fn write_translations(json: &mut Value, touched: &BTreeMap<usize, DVec3>) {
    for (&node, t) in touched {
        let nd = &mut json["nodes"][node];
        if let Some(m) = nd.get_mut("matrix").and_then(Value::as_array_mut) {
            for (k, v) in t.to_array().into_iter().enumerate() {
                m[12 + k] = json!(v);
            }
        } else {
            nd["translation"] = json!(t.to_array());
        }
    }
}

/// Merges every buffer into one (each start 4-byte aligned) and points the
/// buffer views into it; returns the buffers as read and the merged bytes.
fn merge_buffers(
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
        pad4(&mut bin);
        starts.push(bin.len());
        bin.extend_from_slice(d);
    }
    if let Some(views) = json["bufferViews"].as_array_mut() {
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

/// Appends new inverse bind matrices B' = W'^-1 W B for every skin whose joints
/// moved, as a new accessor, so the mesh keeps its rest shape.
fn rebind_skins(
    file: &GltfFile,
    json: &mut Value,
    data: &[Vec<u8>],
    bin: &mut Vec<u8>,
    world: &[DMat4],
) -> Result<(), DataError> {
    for skin in file.document.skins() {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        if !joints.iter().any(|&j| world[j] != file.world[j]) {
            continue;
        }
        let ibm = inverse_binds(data, &skin, joints.len())
            .map_err(|e| DataError::whole_file(&file.label, e))?;
        pad4(bin);
        let offset = bin.len();
        for (&j, b) in joints.iter().zip(&ibm) {
            let new = world[j].inverse() * file.world[j] * *b;
            if !new.is_finite() {
                return Err(DataError::whole_file(
                    &file.label,
                    format!(
                        "joint node {j} has a singular world transform; cannot update its inverse bind matrix"
                    ),
                ));
            }
            for v in new.to_cols_array() {
                bin.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        let view = push(
            json,
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": 64 * joints.len()}),
        );
        let accessor = push(
            json,
            "accessors",
            json!({"bufferView": view, "componentType": 5126, "count": joints.len(), "type": "MAT4"}),
        );
        json["skins"][skin.index()]["inverseBindMatrices"] = json!(accessor);
    }
    Ok(())
}

/// Remarks on what the fix cannot carry over: animations that key a moved
/// joint's translation, and images left as external files.
fn warnings(file: &GltfFile, moved_nodes: &[usize]) -> Vec<String> {
    let mut warnings = Vec::new();
    for anim in file.document.animations() {
        let mut keyed: Vec<String> = anim
            .channels()
            .map(|ch| ch.target())
            .filter(|t| {
                t.property() == gltf::animation::Property::Translation
                    && moved_nodes.contains(&t.node().index())
            })
            .map(|t| super::shown(t.node().name().unwrap_or("unnamed")))
            .collect();
        keyed.dedup();
        if !keyed.is_empty() {
            warnings.push(format!(
                "animation {} keys the translation of {}: its keyframes are unchanged, and with the new \
                 inverse bind matrices they would now distort the mesh; delete or re-bake those channels",
                anim.name().map_or_else(|| format!("#{}", anim.index()), super::shown),
                keyed.join(", ")
            ));
        }
    }
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
fn container(file: &GltfFile, json: &Value, bin: Vec<u8>, glb: bool) -> Result<Vec<u8>, DataError> {
    let text =
        serde_json::to_vec(json).map_err(|e| DataError::whole_file(&file.label, e.to_string()))?;
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
    Ok(bytes)
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
