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
use crate::rig::read::naming::Side;
use crate::rig::read::skin::{SkinnedMesh, weld};
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

/// The WebXR name of a finger (`index-finger`, `pinky-finger`, `thumb`): the
/// nodes are named as WebXR names its joints, so `naming` recognises them.
fn webxr_prefix(finger: Finger) -> &'static str {
    match finger {
        Finger::Thumb => "thumb",
        Finger::Index => "index-finger",
        Finger::Middle => "middle-finger",
        Finger::Ring => "ring-finger",
        Finger::Little => "pinky-finger",
    }
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// One finger's straight line: its CMC, unit direction, and the arc length
/// from the CMC of each node's origin (CMC, MCP, ..., tip).
struct FingerLine {
    cmc: DVec3,
    dir: DVec3,
    s: Vec<f64>,
}

/// The hand being built: nodes, then the mesh.
#[derive(Default)]
struct Builder {
    names: Vec<String>,
    parent: Vec<Option<usize>>,
    world: Vec<DMat4>,
    chains: Vec<FingerNodes>,
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    influences: Vec<Vec<(u16, f64)>>,
}

/// Builds the hand (see the module doc), in steps: per finger its line, its
/// nodes, its tube; then the skin's joints and the flat influence lists.
pub fn tube_hand(spec: &HandSpec) -> SyntheticRig {
    let mirror = match spec.side {
        Side::Right => DVec3::ONE,
        Side::Left => DVec3::new(-1.0, 1.0, 1.0),
    };
    let mut b = Builder {
        names: vec!["Armature".to_string(), "wrist".to_string()],
        parent: vec![None, Some(0)],
        world: vec![DMat4::IDENTITY, DMat4::IDENTITY],
        ..Builder::default()
    };
    // Skin joints: every node but the Armature; slot = node - 1.
    for &finger in &spec.fingers {
        let line = finger_line(finger, mirror);
        let nodes = b.add_nodes(finger, spec, &line);
        b.add_tube(spec, &line, &nodes, mirror);
    }
    if spec.side == Side::Left {
        // Mirroring turns the triangles inside out; keep them facing outwards.
        for t in &mut b.triangles {
            t.swap(1, 2);
        }
    }
    b.finish(spec.side)
}

/// The line of `finger` (mirrored by `mirror`), from [`layout`].
fn finger_line(finger: Finger, mirror: DVec3) -> FingerLine {
    let (mcp, dir, bones) = layout(finger);
    let dir = DVec3::from_array(dir).normalize() * mirror;
    let mcp = DVec3::from_array(mcp) * 0.001 * mirror;
    let cmc = mcp - dir * bones[0] * 0.001;
    let mut s = vec![0.0];
    for b in bones {
        s.push(s[s.len() - 1] + b * 0.001);
    }
    FingerLine { cmc, dir, s }
}

