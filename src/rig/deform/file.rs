//! One glTF file deformed: each of its hands found ([`super::hand`]), its
//! skinned mesh read ([`crate::rig::read::skin`]), curled to a pose and measured
//! ([`super::deform`]); and two files compared hand by hand ([`super::verdict`]).

use super::verdict::{self, JointVerdict};
use super::{Deformation, HandChains, Pose, PosedHand, Skeleton, Skinning};
use crate::dataset::DataError;
use crate::rig::read::GltfFile;
use crate::rig::read::map::NameMap;
use crate::rig::read::naming::Side;
use crate::rig::read::skin::{SkinnedMesh, pick_skin};
use std::path::Path;

/// One hand of a file, deformed.
#[derive(Debug, Clone)]
pub struct HandDeformation {
    pub chains: HandChains,
    pub posed: PosedHand,
    pub mesh: SkinnedMesh,
    pub deformation: Deformation,
}

impl HandDeformation {
    /// Per vertex of the mesh: whether the hand's bones skin it, that is,
    /// whether its largest weight is on the wrist, a metacarpal, or a node
    /// the pose moves (the fingers' joints and tips and whatever hangs from
    /// them). A figure frames these; a whole body's other vertices are not
    /// the hand.
    pub fn hand_vertices(&self) -> Vec<bool> {
        let n = self.posed.motion.len();
        let mut hand = vec![false; n];
        for (k, d) in self.posed.motion.iter().enumerate() {
            hand[k] = *d != glam::DMat4::IDENTITY;
        }
        let fixed = self
            .chains
            .wrist
            .into_iter()
            .chain(self.chains.fingers.iter().filter_map(|f| f.metacarpal))
            .chain(self.chains.fingers.iter().flat_map(|f| f.finger_nodes()));
        for k in fixed {
            if let Some(h) = hand.get_mut(k) {
                *h = true;
            }
        }
        (0..self.mesh.positions.len())
            .map(|v| {
                self.mesh
                    .dominant(v)
                    .and_then(|slot| self.mesh.joints.get(usize::from(slot)))
                    .is_some_and(|&node| hand.get(node).copied().unwrap_or(false))
            })
            .collect()
    }
}

/// Every hand of a file, deformed.
#[derive(Debug, Clone)]
pub struct FileDeformation {
    /// The file as the user named it (or what it is, for a fixed copy in memory).
    pub label: String,
    pub hands: Vec<HandDeformation>,
}

/// What to do to a file.
#[derive(Debug, Clone, Copy)]
pub struct DeformRequest<'a> {
    /// Custom joint names.
    pub map: Option<&'a NameMap>,
    /// The side of a hand whose names do not say.
    pub side: Option<Side>,
    pub pose: &'a Pose,
    pub method: Skinning,
}

/// Deforms every hand of `file`; `dir` resolves external buffers. Errors name
/// the file and the hand; a file whose hand has no skinned mesh is refused.
pub fn deform_file(
    file: &GltfFile,
    dir: &Path,
    req: &DeformRequest<'_>,
) -> Result<FileDeformation, DataError> {
    let skeleton = Skeleton::of(file);
    let mut hands = Vec::new();
    for chains in super::hand::hands(file, req.map, req.side)? {
        let side = chains.side.name();
        let nodes: Vec<usize> = chains
            .fingers
            .iter()
            .flat_map(|f| f.joints.iter().copied())
            .collect();
        let Some(skin) = pick_skin(file, &nodes) else {
            return Err(DataError::whole_file(
                &file.label,
                format!(
                    "no skin has the {side} hand's finger joints among its joints, so there is no \
                     skin to deform; deform needs a skinned mesh (audit judges bare skeletons)"
                ),
            ));
        };
        let mesh = SkinnedMesh::read(file, dir, skin)?;
        if mesh.triangles.is_empty() {
            return Err(DataError::whole_file(
                &file.label,
                format!("/skins/{skin}: the {side} hand's skinned mesh has no triangles to deform"),
            ));
        }
        let posed = super::pose::pose_hand(&skeleton, &chains, req.pose)
            .map_err(|e| DataError::whole_file(&file.label, format!("the {side} hand: {e}")))?;
        let deformation = super::deform(&mesh, &skeleton, &posed, req.method);
        hands.push(HandDeformation {
            chains,
            posed,
            mesh,
            deformation,
        });
    }
    Ok(FileDeformation {
        label: file.label.clone(),
        hands,
    })
}

/// The verdicts of every joint of every hand the two files both have (A = `a`).
pub fn compare_files(a: &FileDeformation, b: &FileDeformation) -> Vec<(Side, Vec<JointVerdict>)> {
    a.hands
        .iter()
        .filter_map(|ha| {
            let hb = b.hands.iter().find(|h| h.chains.side == ha.chains.side)?;
            Some((
                ha.chains.side,
                verdict::compare(&ha.deformation.measures, &hb.deformation.measures),
            ))
        })
        .collect()
}
