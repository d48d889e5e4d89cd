//! What an edit writes at its finish: the rest skin matrices joints bind
//! at, the inverse bind matrices that keep the rest shape, and the weights.

use super::{Edit, Write};
use crate::dataset::DataError;
use crate::rig::fix::accessor::{self, push};
use crate::rig::fix::remap;
use crate::rig::read::gltf::inverse_binds;
use glam::{DMat4, DVec3};
use serde_json::json;
use std::collections::BTreeSet;

/// The glTF componentType of unsigned shorts, and of floats.
const UNSIGNED_SHORT: u64 = 5123;
const FLOAT: u64 = 5126;
/// The buffer view target of vertex attributes.
const ARRAY_BUFFER: u64 = 34962;

impl Edit<'_> {
    /// The rest skin matrices M = W B of the file's skin `skin`, by joint slot.
    pub(super) fn file_rest(&self, skin: usize) -> Result<(Vec<usize>, Vec<DMat4>), DataError> {
        let s = self
            .file
            .document
            .skins()
            .nth(skin)
            .ok_or_else(|| self.fail(format!("has no skin {skin}")))?;
        let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
        let ibm = inverse_binds(&self.data, &s, joints.len()).map_err(|e| self.fail(e))?;
        let rest = joints
            .iter()
            .zip(&ibm)
            .map(|(&j, b)| self.file.world[j] * *b)
            .collect();
        Ok((joints, rest))
    }

    /// Where a joint added to skin `skin` binds: a new skin's mesh's rest
    /// matrix, or the rest skin matrix of the node's nearest ancestor among
    /// the file's joints of the skin (its first joint when none is one).
    pub(super) fn rest_of_new_joint(&self, skin: usize, node: usize) -> Result<DMat4, DataError> {
        if let Some(&m) = self.new_skins.get(&skin) {
            return Ok(m);
        }
        let (joints, rest) = self.file_rest(skin)?;
        let mut at = Some(node);
        while let Some(n) = at {
            if let Some(k) = joints.iter().position(|&j| j == n) {
                return Ok(rest[k]);
            }
            at = self.parent[n];
        }
        rest.first()
            .copied()
            .ok_or_else(|| self.fail(format!("skin {skin} has no joints")))
    }

    /// When new weights move vertices of the file's skin `skin` off their
    /// rest (its joints bind at different rest matrices), a remark saying how
    /// many and how far.
    pub(super) fn rest_drift(
        &self,
        skin: usize,
        mesh: usize,
        primitive: usize,
        slots: &[Vec<(u32, f64)>],
    ) -> Option<String> {
        if self.new_skins.contains_key(&skin) {
            return None;
        }
        let (joints, mut rest) = self.file_rest(skin).ok()?;
        rest.extend(self.added.get(&skin).into_iter().flatten().map(|a| a.1));
        if rest.iter().all(|m| m.abs_diff_eq(rest[0], 1e-9)) {
            return None;
        }
        let prim = self
            .file
            .document
            .meshes()
            .nth(mesh)?
            .primitives()
            .nth(primitive)?;
        let at = format!("/meshes/{mesh}/primitives/{primitive}");
        let (positions, old) =
            crate::rig::read::skin::read_vertices(&prim, &at, &self.data, joints.len()).ok()?;
        let was = |v: usize| {
            let sum: f64 = old[v].iter().map(|x| x.1).sum();
            let at: DVec3 = old[v]
                .iter()
                .map(|&(s, w)| w * rest[usize::from(s)].transform_point3(positions[v]))
                .sum();
            (sum > 0.0).then(|| at / sum)
        };
        let (lo, hi) = positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let tolerance = 1e-5 * lo.distance(hi).max(1e-9);
        let (mut moved, mut most) = (0usize, 0.0f64);
        for (v, s) in slots.iter().enumerate() {
            let Some(before) = was(v) else { continue };
            let now: DVec3 = s
                .iter()
                .filter_map(|&(k, w)| {
                    rest.get(k as usize)
                        .map(|m| w * m.transform_point3(positions[v]))
                })
                .sum();
            let d = now.distance(before);
            if d > tolerance {
                moved += 1;
                most = most.max(d);
            }
        }
        (moved > 0).then(|| {
            format!(
                "{at}: {moved} vertices rest up to {} (the file's units) from where they did: \
                 skin {skin} binds its joints at different rest matrices (its bind pose is not its \
                 rest pose), so new weights move them",
                crate::format::num(most, 6)
            )
        })
    }

    /// Every primitive of a mesh bound to a new skin must have weights.
    pub(super) fn check_new_skins_weighted(&self) -> Result<(), DataError> {
        for &skin in self.new_skins.keys() {
            let meshes: BTreeSet<usize> = (0..self.parent.len())
                .filter(|&n| self.json["nodes"][n]["skin"].as_u64() == Some(skin as u64))
                .filter_map(|n| self.json["nodes"][n]["mesh"].as_u64().map(|m| m as usize))
                .collect();
            for m in meshes {
                let prims = self.json["meshes"][m]["primitives"].as_array();
                for (p, prim) in prims.into_iter().flatten().enumerate() {
                    let set = self.writes.iter().any(|w| {
                        matches!(w, Write::Set { mesh, primitive, .. } if *mesh == m && *primitive == p)
                    });
                    if !set && prim["attributes"].get("JOINTS_0").is_none() {
                        return Err(self.fail(format!(
                            "/meshes/{m}/primitives/{p} is bound to new skin {skin} but has no weights; set them"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// Inverse bind matrices for every skin of the file whose joints moved or
    /// were added, and for every new skin: written over the old ones when
    /// that accessor serves this skin alone and keeps its count, else as a
    /// new accessor (the old one, when it served only this skin, joins
    /// `unused`).
    pub(super) fn rebind(&mut self, unused: &mut BTreeSet<usize>) -> Result<(), DataError> {
        let file = self.file;
        for skin in file.document.skins() {
            let s = skin.index();
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            let added = self.added.get(&s).cloned().unwrap_or_default();
            if added.is_empty() && !joints.iter().any(|&j| self.world[j] != file.world[j]) {
                continue;
            }
            let ibm = inverse_binds(&self.data, &skin, joints.len()).map_err(|e| self.fail(e))?;
            let mut new = Vec::with_capacity(joints.len() + added.len());
            for (&j, b) in joints.iter().zip(&ibm) {
                new.push(self.checked(j, self.world[j].inverse() * file.world[j] * *b)?);
            }
            for &(n, m) in &added {
                new.push(self.checked(n, self.world[n].inverse() * m)?);
            }
            let own = skin
                .inverse_bind_matrices()
                .map(|a| a.index())
                .filter(|&a| accessor::references(&self.json).get(&a) == Some(&1));
            let span = own
                .filter(|_| added.is_empty())
                .and_then(|a| accessor::span(&self.json, a, self.bin.len()).map(|s| (a, s)));
            match span {
                Some((a, span)) if span.component == FLOAT && span.components == 16 => {
                    for (k, m) in new.iter().enumerate() {
                        span.write_f32(&mut self.bin, k, m);
                    }
                    accessor::refresh_bounds(&mut self.json, a, &span, &self.bin);
                }
                _ => {
                    self.append_binds(s, &new);
                    if !added.is_empty() {
                        unused.extend(own);
                    }
                }
            }
        }
        let new_skins: Vec<usize> = self.new_skins.keys().copied().collect();
        for s in new_skins {
            let mut new = Vec::new();
            for &(n, m) in self.added.get(&s).map(Vec::as_slice).unwrap_or_default() {
                new.push(self.checked(n, self.world[n].inverse() * m)?);
            }
            self.append_binds(s, &new);
        }
        Ok(())
    }

    /// An inverse bind matrix as stored, or the error of a singular joint.
    pub(super) fn checked(&self, joint: usize, m: DMat4) -> Result<[f32; 16], DataError> {
        if m.is_finite() {
            Ok(m.to_cols_array().map(|v| v as f32))
        } else {
            Err(self.fail(format!(
                "joint node {joint} has a singular world transform; cannot update its inverse bind matrix"
            )))
        }
    }

    /// Appends inverse bind matrices as a new accessor of skin `skin`.
    pub(super) fn append_binds(&mut self, skin: usize, matrices: &[[f32; 16]]) {
        let bytes: Vec<u8> = matrices
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = accessor::append_view(&mut self.json, &mut self.bin, &bytes, None);
        let acc = push(
            &mut self.json["accessors"],
            json!({"bufferView": view, "componentType": FLOAT, "count": matrices.len(), "type": "MAT4"}),
        );
        self.json["skins"][skin]["inverseBindMatrices"] = json!(acc);
    }

    /// Writes one primitive's weights (see [`Edit::set_weights`]); the
    /// accessors a replacement stops naming join `unused`.
    pub(super) fn write_set(
        &mut self,
        mesh: usize,
        primitive: usize,
        slots: &[Vec<(u32, f64)>],
        unused: &mut BTreeSet<usize>,
    ) {
        let attrs = &self.json["meshes"][mesh]["primitives"][primitive]["attributes"];
        let mut sets = Vec::new();
        while let (Some(j), Some(w)) = (
            attrs[format!("JOINTS_{}", sets.len())].as_u64(),
            attrs[format!("WEIGHTS_{}", sets.len())].as_u64(),
        ) {
            sets.push((j as usize, w as usize));
        }
        let named = accessor::references(&self.json);
        let count = slots.len();
        let plain = |a: usize, joints: bool| {
            let sp = accessor::span(&self.json, a, self.bin.len())?;
            let stored = if joints {
                matches!(sp.component, 5121 | 5123) && !sp.normalized
            } else {
                matches!(
                    (sp.component, sp.normalized),
                    (FLOAT, false) | (5121 | 5123, true)
                )
            };
            (named.get(&a) == Some(&1) && sp.count == count && sp.components == 4 && stored)
                .then_some(sp)
        };
        let spans: Option<Vec<_>> = sets
            .iter()
            .map(|&(j, w)| Some((plain(j, true)?, plain(w, false)?)))
            .collect();
        let top = slots.iter().flatten().map(|s| s.0).max().unwrap_or(0);
        if let Some(spans) = spans.filter(|s| s.first().is_some_and(|(j, _)| top <= j.uint_max())) {
            for (v, s) in slots.iter().enumerate() {
                remap::write_vertex(&mut self.bin, &spans, v, s);
            }
            for (&(j, w), (js, ws)) in sets.iter().zip(&spans) {
                accessor::refresh_bounds(&mut self.json, j, js, &self.bin);
                accessor::refresh_bounds(&mut self.json, w, ws, &self.bin);
            }
            return;
        }
        let mut joints = Vec::with_capacity(8 * count);
        let mut weights = Vec::with_capacity(16 * count);
        for s in slots {
            let mut j = [0u16; 4];
            let mut w = [0.0f64; 4];
            for (k, &(slot, x)) in s.iter().take(4).enumerate() {
                j[k] = slot as u16;
                w[k] = x;
            }
            joints.extend(j.iter().flat_map(|x| x.to_le_bytes()));
            weights.extend(
                remap::float_weights(&w)
                    .iter()
                    .flat_map(|x| x.to_le_bytes()),
            );
        }
        let mut add = |bytes: &[u8], component: u64| {
            let view =
                accessor::append_view(&mut self.json, &mut self.bin, bytes, Some(ARRAY_BUFFER));
            push(
                &mut self.json["accessors"],
                json!({"bufferView": view, "componentType": component, "count": count, "type": "VEC4"}),
            )
        };
        let (j, w) = (add(&joints, UNSIGNED_SHORT), add(&weights, FLOAT));
        if let Some(attrs) =
            self.json["meshes"][mesh]["primitives"][primitive]["attributes"].as_object_mut()
        {
            for (n, &(js, ws)) in sets.iter().enumerate() {
                attrs.remove(&format!("JOINTS_{n}"));
                attrs.remove(&format!("WEIGHTS_{n}"));
                unused.extend([js, ws]);
            }
            attrs.insert("JOINTS_0".into(), json!(j));
            attrs.insert("WEIGHTS_0".into(), json!(w));
        }
    }
}
