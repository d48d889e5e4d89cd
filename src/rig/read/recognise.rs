//! Recognising a rig's fingers: the best node for each joint of each finger
//! (a `--map` entry, a VRM humanoid table, then the names, with skin weight
//! deciding between namesakes), each finger's chain from those, its
//! metacarpal and the hand's wrist bone. [`Rig::load`] and [`Rig::from_file`].

use super::gltf::{GltfFile, candidates, vrm_bones};
use super::map::NameMap;
use super::naming::{self, Part, Side, Slot, shown};
use super::weights::SkinWeights;
use super::{FingerChain, Rig, RigJoint, RigNode};
use crate::analysis::placement::Joint;
use crate::dataset::{DataError, Finger, Problem};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// How a node was recognised: (side, finger, slot, priority; lower wins).
pub(crate) type Found = (Option<Side>, Finger, Slot, u8);

/// Priorities of the nodes that fit a joint (lower wins): a `--map` entry, a
/// VRM humanoid table, then a bone carrying skin weight (a Rigify `DEF-` bone
/// first), a `DEF-` bone without weight, a skin joint, any other node.
mod priority {
    pub const MAP: u8 = 0;
    pub const VRM: u8 = 1;
    pub const WEIGHTED_DEFORM: u8 = 2;
    pub const WEIGHTED: u8 = 3;
    pub const DEFORM: u8 = 4;
    pub const SKIN_JOINT: u8 = 5;
    pub const OTHER: u8 = 6;

    /// The priority of a node recognised by its name.
    pub fn of(deform: bool, weighted: bool, skin_joint: bool) -> u8 {
        match (weighted, deform, skin_joint) {
            (true, true, _) => WEIGHTED_DEFORM,
            (true, false, _) => WEIGHTED,
            (false, true, _) => DEFORM,
            (false, false, true) => SKIN_JOINT,
            _ => OTHER,
        }
    }

    /// True when the priority says the node carries skin weight.
    pub fn weighted(p: u8) -> bool {
        p == WEIGHTED_DEFORM || p == WEIGHTED
    }
}

/// The skin weights of a file with a skin whose buffers are at hand.
pub(crate) fn skin_weights(file: &GltfFile) -> Option<SkinWeights> {
    (file.document.skins().next().is_some())
        .then(|| file.buffer_data())
        .flatten()
        .map(|data| SkinWeights::read(file, &data))
}

/// Per node, whether any vertex is weighted to it (empty without weights).
pub(crate) fn weighted_nodes(weights: Option<&SkinWeights>, nodes: usize) -> Vec<bool> {
    weights.map_or_else(Vec::new, |w| w.weighted_nodes(nodes))
}

