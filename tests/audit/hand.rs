//! Small skinned glTF hands built in the tests, and an independent skinning check.
//!
//! The fingers have the segment lengths of X-ray 1b of the paper's Table 1
//! (data/measurements.csv), 0.0125 cm per image unit, so each finger is one of
//! the five measured hands and must fall inside the X-ray range. The hand sits
//! under an `Armature` scaled 0.01 (centimetres, as Mixamo exports), turned 30
//! degrees, and each finger bends 12 degrees at its middle joints, so world
//! transforms compose rotation, scale and translation. Tip nodes sit where
//! X-ray 1b's last segment ends: at the skin, as the paper's rows are (their tip
//! column; Buryanov & Kotiuk 2010, data/literature/), unless the spec adds tissue.

use glam::{DMat4, DQuat, DVec3};
use serde_json::{Value, json};

/// How the joints are named.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Naming {
    /// mixamorig:RightHandIndex1..4, thumb 1..4 (1 = CMC).
    Mixamo,
    /// rightIndexProximal.., VRM 1.0 thumb (Metacarpal, Proximal, Distal); no tips.
    Vrm,
    /// Bone.000.. with a VRMC_vrm (1.0) humanoid table naming them; no tips.
    VrmTable,
    /// Bone.000.. with a VRM 0.x humanoid table (thumb MCP = Intermediate); no tips.
    Vrm0Table,
    /// VRM 0.x names on the nodes, no table: rightThumbIntermediate is the thumb's MCP.
    Vrm0,
    /// DEF-f_index.01.R.. with skinned control twins (no DEF-) placed elsewhere, and _end leaf tips.
    Rigify,
    /// Unreal mannequin: index_01_r.., thumb_02_r = MCP; no tips.
    Unreal,
    /// UE5 mannequin: index_01_r..index_03_r, index_04_leaf_r tips, hand_r.
    Unreal5,
    /// WebXR joint names, no side: index-finger-phalanx-proximal.., index-finger-tip.
    WebXr,
    /// Blender's duplicate names, as a cartoon robot has them: `Index.R`,
    /// `Index.R.001`, `Index.R.002`, tip `Index.R.003`; the thumb's first bone
    /// `Thumb.R` (its CMC: give `metacarpals`), then `Thumb.R.001`,
    /// `Thumb.R.002` and the leaf `Thumb.R.002_end`; hand `Hand.R`.
    Blender,
    /// Hips, Spine, Bone.000..: nothing recognisable.
    Anonymous,
}

/// X-ray 1b of Table 1: (finger, segment lengths in image units).
pub const XRAY_1B: [(&str, &[f64]); 5] = [
    ("thumb", &[259.53, 251.34]),
    ("index", &[342.47, 195.24, 186.70]),
    ("middle", &[389.42, 239.15, 197.31]),
    ("ring", &[372.98, 226.72, 212.12]),
    ("little", &[291.24, 166.72, 170.56]),
];

/// Centimetres per image unit.
pub const CM_PER_UNIT: f64 = 0.0125;

