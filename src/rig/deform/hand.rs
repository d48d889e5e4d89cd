//! The hands of a glTF file as deformation needs them: per hand its side,
//! its wrist and, per finger, the metacarpal, bending joints and tip nodes.
//!
//! Joints are recognised by name exactly as the audit recognises them (the
//! `--map` file, VRM tables, then the naming conventions), but the nodes of
//! a finger need not be one parent-child chain: WebXR's joints are siblings,
//! and the pose carries each distal joint with the proximal ones anyway
//! ([`super::pose`]). The metacarpal is the node named so, or else the MCP's
//! parent when that is not the wrist. The wrist is a node whose whole name is
//! `wrist` or `hand` (with a side and a `mixamorig`/`DEF` prefix allowed), or
//! else the nearest common ancestor of the fingers' MCPs when that is not a
//! scene root (Armature nodes sit at the origin, not at the wrist).

use super::{FingerNodes, HandChains};
use crate::analysis::placement::Joint;
use crate::dataset::{DataError, Finger};
use crate::rig::read::map::NameMap;
use crate::rig::read::naming::{Side, Slot};
use crate::rig::read::recognise::{choose_nodes, recognise, skin_weights, weighted_nodes};
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
    let mut out: Vec<HandChains> = Vec::new();
    for (s, fingers) in groups {
        let fingers: Vec<FingerNodes> = fingers
            .into_iter()
            .filter_map(|(finger, slots)| finger_nodes(file, finger, &slots))
            .collect();
        if fingers.is_empty() {
            continue;
        }
        let side = match s.or(side).or_else(|| side_from_label(&file.label)) {
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
        let wrist = wrist_of(file, &names, side, &fingers);
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

/// `left`/`right` in a file name, when exactly one of them is.
pub(crate) fn side_from_label(label: &str) -> Option<Side> {
    let stem = std::path::Path::new(label)
        .file_stem()?
        .to_string_lossy()
        .to_ascii_lowercase();
    match (stem.contains("left"), stem.contains("right")) {
        (true, false) => Some(Side::Left),
        (false, true) => Some(Side::Right),
        _ => None,
    }
}

/// A finger's nodes from its recognised slots; `None` without the MCP or an inner joint.
fn finger_nodes(
    file: &GltfFile,
    finger: Finger,
    slots: &HashMap<Slot, usize>,
) -> Option<FingerNodes> {
    let mcp = *slots.get(&Slot::Mcp)?;
    let mut joints = vec![mcp, *slots.get(&Slot::First)?];
    if finger != Finger::Thumb {
        joints.push(*slots.get(&Slot::Second)?);
    }
    let metacarpal = slots.get(&Slot::Carpal).copied().or_else(|| {
        // The MCP's parent, unless it is the hand itself (a name like `hand`/`wrist`).
        file.parent[mcp]
            .filter(|&p| file.parent[p].is_some() && !is_wrist_name(&file.node_names()[p]))
    });
    Some(FingerNodes {
        finger,
        metacarpal: metacarpal.filter(|m| !joints.contains(m)),
        joints,
        tip: slots.get(&Slot::Tip).copied(),
    })
}

/// A name that is a wrist or a hand as a whole: `wrist`, `hand`, `RightHand`,
/// `mixamorig:LeftHand`, `hand.R`, `DEF-hand.L`, `hand_l`.
fn is_wrist_name(name: &str) -> bool {
    let mut n: String = name
        .to_ascii_lowercase()
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .collect();
    for prefix in ["mixamorig", "def"] {
        if let Some(rest) = n.strip_prefix(prefix) {
            n = rest.to_string();
        }
    }
    for side in ["left", "right"] {
        if let Some(rest) = n.strip_prefix(side).or_else(|| n.strip_suffix(side)) {
            n = rest.to_string();
        }
    }
    if n.len() == 5 && (n.ends_with('l') || n.ends_with('r')) && n.starts_with("hand") {
        n.truncate(4);
    }
    n == "wrist" || n == "hand"
}

/// The wrist node of a hand (see the module doc), if one is found.
fn wrist_of(
    file: &GltfFile,
    names: &[String],
    side: Side,
    fingers: &[FingerNodes],
) -> Option<usize> {
    let named: Vec<usize> = (0..names.len())
        .filter(|&i| is_wrist_name(&names[i]))
        .collect();
    let sided = |i: &&usize| {
        let n = names[**i].to_ascii_lowercase();
        let other = match side {
            Side::Left => ["right", ".r", "_r"],
            Side::Right => ["left", ".l", "_l"],
        };
        !other.iter().any(|o| n.contains(o))
    };
    if let Some(&w) = named.iter().find(sided) {
        return Some(w);
    }
    // The nearest common ancestor of the MCPs.
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
    fn wrist_names() {
        for yes in [
            "wrist",
            "hand",
            "RightHand",
            "mixamorig:LeftHand",
            "hand.R",
            "DEF-hand.L",
            "hand_l",
        ] {
            assert!(is_wrist_name(yes), "{yes}");
        }
        for no in ["handle", "RightHandIndex1", "forearm", "palm.01.R"] {
            assert!(!is_wrist_name(no), "{no}");
        }
        assert_eq!(side_from_label("rigs/left.glb"), Some(Side::Left));
        assert_eq!(side_from_label("Right-Hand.glb"), Some(Side::Right));
        assert_eq!(side_from_label("hands.glb"), None);
    }
}