/// How each node is recognised: by the `--map` file first, then by a VRM
/// humanoid table, then by its name; with the priority of each (lower wins).
pub(crate) fn recognise(
    file: &GltfFile,
    names: &[String],
    map: Option<&NameMap>,
    weighted: &[bool],
) -> Result<Vec<Option<Found>>, DataError> {
    let n = names.len();
    let (candidate, skinned) = candidates(file);
    let mut found: Vec<Option<Found>> = vec![None; n];
    let mut problems = Vec::new();
    if let Some(map) = map {
        for (name, &(side, finger, slot, line)) in &map.entries {
            match names.iter().position(|x| x == name) {
                Some(i) => found[i] = Some((side, finger, slot, priority::MAP)),
                None => problems.push(Problem::line(
                    line,
                    format!(
                        "node {} is not in {}; node names must match exactly",
                        crate::dataset::csvinput::quote(name),
                        file.label
                    ),
                )),
            }
        }
        if !problems.is_empty() {
            problems.sort_by_key(|p| p.line);
            return Err(DataError {
                file: map.file.clone(),
                problems,
            });
        }
    }
    // VRM tables, then names; a VRM 0.x thumb shifts by one (see naming).
    let mut parsed: Vec<Option<(naming::Parsed, Option<bool>)>> = vec![None; n];
    for (node, bone, vrm0) in vrm_bones(&file.json) {
        if let (Some(slot), Some(p)) = (parsed.get_mut(node), naming::parse(&bone)) {
            *slot = Some((p, Some(vrm0)));
        }
    }
    for (i, name) in names.iter().enumerate() {
        if parsed[i].is_none() && candidate[i] {
            parsed[i] = naming::parse(name).map(|p| (p, None));
        }
    }
    for (i, p) in bare_chains(&file.parent, names, &candidate, &parsed) {
        parsed[i] = Some((p, None));
    }
    let vrm0_thumb: Vec<Option<Side>> = parsed
        .iter()
        .flatten()
        .filter(|(p, _)| p.finger == Finger::Thumb && p.part == Part::Intermediate)
        .map(|(p, _)| p.side)
        .collect();
    for i in 0..n {
        if found[i].is_some() {
            continue;
        }
        if let Some((p, vrm)) = parsed[i] {
            let vrm0 = vrm.unwrap_or_else(|| vrm0_thumb.contains(&p.side));
            if let Some(slot) = naming::slot(p.finger, p.part, vrm0) {
                let prio = if vrm.is_some() {
                    priority::VRM
                } else {
                    priority::of(p.deform, weighted.get(i) == Some(&true), skinned[i])
                };
                found[i] = Some((p.side, p.finger, slot, prio));
            }
        }
    }
    Ok(found)
}

/// The parts of finger bones named without one (`Index.L`, `Index.L.001`,
/// `Index.L.002`; [`naming::parse_bare`]), read from their place in the
/// hierarchy: a chain of such bones of one side and finger, each the only
/// child of its kind of the one above, numbers 1, 2, 3 from its top (the
/// thumb's 1 is its CMC, as in every numbered convention). A bare bone whose
/// child of the same finger is numbered 2 (`Index.L` above `Index2.L`) is 1.
/// A lone bare bone is nothing. O(n).
fn bare_chains(
    parent: &[Option<usize>],
    names: &[String],
    candidate: &[bool],
    parsed: &[Option<(naming::Parsed, Option<bool>)>],
) -> Vec<(usize, naming::Parsed)> {
    let n = names.len();
    let bare: Vec<Option<naming::Bare>> = (0..n)
        .map(|i| {
            (candidate[i] && parsed[i].is_none())
                .then(|| naming::parse_bare(&names[i]))
                .flatten()
        })
        .collect();
    let key = |b: &naming::Bare| (b.side, b.finger);
    let mut children = vec![Vec::new(); n];
    for (i, p) in parent.iter().enumerate() {
        if let Some(p) = *p {
            children[p].push(i);
        }
    }
    let numbered = |i: usize, side: Option<Side>, finger: Finger, k: u8| {
        parsed[i]
            .is_some_and(|(p, _)| p.side == side && p.finger == finger && p.part == Part::Number(k))
    };
    let mut out = Vec::new();
    for head in 0..n {
        let Some(b) = bare[head] else { continue };
        if b.leaf
            || parent[head]
                .and_then(|p| bare[p])
                .is_some_and(|a| key(&a) == key(&b))
        {
            continue;
        }
        let parsed_as = |k: u8, deform: bool| naming::Parsed {
            side: b.side,
            finger: b.finger,
            part: Part::Number(k),
            deform,
        };
        let mut chain = vec![head];
        loop {
            let last = chain[chain.len() - 1];
            let next: Vec<usize> = children[last]
                .iter()
                .copied()
                .filter(|&c| bare[c].is_some_and(|x| key(&x) == key(&b)))
                .collect();
            match next[..] {
                [c] if chain.len() < 5 => chain.push(c),
                _ => break,
            }
        }
        if chain.len() >= 2 {
            for (k, &i) in chain.iter().enumerate() {
                let deform = bare[i].is_some_and(|x| x.deform);
                out.push((i, parsed_as(k as u8 + 1, deform)));
            }
        } else if children[head]
            .iter()
            .any(|&c| numbered(c, b.side, b.finger, 2))
        {
            out.push((head, parsed_as(1, b.deform)));
        }
    }
    out
}

