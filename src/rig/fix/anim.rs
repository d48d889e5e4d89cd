//! Translation keys of moved joints (`--fix`); the channels are read by
//! [`crate::rig::read::anim`].
//!
//! When `--fix` moves a joint it changes the node's rest translation by d
//! (in its parent's space). Translation keys of that node are offset by the
//! same d: a constant channel equal to the old rest translation (what Mixamo
//! and Blender export on every bone) becomes the new rest translation; a
//! channel that varies keeps its motion about the new rest, with a note.
//! Cubic-spline keys offset their values, not their tangents.

use super::accessor::{self, Span, push};
use crate::rig::read::anim::{Channel, animation_name, channels};
use crate::rig::read::naming::shown;
use glam::DVec3;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Offsets the translation keys of every node in `delta` (node -> change of
/// its rest translation), in place where the keys' accessor serves only
/// those keys, else in a copy with its own sampler. Returns remarks.
pub fn offset_translations(
    json: &mut Value,
    bin: &mut Vec<u8>,
    delta: &BTreeMap<usize, (DVec3, DVec3)>,
) -> Vec<String> {
    let mut notes = Vec::new();
    let mut varying: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    let mut constant: BTreeMap<usize, usize> = BTreeMap::new();
    let all = channels(json);
    for ch in &all {
        let (Some(node), Some(sampler), Some("translation")) =
            (ch.node, ch.sampler, ch.path.as_deref())
        else {
            continue;
        };
        let Some(&(old, d)) = delta.get(&node) else {
            continue;
        };
        let name = json["nodes"][node]["name"]
            .as_str()
            .map_or_else(|| format!("node {node}"), shown);
        let Some((output, cubic)) = key_output(json, ch.animation, sampler) else {
            continue;
        };
        let span = match accessor::span(json, output, bin.len()) {
            Some(sp) if sp.component == 5126 && sp.components == 3 => sp,
            _ => {
                notes.push(format!(
                    "animation {}: the translation keys of {name} are not stored as plain floats; \
                     they are not offset: re-bake them",
                    animation_name(json, ch.animation)
                ));
                continue;
            }
        };
        let values: Vec<usize> = (0..span.count).filter(|i| !cubic || i % 3 == 1).collect();
        let keys: Vec<DVec3> = values
            .iter()
            .map(|&i| DVec3::from_slice(&span.read(bin, i)))
            .collect();
        let tol = 1e-6 * old.length().max(1e-3);
        if keys.iter().all(|k| k.distance(old) <= tol) {
            *constant.entry(ch.animation).or_default() += 1;
        } else {
            varying.entry(ch.animation).or_default().push(name.clone());
        }
        let Some(target) = own_keys(json, bin, ch, &all, (output, span)) else {
            continue;
        };
        for (&i, k) in values.iter().zip(&keys) {
            let v = *k + d;
            target
                .1
                .write_f32(bin, i, &[v.x as f32, v.y as f32, v.z as f32]);
        }
        accessor::refresh_bounds(json, target.0, &target.1, bin);
    }
    notes.extend(offset_summary(json, constant, varying));
    notes
}

/// The output accessor of sampler `sampler` of animation `a`, and whether it is a
/// cubic spline (keys stored as in-tangent, value, out-tangent).
fn key_output(json: &Value, a: usize, sampler: usize) -> Option<(usize, bool)> {
    let s = &json["animations"][a]["samplers"][sampler];
    let output = s["output"].as_u64().map(|o| o as usize)?;
    Some((output, s["interpolation"].as_str() == Some("CUBICSPLINE")))
}

/// The keys of channel `ch` as an accessor that serves only it: `keys` itself when no
/// other sampler or channel uses it, else a copy with its own sampler (the channel is
/// pointed at it). `None` when the copy cannot be made.
fn own_keys(
    json: &mut Value,
    bin: &mut Vec<u8>,
    ch: &Channel,
    all: &[Channel],
    keys: (usize, Span),
) -> Option<(usize, Span)> {
    let (output, span) = keys;
    let sampler = ch.sampler?;
    let users = all
        .iter()
        .filter(|c| c.animation == ch.animation && c.sampler == Some(sampler))
        .count();
    if accessor::references(json).get(&output) == Some(&1) && users == 1 {
        return Some((output, span));
    }
    let t = copy_accessor(json, bin, output, &span)?;
    let mut s2 = json["animations"][ch.animation]["samplers"][sampler].clone();
    s2["output"] = json!(t.0);
    let new = push(&mut json["animations"][ch.animation]["samplers"], s2);
    json["animations"][ch.animation]["channels"][ch.channel]["sampler"] = json!(new);
    Some(t)
}

/// The remarks on offset keys: per animation, how many constant channels now key the
/// new rest translation, and which joints' varying keys were offset.
fn offset_summary(
    json: &Value,
    constant: BTreeMap<usize, usize>,
    varying: BTreeMap<usize, Vec<String>>,
) -> Vec<String> {
    let mut notes = Vec::new();
    for (a, n) in constant {
        notes.push(format!(
            "animation {}: {n} constant translation channel{} of moved joints now key the new rest \
             translation",
            animation_name(json, a),
            if n == 1 { "" } else { "s" }
        ));
    }
    for (a, names) in varying {
        notes.push(format!(
            "animation {}: the translation keys of {} vary; each key is offset by its joint's \
             move, so the motion is kept about the new rest position: check it",
            animation_name(json, a),
            names.join(", ")
        ));
    }
    notes
}

/// Appends a copy of a float accessor's elements (tightly packed, 4-byte
/// aligned) with its own view; returns the new accessor and its span.
fn copy_accessor(
    json: &mut Value,
    bin: &mut Vec<u8>,
    acc: usize,
    span: &Span,
) -> Option<(usize, Span)> {
    let mut bytes = Vec::with_capacity(4 * span.components * span.count);
    for i in 0..span.count {
        for x in span.read(bin, i) {
            bytes.extend_from_slice(&(x as f32).to_le_bytes());
        }
    }
    let view = accessor::append_view(json, bin, &bytes, None);
    let start = bin.len() - bytes.len();
    let mut a = json["accessors"][acc].clone();
    let o = a.as_object_mut()?;
    o.insert("bufferView".into(), json!(view));
    o.remove("byteOffset");
    let new = push(&mut json["accessors"], a);
    Some((
        new,
        Span {
            start,
            stride: 4 * span.components,
            ..*span
        },
    ))
}
