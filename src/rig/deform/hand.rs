//! The hands of a glTF file as deformation needs them: per hand its side,
//! its wrist and, per finger, the metacarpal, bending joints and tip nodes.
//!
//! Joints are recognised by name exactly as the audit recognises them (the
//! `--map` file, VRM tables, then the naming conventions), but the nodes of
//! a finger need not be one parent-child chain: WebXR's joints are siblings,
//! and the pose carries each distal joint with the proximal ones anyway
//! ([`super::pose`]). The wrist is the hand bone the audit recognises (a VRM
//! humanoid table's `rightHand`, or a name such as `wrist`, `RightHand`,
//! `J_Bip_R_Hand`, `hand_r`; see [`crate::rig::read::naming::parse_hand`]), or
//! else the nearest common ancestor of the fingers' MCPs when that is not a
//! scene root (Armature nodes sit at the origin, not at the wrist). The
//! metacarpal is the node named so, or else the MCP's parent when that is
//! neither the wrist nor the parent of another finger's MCP: every finger of a
//! VRM avatar hangs from the one hand bone, which is no finger's metacarpal.

use super::{FingerNodes, HandChains};
use crate::analysis::placement::Joint;
use crate::dataset::{DataError, Finger};
use crate::rig::read::map::NameMap;
use crate::rig::read::naming::{Side, Slot, hand_side};
use crate::rig::read::recognise::{
    choose_nodes, recognise, skin_weights, weighted_nodes, wrist_of, wrists,
};
use crate::rig::read::{GltfFile, Rig};
use std::collections::{BTreeMap, HashMap};

/// Every hand of `file` with at least one complete finger (MCP and its inner
/// joints), left before right. A hand whose names carry no side takes `side`,
/// or else the side the file name says (`left`/`right` in it); without
/// either it is refused, saying so.
pub fn hands(
    file: &GltfFile,
    map: Option<&NameMap>,
    side: Option<Side>,
) -> Result<Vec<HandChains>, DataError> {
    let names = file.node_names();
    // The same weights as the audit weighs candidates with.
    let weights = skin_weights(file);
    let weighted = weighted_nodes(weights.as_ref(), names.len());
    let found = recognise(file, &names, map, &weighted)?;
    let (best, _) = choose_nodes(&found);
    let mut groups: BTreeMap<Option<Side>, BTreeMap<Finger, HashMap<Slot, usize>>> =
        BTreeMap::new();
    for (&(s, finger, slot), &(_, node)) in &best {
        groups
            .entry(s)
            .or_default()
            .entry(finger)
            .or_default()
            .insert(slot, node);
    }
    let hand_bones = wrists(file, &names, &weighted);
    let mut out: Vec<HandChains> = Vec::new();
    for (s, fingers) in groups {
        let mut fingers: Vec<FingerNodes> = fingers
            .into_iter()
            .filter_map(|(finger, slots)| finger_nodes(finger, &slots))
            .collect();
        if fingers.is_empty() {
            continue;
        }
        let side = match hand_side(s, side, &file.label) {
            Some(x) => x,
            None => {
                return Err(DataError::whole_file(
                    &file.label,
                    "its joint names do not say which hand this is (as WebXR's do not), nor does \
                     the file name; give --side left or --side right",
                ));
            }
        };
        if out.iter().any(|h| h.side == side) {
            return Err(DataError::whole_file(
                &file.label,
                format!(
                    "has two {} hands (one named with the side, one without); give --map to choose",
                    side.name()
                ),
            ));
        }
        let wrist = wrist_of(&hand_bones, s)
            .or_else(|| common_ancestor(file, &fingers))
            .filter(|w| !fingers.iter().any(|f| f.finger_nodes().contains(w)));
        parent_metacarpals(file, wrist, &mut fingers);
        out.push(HandChains {
            side,
            wrist,
            fingers,
        });
    }
    if out.is_empty() {
        return Err(DataError::whole_file(
            &file.label,
            "has no finger with an MCP and its inner joints named as the audit knows them \
             (see `phalanx audit --help`); give --map FILE to name them",
        ));
    }
    out.sort_by_key(|h| h.side);
    Ok(out)
}

