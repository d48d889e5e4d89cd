//! `audit --moves FILE.csv`: the joints a fix moves, as values a technical
//! artist types into a DCC's channel box or sets from a script.
//!
//! The list is read off the fix itself: the rig as given and its fixed copy
//! (as `--fix` would write it, in memory) are compared node by node, and
//! every node whose local translation changed is listed, so the CSV follows
//! whatever the fix decides (the joints it moves, and the ones after them on
//! the chain that it pins where they were). Per node: its name, its old and
//! new world positions in metres (+Y up), and its new local translation in
//! the file's own units and its parent's axes. For glTF that is the fixed
//! copy's `translation`; for FBX it is the node's `Lcl Translation` plus the
//! change of its origin in its parent's frame (only translations move, so
//! the rest of FBX's transform stack, pivots and pre-rotations included, is
//! a fixed offset). Cost: O(nodes).

use super::GltfFile;
use crate::dataset::csvinput::quote;
use glam::DVec3;
use serde_json::Value;

/// One moved node.
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    pub node: usize,
    pub name: String,
    /// World position before and after, in metres.
    pub old_world: DVec3,
    pub new_world: DVec3,
    /// The new local translation, in the file's units and the parent's axes
    /// (FBX: the new `Lcl Translation`).
    pub new_local: DVec3,
}

/// The header of the CSV `--moves` writes (report::csv_out::moves).
pub const HEADER: [&str; 10] = [
    "node",
    "old_x_m",
    "old_y_m",
    "old_z_m",
    "new_x_m",
    "new_y_m",
    "new_z_m",
    "new_local_x",
    "new_local_y",
    "new_local_z",
];

/// A change of local translation smaller than this (file units) is no move:
/// the fix rewrites pinned nodes that did not move in f64 from f32 values.
const UNMOVED: f64 = 1e-9;

/// A node's local translation as the JSON stores it (full f64): its
/// `translation`, or the last column of its `matrix`.
fn translation(json: &Value, node: usize) -> DVec3 {
    let nd = &json["nodes"][node];
    let at = |v: &Value, k: usize| v.get(k).and_then(Value::as_f64).unwrap_or(0.0);
    if let Some(m) = nd.get("matrix") {
        DVec3::new(at(m, 12), at(m, 13), at(m, 14))
    } else {
        let t = &nd["translation"];
        DVec3::new(at(t, 0), at(t, 1), at(t, 2))
    }
}

/// The nodes whose local translation differs between `original` and
/// `fixed` (its fixed copy), in node order; and the warnings a TD needs
/// (an FBX node that does not inherit its parent's scale).
pub fn moves(original: &GltfFile, fixed: &GltfFile) -> (Vec<Move>, Vec<String>) {
    let names = original.node_names();
    let mut out = Vec::new();
    let mut warnings = Vec::new();
    for (i, (name, (w_old, w_new))) in names
        .iter()
        .zip(original.world.iter().zip(&fixed.world))
        .enumerate()
    {
        let old = translation(&original.json, i);
        let new = translation(&fixed.json, i);
        let delta = new - old;
        // A NaN change is no move either (the reader refuses non-finite transforms).
        if delta.abs().max_element().is_nan() || delta.abs().max_element() <= UNMOVED {
            continue;
        }
        let new_local = match &original.fbx {
            Some(src) => {
                if src.inherits_normally.get(i) == Some(&false) {
                    warnings.push(format!(
                        "{} does not inherit its parent's scale in full (FBX InheritType); its new \
                         Lcl Translation may be off by that scale: check its world position",
                        quote(name)
                    ));
                }
                src.lcl_translation.get(i).copied().flatten().unwrap_or(old) + delta
            }
            None => new,
        };
        out.push(Move {
            node: i,
            name: name.clone(),
            old_world: w_old.w_axis.truncate(),
            new_world: w_new.w_axis.truncate(),
            new_local,
        });
    }
    (out, warnings)
}