impl Rig {
    /// Reads a rig and finds its finger chains. Fails, listing the names it
    /// saw, when no complete finger is found.
    pub fn load(path: &Path, map: Option<&NameMap>) -> Result<Rig, DataError> {
        Rig::from_file(super::open(path)?, map)
    }

    /// Finds the finger chains of a parsed file: the best node for each joint
    /// of each finger, then each finger's chain from those, with its
    /// metacarpal and the hand's wrist bone when recognised.
    pub fn from_file(file: GltfFile, map: Option<&NameMap>) -> Result<Rig, DataError> {
        let rig = Rig::with_any_chains(file, map)?;
        if rig.chains.is_empty() {
            return Err(no_hand(&rig.file.label, &rig.file.node_names(), rig.notes));
        }
        Ok(rig)
    }

    /// As [`Rig::from_file`], but a file with no finger chain is read too
    /// (a hand mesh to rig: unskinned, or skinned to a hand bone alone).
    pub fn with_any_chains(file: GltfFile, map: Option<&NameMap>) -> Result<Rig, DataError> {
        let names = file.node_names();
        let weights = skin_weights(&file);
        let weighted = weighted_nodes(weights.as_ref(), names.len());
        let known = |i: usize| weights.as_ref().map(|_| weighted.get(i) == Some(&true));
        let found = recognise(&file, &names, map, &weighted)?;
        let (best, ties) = choose_nodes(&found);
        let mut notes = tie_notes(&best, &ties, &names);
        notes.extend(weight_note(&best, &found, &names));
        let hands = wrists(&file, &names, &weighted);
        let mut groups: BTreeMap<(Option<Side>, Finger), HashMap<Slot, usize>> = BTreeMap::new();
        for (&(side, finger, slot), &(_, node)) in &best {
            groups.entry((side, finger)).or_default().insert(slot, node);
        }
        let mut chains = Vec::new();
        let mut bad = Vec::new();
        let mut by_name = Vec::new();
        for ((side, finger), slots) in groups {
            let unambiguous = !ties.keys().any(|k| k.0 == side && k.1 == finger);
            let found = FingerFound {
                side,
                finger,
                slots: &slots,
                unambiguous,
            };
            match finger_chain(&file, &names, &found, &mut notes) {
                Ok(Some(mut chain)) => {
                    for j in &mut chain.joints {
                        j.weighted = j.node.and_then(known);
                    }
                    let node = |i: usize| RigNode {
                        node: i,
                        name: names[i].clone(),
                        position: file.world[i].w_axis.truncate(),
                        weighted: known(i),
                    };
                    chain.metacarpal = slots
                        .get(&Slot::Carpal)
                        .filter(|&&i| file.world[i].is_finite())
                        .map(|&i| node(i));
                    chain.wrist = wrist_of(&hands, side)
                        .filter(|&i| file.world[i].is_finite())
                        .map(node);
                    if !chain.hierarchy {
                        by_name.push(chain.label());
                    }
                    chains.push(chain);
                }
                Ok(None) => {}
                Err(problem) => bad.push(problem),
            }
        }
        if !bad.is_empty() {
            return Err(DataError {
                file: file.label.clone(),
                problems: bad,
            });
        }
        if !by_name.is_empty() {
            notes.push(format!(
                "{}: the joints are not parent and child in the node hierarchy (siblings, as in \
                 WebXR's hands); each finger is read from its joint names alone, its lengths from \
                 the joints' world positions, and --fix moves each joint node with its own inverse \
                 bind matrix",
                by_name.join(", ")
            ));
        }
        if let Some(w) = &weights {
            notes.extend(w.notes.iter().cloned());
        }
        Ok(Rig {
            file,
            chains,
            notes,
            weights,
        })
    }
}

