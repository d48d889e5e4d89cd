//! `audit --moves FILE.csv`: the joints a fix moves, as values a technical
//! artist types into a DCC's channel box or sets from a script.
//!
//! The list is read off the fix itself: the rig as given and its fixed copy
//! (the bytes `--fix` writes, made once for both in `rig::session`) are
//! compared node by node, and every node whose local translation changed is
//! listed, so the CSV follows whatever the fix decides (the joints it moves,
//! and the ones after them on the chain that it pins where they were),
//! however the fix comes to decide it. A change the CSV cannot carry (a
//! node's rotation or scale) is a warning, never left out silently. Per node: its name, its old and
//! new world positions in metres (+Y up), and its new local translation in
//! the file's own units and its parent's axes. For glTF that is the fixed
//! copy's `translation`; for FBX it is the node's `Lcl Translation` plus the
//! change of its origin in its parent's frame (only translations move, so
//! the rest of FBX's transform stack, pivots and pre-rotations included, is
//! a fixed offset). Cost: O(nodes).

use crate::dataset::csvinput::quote;
use crate::rig::read::GltfFile;
use crate::rig::read::gltf::local_matrix;
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

/// A change of a local matrix's rotation and scale columns larger than this
/// is a change the CSV cannot carry (the fix moves translations only; f32
/// rounding stays far below it).
const UNROTATED: f64 = 1e-6;

