//! `audit --fix`: a copy of a rig with the joints the audit's explanation
//! moves (see [`crate::rig::judge`]) where it puts them, and everything else
//! kept. Joints the judge holds (at their skin bend, or a move under 1 mm:
//! [`crate::rig::judge::Held`]) stay.
//!
//! For each finger the explanation's joints (MCP, PIP, DIP: the fewest that
//! bring the finger inside the X-rays' prediction intervals; with
//! `--only-outside` only those whose own standing is outside) move to their
//! suggested points on the rig's own chain; the tip and the other joints keep
//! their world positions. Only translations change: a moved node's local
//! translation becomes P'^-1 x (P' its parent's new world matrix, x the
//! target), and every later chain node is re-pinned where it was, so
//! descendants off the chain follow their parent. In a rig whose joints are
//! siblings (WebXR) each joint node moves alone. World rotations and scales
//! are untouched.
//!
//! The mesh's rest shape is kept exactly: a joint whose world matrix goes from
//! W to W' gets the inverse bind matrix B' = W'^-1 W B, so W' B' = W B and every
//! skinned vertex is where it was (up to the f32 the file stores). `audit
//! --fix` leaves the skin weights as painted (the judge keeps every moved
//! joint within 1 mm of where they bend the skin); given `weights`,
//! [`fix_with`] moves each moved finger's weights with its joints (`remap`).
//! Translation keys of moved
//! nodes are offset by their rest translation's change (`anim`);
//! channels with paths glTF does not define are reported and left alone.
//!
//! Inverse bind matrices, weights and keys are rewritten in place in their
//! accessors when nothing else uses them (else a copy is appended), so the
//! fix leaves no unused accessor and a second fix of the fixed copy, which
//! moves nothing, writes the same bytes. Everything else in the file's JSON
//! is kept. The output is one .glb (or a .gltf with its buffer embedded),
//! every buffer merged into one.
//!
//! The writing is [`Edit`]'s ([`edit`]), the one glTF writer: the fix is
//! a plan of moves and carried weights handed to it.

pub(crate) mod accessor;
pub(crate) mod anim;
pub mod edit;
pub mod moves;
pub(crate) mod remap;

pub use edit::Edit;

use crate::dataset::DataError;
use crate::rig::judge::AuditedFinger;
use crate::rig::read::RigJoint;
use crate::rig::read::gltf::GltfFile;
use crate::rig::read::weights::SkinWeights;
use glam::DVec3;
use std::path::Path;

/// How a fix chooses the joints it moves.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FixOptions {
    /// Move only joints whose own standing is outside the prediction interval.
    pub only_outside: bool,
}

/// The outcome of a fix: the new file's bytes and what was done.
pub struct Fixed {
    pub bytes: Vec<u8>,
    /// (node name, distance moved), in chain order.
    pub moved: Vec<(String, f64)>,
    /// Remarks for the user (animations that drive moved joints, external images).
    pub warnings: Vec<String>,
    /// Each moved joint's node and how many of its finger's vertices took
    /// new weights nearest it (empty when the weights stay as painted).
    pub reweighted: Vec<(String, usize)>,
}

/// Writes the fixed copy with the default options and without moving skin
/// weights. `dir` resolves external buffers; `glb` picks the container.
pub fn fix(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    dir: &Path,
    glb: bool,
) -> Result<Fixed, DataError> {
    fix_with(file, fingers, None, dir, glb, &FixOptions::default())
}