/// What was found for one finger: its nodes per slot, and whether no other
/// node would fit any of them as well.
struct FingerFound<'a> {
    side: Option<Side>,
    finger: Finger,
    slots: &'a HashMap<Slot, usize>,
    unambiguous: bool,
}

/// The wrist (hand) bones recognised: (side, priority, node), best first per
/// side; a VRM humanoid table's `rightHand`/`leftHand` first, then names.
pub(crate) fn wrists(
    file: &GltfFile,
    names: &[String],
    weighted: &[bool],
) -> Vec<(Option<Side>, u8, usize)> {
    let (candidate, skinned) = candidates(file);
    let mut out: Vec<(Option<Side>, u8, usize)> = vrm_bones(&file.json)
        .into_iter()
        .filter(|&(node, _, _)| node < names.len())
        .filter_map(|(node, bone, _)| {
            let side = match bone.as_str() {
                "rightHand" => Side::Right,
                "leftHand" => Side::Left,
                _ => return None,
            };
            Some((Some(side), priority::VRM, node))
        })
        .collect();
    out.extend(
        names
            .iter()
            .enumerate()
            .filter(|&(i, _)| candidate[i] || skinned[i])
            .filter_map(|(i, name)| {
                naming::parse_hand(name).map(|h| {
                    let p = priority::of(h.deform, weighted.get(i) == Some(&true), skinned[i]);
                    (h.side, p, i)
                })
            }),
    );
    out.sort();
    out
}

/// The wrist of the hand on `side`: the best of that side; for a finger
/// without a side, the only hand bone of the file.
pub(crate) fn wrist_of(hands: &[(Option<Side>, u8, usize)], side: Option<Side>) -> Option<usize> {
    if let Some(&(_, _, i)) = hands.iter().find(|h| h.0 == side) {
        return Some(i);
    }
    let sides: std::collections::BTreeSet<Option<Side>> = hands.iter().map(|h| h.0).collect();
    (side.is_none() && sides.len() == 1).then(|| hands[0].2)
}

/// One note for the joints where a bone carrying skin weight was chosen over
/// an unweighted namesake (Rigify's `DEF-thumb.02.R` over `ORG-thumb.02.R`).
fn weight_note(best: &Best, found: &[Option<Found>], names: &[String]) -> Option<String> {
    let mut pairs = Vec::new();
    for (&(side, finger, slot), &(prio, chosen)) in best {
        if !priority::weighted(prio) {
            continue;
        }
        let losers: Vec<usize> = found
            .iter()
            .enumerate()
            .filter(|&(i, f)| {
                i != chosen
                    && f.is_some_and(|(s, g, t, p)| {
                        (s, g, t) == (side, finger, slot) && p > priority::WEIGHTED
                    })
            })
            .map(|(i, _)| i)
            .collect();
        if let Some(&l) = losers.first() {
            pairs.push(format!(
                "{} over {}",
                shown(&names[chosen]),
                shown(&names[l])
            ));
        }
    }
    if pairs.is_empty() {
        return None;
    }
    let n = pairs.len();
    pairs.truncate(3);
    Some(format!(
        "{n} joint{} had a namesake without skin weight; the bone that carries skin weight was \
         used: {}{}",
        if n == 1 { "" } else { "s" },
        pairs.join(", "),
        if n > 3 { ", ..." } else { "" }
    ))
}

/// A joint of a finger of a hand: (side, finger, slot).
pub(crate) type JointKey = (Option<Side>, Finger, Slot);
/// The node chosen for each joint, with its priority: joint -> (priority, node).
pub(crate) type Best = BTreeMap<JointKey, (u8, usize)>;
/// Other nodes as fit as the chosen one, per joint.
pub(crate) type Ties = BTreeMap<JointKey, Vec<usize>>;

