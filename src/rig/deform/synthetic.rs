//! Synthetic skinned hands made of tubes, with joints and weights known
//! exactly: for the tests and the benchmarks of deformation.
//!
//! A right hand lies in the plane z = 0 with the wrist at the origin, fingers
//! along +y (fanned a little), the palm facing -z and the thumb on the -x side;
//! a left hand is its mirror image in x = 0, built the same way with x negated.
//! Each finger (thumb included) is one straight open tube of radius
//! [`HandSpec::radius`] from its CMC to its tip, closed at the tip by a fan,
//! with rings every [`HandSpec::ring_spacing`] of [`HandSpec::around`]
//! vertices. Bones: metacarpal (CMC to MCP), then one per phalanx; the tip
//! node ends the last. At each joint the weight passes from the bone before to
//! the bone after by a smoothstep over a band of half-width
//! [`HandSpec::blend`] centred [`HandSpec::weight_shift`] distal of the joint
//! (0: centred on it, weight 1/2 exactly at the joint).

use super::{FingerNodes, HandChains, Skeleton};
use crate::dataset::Finger;
use crate::rig::naming::Side;
use crate::rig::skin::{SkinnedMesh, weld};
use glam::{DMat4, DQuat, DVec3};

/// What to build.
#[derive(Debug, Clone, PartialEq)]
pub struct HandSpec {
    pub side: Side,
    /// All joints children of one root (as WebXR's), instead of a parent-child chain.
    pub siblings: bool,
    /// Which fingers to build.
    pub fingers: Vec<Finger>,
    /// Tube radius, m.
    pub radius: f64,
    /// Vertices per ring.
    pub around: usize,
    /// Distance between rings, m.
    pub ring_spacing: f64,
    /// Half-width of the weight band at each joint, m.
    pub blend: f64,
    /// How far distal of the joint the weight band is centred, m.
    pub weight_shift: f64,
}

impl Default for HandSpec {
    fn default() -> Self {
        HandSpec {
            side: Side::Right,
            siblings: false,
            fingers: Finger::ALL.to_vec(),
            radius: 0.008,
            around: 16,
            ring_spacing: 0.001,
            blend: 0.006,
            weight_shift: 0.0,
        }
    }
}

/// A built hand: its skeleton, mesh and finger chains.
#[derive(Debug, Clone)]
pub struct SyntheticRig {
    pub skeleton: Skeleton,
    pub mesh: SkinnedMesh,
    pub chains: HandChains,
    pub names: Vec<String>,
}

