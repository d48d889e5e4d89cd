//! What deformation is given: the joint nodes of each finger and of each hand
//! (from the caller, [`super::hand`] for a file), and the skeleton they
//! belong to.

use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use crate::rig::read::naming::Side;
use glam::{DMat4, DVec3};
use serde::Serialize;

/// The joint nodes of one finger, root first; given by the caller, so the
/// node hierarchy is not needed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FingerNodes {
    pub finger: Finger,
    /// The metacarpal bone's node (its origin is the CMC joint), when the rig has one.
    pub metacarpal: Option<usize>,
    /// The bending joints' nodes from the root: MCP, PIP, DIP (thumb: MCP, IP);
    /// a node's origin is its joint. Fewer are allowed (the rest stay straight).
    pub joints: Vec<usize>,
    /// The fingertip node (the end of the last bone), when the rig has one.
    pub tip: Option<usize>,
}

impl FingerNodes {
    /// The anatomical joint of each entry of `joints`.
    pub fn joint_kinds(&self) -> Vec<Joint> {
        let all: &[Joint] = match self.finger {
            Finger::Thumb => &[Joint::Mcp, Joint::Ip],
            _ => &[Joint::Mcp, Joint::Pip, Joint::Dip],
        };
        all.iter().copied().take(self.joints.len()).collect()
    }

    /// Every node of the finger proper: its joints and the tip (not the metacarpal).
    pub fn finger_nodes(&self) -> Vec<usize> {
        self.joints.iter().copied().chain(self.tip).collect()
    }
}

/// The fingers of one hand and what is needed to find its palm.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HandChains {
    /// Which hand: it decides which side of the palm plane the fingers curl to.
    pub side: Side,
    /// The wrist (or hand) node, when the rig has one.
    pub wrist: Option<usize>,
    pub fingers: Vec<FingerNodes>,
}

impl HandChains {
    /// Checks the chains against a skeleton of `nodes` nodes: every index in
    /// range, no node used twice, one chain per finger, at most 3 bending
    /// joints (2 for the thumb). Lists every problem.
    pub fn check(&self, nodes: usize) -> Result<(), Vec<String>> {
        let mut problems = Vec::new();
        let mut seen = std::collections::BTreeMap::new();
        let mut fingers = std::collections::BTreeSet::new();
        for f in &self.fingers {
            if !fingers.insert(f.finger) {
                problems.push(format!("{} is given twice", f.finger));
            }
            let most = if f.finger == Finger::Thumb { 2 } else { 3 };
            if f.joints.is_empty() || f.joints.len() > most {
                problems.push(format!(
                    "{} has {} bending joints; give 1 to {most} (MCP first)",
                    f.finger,
                    f.joints.len()
                ));
            }
            for n in f.metacarpal.iter().chain(&f.joints).chain(&f.tip) {
                if *n >= nodes {
                    problems.push(format!(
                        "{}: node {n} does not exist (the file has {nodes} nodes)",
                        f.finger
                    ));
                } else if let Some(other) = seen.insert(*n, f.finger) {
                    problems.push(format!("node {n} is used by both {other} and {}", f.finger));
                }
            }
        }
        if let Some(w) = self.wrist {
            if w >= nodes {
                problems.push(format!("wrist node {w} does not exist"));
            } else if let Some(f) = seen.get(&w) {
                problems.push(format!("wrist node {w} is also a joint of {f}"));
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(problems)
        }
    }
}

/// The node hierarchy and rest (node pose) world matrices of a rig.
#[derive(Debug, Clone)]
pub struct Skeleton {
    pub parent: Vec<Option<usize>>,
    pub world: Vec<DMat4>,
}

impl Skeleton {
    /// The skeleton of a parsed glTF file.
    pub fn of(file: &crate::rig::read::GltfFile) -> Skeleton {
        Skeleton {
            parent: file.parent.clone(),
            world: file.world.clone(),
        }
    }

    /// The rest world position of node `n` (origin of its world matrix).
    pub fn position(&self, n: usize) -> DVec3 {
        self.world
            .get(n)
            .map_or(DVec3::ZERO, |m| m.w_axis.truncate())
    }
}