/// The best node for each joint (lowest priority value, then the first node),
/// with (priority, node); and the other nodes of the same priority, per joint.
pub(crate) fn choose_nodes(found: &[Option<Found>]) -> (Best, Ties) {
    let mut best = Best::new();
    let mut ties = Ties::new();
    for (i, f) in found.iter().enumerate() {
        if let Some((side, finger, slot, prio)) = *f {
            let key = (side, finger, slot);
            let e = best.entry(key).or_insert((prio, i));
            if prio < e.0 {
                *e = (prio, i);
                ties.remove(&key);
            } else if prio == e.0 && e.1 != i {
                ties.entry(key).or_default().push(i);
            }
        }
    }
    (best, ties)
}

/// A note for each joint that other nodes would fit as well as the chosen one.
fn tie_notes(best: &Best, ties: &Ties, names: &[String]) -> Vec<String> {
    let mut notes = Vec::new();
    for ((side, finger, slot), others) in ties {
        let chosen = best[&(*side, *finger, *slot)].1;
        let side = side.map_or(String::new(), |s| format!("{} ", s.name()));
        let also: Vec<String> = others.iter().map(|&i| shown(&names[i])).collect();
        notes.push(format!(
            "{side}{finger} {}: {} was used; {} would also fit (give --map to choose)",
            slot_name(*finger, *slot),
            shown(&names[chosen]),
            also.join(", ")
        ));
    }
    notes
}

/// The chain of one finger from the nodes chosen for its slots. `Ok(None)`, with
/// a note why when it helps, when the finger lacks a joint, or its nodes are
/// not one chain in the hierarchy while other nodes would fit as well (when
/// the names leave no doubt, the chain needs no hierarchy); an error when a
/// node's world transform is not finite.
fn finger_chain(
    file: &GltfFile,
    names: &[String],
    found: &FingerFound<'_>,
    notes: &mut Vec<String>,
) -> Result<Option<FingerChain>, Problem> {
    let (side, finger, slots) = (found.side, found.finger, found.slots);
    let label = match side {
        Some(s) => format!("{} {finger}", s.name()),
        None => finger.to_string(),
    };
    let mut wanted = vec![(Slot::Mcp, Joint::Mcp)];
    wanted.extend(
        Joint::inner(finger)
            .iter()
            .zip([Slot::First, Slot::Second])
            .map(|(&j, s)| (s, j)),
    );
    let missing: Vec<&str> = wanted
        .iter()
        .filter(|(s, _)| !slots.contains_key(s))
        .map(|(_, j)| j.name())
        .collect();
    if !missing.is_empty() {
        if wanted.iter().any(|(s, _)| slots.contains_key(s)) {
            notes.push(format!(
                "{label}: no {} joint found, so this finger is left out",
                missing.join(" or ")
            ));
        }
        return Ok(None);
    }
    let mut tip = slots.get(&Slot::Tip).copied();
    let mut hierarchy = true;
    if let Some(t) = tip {
        let last = slots[&wanted[wanted.len() - 1].0];
        if below(&file.parent, t, last) {
            wanted.push((Slot::Tip, Joint::Tip));
        } else if found.unambiguous {
            wanted.push((Slot::Tip, Joint::Tip));
            hierarchy = false;
        } else {
            notes.push(format!(
                "{label}: tip {} is not below {} in the node hierarchy, so it is not used",
                shown(&names[t]),
                shown(&names[last])
            ));
            tip = None;
        }
    }
    if let Some(w) = wanted
        .windows(2)
        .find(|w| !below(&file.parent, slots[&w[1].0], slots[&w[0].0]))
    {
        if !found.unambiguous {
            notes.push(format!(
                "{label}: {} is not below {} in the node hierarchy, so these are not one finger; left out (give --map to choose)",
                shown(&names[slots[&w[1].0]]),
                shown(&names[slots[&w[0].0]])
            ));
            return Ok(None);
        }
        hierarchy = false;
    }
    Ok(Some(FingerChain {
        side,
        finger,
        joints: rig_joints(file, names, &label, &wanted, slots)?,
        has_tip: tip.is_some(),
        metacarpal: None,
        wrist: None,
        hierarchy,
    }))
}

