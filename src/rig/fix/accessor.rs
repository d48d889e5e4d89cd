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

/// How many times each accessor is named where glTF 2.0 and its common
/// extensions name accessors: primitive attributes, indices and morph
/// targets, skins' inverse bind matrices, animation samplers, and
/// EXT_mesh_gpu_instancing attributes. O(size of the JSON's lists).
pub fn references(json: &Value) -> HashMap<usize, usize> {
    let mut count: HashMap<usize, usize> = HashMap::new();
    let mut add = |v: &Value| {
        if let Some(i) = v.as_u64() {
            *count.entry(i as usize).or_default() += 1;
        }
    };
    let list = |v: &Value| v.as_array().cloned().unwrap_or_default();
    for mesh in list(&json["meshes"]) {
        for prim in list(&mesh["primitives"]) {
            prim["attributes"]
                .as_object()
                .into_iter()
                .flatten()
                .for_each(|(_, v)| add(v));
            add(&prim["indices"]);
            for t in list(&prim["targets"]) {
                t.as_object()
                    .into_iter()
                    .flatten()
                    .for_each(|(_, v)| add(v));
            }
        }
    }
    for skin in list(&json["skins"]) {
        add(&skin["inverseBindMatrices"]);
    }
    for anim in list(&json["animations"]) {
        for s in list(&anim["samplers"]) {
            add(&s["input"]);
            add(&s["output"]);
        }
    }
    for node in list(&json["nodes"]) {
        node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]
            .as_object()
            .into_iter()
            .flatten()
            .for_each(|(_, v)| add(v));
    }
    count
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
}
