//! `--map FILE`: custom joint names for rigs no convention covers.
//!
//! A CSV file with the header `node,side,finger,joint`: the exact node name in
//! the glTF file, the hand (`left`, `right`, or empty when the file has one
//! hand), the finger, and the joint (`MCP`, `PIP`, `DIP`, `IP`, `tip`).
//! Mapped nodes are read by the map alone; other nodes still by convention.

use super::naming::{Side, Slot};
use crate::dataset::csvinput::{Cells, Columns, quote, read_input, read_table};
use crate::dataset::{DataError, Finger};
use std::collections::HashMap;
use std::path::Path;

/// The columns of a map file, all required.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Column {
    Node,
    Side,
    Finger,
    Joint,
}

impl Columns for Column {
    const ALL: &'static [Column] = &[Column::Node, Column::Side, Column::Finger, Column::Joint];
    const EMPTY: &'static str =
        "is empty; it needs the header node,side,finger,joint and one row per joint";
    const NO_HEADER: Option<&'static str> = Some(Self::EMPTY);
    const NO_ROWS: Option<&'static str> = None;

    fn name(self) -> &'static str {
        match self {
            Column::Node => "node",
            Column::Side => "side",
            Column::Finger => "finger",
            Column::Joint => "joint",
        }
    }

    fn required(self) -> bool {
        true
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// A mapped joint: side (`None` for a one-hand file), finger and slot.
type Mapped = (Option<Side>, Finger, Slot);

/// Node names mapped to joints.
#[derive(Debug, Clone, Default)]
pub struct NameMap {
    /// The map file as named by the user.
    pub file: String,
    /// Node name -> (side, finger, slot, line).
    pub(crate) entries: HashMap<String, (Option<Side>, Finger, Slot, u64)>,
}

impl NameMap {
    /// Reads and validates a map file, reporting every problem together.
    pub fn load(path: &Path) -> Result<NameMap, DataError> {
        let bytes = read_input(path)?;
        NameMap::from_bytes(&path.display().to_string(), &bytes)
    }

    /// Validates the bytes of a map file; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<NameMap, DataError> {
        let mut entries = HashMap::new();
        let mut seen: HashMap<Mapped, u64> = HashMap::new();
        read_table::<Column>(label, bytes, |cells| {
            let Some((node, mapped)) = read_entry(cells) else {
                return;
            };
            let line = cells.line();
            if let Some(first) = seen.insert(mapped, line) {
                cells.bad(
                    Column::Joint,
                    format!("this joint is already mapped on line {first}; map each joint once"),
                );
            } else if let Some((_, _, _, first)) = entries.get(&node) {
                cells.bad(
                    Column::Node,
                    format!("{} is already mapped on line {first}", quote(&node)),
                );
            } else {
                let (side, finger, slot) = mapped;
                entries.insert(node, (side, finger, slot, line));
            }
        })?;
        Ok(NameMap {
            file: label.to_string(),
            entries,
        })
    }
}

/// Reads one row: the node's name and the joint it stands for. `None` when a
/// cell is refused (reported) or the node's name is empty.
fn read_entry(cells: &mut Cells<'_, '_, Column>) -> Option<(String, Mapped)> {
    let node = cells.text(Column::Node).unwrap_or("").to_string();
    if node.is_empty() {
        cells.bad(
            Column::Node,
            "is empty; give the node's name exactly as in the glTF file",
        );
    }
    let side = match cells.text(Column::Side).unwrap_or("") {
        "" => Some(None),
        t => match Side::parse(t) {
            Some(s) => Some(Some(s)),
            None => {
                cells.bad(
                    Column::Side,
                    format!(
                        "unknown side {}; use left, right or leave it empty",
                        quote(t)
                    ),
                );
                None
            }
        },
    };
    let finger_text = cells.text(Column::Finger).unwrap_or("");
    let finger = Finger::parse(finger_text);
    if finger.is_none() {
        cells.bad(
            Column::Finger,
            format!(
                "unknown finger {}; use one of {}",
                quote(finger_text),
                Finger::ACCEPTED
            ),
        );
    }
    let joint = cells.text(Column::Joint).unwrap_or("").to_ascii_lowercase();
    let slot = parse_joint(finger, &joint);
    if let Err(message) = &slot {
        cells.bad(Column::Joint, message.clone());
    }
    if node.is_empty() {
        return None;
    }
    Some((node, (side?, finger?, slot.ok()?)))
}

/// The slot a joint name (lower case) stands for on `finger` (when known).
fn parse_joint(finger: Option<Finger>, joint: &str) -> Result<Slot, String> {
    match (finger, joint) {
        (_, "mcp") => Ok(Slot::Mcp),
        (Some(Finger::Thumb), "ip") | (Some(Finger::Thumb) | None, "pip") => Ok(Slot::First),
        (Some(f), "pip") if f != Finger::Thumb => Ok(Slot::First),
        (Some(f), "dip") if f != Finger::Thumb => Ok(Slot::Second),
        (_, "tip") => Ok(Slot::Tip),
        (f, t) => {
            let allowed = if f == Some(Finger::Thumb) {
                "MCP, IP or tip (the thumb has no PIP/DIP)"
            } else {
                "MCP, PIP, DIP or tip"
            };
            Err(format!("unknown joint {}; use {allowed}", quote(t)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_rows_and_reports_every_bad_field() {
        let m = NameMap::from_bytes(
            "map.csv",
            b"node,side,finger,joint\nBone.1,right,index,MCP\nBone.2,,thumb,ip\n",
        )
        .unwrap();
        assert_eq!(m.entries["Bone.1"].2, Slot::Mcp);
        assert_eq!(m.entries["Bone.2"], (None, Finger::Thumb, Slot::First, 3));
        let e = NameMap::from_bytes(
            "map.csv",
            b"node,side,finger,joint\nA,middle,index,MCP\nB,left,toe,PIP\nC,left,thumb,DIP\n",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("map.csv:2:2: side: unknown side 'middle'"),
            "{e}"
        );
        assert!(
            e.contains("map.csv:3:3: finger: unknown finger 'toe'"),
            "{e}"
        );
        assert!(
            e.contains("map.csv:4:4: joint: unknown joint 'dip'; use MCP, IP or tip"),
            "{e}"
        );
    }

    #[test]
    fn problems_come_in_file_order_and_name_their_column() {
        // The header's missing column (line 1, no column) comes before its
        // unknown one (line 1, column 4); a field that is not UTF-8 names its column.
        let e = NameMap::from_bytes("map.csv", b"node,side,finger,jiont\nA,right,index,MCP\n")
            .unwrap_err();
        let columns: Vec<_> = e.problems.iter().map(|p| (p.line, p.column)).collect();
        assert_eq!(columns, [(Some(1), None), (Some(1), Some(4))], "{e}");
        let e = NameMap::from_bytes(
            "map.csv",
            b"node,side,finger,joint\nA,ri\xffght,index,MCP\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("map.csv:2:2: side: is not UTF-8 text"), "{e}");
    }
}