/// The `wanted` joints of a finger (`label`) at their nodes' world positions;
/// an error when a node's world transform is not finite.
fn rig_joints(
    file: &GltfFile,
    names: &[String],
    label: &str,
    wanted: &[(Slot, Joint)],
    slots: &HashMap<Slot, usize>,
) -> Result<Vec<RigJoint>, Problem> {
    if let Some(&(slot, j)) = wanted
        .iter()
        .find(|(s, _)| !file.world[slots[s]].is_finite())
    {
        return Err(Problem::file(format!(
            "node {} ({label} {}) has a non-finite world transform (a zero rotation quaternion, \
             a zero scale above it, or a huge value); fix its transform or its parents'",
            shown(&names[slots[&slot]]),
            j.name()
        )));
    }
    Ok(wanted
        .iter()
        .map(|&(s, joint)| {
            let node = slots[&s];
            RigJoint {
                joint,
                node: Some(node),
                name: names[node].clone(),
                position: file.world[node].w_axis.truncate(),
                weighted: None,
            }
        })
        .collect())
}

/// The error of a file with no complete finger: the names it has (the first
/// 60), the conventions known, and the notes on fingers left out.
fn no_hand(label: &str, names: &[String], notes: Vec<String>) -> DataError {
    const SHOWN: usize = 60;
    let n = names.len();
    let mut listed: Vec<String> = names.iter().take(SHOWN).map(|s| shown(s)).collect();
    if n > SHOWN {
        listed.push(format!("and {} more", n - SHOWN));
    }
    let seen = if n == 0 {
        "no nodes at all".to_string()
    } else {
        format!("{n} node names: {}", listed.join(", "))
    };
    let generic = naming::generic_joint_names(names);
    let what = if generic.len() >= 3 {
        format!(
            "has no recognisable hand: its joints carry generic names ({}{}), as Maya names \
             joints it creates, which do not say which finger or joint each is. Name them with \
             --map FILE (columns node,side,finger,joint, one line per joint: e.g. joint5,right,index,MCP)",
            generic
                .iter()
                .take(6)
                .map(|s| shown(s))
                .collect::<Vec<_>>()
                .join(", "),
            if generic.len() > 6 {
                format!(" and {} more", generic.len() - 6)
            } else {
                String::new()
            }
        )
    } else {
        format!(
            "has no recognisable hand: no finger chain (MCP and its inner joints) was found among its {seen}. \
             Known conventions: Mixamo (mixamorig:RightHandIndex1..4, LeftHandIndex1), Rigify (f_index.01.R, DEF-f_index.01.R, thumb.01.R), \
             VRM (rightIndexProximal), Unreal (index_01_r), WebXR (index-finger-phalanx-proximal), \
             Oculus (b_l_index1, b_l_index_null), SteamVR (finger_index_0_r), Unity (EthanLeftHandIndex1, Left_Index_Finger_Joint_01a), \
             Blender (Index.R, Index.R.001); \
             for other names give --map FILE (columns node,side,finger,joint)"
        )
    };
    let mut e = DataError::whole_file(label, what);
    e.problems.extend(notes.into_iter().map(Problem::file));
    e
}

/// The joint a slot stands for on `finger`, for messages.
fn slot_name(finger: Finger, slot: Slot) -> &'static str {
    match (slot, finger) {
        (Slot::Carpal, _) => "CMC",
        (Slot::Mcp, _) => "MCP",
        (Slot::First, Finger::Thumb) => "IP",
        (Slot::First, _) => "PIP",
        (Slot::Second, _) => "DIP",
        (Slot::Tip, _) => "tip",
    }
}

/// True when `node` lies below `ancestor` in the node hierarchy (or is it).
fn below(parent: &[Option<usize>], node: usize, ancestor: usize) -> bool {
    let mut at = Some(node);
    let mut steps = 0;
    while let Some(i) = at {
        if i == ancestor {
            return true;
        }
        steps += 1;
        if steps > parent.len() {
            return false;
        }
        at = parent[i];
    }
    false
}
