//! What a fix moved, judged again: the fingers with a moved joint and each
//! moved joint's distance to its skin's bend before and after.

use crate::rig::judge::AuditedRig;

/// A finger the fix moved, judged again from the written copy.
#[derive(Debug, Clone, PartialEq)]
pub struct MovedFinger {
    /// The finger, as "right index".
    pub label: String,
    /// Its T^2 and the region's bound in the re-audit (`None`: judged
    /// without a region, on J2/J1).
    pub t2: Option<(f64, f64)>,
    /// Inside the region (or J2/J1's interval) after the fix.
    pub inside: bool,
}

/// The fingers of `after` (the written copy, judged) that hold a node of
/// `moved`, in the copy's order.
pub fn moved_fingers(after: &AuditedRig, moved: &[(String, f64)]) -> Vec<MovedFinger> {
    after
        .fingers
        .iter()
        .filter(|f| {
            f.chain
                .joints
                .iter()
                .any(|j| moved.iter().any(|(node, d)| *d > 0.0 && *node == j.name))
        })
        .map(|f| MovedFinger {
            label: f.chain.label(),
            t2: f.audit.region.as_ref().map(|r| (r.t2, r.bound)),
            inside: f.audit.is_consistent(),
        })
        .collect()
}

/// A moved joint and its distance to where its skin bends, in rig units.
#[derive(Debug, Clone, PartialEq)]
pub struct MovedBend {
    /// The node.
    pub node: String,
    /// The joint, as "right index PIP".
    pub joint: String,
    /// Before the fix: from the rig's joint to its bend (`None`: no bend found).
    pub before: Option<f64>,
    /// After it: from the moved joint to its bend in the fixed copy.
    pub after: Option<f64>,
    /// Vertices whose weights the fix changed, counted for the moved joint
    /// nearest each (0 with the weights as painted).
    pub reweighted: usize,
}

/// The distance from joint `node` of `rig` to where its skin bends, with the
/// joint's label ("right index PIP"); `None` when the node is not a judged
/// finger's joint.
fn bend_of(rig: &AuditedRig, node: &str) -> Option<(String, Option<f64>)> {
    rig.fingers.iter().find_map(|f| {
        let j = f.chain.joints.iter().find(|j| j.name == node)?;
        let d = f
            .bends
            .iter()
            .find(|b| b.joint == j.joint)
            .and_then(|b| b.at)
            .map(|at| at.distance(j.position));
        Some((format!("{} {}", f.chain.label(), j.joint.name()), d))
    })
}

/// The moved joints' bends before and after a fix, and the bend defects
/// `after` (the fixed copy, judged) flags that `before` (the rig) did not.
pub fn bends_across(
    before: &AuditedRig,
    after: &AuditedRig,
    moved: &[(String, f64)],
) -> (Vec<MovedBend>, Vec<String>) {
    let bends = moved
        .iter()
        .filter_map(|(node, _)| {
            let (joint, d0) = bend_of(before, node)?;
            let d1 = bend_of(after, node).and_then(|b| b.1);
            Some(MovedBend {
                node: node.clone(),
                joint,
                before: d0,
                after: d1,
                reweighted: 0,
            })
        })
        .collect();
    let flagged = |rig: &AuditedRig| -> Vec<String> {
        rig.fingers
            .iter()
            .flat_map(|f| {
                f.bends
                    .iter()
                    .filter(|b| b.flagged)
                    .map(move |b| format!("{} {}", f.chain.label(), b.joint.name()))
            })
            .collect()
    };
    let old = flagged(before);
    let new = flagged(after)
        .into_iter()
        .filter(|j| !old.contains(j))
        .collect();
    (bends, new)
}
