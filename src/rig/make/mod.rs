//! Making a rig's fingers from its skin and the statistics: [`place`] puts
//! each finger's joints on the axis `find` traced (the paper's rule), and
//! the rest (the skin's weights, the written nodes) follows. Uses `read`,
//! `find`, `judge` (its chain geometry) and `fix` (the one glTF writer).

pub mod names;
pub mod place;
pub mod weights;
pub mod write;

use crate::dataset::DataError;
use crate::rig::find::{FindError, FindOptions, MeshSelect, find_hand, hand_mesh};
use crate::rig::read::naming::Side;
use crate::rig::read::{FingerChain, Rig};
use glam::DVec3;
use place::{MadeHand, Proportions};
use std::path::Path;
use write::{WriteOptions, Written};

/// What to rig, and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MakeOptions {
    /// Which hand, when the file has two (or its side is not said).
    pub side: Option<Side>,
    /// The wrist, when the file has no hand bone to give it.
    pub wrist: Option<DVec3>,
    /// How many fingers the hand has, the thumb included (default: as many
    /// chains as the file has when replacing them, else 5).
    pub fingers: Option<usize>,
    pub write: WriteOptions,
}

/// A hand rigged.
#[derive(Debug, Clone)]
pub struct Made {
    pub hand: MadeHand,
    pub written: Written,
    /// How the hand was found and what was left out.
    pub notes: Vec<String>,
    /// How many triangles the hand's skin has.
    pub triangles: usize,
}

/// Why a hand could not be rigged.
#[derive(Debug, thiserror::Error)]
pub enum MakeError {
    /// Reading the mesh or writing the copy failed.
    #[error(transparent)]
    File(#[from] DataError),
    /// No hand was found on the skin.
    #[error("{0}")]
    Find(FindError),
    /// Anything else the user must change, said whole.
    #[error("{0}")]
    Refused(String),
}

/// Rigs one hand of `rig`: finds it on its skin, places its joints from
/// `proportions`, weights the skin and writes the copy's bytes (see
/// [`place`], [`weights`], [`write`]). `dir` resolves external buffers.
pub fn make(
    rig: &Rig,
    proportions: &Proportions,
    opts: &MakeOptions,
    dir: &Path,
) -> Result<Made, MakeError> {
    let (side, hands) = side_of(rig, opts.side)?;
    let chains: Vec<&FingerChain> = rig
        .chains
        .iter()
        .filter(|c| side.is_none() || c.side.is_none() || c.side == side)
        .collect();
    if !opts.write.replace_fingers && !chains.is_empty() {
        let names: Vec<String> = chains.iter().map(|c| c.label()).collect();
        return Err(MakeError::Refused(format!(
            "the hand already has finger bones ({}): give --replace-fingers to place them anew \
             and weight its skin to them, or rig a hand without finger bones",
            names.join(", ")
        )));
    }
    let hand_node = hand_bone(rig, side);
    let select = MeshSelect::for_hand(hand_node.map(|(n, _)| n), hands > 1, rig.weights.is_some());
    let mesh = hand_mesh(&rig.file, &select)?;
    let fingers = opts
        .fingers
        .unwrap_or(if opts.write.replace_fingers && !chains.is_empty() {
            chains.len()
        } else {
            5
        });
    // The finder names the wrist it is handed as `wrist_is` says.
    let wrist_is = match (opts.wrist, hand_node) {
        (None, Some((node, _))) => format!("the hand bone's origin ({})", rig.file.node_name(node)),
        _ => "the point given (--wrist)".to_string(),
    };
    let find = FindOptions {
        fingers,
        wrist: opts.wrist.or(hand_node.map(|(_, at)| at)),
        side,
        wrist_is: Some(wrist_is),
    };
    let found = find_hand(&mesh, &find).map_err(MakeError::Find)?;
    let hand = place::place(&mesh, &found, proportions);
    if hand.fingers.is_empty() {
        return Err(MakeError::Refused(format!(
            "no finger could be placed: {}",
            hand.notes.join("; ")
        )));
    }
    let w = weights::weigh(&mesh, &found, &hand);
    let written = write::write(
        rig,
        &chains,
        hand_node.map(|(n, _)| n),
        &mesh,
        &hand,
        &w,
        &opts.write,
        dir,
    )?;
    let mut notes: Vec<String> = found.notes.clone();
    notes.extend(mesh.notes.iter().cloned());
    notes.extend(hand.notes.iter().cloned());
    Ok(Made {
        hand,
        written,
        notes,
        triangles: mesh.triangles.len(),
    })
}

/// The hand to rig: `given` (`--side`), else the one side the file's bones
/// name, else none; with how many sides they name. A side the bones do not
/// have, or two sides without `--side`, is refused.
fn side_of(rig: &Rig, given: Option<Side>) -> Result<(Option<Side>, usize), MakeError> {
    let mut sides: Vec<Option<Side>> = rig.chains.iter().map(|c| c.side).collect();
    sides.extend(
        rig.file
            .document
            .nodes()
            .filter_map(|n| crate::rig::read::naming::parse_hand(n.name()?))
            .map(|h| h.side),
    );
    sides.sort();
    sides.dedup();
    let named: Vec<Side> = sides.iter().flatten().copied().collect();
    let side = match (given, named.as_slice()) {
        (Some(s), [one]) if *one != s => {
            return Err(MakeError::Refused(format!(
                "--side {}: the file's bones name only its {} hand; give --side {} or leave \
                 it out",
                s.name(),
                one.name(),
                one.name()
            )));
        }
        (Some(s), _) => Some(s),
        (None, [one]) => Some(*one),
        (None, [_, _, ..]) => {
            return Err(MakeError::Refused(
                "the file has two hands (bones named for both sides): give --side left or \
                 --side right to rig one, and run again for the other"
                    .into(),
            ));
        }
        (None, []) => None,
    };
    Ok((side, named.len()))
}

/// The file's hand (wrist) bone of `side` (any side when `None`): its node
/// and world position, when its name says it is one.
fn hand_bone(rig: &Rig, side: Option<Side>) -> Option<(usize, DVec3)> {
    if let Some(w) = rig
        .chains
        .iter()
        .filter(|c| side.is_none() || c.side == side)
        .find_map(|c| c.wrist.as_ref())
    {
        return Some((w.node, w.position));
    }
    rig.file.document.nodes().find_map(|n| {
        let h = crate::rig::read::naming::parse_hand(n.name()?)?;
        (side.is_none() || h.side.is_none() || h.side == side).then(|| {
            let at = rig.file.world[n.index()].w_axis.truncate();
            (n.index(), at)
        })
    })
}
