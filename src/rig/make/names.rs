//! The names a made rig gives its nodes, in the convention `--names` picks:
//! each one read back by the audit's own recogniser as the joint it is (the
//! tests check every name of every convention).

use crate::dataset::Finger;
use crate::rig::read::naming::Side;

/// A naming convention for the nodes `rig` adds.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Names {
    /// OpenXR's hand joints as Godot spells them: `Wrist_R`, `Index_Proximal_R`, `Index_Tip_R`.
    Openxr,
    /// VRM 1.0's humanoid bones: `rightHand`, `rightIndexProximal`, `rightThumbMetacarpal`.
    Vrm,
    /// Mixamo's: `mixamorig:RightHand`, `mixamorig:RightHandIndex1` .. `4`.
    Mixamo,
    /// Unreal's mannequin: `hand_r`, `index_01_r` .. `index_03_r`, `index_04_leaf_r`.
    Unreal,
    /// Blender Rigify's deform bones: `DEF-hand.R`, `DEF-f_index.01.R`, `DEF-f_index.03.R_end`.
    Rigify,
}

/// One bone's place in a made finger: its chain point from the root (the
/// thumb: 0 CMC, 1 MCP, 2 IP, 3 tip; a finger: 0 MCP, 1 PIP, 2 DIP, 3 tip).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Point {
    pub finger: Finger,
    pub k: usize,
}

impl Names {
    /// The hand (wrist) bone's name.
    pub fn hand(self, side: Side) -> String {
        let (s, big, word) = sides(side);
        match self {
            Names::Openxr => format!("Wrist_{big}"),
            Names::Vrm => format!("{word}Hand"),
            Names::Mixamo => format!("mixamorig:{}Hand", capital(word)),
            Names::Unreal => format!("hand_{s}"),
            Names::Rigify => format!("DEF-hand.{big}"),
        }
    }

    /// The name of the node at chain point `p` (see [`Point`]).
    pub fn joint(self, side: Side, p: Point) -> String {
        let (s, big, word) = sides(side);
        let thumb = p.finger == Finger::Thumb;
        let title = match p.finger {
            Finger::Thumb => "Thumb",
            Finger::Index => "Index",
            Finger::Middle => "Middle",
            Finger::Ring => "Ring",
            Finger::Little => "Little",
        };
        // Mixamo, Unreal and Rigify call the little finger the pinky.
        let pinky = if p.finger == Finger::Little {
            "Pinky"
        } else {
            title
        };
        // The numbered conventions count the thumb from its CMC and the
        // fingers from their MCP, both from 1: the k-th point is number k + 1.
        let number = p.k + 1;
        let part = if thumb {
            ["Metacarpal", "Proximal", "Distal", "Tip"]
        } else {
            ["Proximal", "Intermediate", "Distal", "Tip"]
        }[p.k.min(3)];
        match self {
            Names::Openxr => format!("{title}_{part}_{big}"),
            Names::Vrm => format!("{word}{title}{part}"),
            Names::Mixamo => format!("mixamorig:{}Hand{pinky}{number}", capital(word)),
            Names::Unreal if p.k >= 3 => format!("{}_04_leaf_{s}", pinky.to_lowercase()),
            Names::Unreal => format!("{}_{number:02}_{s}", pinky.to_lowercase()),
            Names::Rigify => {
                let bone = if thumb {
                    "thumb".to_string()
                } else {
                    format!("f_{}", pinky.to_lowercase())
                };
                if p.k >= 3 {
                    format!("DEF-{bone}.03.{big}_end")
                } else {
                    format!("DEF-{bone}.{number:02}.{big}")
                }
            }
        }
    }
}

/// The side as `r`, `R` and `right`.
fn sides(side: Side) -> (&'static str, &'static str, &'static str) {
    match side {
        Side::Left => ("l", "L", "left"),
        Side::Right => ("r", "R", "right"),
    }
}

/// `right` -> `Right`.
fn capital(word: &str) -> String {
    let mut c = word.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::read::naming::{Slot, parse, parse_hand, slot};
    use clap::ValueEnum;

    /// Every name of every convention reads back, by the audit's recogniser,
    /// as the side, finger and joint it was made for, and the hand as the hand.
    #[test]
    fn every_convention_reads_back_as_made() {
        for names in Names::value_variants() {
            for side in [Side::Left, Side::Right] {
                let hand = names.hand(side);
                let read = parse_hand(&hand).unwrap_or_else(|| panic!("{hand} is no hand"));
                assert_eq!(read.side, Some(side), "{hand}");
                for finger in Finger::ALL {
                    let slots = if finger == Finger::Thumb {
                        [Slot::Carpal, Slot::Mcp, Slot::First, Slot::Tip]
                    } else {
                        [Slot::Mcp, Slot::First, Slot::Second, Slot::Tip]
                    };
                    for (k, want) in slots.into_iter().enumerate() {
                        let name = names.joint(side, Point { finger, k });
                        let p = parse(&name).unwrap_or_else(|| panic!("{name} is no joint"));
                        assert_eq!(
                            (p.side, p.finger, slot(p.finger, p.part, false)),
                            (Some(side), finger, Some(want)),
                            "{name}"
                        );
                    }
                }
            }
        }
    }
}