/// A hand to build.
#[derive(Clone, Debug)]
pub struct HandSpec {
    pub naming: Naming,
    /// Also build a mirrored left hand (names that carry a side only).
    pub left_too: bool,
    /// Write every node's transform as a `matrix` instead of translation, rotation, scale.
    pub matrices: bool,
    /// Moves: (finger, joint index along the chain from MCP = 0, distance in cm
    /// along the finger's direction; + towards the tip). Children follow.
    pub moves: Vec<(&'static str, usize, f64)>,
    /// Extra top-level JSON members (e.g. extensionsRequired).
    pub extra: Vec<(&'static str, Value)>,
    /// Extra length past the X-rays' (skin) tip, in cm: where the tip nodes sit.
    pub tip_tissue_cm: f64,
    /// The Armature's scale: 0.01 makes the centimetres of the nodes metres.
    pub armature_scale: f64,
    /// Every finger node a child of the hand node (matrices), as WebXR's siblings.
    pub siblings: bool,
    /// A metacarpal node between the hand and each finger (named by the convention).
    pub metacarpals: bool,
    /// Rigify twins named `ORG-` and carrying no skin weight (else `f_index.01.R`, weighted).
    pub org_twins: bool,
    /// A dense tube of skin around each finger with smooth weights, instead of two
    /// vertices per joint; each joint's skin bends this many mm from it (+ distal):
    /// (finger, joint from MCP = 0, mm).
    pub smooth: Option<Vec<(&'static str, usize, f64)>>,
    /// Two keyframes per finger joint: translation and rotation at rest.
    pub animate: bool,
    /// Finger joints (finger, joint) whose second translation key moves 3 mm along y.
    pub varying: Vec<(&'static str, usize)>,
    /// Scales the MCPs' positions in the hand's frame (1: as built): the
    /// wrist-to-MCP distances grow, the fingers stay as they are.
    pub palm: f64,
}

impl HandSpec {
    pub fn new(naming: Naming) -> HandSpec {
        HandSpec {
            naming,
            left_too: false,
            matrices: false,
            moves: Vec::new(),
            extra: Vec::new(),
            tip_tissue_cm: 0.0,
            armature_scale: 0.01,
            siblings: false,
            metacarpals: false,
            org_twins: false,
            smooth: None,
            animate: false,
            varying: Vec::new(),
            palm: 1.0,
        }
    }

    pub fn moved(mut self, finger: &'static str, joint: usize, cm: f64) -> HandSpec {
        self.moves.push((finger, joint, cm));
        self
    }
}

fn cap(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or_else(String::new, |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}

/// The node name of joint `k` (0 = MCP) of `finger`, `None` where the naming has no such node.
fn joint_name(
    naming: Naming,
    left: bool,
    finger: &str,
    k: usize,
    count: usize,
    serial: usize,
) -> Option<String> {
    let thumb = finger == "thumb";
    let tip = k + 1 == count;
    let pinky = if finger == "little" { "pinky" } else { finger };
    let (side, s) = if left { ("Left", "L") } else { ("Right", "R") };
    Some(match naming {
        Naming::Mixamo => format!(
            "mixamorig:{side}Hand{}{}",
            cap(pinky),
            k + 1 + usize::from(thumb)
        ),
        Naming::Vrm | Naming::Vrm0 | Naming::VrmTable | Naming::Vrm0Table | Naming::Unreal
            if tip =>
        {
            return None;
        }
        Naming::Vrm0 => format!(
            "{}{}{}",
            side.to_lowercase(),
            cap(finger),
            vrm_part(finger, k, true)
        ),
        Naming::Vrm => format!(
            "{}{}{}",
            side.to_lowercase(),
            cap(finger),
            vrm_part(finger, k, false)
        ),
        Naming::VrmTable | Naming::Vrm0Table | Naming::Anonymous => format!("Bone.{serial:03}"),
        Naming::Blender if thumb && tip => format!("Thumb.{s}.{k:03}_end"),
        Naming::Blender if thumb => format!("Thumb.{s}.{:03}", k + 1),
        Naming::Blender if k == 0 => format!("{}.{s}", cap(pinky)),
        Naming::Blender => format!("{}.{s}.{k:03}", cap(pinky)),
        Naming::Unreal => format!(
            "{pinky}_{:02}_{}",
            k + 1 + usize::from(thumb),
            s.to_lowercase()
        ),
        Naming::Unreal5 if tip => format!("{pinky}_04_leaf_{}", s.to_lowercase()),
        Naming::Unreal5 => format!(
            "{pinky}_{:02}_{}",
            k + 1 + usize::from(thumb),
            s.to_lowercase()
        ),
        Naming::WebXr => {
            let f = if thumb {
                "thumb".to_string()
            } else {
                format!("{pinky}-finger")
            };
            let parts: &[&str] = if thumb {
                &["phalanx-proximal", "phalanx-distal", "tip"]
            } else {
                &[
                    "phalanx-proximal",
                    "phalanx-intermediate",
                    "phalanx-distal",
                    "tip",
                ]
            };
            format!("{f}-{}", parts[k])
        }
        Naming::Rigify => {
            let f = if thumb {
                "thumb".to_string()
            } else {
                format!("f_{pinky}")
            };
            let n = k + 1 + usize::from(thumb);
            if tip {
                format!("DEF-{f}.{:02}.{s}_end", n - 1)
            } else {
                format!("DEF-{f}.{n:02}.{s}")
            }
        }
    })
}

/// The name of a finger's metacarpal node, where the convention has one.
fn metacarpal_name(naming: Naming, left: bool, finger: &str) -> Option<String> {
    let pinky = if finger == "little" { "pinky" } else { finger };
    let (side, s) = if left { ("left", "L") } else { ("right", "R") };
    let thumb = finger == "thumb";
    let palm = ["index", "middle", "ring", "little"]
        .iter()
        .position(|f| *f == finger)
        .map(|i| i + 1);
    Some(match naming {
        Naming::Unreal5 if thumb => format!("thumb_01_{}", s.to_lowercase()),
        Naming::Unreal5 => format!("{pinky}_metacarpal_{}", s.to_lowercase()),
        Naming::WebXr if thumb => "thumb-metacarpal".into(),
        Naming::WebXr => format!("{pinky}-finger-metacarpal"),
        Naming::Rigify if thumb => format!("DEF-thumb.01.{s}"),
        Naming::Rigify => format!("DEF-palm.{:02}.{s}", palm?),
        Naming::Vrm if thumb => format!("{side}ThumbMetacarpal"),
        Naming::Blender if thumb => format!("Thumb.{s}"),
        _ => return None,
    })
}

/// The VRM part name of joint `k` of `finger` (1.0, or 0.x with its thumb one further).
fn vrm_part(finger: &str, k: usize, vrm0: bool) -> &'static str {
    let parts: &[&'static str] = if finger == "thumb" && vrm0 {
        &["Intermediate", "Distal"]
    } else if finger == "thumb" {
        &["Proximal", "Distal"]
    } else {
        &["Proximal", "Intermediate", "Distal"]
    };
    parts[k]
}

struct Tree {
    nodes: Vec<Value>,
    children: Vec<Vec<usize>>,
}

impl Tree {
    fn add(&mut self, parent: Option<usize>, node: Value) -> usize {
        self.nodes.push(node);
        self.children.push(Vec::new());
        let i = self.nodes.len() - 1;
        if let Some(p) = parent {
            self.children[p].push(i);
        }
        i
    }
}

/// Builds the hand as GLB bytes.
pub fn build(spec: &HandSpec) -> Vec<u8> {
    let mut tree = Tree {
        nodes: Vec::new(),
        children: Vec::new(),
    };
    let hips = if spec.naming == Naming::Mixamo {
        "mixamorig:Hips"
    } else {
        "Hips"
    };
    let armature = tree.add(
        None,
        json!({"name": "Armature", "scale": [spec.armature_scale, spec.armature_scale, spec.armature_scale], "rotation": quat_arr(DQuat::from_rotation_x(0.2))}),
    );
    let hips = tree.add(
        Some(armature),
        json!({"name": hips, "translation": [0.0, 100.0, 0.0]}),
    );
    let mut joints = Vec::new();
    // Per skin joint: whether vertices are weighted to it.
    let mut weighted: Vec<bool> = Vec::new();
    // Per finger: the node its root bends against (hand or metacarpal), its chain nodes.
    let mut chains: Vec<(usize, Vec<usize>)> = Vec::new();
    // Finger joint nodes: (node, finger, joint from MCP = 0).
    let mut tags: Vec<(usize, &str, usize)> = Vec::new();
    let mut hands: Vec<usize> = Vec::new();
    let mut vrm_table = serde_json::Map::new();
    let mut vrm0_table = Vec::new();
    let mut serial = 0;
    // MCP positions in the hand's frame (cm); fingers point along +y.
    let roots = [
        (-3.5, 2.0, 1.5),
        (-1.6, 9.0, 0.0),
        (0.4, 9.3, 0.0),
        (2.2, 8.8, 0.0),
        (3.8, 7.9, 0.0),
    ];
    let sides: &[bool] = if spec.left_too {
        &[false, true]
    } else {
        &[false]
    };
    for &left in sides {
        let mirror = if left { -1.0 } else { 1.0 };
        let hand_name = match (spec.naming, left) {
            (Naming::Anonymous, _) => "Spine".to_string(),
            (Naming::Mixamo, false) => "mixamorig:RightHand".into(),
            (Naming::Mixamo, true) => "mixamorig:LeftHand".into(),
            (Naming::Unreal5, false) => "hand_r".into(),
            (Naming::Unreal5, true) => "hand_l".into(),
            (Naming::WebXr, _) => "wrist".into(),
            (Naming::Rigify, false) => "DEF-hand.R".into(),
            (Naming::Rigify, true) => "DEF-hand.L".into(),
            (Naming::Blender, false) => "Hand.R".into(),
            (Naming::Blender, true) => "Hand.L".into(),
            (_, false) => "RightHand".into(),
            (_, true) => "LeftHand".into(),
        };
        let rot = DQuat::from_rotation_z(mirror * 30f64.to_radians());
        let pos = DVec3::new(mirror * 40.0, 30.0, 2.0);
        let hand_node =
            json!({"name": hand_name, "translation": pos.to_array(), "rotation": quat_arr(rot)});
        let hand = tree.add(Some(hips), hand_node);
        hands.push(hand);
        joints.push(hand);
        weighted.push(true);
        for (fi, (finger, segs)) in XRAY_1B.iter().enumerate() {
            let count = segs.len() + 1;
            let mut parent = hand;
            let r = roots[fi];
            let root = spec.palm * DVec3::new(mirror * r.0, r.1, r.2);
            // A metacarpal node 35% of the way from the hand to the MCP.
            let mc_share = match metacarpal_name(spec.naming, left, finger) {
                Some(name) if spec.metacarpals => {
                    let mc = tree.add(
                        Some(hand),
                        json!({"name": name, "translation": (0.35 * root).to_array()}),
                    );
                    joints.push(mc);
                    weighted.push(true);
                    chains.push((mc, vec![]));
                    parent = mc;
                    0.35
                }
                _ => 0.0,
            };
            let chain_at = chains.len();
            chains.push((hand, Vec::new()));
            if mc_share > 0.0 {
                chains[chain_at].0 = parent;
            }
            for k in 0..count {
                let mut t = if k == 0 {
                    (1.0 - mc_share) * root
                } else if k + 1 == count {
                    DVec3::new(0.0, segs[k - 1] * CM_PER_UNIT + spec.tip_tissue_cm, 0.0)
                } else {
                    DVec3::new(0.0, segs[k - 1] * CM_PER_UNIT, 0.0)
                };
                for &(mf, mk, cm) in &spec.moves {
                    if mf == *finger && mk == k {
                        t.y += cm;
                    }
                    // Keep the later joints about where they were: the next offset shrinks.
                    if mf == *finger && mk + 1 == k {
                        t.y -= cm;
                    }
                }
                let name = joint_name(spec.naming, left, finger, k, count, serial);
                serial += 1;
                let Some(name) = name else { continue };
                let mut node = json!({"name": name, "translation": t.to_array()});
                tags.push((tree.nodes.len(), finger, k));
                if k >= 1 && k + 1 < count {
                    node["rotation"] = quat_arr(DQuat::from_rotation_x(12f64.to_radians()));
                }
                let i = tree.add(Some(parent), node);
                if matches!(spec.naming, Naming::VrmTable | Naming::Vrm0Table) {
                    let bone = format!(
                        "right{}{}",
                        cap(finger),
                        vrm_part(finger, k, spec.naming == Naming::Vrm0Table)
                    );
                    if spec.naming == Naming::VrmTable {
                        vrm_table.insert(bone, json!({"node": i}));
                    } else {
                        vrm0_table.push(json!({"bone": bone, "node": i}));
                    }
                }
                if spec.naming == Naming::Rigify && k + 1 < count {
                    // A control twin 1 cm off: the reader must take the DEF- bone.
                    // Either skinned and weighted without DEF-, or an ORG- twin
                    // listed in the skin without any weight (Rigify's ORG bones).
                    let prefix = if spec.org_twins { "ORG-" } else { "" };
                    let twin = tree.nodes[i]["name"]
                        .as_str()
                        .unwrap()
                        .replacen("DEF-", prefix, 1);
                    let twin = tree.add(
                        Some(parent),
                        json!({"name": twin, "translation": [t.x + 1.0, t.y, t.z]}),
                    );
                    joints.push(twin);
                    weighted.push(!spec.org_twins);
                }
                // Tips are unskinned leaves, as Blender's leaf bones are.
                if k + 1 < count || spec.naming == Naming::Mixamo {
                    joints.push(i);
                    weighted.push(k + 1 < count || spec.smooth.is_none());
                }
                chains[chain_at].1.push(i);
                parent = i;
            }
        }
    }
    chains.retain(|c| !c.1.is_empty());
    let Tree {
        mut nodes,
        mut children,
    } = tree;
    let set_children = |nodes: &mut Vec<Value>, children: &[Vec<usize>]| {
        for (i, c) in children.iter().enumerate() {
            if let Some(o) = nodes[i].as_object_mut() {
                o.remove("children");
            }
            if !c.is_empty() {
                nodes[i]["children"] = json!(c);
            }
        }
    };
    set_children(&mut nodes, &children);
    if spec.siblings {
        // Every node below a hand (finger joints, tips, metacarpals, twins)
        // becomes a child of the hand, with the local matrix that keeps its
        // world matrix.
        let world = world_of(&nodes);
        for &h in &hands {
            let mut below = Vec::new();
            let mut stack: Vec<usize> = children[h].clone();
            while let Some(n) = stack.pop() {
                below.push(n);
                stack.extend(children[n].iter().copied());
            }
            for n in below {
                for c in children.iter_mut() {
                    c.retain(|&x| x != n);
                }
                children[h].push(n);
                let local = world[h].inverse() * world[n];
                if let Some(o) = nodes[n].as_object_mut() {
                    for k in ["translation", "rotation", "scale"] {
                        o.remove(k);
                    }
                }
                nodes[n]["matrix"] = json!(local.to_cols_array());
            }
        }
        set_children(&mut nodes, &children);
    }
    if spec.matrices {
        for n in nodes.iter_mut() {
            let m = local_of(n);
            if let Some(o) = n.as_object_mut() {
                for k in ["translation", "rotation", "scale"] {
                    o.remove(k);
                }
            }
            n["matrix"] = json!(m.to_cols_array());
        }
    }
    // World matrices of the bind pose, computed here independently of phalanx.
    let world = world_of(&nodes);
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut joint_ids: Vec<[u16; 4]> = Vec::new();
    let mut weights: Vec<[f32; 4]> = Vec::new();
    let slot = |node: usize| joints.iter().position(|&j| j == node).unwrap() as u16;
    if let Some(offsets) = &spec.smooth {
        for (root, chain) in &chains {
            let finger = tags.iter().find(|t| t.0 == chain[0]).map_or("", |t| t.1);
            let has_tip = chain.len()
                == XRAY_1B
                    .iter()
                    .find(|f| f.0 == finger)
                    .map_or(0, |f| f.1.len() + 1);
            let bending = if has_tip {
                chain.len() - 1
            } else {
                chain.len()
            };
            let pts: Vec<DVec3> = chain.iter().map(|&n| world[n].w_axis.truncate()).collect();
            let bends: Vec<f64> = (0..bending)
                .map(|k| {
                    offsets
                        .iter()
                        .find(|o| o.0 == finger && o.1 == k)
                        .map_or(0.0, |o| o.2 / 1000.0)
                })
                .collect();
            let mut owners = vec![*root];
            owners.extend(chain.iter().take(bending).copied());
            tube(
                &pts,
                has_tip,
                &bends,
                &owners.iter().map(|&n| slot(n)).collect::<Vec<_>>(),
                &mut positions,
                &mut joint_ids,
                &mut weights,
            );
        }
    } else {
        // Two vertices per weighted joint, 3 mm off its centre, weighted 0.6 to
        // the joint and 0.4 to its parent joint (or the first hand); wholly to
        // the joint when that is itself, as glTF forbids a joint named twice
        // for one vertex with non-zero weights.
        for (ji, &node) in joints.iter().enumerate() {
            if !weighted[ji] {
                continue;
            }
            let parent_ji = nodes_parent(&children, node)
                .and_then(|p| joints.iter().position(|&j| j == p))
                .filter(|&p| weighted[p])
                .unwrap_or(0);
            let (ids, ws) = if parent_ji == ji {
                ([ji as u16, 0, 0, 0], [1.0, 0.0, 0.0, 0.0])
            } else {
                ([ji as u16, parent_ji as u16, 0, 0], [0.6, 0.4, 0.0, 0.0])
            };
            let c = world[node].w_axis.truncate();
            for off in [DVec3::new(0.003, 0.0, 0.0), DVec3::new(0.0, 0.0, -0.003)] {
                let p = c + off;
                positions.push([p.x as f32, p.y as f32, p.z as f32]);
                joint_ids.push(ids);
                weights.push(ws);
            }
        }
    }
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push_view = |bin: &mut Vec<u8>, bytes: &[u8]| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let off = bin.len();
        bin.extend_from_slice(bytes);
        views.push(json!({"buffer": 0, "byteOffset": off, "byteLength": bytes.len()}));
        views.len() - 1
    };
    let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let pos_flat: Vec<f32> = positions.iter().flatten().copied().collect();
    let v_pos = push_view(&mut bin, &f32s(&pos_flat));
    let ids: Vec<u8> = joint_ids
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let v_ids = push_view(&mut bin, &ids);
    let w_flat: Vec<f32> = weights.iter().flatten().copied().collect();
    let v_w = push_view(&mut bin, &f32s(&w_flat));
    let ibm: Vec<f32> = joints
        .iter()
        .flat_map(|&j| world[j].inverse().to_cols_array().map(|x| x as f32))
        .collect();
    let v_ibm = push_view(&mut bin, &f32s(&ibm));
    // Two keyframes on every finger joint: translation and rotation at rest
    // (the varying ones move 0.3 node units along y on the second key).
    let mut anim_accessors = Vec::new();
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    if spec.animate {
        let v_time = push_view(&mut bin, &f32s(&[0.0, 1.0]));
        anim_accessors.push(json!({"bufferView": v_time, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]}));
        for &(node, finger, k) in &tags {
            let n = &nodes[node];
            let t = n["translation"].as_array().map_or([0.0; 3], |a| {
                [
                    a[0].as_f64().unwrap(),
                    a[1].as_f64().unwrap(),
                    a[2].as_f64().unwrap(),
                ]
            });
            let r: Vec<f32> = n["rotation"]
                .as_array()
                .map_or(vec![0.0, 0.0, 0.0, 1.0], |a| {
                    a.iter().map(|x| x.as_f64().unwrap() as f32).collect()
                });
            let mut t2 = t;
            if spec.varying.contains(&(finger, k)) {
                t2[1] += 0.3;
            }
            let keys: Vec<f32> = t.iter().chain(&t2).map(|&x| x as f32).collect();
            let v_t = push_view(&mut bin, &f32s(&keys));
            let v_r = push_view(&mut bin, &f32s(&[r.clone(), r].concat()));
            for (view, ty, path) in [(v_t, "VEC3", "translation"), (v_r, "VEC4", "rotation")] {
                anim_accessors.push(
                    json!({"bufferView": view, "componentType": 5126, "count": 2, "type": ty}),
                );
                samplers.push(json!({"input": 4, "output": 4 + anim_accessors.len() - 1, "interpolation": "LINEAR"}));
                channels.push(
                    json!({"sampler": samplers.len() - 1, "target": {"node": node, "path": path}}),
                );
            }
        }
    }
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for p in &positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let nv = positions.len();
    let mesh_node = nodes.len();
    nodes.push(json!({"name": "HandMesh", "mesh": 0, "skin": 0}));
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": "phalanx tests"},
        "scene": 0,
        "scenes": [{"nodes": [armature, mesh_node]}],
        "nodes": nodes,
        "meshes": [{"primitives": [{"mode": 0, "attributes": {"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}]}],
        "skins": [{"joints": joints, "inverseBindMatrices": 3, "skeleton": armature}],
        "accessors": [
            {"bufferView": v_pos, "componentType": 5126, "count": nv, "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": v_ids, "componentType": 5123, "count": nv, "type": "VEC4"},
            {"bufferView": v_w, "componentType": 5126, "count": nv, "type": "VEC4"},
            {"bufferView": v_ibm, "componentType": 5126, "count": joints.len(), "type": "MAT4"}
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}]
    });
    if spec.naming == Naming::VrmTable {
        doc["extensionsUsed"] = json!(["VRMC_vrm"]);
        doc["extensions"] =
            json!({"VRMC_vrm": {"specVersion": "1.0", "humanoid": {"humanBones": vrm_table}}});
    } else if spec.naming == Naming::Vrm0Table {
        doc["extensionsUsed"] = json!(["VRM"]);
        doc["extensions"] = json!({"VRM": {"humanoid": {"humanBones": vrm0_table}}});
    }
    if spec.animate {
        doc["accessors"]
            .as_array_mut()
            .unwrap()
            .extend(anim_accessors);
        doc["animations"] = json!([{"name": "Idle", "samplers": samplers, "channels": channels}]);
    }
    for (k, v) in &spec.extra {
        doc[*k] = v.clone();
    }
    glb(&doc, bin)
}

/// A tube of skin around a finger through `pts` (MCP first; the last is the
/// tip when `has_tip`): rings of 8 vertices 6 mm from the axis every 0.5 mm,
/// from one first segment before the MCP (the palm) to the tip (or one last
/// segment past the last joint). The weights pass from bone to bone with a
/// smoothstep 8 mm wide centred `bends[k]` (m) distal of joint k; `owners`
/// are the skin slots of the bone before the MCP and of each bone from a
/// joint (MCP first).
fn tube(
    pts: &[DVec3],
    has_tip: bool,
    bends: &[f64],
    owners: &[u16],
    positions: &mut Vec<[f32; 3]>,
    joint_ids: &mut Vec<[u16; 4]>,
    weights: &mut Vec<[f32; 4]>,
) {
    let n = pts.len();
    let mut axis = vec![pts[0] - (pts[1] - pts[0])];
    axis.extend_from_slice(pts);
    if !has_tip {
        axis.push(pts[n - 1] + (pts[n - 1] - pts[n - 2]));
    }
    let mut arcs = vec![0.0];
    for w in axis.windows(2) {
        arcs.push(arcs.last().unwrap() + w[0].distance(w[1]));
    }
    let origin = arcs[1];
    let joint_u: Vec<f64> = (0..bends.len()).map(|k| arcs[k + 1] - origin).collect();
    let smooth = |x: f64| {
        let t = ((x + 0.004) / 0.008).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    };
    let total = arcs[arcs.len() - 1];
    let mut a = 0.0;
    while a <= total + 1e-12 {
        let seg = (0..axis.len() - 1)
            .find(|&i| a <= arcs[i + 1] + 1e-12)
            .unwrap_or(axis.len() - 2);
        let t = (a - arcs[seg]) / (arcs[seg + 1] - arcs[seg]);
        let c = axis[seg].lerp(axis[seg + 1], t);
        let dir = (axis[seg + 1] - axis[seg]).normalize();
        let side = dir.cross(DVec3::Z).normalize();
        let up = dir.cross(side);
        let u = a - origin;
        // s_k: how far past joint k's bend; the bone from joint k weighs s_k - s_(k+1).
        let s: Vec<f64> = joint_u
            .iter()
            .zip(bends)
            .map(|(j, b)| smooth(u - j - b))
            .collect();
        let mut w: Vec<(u16, f64)> = vec![(owners[0], 1.0 - s[0])];
        for k in 0..s.len() {
            let next = s.get(k + 1).copied().unwrap_or(0.0);
            w.push((owners[k + 1], s[k] - next));
        }
        w.retain(|x| x.1 > 0.0);
        w.sort_by(|x, y| y.1.total_cmp(&x.1));
        w.truncate(4);
        let sum: f64 = w.iter().map(|x| x.1).sum();
        for i in 0..8 {
            let ang = i as f64 * std::f64::consts::TAU / 8.0;
            let p = c + 0.006 * (ang.cos() * side + ang.sin() * up);
            positions.push([p.x as f32, p.y as f32, p.z as f32]);
            // Distinct joints (the owners are), unused slots joint 0 with weight 0,
            // and the heaviest takes what the f32 rounding of the others leaves,
            // so the stored weights sum to 1 as glTF asks.
            let mut ids = [0u16; 4];
            let mut ws = [0f32; 4];
            for (k, &(j, x)) in w.iter().enumerate() {
                ids[k] = j;
                ws[k] = (x / sum) as f32;
            }
            ws[0] = 1.0 - ws[1..].iter().sum::<f32>();
            joint_ids.push(ids);
            weights.push(ws);
        }
        a += 0.0005;
    }
}

/// A GLB container around a JSON document and a binary chunk.
pub fn glb(doc: &Value, bin: Vec<u8>) -> Vec<u8> {
    gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: serde_json::to_vec(doc).unwrap().into(),
        bin: Some(bin.into()),
    }
    .to_vec()
    .unwrap()
}

fn quat_arr(q: DQuat) -> Value {
    json!([q.x, q.y, q.z, q.w])
}

fn nodes_parent(children: &[Vec<usize>], node: usize) -> Option<usize> {
    children.iter().position(|c| c.contains(&node))
}

fn local_of(n: &Value) -> DMat4 {
    let v3 = |k: &str, d: [f64; 3]| {
        n.get(k)
            .and_then(Value::as_array)
            .map_or(DVec3::from_array(d), |a| {
                DVec3::new(
                    a[0].as_f64().unwrap(),
                    a[1].as_f64().unwrap(),
                    a[2].as_f64().unwrap(),
                )
            })
    };
    if let Some(m) = n.get("matrix").and_then(Value::as_array) {
        let m: Vec<f64> = m.iter().map(|x| x.as_f64().unwrap()).collect();
        return DMat4::from_cols_slice(&m);
    }
    let r = n
        .get("rotation")
        .and_then(Value::as_array)
        .map_or(DQuat::IDENTITY, |a| {
            DQuat::from_xyzw(
                a[0].as_f64().unwrap(),
                a[1].as_f64().unwrap(),
                a[2].as_f64().unwrap(),
                a[3].as_f64().unwrap(),
            )
        });
    DMat4::from_scale_rotation_translation(v3("scale", [1.0; 3]), r, v3("translation", [0.0; 3]))
}

/// World matrices of the nodes of a glTF JSON document (parents by `children`).
pub fn world_of(nodes: &[Value]) -> Vec<DMat4> {
    let n = nodes.len();
    let mut parent = vec![None; n];
    for (i, nd) in nodes.iter().enumerate() {
        for c in nd
            .get("children")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            parent[c.as_u64().unwrap() as usize] = Some(i);
        }
    }
    (0..n)
        .map(|mut i| {
            let mut m = local_of(&nodes[i]);
            while let Some(p) = parent[i] {
                m = local_of(&nodes[p]) * m;
                i = p;
            }
            m
        })
        .collect()
}

/// The JSON and binary chunk of a GLB file, or of a .gltf whose one buffer is
/// an embedded base64 data URI.
pub fn read_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    if !bytes.starts_with(b"glTF") {
        let doc: Value = serde_json::from_slice(bytes).unwrap();
        let uri = doc["buffers"][0]["uri"].as_str().unwrap();
        let b64 = uri.split_once(";base64,").unwrap().1;
        let bin = base64::Engine::decode(&base64::engine::general_purpose::STANDARD, b64).unwrap();
        return (doc, bin);
    }
    let g = gltf::binary::Glb::from_slice(bytes).unwrap();
    (
        serde_json::from_slice(&g.json).unwrap(),
        g.bin.map(|b| b.into_owned()).unwrap_or_default(),
    )
}

/// Every vertex of skin 0's mesh in its rest pose: sum_i w_i (W_i B_i) v, with W
/// the joints' world matrices and B the inverse bind matrices (glTF 2.0 skinning).
pub fn skinned_rest_vertices(bytes: &[u8]) -> Vec<DVec3> {
    skinned_vertices(bytes, None)
}

/// `doc` with its nodes posed by keyframe `key` of animation 0 (unchanged
/// for `None`): each channel's output element `key` (linear keys) replaces
/// its node's translation, rotation or scale.
pub fn posed(mut doc: Value, bin: &[u8], key: Option<usize>) -> Value {
    let Some(k) = key else { return doc };
    let f32_at = |o: usize| f32::from_le_bytes(bin[o..o + 4].try_into().unwrap()) as f64;
    let anim = doc["animations"][0].clone();
    for ch in anim["channels"].as_array().unwrap() {
        let s = &anim["samplers"][ch["sampler"].as_u64().unwrap() as usize];
        let a = &doc["accessors"][s["output"].as_u64().unwrap() as usize];
        let v = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let o = v["byteOffset"].as_u64().unwrap_or(0) as usize
            + a["byteOffset"].as_u64().unwrap_or(0) as usize;
        let path = ch["target"]["path"].as_str().unwrap();
        let n = match path {
            "translation" | "scale" => 3,
            "rotation" => 4,
            _ => continue,
        };
        let vals: Vec<f64> = (0..n).map(|c| f32_at(o + 4 * (n * k + c))).collect();
        let node = ch["target"]["node"].as_u64().unwrap() as usize;
        doc["nodes"][node][path] = json!(vals);
    }
    doc
}

/// Every vertex of skin 0's mesh (first primitive), with the nodes posed by
/// keyframe `key` of animation 0 when given: each channel's output element
/// `key` (linear keys) replaces its node's translation, rotation or scale.
/// Written here from the glTF 2.0 specification, independently of phalanx.
pub fn skinned_vertices(bytes: &[u8], key: Option<usize>) -> Vec<DVec3> {
    let (doc, bin) = read_glb(bytes);
    let doc = posed(doc, &bin, key);
    let f32_at = |o: usize| f32::from_le_bytes(bin[o..o + 4].try_into().unwrap()) as f64;
    // (byte offset, count, stride in bytes or 0 when packed, componentType).
    let accessor = |doc: &Value, i: usize| -> (usize, usize, usize, u64) {
        let a = &doc["accessors"][i];
        let v = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let off = v["byteOffset"].as_u64().unwrap_or(0) as usize
            + a["byteOffset"].as_u64().unwrap_or(0) as usize;
        (
            off,
            a["count"].as_u64().unwrap() as usize,
            v["byteStride"].as_u64().unwrap_or(0) as usize,
            a["componentType"].as_u64().unwrap(),
        )
    };
    let nodes = doc["nodes"].as_array().unwrap();
    let world = world_of(nodes);
    let skin = &doc["skins"][0];
    let joints: Vec<usize> = skin["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_u64().unwrap() as usize)
        .collect();
    let (ib, ..) = accessor(&doc, skin["inverseBindMatrices"].as_u64().unwrap() as usize);
    let mats: Vec<DMat4> = joints
        .iter()
        .enumerate()
        .map(|(k, &j)| {
            let cols: Vec<f64> = (0..16).map(|e| f32_at(ib + 64 * k + 4 * e)).collect();
            world[j] * DMat4::from_cols_slice(&cols)
        })
        .collect();
    let prim = &doc["meshes"][0]["primitives"][0]["attributes"];
    let (p, n, ps, _) = accessor(&doc, prim["POSITION"].as_u64().unwrap() as usize);
    let (ji, _, js, jt) = accessor(&doc, prim["JOINTS_0"].as_u64().unwrap() as usize);
    let (w, _, ws, _) = accessor(&doc, prim["WEIGHTS_0"].as_u64().unwrap() as usize);
    let (ps, ws) = (ps.max(12), ws.max(16));
    let jsize = if jt == 5121 { 1 } else { 2 };
    let js = js.max(4 * jsize);
    (0..n)
        .map(|v| {
            let pos = DVec3::new(
                f32_at(p + ps * v),
                f32_at(p + ps * v + 4),
                f32_at(p + ps * v + 8),
            );
            let mut out = DVec3::ZERO;
            for k in 0..4 {
                let at = ji + js * v + jsize * k;
                let j = if jsize == 1 {
                    bin[at] as usize
                } else {
                    u16::from_le_bytes(bin[at..at + 2].try_into().unwrap()) as usize
                };
                let wt = f32_at(w + ws * v + 4 * k);
                out += wt * mats[j].transform_point3(pos);
            }
            out
        })
        .collect()
}