/// A finger's nodes from its recognised slots, its metacarpal the one named
/// so (see [`parent_metacarpals`] for the others); `None` without the MCP or an
/// inner joint.
fn finger_nodes(finger: Finger, slots: &HashMap<Slot, usize>) -> Option<FingerNodes> {
    let mcp = *slots.get(&Slot::Mcp)?;
    let mut joints = vec![mcp, *slots.get(&Slot::First)?];
    if finger != Finger::Thumb {
        joints.push(*slots.get(&Slot::Second)?);
    }
    Some(FingerNodes {
        finger,
        metacarpal: slots
            .get(&Slot::Carpal)
            .copied()
            .filter(|m| !joints.contains(m)),
        joints,
        tip: slots.get(&Slot::Tip).copied(),
    })
}

/// Gives each finger without a named metacarpal its MCP's parent, unless that
/// parent is the wrist, a scene root, a node of a finger, or the parent of
/// another finger's MCP (the hand bone every finger of a VRM hangs from).
fn parent_metacarpals(file: &GltfFile, wrist: Option<usize>, fingers: &mut [FingerNodes]) {
    let parent_of_mcp = |f: &FingerNodes| file.parent[f.joints[0]];
    let used: Vec<usize> = fingers
        .iter()
        .flat_map(|f| f.finger_nodes().into_iter().chain(f.metacarpal))
        .collect();
    let parents: Vec<Option<usize>> = fingers.iter().map(parent_of_mcp).collect();
    for (k, f) in fingers.iter_mut().enumerate() {
        if f.metacarpal.is_some() {
            continue;
        }
        f.metacarpal = parents[k].filter(|&p| {
            file.parent[p].is_some()
                && Some(p) != wrist
                && !used.contains(&p)
                && parents.iter().filter(|&&q| q == Some(p)).count() == 1
        });
    }
}

/// The nearest common ancestor of the fingers' MCPs, when it is not a scene root.
fn common_ancestor(file: &GltfFile, fingers: &[FingerNodes]) -> Option<usize> {
    let ancestors = |mut n: usize| {
        let mut up = Vec::new();
        let mut steps = 0;
        while let Some(p) = file.parent[n] {
            up.push(p);
            n = p;
            steps += 1;
            if steps > file.parent.len() {
                break;
            }
        }
        up
    };
    let mut lists = fingers.iter().map(|f| ancestors(f.joints[0]));
    let first = lists.next()?;
    let rest: Vec<Vec<usize>> = lists.collect();
    first
        .into_iter()
        .find(|a| rest.iter().all(|l| l.contains(a)))
        .filter(|&a| file.parent[a].is_some())
}

impl Rig {
    /// The chains of each hand for the deformation measures ([`super`]):
    /// per side, the fingers' metacarpal, bending joints and tip nodes and the
    /// wrist. Fingers whose names carry no side (WebXR) are given `unsided`,
    /// or left out when it is `None`. Reference chains without nodes are left out.
    pub fn hand_chains(&self, unsided: Option<Side>) -> Vec<HandChains> {
        let mut hands: BTreeMap<Side, HandChains> = BTreeMap::new();
        for c in &self.chains {
            let Some(side) = c.side.or(unsided) else {
                continue;
            };
            if c.joints.iter().any(|j| j.node.is_none()) {
                continue;
            }
            let bending: Vec<usize> = c
                .joints
                .iter()
                .filter(|j| j.joint != Joint::Tip)
                .filter_map(|j| j.node)
                .collect();
            let hand = hands.entry(side).or_insert_with(|| HandChains {
                side,
                wrist: c.wrist.as_ref().map(|w| w.node),
                fingers: Vec::new(),
            });
            if hand.wrist.is_none() {
                hand.wrist = c.wrist.as_ref().map(|w| w.node);
            }
            hand.fingers.push(FingerNodes {
                finger: c.finger,
                metacarpal: c.metacarpal.as_ref().map(|m| m.node),
                joints: bending,
                tip: c
                    .joints
                    .iter()
                    .find(|j| j.joint == Joint::Tip)
                    .and_then(|j| j.node),
            });
        }
        hands.into_values().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sides_from_file_names() {
        use crate::rig::read::naming::side_from_label;
        assert_eq!(side_from_label("rigs/left.glb"), Some(Side::Left));
        assert_eq!(side_from_label("Right-Hand.glb"), Some(Side::Right));
        assert_eq!(side_from_label("hands.glb"), None);
    }
}
