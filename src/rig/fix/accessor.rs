//! Accessor elements read and written in place in the merged buffer of a
//! fixed copy (see [`super`]): after the merge every buffer view points
//! into buffer 0, so an accessor's elements lie at
//! view.byteOffset + accessor.byteOffset + i x stride.
//!
//! Writing in place keeps the file's structure: no accessor is added or left
//! unused, and a second fix that moves nothing writes the same bytes. It is
//! used only for an accessor that one user owns ([`references`]).

use serde_json::Value;
use std::collections::HashMap;

/// Where an accessor's elements lie in the merged buffer, and how they are stored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub start: usize,
    pub stride: usize,
    pub count: usize,
    /// The glTF componentType: 5121 unsigned byte, 5123 unsigned short, 5126 float, ...
    pub component: u64,
    /// Components per element (1 SCALAR, 3 VEC3, 4 VEC4, 16 MAT4).
    pub components: usize,
    pub normalized: bool,
}

/// Bytes per component of a componentType; `None` for an unknown one.
fn component_size(c: u64) -> Option<usize> {
    match c {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

/// The span of accessor `acc` in a merged buffer of `len` bytes; `None` for a
/// sparse accessor, one without a view, or one whose elements do not fit
/// (every offset checked).
pub fn span(json: &Value, acc: usize, len: usize) -> Option<Span> {
    let a = json["accessors"].get(acc)?;
    if a.get("sparse").is_some() {
        return None;
    }
    let view = &json["bufferViews"][a["bufferView"].as_u64()? as usize];
    let component = a["componentType"].as_u64()?;
    let components = match a["type"].as_str()? {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    };
    let size = component_size(component)?.checked_mul(components)?;
    let stride = view["byteStride"].as_u64().map_or(size, |s| s as usize);
    let count = a["count"].as_u64()? as usize;
    let start = (view["byteOffset"].as_u64().unwrap_or(0) as usize)
        .checked_add(a["byteOffset"].as_u64().unwrap_or(0) as usize)?;
    let view_end = (view["byteOffset"].as_u64().unwrap_or(0) as usize)
        .checked_add(view["byteLength"].as_u64()? as usize)?;
    let end = stride
        .checked_mul(count.checked_sub(1)?)?
        .checked_add(size)?
        .checked_add(start)?;
    // Matrices of byte or short components are padded per column; only
    // float matrices (the only kind written here) are read.
    let padded = components >= 4 && a["type"].as_str()?.starts_with("MAT") && component != 5126;
    (stride >= size && end <= view_end && view_end <= len && !padded).then_some(Span {
        start,
        stride,
        count,
        component,
        components,
        normalized: a["normalized"].as_bool().unwrap_or(false),
    })
}

impl Span {
    fn at(&self, i: usize, k: usize) -> usize {
        let size = component_size(self.component).unwrap_or(4);
        self.start + i * self.stride + k * size
    }

    /// Element `i` as numbers: floats as they are, integers as integers, or
    /// normalised to [0, 1] when the accessor says `normalized`.
    pub fn read(&self, bin: &[u8], i: usize) -> Vec<f64> {
        (0..self.components)
            .map(|k| {
                let o = self.at(i, k);
                match self.component {
                    5126 => f64::from(f32::from_le_bytes([
                        bin[o],
                        bin[o + 1],
                        bin[o + 2],
                        bin[o + 3],
                    ])),
                    5121 if self.normalized => f64::from(bin[o]) / 255.0,
                    5121 => f64::from(bin[o]),
                    5123 => {
                        let v = f64::from(u16::from_le_bytes([bin[o], bin[o + 1]]));
                        if self.normalized { v / 65535.0 } else { v }
                    }
                    5125 => f64::from(u32::from_le_bytes([
                        bin[o],
                        bin[o + 1],
                        bin[o + 2],
                        bin[o + 3],
                    ])),
                    5120 => f64::from(bin[o] as i8),
                    _ => f64::from(i16::from_le_bytes([bin[o], bin[o + 1]])),
                }
            })
            .collect()
    }

    /// Writes element `i` of a float accessor.
    pub fn write_f32(&self, bin: &mut [u8], i: usize, values: &[f32]) {
        for (k, v) in values.iter().enumerate().take(self.components) {
            let o = self.at(i, k);
            bin[o..o + 4].copy_from_slice(&v.to_le_bytes());
        }
    }

    /// Writes element `i` of an unsigned byte, short or int accessor as raw integers.
    pub fn write_uint(&self, bin: &mut [u8], i: usize, values: &[u32]) {
        for (k, &v) in values.iter().enumerate().take(self.components) {
            let o = self.at(i, k);
            match self.component {
                5121 => bin[o] = v.min(255) as u8,
                5123 => bin[o..o + 2].copy_from_slice(&(v.min(65535) as u16).to_le_bytes()),
                _ => bin[o..o + 4].copy_from_slice(&v.to_le_bytes()),
            }
        }
    }

    /// The largest raw value an unsigned component holds.
    pub fn uint_max(&self) -> u32 {
        match self.component {
            5121 => 255,
            5123 => 65535,
            _ => u32::MAX,
        }
    }
}

/// A place in the JSON that may name an index, and how to make its JSON pointer.
type Place<'p> = &'p mut dyn FnMut(&Value, &dyn Fn() -> String);

/// Calls `f` on every place glTF 2.0 and its common extensions name an
/// accessor: primitive attributes, indices and morph targets, skins' inverse
/// bind matrices, animation samplers, and EXT_mesh_gpu_instancing
/// attributes; with a closure that makes the place's JSON pointer. O(size of
/// the JSON's lists).
fn accessor_places(json: &Value, f: Place<'_>) {
    for (m, mesh) in list(&json["meshes"]).iter().enumerate() {
        for (p, prim) in list(&mesh["primitives"]).iter().enumerate() {
            let at = || format!("/meshes/{m}/primitives/{p}");
            for (k, v) in map(&prim["attributes"]) {
                f(v, &|| format!("{}/attributes/{}", at(), escape(k)));
            }
            f(&prim["indices"], &|| format!("{}/indices", at()));
            for (t, target) in list(&prim["targets"]).iter().enumerate() {
                for (k, v) in map(target) {
                    f(v, &|| format!("{}/targets/{t}/{}", at(), escape(k)));
                }
            }
        }
    }
    for (s, skin) in list(&json["skins"]).iter().enumerate() {
        f(&skin["inverseBindMatrices"], &|| {
            format!("/skins/{s}/inverseBindMatrices")
        });
    }
    for (a, anim) in list(&json["animations"]).iter().enumerate() {
        for (k, s) in list(&anim["samplers"]).iter().enumerate() {
            f(&s["input"], &|| {
                format!("/animations/{a}/samplers/{k}/input")
            });
            f(&s["output"], &|| {
                format!("/animations/{a}/samplers/{k}/output")
            });
        }
    }
    for (n, node) in list(&json["nodes"]).iter().enumerate() {
        for (k, v) in map(&node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]) {
            f(v, &|| {
                format!(
                    "/nodes/{n}/extensions/EXT_mesh_gpu_instancing/attributes/{}",
                    escape(k)
                )
            });
        }
    }
}

/// Calls `f` on every place glTF 2.0 and its common extensions name a
/// buffer view: accessors and their sparse indices and values, images, and
/// KHR_draco_mesh_compression primitives; as [`accessor_places`] does.
fn view_places(json: &Value, f: Place<'_>) {
    for (a, acc) in list(&json["accessors"]).iter().enumerate() {
        f(&acc["bufferView"], &|| format!("/accessors/{a}/bufferView"));
        for part in ["indices", "values"] {
            f(&acc["sparse"][part]["bufferView"], &|| {
                format!("/accessors/{a}/sparse/{part}/bufferView")
            });
        }
    }
    for (i, image) in list(&json["images"]).iter().enumerate() {
        f(&image["bufferView"], &|| format!("/images/{i}/bufferView"));
    }
    for (m, mesh) in list(&json["meshes"]).iter().enumerate() {
        for (p, prim) in list(&mesh["primitives"]).iter().enumerate() {
            f(
                &prim["extensions"]["KHR_draco_mesh_compression"]["bufferView"],
                &|| {
                    format!(
                        "/meshes/{m}/primitives/{p}/extensions/KHR_draco_mesh_compression/bufferView"
                    )
                },
            );
        }
    }
}

/// How many times each index is named at the places `each` visits.
fn count(json: &Value, each: fn(&Value, Place<'_>)) -> HashMap<usize, usize> {
    let mut count: HashMap<usize, usize> = HashMap::new();
    each(json, &mut |v, _| {
        if let Some(i) = v.as_u64() {
            *count.entry(i as usize).or_default() += 1;
        }
    });
    count
}

/// The JSON pointers of the places `each` visits that name an index.
fn pointers(json: &Value, each: fn(&Value, Place<'_>)) -> Vec<String> {
    let mut out = Vec::new();
    each(json, &mut |v, at| {
        if v.as_u64().is_some() {
            out.push(at());
        }
    });
    out
}

/// The elements of a JSON array (none when it is not one).
fn list(v: &Value) -> &[Value] {
    v.as_array().map(Vec::as_slice).unwrap_or_default()
}

/// The entries of a JSON object (none when it is not one).
fn map(v: &Value) -> impl Iterator<Item = (&String, &Value)> {
    v.as_object().into_iter().flatten()
}

/// A key as one token of a JSON pointer (RFC 6901).
fn escape(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// How many times each accessor is named where glTF 2.0 and its common
/// extensions name accessors: primitive attributes, indices and morph
/// targets, skins' inverse bind matrices, animation samplers, and
/// EXT_mesh_gpu_instancing attributes. O(size of the JSON's lists).
pub fn references(json: &Value) -> HashMap<usize, usize> {
    count(json, accessor_places)
}

/// How many times each buffer view is named (by accessors and their sparse
/// parts, images, and KHR_draco_mesh_compression).
pub fn view_references(json: &Value) -> HashMap<usize, usize> {
    count(json, view_places)
}

/// Pads the merged buffer to a multiple of 4 bytes.
pub fn pad4(bin: &mut Vec<u8>) {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
}

/// Appends `value` to the JSON array `list` (made one when it is not); its index.
pub fn push(list: &mut Value, value: Value) -> usize {
    if !list.is_array() {
        *list = serde_json::json!([]);
    }
    match list.as_array_mut() {
        Some(arr) => {
            arr.push(value);
            arr.len() - 1
        }
        None => 0,
    }
}

/// Appends `bytes` to the merged buffer (from a 4-byte boundary) as a new
/// buffer view of buffer 0, with `target` when given (34962 for vertex
/// attributes); returns the view's index.
pub fn append_view(
    json: &mut Value,
    bin: &mut Vec<u8>,
    bytes: &[u8],
    target: Option<u64>,
) -> usize {
    pad4(bin);
    let offset = bin.len();
    bin.extend_from_slice(bytes);
    let mut view =
        serde_json::json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
    if let Some(t) = target {
        view["target"] = t.into();
    }
    push(&mut json["bufferViews"], view)
}

/// Removes the accessors of `candidates` that nothing names any more, then
/// the buffer views that only they used, renumbering every reference to the
/// accessors and views after them; when a view goes, the merged buffer is
/// compacted to the bytes the remaining views cover (each view keeping its
/// offset modulo 4, views that overlapped or touched keeping their layout).
/// Does nothing when every candidate is still named. O(JSON size + buffer).
pub fn drop_unused(
    json: &mut Value,
    bin: &mut Vec<u8>,
    candidates: &std::collections::BTreeSet<usize>,
) {
    let named = references(json);
    let gone: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|a| !named.contains_key(a) && json["accessors"].get(*a).is_some())
        .collect();
    if gone.is_empty() {
        return;
    }
    let mut views: std::collections::BTreeSet<usize> = std::collections::BTreeSet::new();
    for &a in &gone {
        let acc = &json["accessors"][a];
        for v in [
            &acc["bufferView"],
            &acc["sparse"]["indices"]["bufferView"],
            &acc["sparse"]["values"]["bufferView"],
        ] {
            if let Some(v) = v.as_u64() {
                views.insert(v as usize);
            }
        }
    }
    remove(json, "accessors", &gone, &pointers(json, accessor_places));
    let named = view_references(json);
    let gone: Vec<usize> = views
        .into_iter()
        .filter(|v| !named.contains_key(v))
        .collect();
    if gone.is_empty() {
        return;
    }
    remove(json, "bufferViews", &gone, &pointers(json, view_places));
    compact(json, bin);
}

/// Removes the entries `gone` (ascending) of the array `json[key]` and
/// renumbers the indices at `slots` that name the entries after them.
fn remove(json: &mut Value, key: &str, gone: &[usize], slots: &[String]) {
    let renumber = |i: usize| i - gone.partition_point(|&g| g < i);
    for at in slots {
        if let Some(v) = json.pointer_mut(at)
            && let Some(i) = v.as_u64()
        {
            *v = renumber(i as usize).into();
        }
    }
    if let Some(list) = json[key].as_array_mut() {
        let mut k = 0;
        list.retain(|_| {
            k += 1;
            gone.binary_search(&(k - 1)).is_err()
        });
    }
}

/// Keeps only the bytes of the merged buffer that buffer views cover: runs
/// of overlapping or touching views move together, each run starting at the
/// first free offset congruent to its old one modulo 4 (so every accessor
/// keeps its alignment).
fn compact(json: &mut Value, bin: &mut Vec<u8>) {
    let Some(views) = json["bufferViews"].as_array_mut() else {
        return;
    };
    let span = |v: &Value| {
        let start = v["byteOffset"].as_u64().unwrap_or(0) as usize;
        (
            start,
            start + v["byteLength"].as_u64().unwrap_or(0) as usize,
        )
    };
    let mut order: Vec<usize> = (0..views.len()).collect();
    order.sort_by_key(|&k| span(&views[k]));
    let mut out: Vec<u8> = Vec::with_capacity(bin.len());
    let mut run: Option<(usize, usize, usize)> = None; // (old start, old end, new start)
    for k in order {
        let (start, end) = span(&views[k]);
        let end = end.min(bin.len());
        let (old, new) = match run {
            Some((s, e, n)) if start <= e => {
                if end > e {
                    out.extend_from_slice(&bin[e..end]);
                    run = Some((s, end, n));
                }
                (s, n)
            }
            _ => {
                while out.len() % 4 != start % 4 {
                    out.push(0);
                }
                let n = out.len();
                out.extend_from_slice(&bin[start.min(end)..end]);
                run = Some((start, end, n));
                (start, n)
            }
        };
        views[k]["byteOffset"] = (new + start - old).into();
    }
    *bin = out;
}

/// Recomputes an accessor's `min` and `max` from its elements, when it has them.
pub fn refresh_bounds(json: &mut Value, acc: usize, span: &Span, bin: &[u8]) {
    let a = &json["accessors"][acc];
    if a.get("min").is_none() && a.get("max").is_none() {
        return;
    }
    let mut lo = vec![f64::INFINITY; span.components];
    let mut hi = vec![f64::NEG_INFINITY; span.components];
    for i in 0..span.count {
        // Bounds are of the stored values: raw integers even when normalised.
        let raw = Span {
            normalized: false,
            ..*span
        };
        for (k, v) in raw.read(bin, i).into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    // Integers stay integers in the JSON; floats are the f32 values stored.
    let num = |v: f64| {
        if span.component == 5126 {
            serde_json::json!(v)
        } else {
            serde_json::json!(v as i64)
        }
    };
    json["accessors"][acc]["min"] = Value::Array(lo.into_iter().map(num).collect());
    json["accessors"][acc]["max"] = Value::Array(hi.into_iter().map(num).collect());
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn spans_read_and_write_strided_elements_and_refuse_what_does_not_fit() {
        // A view of 2 VEC3 floats with stride 16 at byte 4, accessor offset 0.
        let mut doc = json!({
            "bufferViews": [{"buffer": 0, "byteOffset": 4, "byteLength": 28, "byteStride": 16}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]},
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 0, "componentType": 5121, "count": 2, "type": "VEC4", "normalized": true}
            ],
            "skins": [{"inverseBindMatrices": 0}, {"inverseBindMatrices": 0}]
        });
        let mut bin = vec![0u8; 32];
        let s = span(&doc, 0, bin.len()).unwrap();
        assert_eq!((s.start, s.stride, s.count), (4, 16, 2));
        s.write_f32(&mut bin, 1, &[1.0, -2.0, 3.5]);
        assert_eq!(&bin[20..24], &1.0f32.to_le_bytes());
        assert_eq!(s.read(&bin, 1), vec![1.0, -2.0, 3.5]);
        refresh_bounds(&mut doc, 0, &s, &bin);
        assert_eq!(doc["accessors"][0]["max"], json!([1.0, 0.0, 3.5]));
        assert_eq!(doc["accessors"][0]["min"], json!([0.0, -2.0, 0.0]));
        // Three elements of stride 16 need 44 bytes from 4: past the view.
        assert!(span(&doc, 1, bin.len()).is_none());
        let b = span(&doc, 2, bin.len()).unwrap();
        b.write_uint(&mut bin, 0, &[255, 0, 51, 300]);
        assert_eq!(b.read(&bin, 0), vec![1.0, 0.0, 0.2, 1.0]);
        assert_eq!(references(&doc)[&0], 2);
    }

    #[test]
    fn unused_accessors_go_with_their_views_and_bytes_and_the_rest_are_renumbered() {
        let mut doc = json!({
            "bufferViews": [
                {"buffer": 0, "byteOffset": 0, "byteLength": 8},
                {"buffer": 0, "byteOffset": 8, "byteLength": 12},
                {"buffer": 0, "byteOffset": 20, "byteLength": 6},
                {"buffer": 0, "byteOffset": 26, "byteLength": 4}
            ],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}
            ],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 2}]}],
            "images": [{"bufferView": 3, "mimeType": "image/png"}]
        });
        let mut bin: Vec<u8> = (0..30).collect();
        // Still named: nothing goes.
        drop_unused(&mut doc, &mut bin, &[0, 2].into());
        assert_eq!(bin.len(), 30);
        drop_unused(&mut doc, &mut bin, &[1].into());
        assert_eq!(doc["accessors"].as_array().unwrap().len(), 2);
        assert_eq!(doc["accessors"][1]["bufferView"], json!(1));
        assert_eq!(doc["meshes"][0]["primitives"][0]["indices"], json!(1));
        assert_eq!(doc["images"][0]["bufferView"], json!(2));
        // The touching views 2 and 3 move together to byte 8, each keeping
        // its offset modulo 4.
        let offsets: Vec<u64> = doc["bufferViews"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v["byteOffset"].as_u64().unwrap())
            .collect();
        assert_eq!(offsets, vec![0, 8, 14]);
        let mut want: Vec<u8> = (0..8).collect();
        want.extend(20..30);
        assert_eq!(bin, want);
        assert_eq!(references(&doc).len(), 2);
        assert_eq!(view_references(&doc).len(), 3);
    }
}