/// The weights of a ring at arc length `t`: the weight passes from bone k-1
/// to bone k around joint k (k = 1.. inner nodes), as (bone, weight).
fn ring_weights(spec: &HandSpec, s: &[f64], t: f64) -> Vec<(usize, f64)> {
    let bones = s.len() - 1;
    let mut weights = vec![(0usize, 1.0)];
    for (k, &sk) in s.iter().enumerate().take(bones).skip(1) {
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
    weights
}

impl Builder {
    /// The nodes of a finger (metacarpal, phalanges, tip), WebXR-named, and
    /// its chain; returns the node indices.
    fn add_nodes(&mut self, finger: Finger, spec: &HandSpec, line: &FingerLine) -> Vec<usize> {
        let rot = DQuat::from_rotation_arc(DVec3::Y, line.dir);
        let first = self.names.len();
        let mut parts = vec!["metacarpal".to_string()];
        let phal: &[&str] = if finger == Finger::Thumb {
            &["proximal", "distal"]
        } else {
            &["proximal", "intermediate", "distal"]
        };
        parts.extend(phal.iter().map(|x| format!("phalanx-{x}")));
        parts.push("tip".into());
        for (k, part) in parts.iter().enumerate() {
            self.names.push(format!("{}-{part}", webxr_prefix(finger)));
            let up = if spec.siblings || k == 0 {
                0
            } else {
                first + k - 1
            };
            self.parent
                .push(Some(if k == 0 && !spec.siblings { 1 } else { up }));
            self.world.push(DMat4::from_rotation_translation(
                rot,
                line.cmc + line.dir * line.s[k],
            ));
        }
        let nodes: Vec<usize> = (first..first + parts.len()).collect();
        self.chains.push(FingerNodes {
            finger,
            metacarpal: Some(nodes[0]),
            joints: nodes[1..nodes.len() - 1].to_vec(),
            tip: Some(nodes[nodes.len() - 1]),
        });
        nodes
    }

    /// The finger's tube: rings from the CMC to the tip, weighted by
    /// [`ring_weights`], closed at the tip by a fan.
    fn add_tube(&mut self, spec: &HandSpec, line: &FingerLine, nodes: &[usize], mirror: DVec3) {
        let (cmc, dir) = (line.cmc, line.dir);
        let u = (DVec3::Z - dir * DVec3::Z.dot(dir)).normalize();
        // Negated for a left hand, so that its vertex i is right's vertex i mirrored.
        let w = dir.cross(u) * mirror.x;
        let len = line.s[line.s.len() - 1];
        let rings = (len / spec.ring_spacing).round().max(1.0) as usize;
        let base = self.positions.len() as u32;
        let n = spec.around as u32;
        for r in 0..=rings {
            let t = len * r as f64 / rings as f64;
            let mut infl: Vec<(u16, f64)> = ring_weights(spec, &line.s, t)
                .iter()
                .map(|&(b, x)| ((nodes[b] - 1) as u16, x))
                .collect();
            infl.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            for i in 0..spec.around {
                let phi = std::f64::consts::TAU * i as f64 / spec.around as f64;
                let p = cmc + dir * t + (u * phi.cos() + w * phi.sin()) * spec.radius;
                self.positions.push(p);
                self.influences.push(infl.clone());
            }
            if r > 0 {
                let a = base + (r as u32 - 1) * n;
                let b = base + r as u32 * n;
                for i in 0..n {
                    let j = (i + 1) % n;
                    self.triangles.push([a + i, a + j, b + j]);
                    self.triangles.push([a + i, b + j, b + i]);
                }
            }
        }
        // Cap the tip with a fan to its centre.
        let centre = self.positions.len() as u32;
        self.positions.push(cmc + dir * len);
        let last_infl = self.influences.last().cloned().unwrap_or_default();
        self.influences.push(last_infl);
        let last = base + rings as u32 * n;
        for i in 0..n {
            self.triangles.push([last + i, last + (i + 1) % n, centre]);
        }
    }

    /// The rig: the skin's joints (every node but the Armature), inverse bind
    /// matrices, flat influence lists and welded vertices.
    fn finish(self, side: Side) -> SyntheticRig {
        let joints: Vec<usize> = (1..self.names.len()).collect();
        let inverse_bind = joints.iter().map(|&j| self.world[j].inverse()).collect();
        let mut flat = Vec::new();
        let mut start = Vec::new();
        for infl in self.influences {
            start.push(flat.len());
            flat.extend(infl);
        }
        start.push(flat.len());
        let welded = weld(&self.positions);
        SyntheticRig {
            skeleton: Skeleton {
                parent: self.parent,
                world: self.world,
            },
            mesh: SkinnedMesh {
                skin: 0,
                positions: self.positions,
                triangles: self.triangles,
                influences: flat,
                influence_start: start,
                joints,
                inverse_bind,
                welded,
                notes: Vec::new(),
            },
            chains: HandChains {
                side,
                wrist: Some(1),
                fingers: self.chains,
            },
            names: self.names,
        }
    }
}

impl SyntheticRig {
    /// The rig as a binary glTF (.glb): its nodes (local translation and
    /// rotation from the world matrices), one skin over every node but the
    /// `Armature`, and one skinned mesh with `JOINTS_n`/`WEIGHTS_n` sets of
    /// four influences (as many sets as the most influenced vertex needs).
    /// Positions, weights and matrices are stored as f32, as glTF stores them.
    pub fn to_glb(&self) -> Result<Vec<u8>, String> {
        let mut out = GlbParts::default();
        let mesh = &self.mesh;
        let positions: Vec<[f32; 3]> = mesh
            .positions
            .iter()
            .map(|p| p.as_vec3().to_array())
            .collect();
        let (lo, hi) = bounds(&positions);
        let pos = out.accessor(
            &positions.concat(),
            5126,
            "VEC3",
            Some((lo.to_vec(), hi.to_vec())),
        );
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let idx = out.accessor(&indices, 5125, "SCALAR", None);
        let mut attributes = serde_json::Map::new();
        attributes.insert("POSITION".into(), pos.into());
        out.weight_sets(mesh, &mut attributes);
        let ibm: Vec<f32> = mesh
            .inverse_bind
            .iter()
            .flat_map(|m| m.as_mat4().to_cols_array())
            .collect();
        let ibm = out.accessor(&ibm, 5126, "MAT4", None);
        let mut nodes = self.nodes_json();
        let mesh_node = nodes.len();
        nodes.push(serde_json::json!({"name": "hand-mesh", "mesh": 0, "skin": 0}));
        let sk = &self.skeleton;
        let roots: Vec<usize> = (0..sk.parent.len())
            .filter(|&i| sk.parent[i].is_none())
            .chain([mesh_node])
            .collect();
        let json = serde_json::json!({
            "asset": {"version": "2.0", "generator": "phalanx synthetic tube hand"},
            "scene": 0,
            "scenes": [{"nodes": roots}],
            "nodes": nodes,
            "skins": [{"joints": mesh.joints, "inverseBindMatrices": ibm}],
            "meshes": [{"primitives": [{"attributes": attributes, "indices": idx, "mode": 4}]}],
            "accessors": out.accessors,
            "bufferViews": out.views,
            "buffers": [{"byteLength": out.bin.len()}],
        });
        crate::rig::read::gltf::glb(&json, out.bin)
    }

    /// The skeleton's nodes as glTF JSON: name, local translation and rotation (from the
    /// world matrices), children.
    fn nodes_json(&self) -> Vec<serde_json::Value> {
        let sk = &self.skeleton;
        (0..sk.world.len())
            .map(|i| {
                let up = sk.parent[i].map_or(DMat4::IDENTITY, |p| sk.world[p]);
                let (_, r, t) = (up.inverse() * sk.world[i]).to_scale_rotation_translation();
                let children: Vec<usize> = (0..sk.parent.len())
                    .filter(|&c| sk.parent[c] == Some(i))
                    .collect();
                let mut node = serde_json::json!({
                    "name": self.names.get(i).cloned().unwrap_or_default(),
                    "translation": t.as_vec3().to_array(),
                    "rotation": r.normalize().as_quat().to_array(),
                });
                if !children.is_empty() {
                    node["children"] = children.into();
                }
                node
            })
            .collect()
    }
}

/// The per-axis minimum and maximum of `points` (infinite when there are none).
fn bounds(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    points.iter().fold(
        ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                std::array::from_fn(|k| lo[k].min(p[k])),
                std::array::from_fn(|k| hi[k].max(p[k])),
            )
        },
    )
}