/// Writes the fixed copy; with `weights`, the moved fingers' skin weights
/// move with their joints.
///
/// In steps: the target of every chain node; an [`Edit`] of the file (every
/// buffer merged into one); the nodes moved there (parents first); the moved
/// fingers' weights carried; then the edit finished: new inverse bind
/// matrices for the skins whose joints moved, the moved nodes' translation
/// keys, the carried weights, the output container.
pub fn fix_with(
    file: &GltfFile,
    fingers: &[AuditedFinger],
    weights: Option<&SkinWeights>,
    dir: &Path,
    glb: bool,
    opts: &FixOptions,
) -> Result<Fixed, DataError> {
    let plan = targets(fingers, opts.only_outside);
    let mut edit = Edit::new(file, dir)?;
    edit.move_nodes(&plan.targets)?;
    let mut reweighted = Vec::new();
    if let Some(w) = weights {
        let mut remapped = remap::Remapped::new();
        for (i, new_positions, _) in &plan.fingers {
            let f = &fingers[*i];
            let m = remap::FingerMove::of(&f.chain, &f.bends, |joint| {
                f.chain
                    .joints
                    .iter()
                    .position(|rj| rj.joint == joint)
                    .map(|k| new_positions[k])
                    .filter(|p| {
                        f.chain
                            .joints
                            .iter()
                            .any(|rj| rj.joint == joint && rj.position != *p)
                    })
            });
            let (carried, _, notes) = crate::rig::judge::carry::carry_finger(
                w,
                &m,
                crate::rig::bend::BEND_TOLERANCE_MM / 1000.0,
            );
            for note in notes {
                edit.warn(note);
            }
            reweighted.extend(remap::changed_per_joint(w, &m, &carried));
            remapped.extend(carried);
        }
        edit.write_carried(w, remapped);
    }
    let (bytes, warnings) = edit.finish(glb)?;
    Ok(Fixed {
        bytes,
        moved: plan.moved,
        warnings,
        reweighted,
    })
}

/// A node and the world position it goes to.
type Target = (usize, DVec3);

/// What a fix moves.
struct Plan {
    /// Nodes and the world positions they go to.
    targets: Vec<Target>,
    /// The moved joints' (name, distance).
    moved: Vec<(String, f64)>,
    /// Fingers (index into the audited fingers) with a moved joint, every
    /// joint's new position, and where each moved joint's skin bends now.
    fingers: Vec<(usize, Vec<DVec3>, Vec<Option<DVec3>>)>,
}

/// Where each chain node goes: the joints the explanation moves to their
/// suggestions, and the chain's other nodes after a moved one pinned where
/// they are. A joint the judge holds ([`crate::rig::judge::Held`]: at its
/// skin bend, or a move under the tolerance) stays. With `only_outside`, a
/// joint moves only when its own standing is outside the prediction interval.
fn targets(fingers: &[AuditedFinger], only_outside: bool) -> Plan {
    let mut plan = Plan {
        targets: Vec::new(),
        moved: Vec::new(),
        fingers: Vec::new(),
    };
    for (i, f) in fingers.iter().enumerate() {
        let (chain, audit) = (&f.chain, &f.audit);
        let moves = |rj: &RigJoint| {
            audit
                .joint(rj.joint)
                .filter(|j| j.fix_moves() && !(only_outside && j.standing.is_consistent()))
        };
        if !chain.joints.iter().any(|rj| moves(rj).is_some()) {
            continue;
        }
        let mut after_moved = false;
        let mut positions = Vec::new();
        let mut anchors = Vec::new();
        for rj in &chain.joints {
            let m = moves(rj);
            positions.push(m.map_or(rj.position, |j| j.suggested));
            anchors.push(m.and_then(|_| {
                f.bends
                    .iter()
                    .find(|b| b.joint == rj.joint)
                    .and_then(|b| b.at)
            }));
            let Some(node) = rj.node else { continue };
            match m {
                Some(j) => {
                    plan.moved.push((rj.name.clone(), j.shift));
                    plan.targets.push((node, j.suggested));
                    after_moved = true;
                }
                // Pinned: a later chain node keeps its place when one before it moves.
                None if after_moved => plan.targets.push((node, rj.position)),
                None => {}
            }
        }
        plan.fingers.push((i, positions, anchors));
    }
    plan
}
