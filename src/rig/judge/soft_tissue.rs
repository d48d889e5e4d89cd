//! The fingertip's soft tissue beyond the distal phalanx, which bridges a rig's tips
//! and the data's when one is at the bone and the other at the skin; and what a
//! dataset's tips mark.

use crate::dataset::{Finger, Segment, SummaryTable, TipCounts, TipKind};
use schemars::JsonSchema;
use serde::Serialize;

/// The published table whose fingertip soft tissue is used when a rig's tips
/// and the data's differ (one at the bone, the other at the skin), read at run
/// time: Buryanov and Kotiuk (2010), Table I, 66 adult right hands.
pub const SOFT_TISSUE_TABLE: &str = "data/literature/buryanov-kotiuk-2010.csv";

/// The fingertip's soft tissue beyond the distal phalanx: what separates a tip
/// at the skin from a tip at the bone.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "from", rename_all = "snake_case")]
pub enum SoftTissue {
    /// No figure is known: a rig is judged only where its tips and the data's agree.
    Unknown,
    /// The same length on every finger, in rig units (`--tip-soft-tissue MM`).
    Length { length: f64 },
    /// Each finger's measured mean from a published table, taken as a share of
    /// the finger's length ([`SoftTissue::correction`]).
    Table {
        /// The table, as given.
        source: String,
        /// The source's short name ("Buryanov & Kotiuk 2010"), from its notes.
        name: Option<String>,
        /// The table's unit (the shares have none).
        unit: String,
        fingers: Vec<FingerSoftTissue>,
    },
}

/// One finger's soft tissue and bones in a published table, in its unit.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct FingerSoftTissue {
    pub finger: Finger,
    /// Mean soft tissue beyond the distal phalanx (the table's `tip_soft_tissue`).
    pub soft_tissue: f64,
    /// The finger's phalanges end to end, MCP to the bone tip: the sum of the
    /// table's means of J1, J2[, J3].
    pub bone: f64,
}

impl FingerSoftTissue {
    /// The soft tissue's share of the finger measured to the tip of `kind`:
    /// t / (b + t) to the skin, t / b to the bone.
    pub fn share(&self, kind: TipKind) -> f64 {
        match kind {
            TipKind::Skin => self.soft_tissue / (self.bone + self.soft_tissue),
            TipKind::Bone => self.soft_tissue / self.bone,
        }
    }
}

impl SoftTissue {
    /// The fingers of `table` that give their soft tissue and every phalanx,
    /// `name` the source's short name. O(rows).
    pub fn from_table(table: &SummaryTable, name: Option<String>) -> SoftTissue {
        let fingers = table
            .fingers()
            .into_iter()
            .filter_map(|finger| {
                let soft_tissue = table.get(finger, Segment::TipSoftTissue)?.mean;
                let bone = Segment::phalanges(finger)
                    .iter()
                    .map(|&s| table.get(finger, s).map(|r| r.mean))
                    .sum::<Option<f64>>()?;
                Some(FingerSoftTissue {
                    finger,
                    soft_tissue,
                    bone,
                })
            })
            .collect();
        SoftTissue::Table {
            source: table.path.clone(),
            name,
            unit: table.unit.clone(),
            fingers,
        }
    }

    /// A table's figures for `finger`, if it gives them.
    pub fn of(&self, finger: Finger) -> Option<&FingerSoftTissue> {
        match self {
            SoftTissue::Table { fingers, .. } => fingers.iter().find(|f| f.finger == finger),
            _ => None,
        }
    }

    /// What is taken off a rig finger's last segment to compare its tip
    /// (`rig`) with a dataset's (`data`), the finger `length` long in rig units
    /// as the rig has it (MCP to its tip); `None` when the tips differ and no
    /// figure for `finger` is known. O(1).
    ///
    /// 0 when the tips agree. Otherwise, with one length s: +s for a skin tip
    /// against bone-tip data, -s the other way. From a table, the soft tissue
    /// is the table's share of the finger, so it scales with the rig in any
    /// unit: L t / (b + t) off a skin tip, L t / b onto a bone tip (L the rig's
    /// finger, t the table's soft tissue, b its phalanges end to end), which
    /// turns a finger of the table's proportions exactly into the table's
    /// finger to the other tip.
    pub fn correction(
        &self,
        rig: TipKind,
        data: TipKind,
        finger: Finger,
        length: f64,
    ) -> Option<f64> {
        if rig == data {
            return Some(0.0);
        }
        let sign = if rig == TipKind::Skin { 1.0 } else { -1.0 };
        match self {
            SoftTissue::Unknown => None,
            SoftTissue::Length { length: s } => Some(sign * s),
            SoftTissue::Table { .. } => Some(sign * length * self.of(finger)?.share(rig)),
        }
    }
}

/// What a dataset's tips mark, from its `tip` column: the one kind all its
/// rows record, else (not recorded, or mixed) taken as bone tips, the usual
/// landmark on an X-ray.
pub fn data_tip_of(tips: &TipCounts) -> TipKind {
    tips.single().unwrap_or(TipKind::Bone)
}
