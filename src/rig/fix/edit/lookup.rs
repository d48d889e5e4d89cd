//! Questions an edit asks of the file as it stands: its nodes' places in
//! the tree, its scenes, its skins and which nodes draw a mesh.

use super::Edit;
use crate::dataset::DataError;
use std::collections::BTreeSet;

impl Edit<'_> {
    /// An error about the whole file being edited.
    pub(super) fn fail(&self, what: impl Into<String>) -> DataError {
        DataError::whole_file(&self.file.label, what)
    }

    /// Refuses a node index the file does not have.
    pub(super) fn check_node(&self, node: usize) -> Result<(), DataError> {
        if node < self.parent.len() {
            Ok(())
        } else {
            Err(self.fail(format!("has no node {node}")))
        }
    }

    /// How many ancestors `node` has.
    pub(super) fn depth(&self, mut node: usize) -> usize {
        let mut d = 0;
        while let Some(p) = self.parent[node] {
            d += 1;
            node = p;
        }
        d
    }

    /// The root of the tree `node` is in.
    pub(super) fn root_of(&self, mut node: usize) -> usize {
        while let Some(p) = self.parent[node] {
            node = p;
        }
        node
    }

    /// Whether `a` is `node` or one of its ancestors.
    pub(super) fn above(&self, a: usize, mut node: usize) -> bool {
        loop {
            if node == a {
                return true;
            }
            match self.parent[node] {
                Some(p) => node = p,
                None => return false,
            }
        }
    }

    /// Joints must share one root, and a skeleton be an ancestor (or one) of
    /// each, as glTF requires.
    pub(super) fn check_skeleton(
        &self,
        what: &str,
        joints: &[usize],
        skeleton: Option<usize>,
    ) -> Result<(), DataError> {
        let root = self.root_of(joints[0]);
        if let Some(&n) = joints.iter().find(|&&n| self.root_of(n) != root) {
            return Err(self.fail(format!(
                "the joints of {what} must share one root node: node {n}'s root is node {}, node {}'s is node {root}",
                self.root_of(n),
                joints[0]
            )));
        }
        if let Some(k) = skeleton
            && let Some(&n) = joints.iter().find(|&&n| !self.above(k, n))
        {
            return Err(self.fail(format!(
                "node {n} is not under node {k}, the skeleton of {what}"
            )));
        }
        Ok(())
    }

    /// The scene the file shows by default: `scene`, else the first.
    pub(super) fn default_scene(&self) -> Option<usize> {
        let scenes = self.json["scenes"].as_array().map_or(0, Vec::len);
        let s = self.json["scene"].as_u64().map_or(0, |s| s as usize);
        (s < scenes).then_some(s)
    }

    /// The scenes that list root node `root`.
    pub(super) fn scenes_with(&self, root: usize) -> Vec<usize> {
        let list = self.json["scenes"].as_array().map(Vec::as_slice);
        list.unwrap_or_default()
            .iter()
            .enumerate()
            .filter(|(_, s)| {
                s["nodes"]
                    .as_array()
                    .is_some_and(|n| n.iter().any(|n| n.as_u64() == Some(root as u64)))
            })
            .map(|(i, _)| i)
            .collect()
    }

    pub(super) fn skin_count(&self) -> usize {
        self.json["skins"].as_array().map_or(0, Vec::len)
    }

    /// The joints of skin `skin` as the edit leaves them.
    pub(super) fn skin_joints(&self, skin: usize) -> Option<Vec<usize>> {
        let joints = self.json["skins"].get(skin)?["joints"].as_array()?;
        Some(
            joints
                .iter()
                .filter_map(|j| j.as_u64().map(|j| j as usize))
                .collect(),
        )
    }

    /// The nodes that draw mesh `mesh`.
    pub(super) fn drawers(&self, mesh: usize) -> Vec<usize> {
        let nodes = self.json["nodes"].as_array().map(Vec::as_slice);
        nodes
            .unwrap_or_default()
            .iter()
            .enumerate()
            .filter(|(_, n)| n["mesh"].as_u64() == Some(mesh as u64))
            .map(|(i, _)| i)
            .collect()
    }

    /// The one skin with which every node that draws `mesh` draws it.
    pub(super) fn skin_of_mesh(&self, mesh: usize) -> Result<usize, DataError> {
        let drawers = self.drawers(mesh);
        let skins: BTreeSet<Option<u64>> = drawers
            .iter()
            .map(|&n| self.json["nodes"][n]["skin"].as_u64())
            .collect();
        match skins.into_iter().collect::<Vec<_>>().as_slice() {
            [Some(s)] => Ok(*s as usize),
            [] => Err(self.fail(format!("no node draws mesh {mesh}"))),
            [None] => Err(self.fail(format!(
                "mesh {mesh} has no skin to weight it to; bind it to one first (a new skin)"
            ))),
            _ => Err(self.fail(format!(
                "mesh {mesh} is drawn by nodes {drawers:?} with different skins (or none); its weights cannot serve them all"
            ))),
        }
    }
}