/// (MCP position in mm, direction, bone lengths in mm: metacarpal, then phalanges) of a right hand.
fn layout(finger: Finger) -> ([f64; 3], [f64; 3], &'static [f64]) {
    match finger {
        Finger::Thumb => ([-30.0, 45.0, -8.0], [-0.55, 0.8, -0.1], &[40.0, 32.0, 28.0]),
        Finger::Index => (
            [-24.0, 90.0, 0.0],
            [-0.1, 1.0, 0.0],
            &[60.0, 40.0, 25.0, 20.0],
        ),
        Finger::Middle => (
            [-5.0, 93.0, 0.0],
            [0.0, 1.0, 0.0],
            &[62.0, 45.0, 28.0, 22.0],
        ),
        Finger::Ring => (
            [13.0, 89.0, 0.0],
            [0.08, 1.0, 0.0],
            &[58.0, 42.0, 27.0, 21.0],
        ),
        Finger::Little => (
            [30.0, 80.0, 0.0],
            [0.16, 1.0, 0.0],
            &[52.0, 33.0, 20.0, 18.0],
        ),
    }
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Builds the hand (see the module doc).
pub fn tube_hand(spec: &HandSpec) -> SyntheticRig {
    let mirror = match spec.side {
        Side::Right => DVec3::ONE,
        Side::Left => DVec3::new(-1.0, 1.0, 1.0),
    };
    let mut names = vec!["Armature".to_string(), "wrist".to_string()];
    let mut parent: Vec<Option<usize>> = vec![None, Some(0)];
    let mut world = vec![DMat4::IDENTITY, DMat4::IDENTITY];
    let mut chains = Vec::new();
    let mut positions = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut influences: Vec<Vec<(u16, f64)>> = Vec::new();
    // Skin joints: every node but the Armature; slot = node - 1.
    for &finger in &spec.fingers {
        let (mcp, dir, bones) = layout(finger);
        let dir = DVec3::from_array(dir).normalize() * mirror;
        let mcp = DVec3::from_array(mcp) * 0.001 * mirror;
        let cmc = mcp - dir * bones[0] * 0.001;
        let rot = DQuat::from_rotation_arc(DVec3::Y, dir);
        // Arc lengths from the CMC of each node's origin: CMC, MCP, ..., tip.
        let mut s = vec![0.0];
        for b in bones {
            s.push(s[s.len() - 1] + b * 0.001);
        }
        let first = names.len();
        let parts: Vec<String> = {
            let mut p = vec!["metacarpal".to_string()];
            let phal: &[&str] = if finger == Finger::Thumb {
                &["proximal", "distal"]
            } else {
                &["proximal", "intermediate", "distal"]
            };
            p.extend(phal.iter().map(|x| format!("phalanx-{x}")));
            p.push("tip".into());
            p
        };
        for (k, part) in parts.iter().enumerate() {
            names.push(format!("{finger}-{part}"));
            let up = if spec.siblings || k == 0 {
                0
            } else {
                first + k - 1
            };
            parent.push(Some(if k == 0 && !spec.siblings { 1 } else { up }));
            world.push(DMat4::from_rotation_translation(rot, cmc + dir * s[k]));
        }
        let nodes: Vec<usize> = (first..first + parts.len()).collect();
        chains.push(FingerNodes {
            finger,
            metacarpal: Some(nodes[0]),
            joints: nodes[1..nodes.len() - 1].to_vec(),
            tip: Some(nodes[nodes.len() - 1]),
        });
        // The tube.
        let u = (DVec3::Z - dir * DVec3::Z.dot(dir)).normalize();
        // Negated for a left hand, so that its vertex i is right's vertex i mirrored.
        let w = dir.cross(u) * mirror.x;
        let len = s[s.len() - 1];
        let rings = (len / spec.ring_spacing).round().max(1.0) as usize;
        let base = positions.len() as u32;
        let n = spec.around as u32;
        for r in 0..=rings {
            let t = len * r as f64 / rings as f64;
            // Bone of this ring: the weight passes from bone k-1 to bone k around joint k (k = 1.. inner nodes).
            let mut weights = vec![(0usize, 1.0)];
            for (k, &sk) in s.iter().enumerate().take(bones.len()).skip(1) {
                let c = sk + spec.weight_shift;
                let x = smoothstep((t - (c - spec.blend)) / (2.0 * spec.blend));
                if x <= 0.0 {
                    break;
                }
                weights = if x >= 1.0 {
                    vec![(k, 1.0)]
                } else {
                    vec![(k - 1, 1.0 - x), (k, x)]
                };
            }
            let mut infl: Vec<(u16, f64)> = weights
                .iter()
                .map(|&(b, x)| ((nodes[b] - 1) as u16, x))
                .collect();
            infl.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            for i in 0..spec.around {
                let phi = std::f64::consts::TAU * i as f64 / spec.around as f64;
                let p = cmc + dir * t + (u * phi.cos() + w * phi.sin()) * spec.radius;
                positions.push(p);
                influences.push(infl.clone());
            }
            if r > 0 {
                let a = base + (r as u32 - 1) * n;
                let b = base + r as u32 * n;
                for i in 0..n {
                    let j = (i + 1) % n;
                    triangles.push([a + i, a + j, b + j]);
                    triangles.push([a + i, b + j, b + i]);
                }
            }
        }
        // Cap the tip with a fan to its centre.
        let centre = positions.len() as u32;
        positions.push(cmc + dir * len);
        influences.push(influences[influences.len() - 1].clone());
        let last = base + rings as u32 * n;
        for i in 0..n {
            triangles.push([last + i, last + (i + 1) % n, centre]);
        }
    }
    if spec.side == Side::Left {
        // Mirroring turns the triangles inside out; keep them facing outwards.
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let joints: Vec<usize> = (1..names.len()).collect();
    let inverse_bind = joints.iter().map(|&j| world[j].inverse()).collect();
    let mut flat = Vec::new();
    let mut start = Vec::new();
    for infl in influences {
        start.push(flat.len());
        flat.extend(infl);
    }
    start.push(flat.len());
    let welded = weld(&positions);
    SyntheticRig {
        skeleton: Skeleton { parent, world },
        mesh: SkinnedMesh {
            skin: 0,
            positions,
            triangles,
            influences: flat,
            influence_start: start,
            joints,
            inverse_bind,
            welded,
            notes: Vec::new(),
        },
        chains: HandChains {
            side: spec.side,
            wrist: Some(1),
            fingers: chains,
        },
        names,
    }
}
