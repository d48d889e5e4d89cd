//! The parts of a GLB being built in memory: its binary chunk, buffer views
//! and accessors. Used to write the synthetic tube hands and to hand an FBX
//! scene on as glTF ([`super::fbx`]); the container around them is
//! [`super::gltf`]'s.

use super::skin::SkinnedMesh;

/// The per-axis minimum and maximum of `points` (infinite when there are none).
pub(crate) fn bounds(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    points.iter().fold(
        ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        },
    )
}

/// The binary chunk of a GLB being written, with its buffer views and accessors.
#[derive(Default)]
pub(crate) struct GlbParts {
    pub bin: Vec<u8>,
    pub views: Vec<serde_json::Value>,
    pub accessors: Vec<serde_json::Value>,
}

impl GlbParts {
    /// Appends `data` (little-endian, 4-byte aligned) to the binary chunk as a buffer
    /// view and an accessor of `component` type and `shape`; returns the accessor's index.
    pub fn accessor<T: LeBytes>(
        &mut self,
        data: &[T],
        component: u32,
        shape: &str,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> usize {
        let per = match shape {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 16,
        };
        let bin = &mut self.bin;
        let offset = bin.len();
        for x in data {
            x.put(bin);
        }
        let length = bin.len() - offset;
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        self.views.push(serde_json::json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": length,
        }));
        let mut acc = serde_json::json!({
            "bufferView": self.views.len() - 1,
            "componentType": component,
            "count": data.len() / per,
            "type": shape,
        });
        if let Some((lo, hi)) = bounds {
            acc["min"] = lo.into();
            acc["max"] = hi.into();
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// The mesh's influences as `JOINTS_n`/`WEIGHTS_n` sets of four (as many sets as the
    /// most influenced vertex needs, at least one), added to `attributes`.
    pub fn weight_sets(
        &mut self,
        mesh: &SkinnedMesh,
        attributes: &mut serde_json::Map<String, serde_json::Value>,
    ) {
        let n = mesh.positions.len();
        let most = (0..n)
            .map(|v| mesh.influences_of(v).len())
            .max()
            .unwrap_or(0);
        for set in 0..most.div_ceil(4).max(1) {
            let mut joints = vec![0u16; 4 * n];
            let mut weights = vec![0f32; 4 * n];
            for v in 0..n {
                for (k, &(j, w)) in mesh
                    .influences_of(v)
                    .iter()
                    .skip(4 * set)
                    .take(4)
                    .enumerate()
                {
                    joints[4 * v + k] = j;
                    weights[4 * v + k] = w as f32;
                }
            }
            let j = self.accessor(&joints, 5123, "VEC4", None);
            let w = self.accessor(&weights, 5126, "VEC4", None);
            attributes.insert(format!("JOINTS_{set}"), j.into());
            attributes.insert(format!("WEIGHTS_{set}"), w.into());
        }
    }
}

/// A number glTF stores little-endian.
pub(crate) trait LeBytes: Copy {
    fn put(self, out: &mut Vec<u8>);
}

impl LeBytes for f32 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl LeBytes for u32 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl LeBytes for u16 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl LeBytes for u8 {
    fn put(self, out: &mut Vec<u8>) {
        out.push(self);
    }
}