/// The nodes whose local translation differs between `original` and
/// `fixed` (its fixed copy), in node order; and the warnings a TD needs (an
/// FBX node that does not inherit its parent's scale; a node whose rotation
/// or scale the fix changed, which a translation cannot say).
pub fn moves(original: &GltfFile, fixed: &GltfFile) -> (Vec<Move>, Vec<String>) {
    let names = original.node_names();
    let mut out = Vec::new();
    let mut warnings = Vec::new();
    let linear = |f: &GltfFile| -> Vec<glam::DMat3> {
        f.document
            .nodes()
            .map(|n| glam::DMat3::from_mat4(local_matrix(&n)))
            .collect()
    };
    for (i, (a, b)) in linear(original).iter().zip(linear(fixed)).enumerate() {
        let off = (*a - b)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        if off.is_nan() || off > UNROTATED {
            let name = names.get(i).map_or("?", String::as_str);
            warnings.push(format!(
                "the fix changed the rotation or scale of {}, which --moves does not list (it \
                 lists translations): apply it with --fix on a glTF copy instead",
                quote(name)
            ));
        }
    }
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
                let parent = original.parent.get(i).copied().flatten();
                let off = |k: Option<usize>| k.is_some_and(|k| src.off_bind.get(k) == Some(&true));
                if off(Some(i)) || off(parent) {
                    warnings.push(format!(
                        "{} (or its parent) is saved out of its bind pose: its new Lcl \
                         Translation is its stored one moved by the fix, in the bind pose's \
                         frame; set it in the bind pose and check its world position",
                        quote(name)
                    ));
                }
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

/// A vertex whose skin weights the fix changed: its mesh (the glTF mesh's
/// name, or the FBX mesh's), its primitive and index there (for FBX, the
/// mesh's control point), and its new influences by node name, largest
/// first, summing to 1.
#[derive(Debug, Clone, PartialEq)]
pub struct WeightChange {
    pub mesh: String,
    pub primitive: usize,
    pub vertex: usize,
    pub influences: Vec<(String, f64)>,
}

/// The header of the weights CSV `--moves` writes beside its moves
/// (`report::csv_out::weight_changes`): one row per influence of a changed
/// vertex, so a script sets each listed vertex's weights to its rows.
pub const WEIGHTS_HEADER: [&str; 5] = ["mesh", "primitive", "vertex", "node", "weight"];

/// Influences this close are the same (the fix writes f32 weights).
const SAME_WEIGHT: f64 = 1e-6;

/// Every vertex whose influences differ between `original` and `fixed` (its
/// fixed copy, whose primitives are the original's, in order), with its new
/// influences. O(vertices x influences).
pub fn weight_changes(original: &GltfFile, fixed: &GltfFile) -> Vec<WeightChange> {
    use crate::rig::read::weights::SkinWeights;
    let (Some(da), Some(db)) = (original.buffer_data(), fixed.buffer_data()) else {
        return Vec::new();
    };
    let (a, b) = (
        SkinWeights::read(original, &da),
        SkinWeights::read(fixed, &db),
    );
    let names = fixed.node_names();
    let mesh_name = |m: usize| {
        fixed
            .document
            .meshes()
            .nth(m)
            .and_then(|x| x.name().map(str::to_string))
            .unwrap_or_else(|| format!("mesh {m}"))
    };
    let mut out = Vec::new();
    for (pa, pb) in a.primitives.iter().zip(&b.primitives) {
        if (pa.mesh, pa.primitive) != (pb.mesh, pb.primitive) {
            continue;
        }
        for (v, (ia, ib)) in pa.influences.iter().zip(&pb.influences).enumerate() {
            let same = ia.len() == ib.len()
                && ia
                    .iter()
                    .zip(ib)
                    .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= SAME_WEIGHT);
            if same {
                continue;
            }
            out.push(WeightChange {
                mesh: mesh_name(pb.mesh),
                primitive: pb.primitive,
                vertex: v,
                influences: ib
                    .iter()
                    .map(|&(n, w)| (names.get(n).cloned().unwrap_or_default(), w))
                    .collect(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::read::source::FbxSource;
    use serde_json::json;

    /// A two-node glTF: a root at `root` and a child at `t` below it, with `r`
    /// the child's rotation (xyzw).
    fn file(t: [f64; 3], r: [f64; 4]) -> GltfFile {
        let doc = json!({
            "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [
                {"name": "root", "translation": [0.0, 1.0, 0.0], "children": [1]},
                {"name": "tip", "translation": t, "rotation": r},
            ],
        });
        GltfFile::from_bytes("t.gltf", doc.to_string().as_bytes()).unwrap()
    }

    const NONE: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

    #[test]
    fn a_moved_node_is_listed_with_its_new_translation_and_world_position() {
        let (a, b) = (file([0.0, 0.1, 0.0], NONE), file([0.0, 0.1, 0.02], NONE));
        let (m, w) = moves(&a, &b);
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(m.len(), 1);
        assert_eq!(m[0].name, "tip");
        // By hand: the root at y = 1 adds to the child's translation (world
        // matrices come from the f32 the gltf crate reads).
        assert!(m[0].old_world.distance(DVec3::new(0.0, 1.1, 0.0)) < 1e-6);
        assert!(m[0].new_world.distance(DVec3::new(0.0, 1.1, 0.02)) < 1e-6);
        assert!(m[0].new_local.distance(DVec3::new(0.0, 0.1, 0.02)) < 1e-12);
        // Nothing moved, nothing listed.
        assert!(moves(&a, &file([0.0, 0.1, 0.0], NONE)).0.is_empty());
    }

    #[test]
    fn an_fbx_node_gets_its_lcl_translation_moved_by_the_change() {
        // Lcl Translation (in cm, say) differs from the glTF's local
        // translation by the transform stack's fixed offsets; the change is added.
        let (mut a, b) = (file([0.0, 0.1, 0.0], NONE), file([0.0, 0.1, 0.02], NONE));
        let src = |off_bind: Vec<bool>, inherits: Vec<bool>| FbxSource {
            version: 7500,
            ascii: false,
            unit_meters: 1.0,
            axes: "+X right, +Y up, +Z front".into(),
            lcl_translation: vec![Some(DVec3::ZERO), Some(DVec3::new(5.0, 6.0, 7.0))],
            inherits_normally: inherits,
            off_bind,
        };
        a.fbx = Some(src(vec![false, false], vec![true, true]));
        let (m, w) = moves(&a, &b);
        assert!(w.is_empty(), "{w:?}");
        assert!(m[0].new_local.distance(DVec3::new(5.0, 6.0, 7.02)) < 1e-12);
        // Saved out of the bind pose (the parent), or not inheriting scale: said.
        a.fbx = Some(src(vec![true, false], vec![true, false]));
        let (_, w) = moves(&a, &b);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].contains("'tip' (or its parent) is saved out of its bind pose"),
            "{w:?}"
        );
        assert!(
            w[1].contains("does not inherit its parent's scale"),
            "{w:?}"
        );
    }

    #[test]
    fn a_changed_rotation_is_a_warning_not_a_silent_omission() {
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let a = file([0.0, 0.1, 0.0], NONE);
        let b = file([0.0, 0.1, 0.0], [0.0, 0.0, half, half]);
        let (m, w) = moves(&a, &b);
        assert!(m.is_empty());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("rotation or scale of 'tip'"), "{w:?}");
    }
}