/// The binary chunk of a GLB being written, with its buffer views and accessors.
#[derive(Default)]
struct GlbParts {
    bin: Vec<u8>,
    views: Vec<serde_json::Value>,
    accessors: Vec<serde_json::Value>,
}

impl GlbParts {
    /// Appends `data` (little-endian, 4-byte aligned) to the binary chunk as a buffer
    /// view and an accessor of `component` type and `shape`; returns the accessor's index.
    fn accessor<T: LeBytes>(
        &mut self,
        data: &[T],
        component: u32,
        shape: &str,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> usize {
        let per = match shape {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 16,
        };
        let bin = &mut self.bin;
        let offset = bin.len();
        for x in data {
            x.put(bin);
        }
        let length = bin.len() - offset;
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        self.views.push(serde_json::json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": length,
        }));
        let mut acc = serde_json::json!({
            "bufferView": self.views.len() - 1,
            "componentType": component,
            "count": data.len() / per,
            "type": shape,
        });
        if let Some((lo, hi)) = bounds {
            acc["min"] = lo.into();
            acc["max"] = hi.into();
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// The mesh's influences as `JOINTS_n`/`WEIGHTS_n` sets of four (as many sets as the
    /// most influenced vertex needs, at least one), added to `attributes`.
    fn weight_sets(
        &mut self,
        mesh: &SkinnedMesh,
        attributes: &mut serde_json::Map<String, serde_json::Value>,
    ) {
        let n = mesh.positions.len();
        let most = (0..n)
            .map(|v| mesh.influences_of(v).len())
            .max()
            .unwrap_or(0);
        for set in 0..most.div_ceil(4).max(1) {
            let mut joints = vec![0u16; 4 * n];
            let mut weights = vec![0f32; 4 * n];
            for v in 0..n {
                for (k, &(j, w)) in mesh
                    .influences_of(v)
                    .iter()
                    .skip(4 * set)
                    .take(4)
                    .enumerate()
                {
                    joints[4 * v + k] = j;
                    weights[4 * v + k] = w as f32;
                }
            }
            let j = self.accessor(&joints, 5123, "VEC4", None);
            let w = self.accessor(&weights, 5126, "VEC4", None);
            attributes.insert(format!("JOINTS_{set}"), j.into());
            attributes.insert(format!("WEIGHTS_{set}"), w.into());
        }
    }
}

/// A number glTF stores little-endian.
trait LeBytes: Copy {
    fn put(self, out: &mut Vec<u8>);
}

impl LeBytes for f32 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl LeBytes for u32 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl LeBytes for u16 {
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}
