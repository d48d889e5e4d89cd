//! `--map FILE`: custom joint names for rigs no convention covers.
//!
//! A CSV file with the header `node,side,finger,joint`: the exact node name in
//! the glTF file, the hand (`left`, `right`, or empty when the file has one
//! hand), the finger, and the joint (`MCP`, `PIP`, `DIP`, `IP`, `tip`).
//! Mapped nodes are read by the map alone; other nodes still by convention.

use super::naming::{Side, Slot};
use crate::dataset::csvinput::{CsvScan, Header, quote, read_input};
use crate::dataset::{DataError, Finger, Problem};
use std::collections::HashMap;
use std::path::Path;

const COLUMNS: [&str; 4] = ["node", "side", "finger", "joint"];

/// Node names mapped to joints.
#[derive(Debug, Clone, Default)]
pub struct NameMap {
    /// The map file as named by the user.
    pub file: String,
    /// Node name -> (side, finger, slot, line).
    pub entries: HashMap<String, (Option<Side>, Finger, Slot, u64)>,
}

impl NameMap {
    /// Reads and validates a map file, reporting every problem together.
    pub fn load(path: &Path) -> Result<NameMap, DataError> {
        let bytes = read_input(path)?;
        NameMap::from_bytes(&path.display().to_string(), &bytes)
    }

    /// Validates the bytes of a map file; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<NameMap, DataError> {
        let mut problems = Vec::new();
        let mut scan = CsvScan::new(label, bytes)?;
        let Some(header_rec) = scan.next_record(&mut problems) else {
            return Err(DataError::whole_file(
                label,
                format!(
                    "is empty; it needs the header {} and one row per joint",
                    COLUMNS.join(",")
                ),
            ));
        };
        let header = Header::parse(&header_rec, &COLUMNS, &[], &mut problems);
        let header_ok = problems.is_empty();
        let mut entries = HashMap::new();
        let mut seen: HashMap<(Option<Side>, Finger, Slot), u64> = HashMap::new();
        while let Some(rec) = scan.next_record(&mut problems) {
            if !header_ok {
                continue;
            }
            if rec.len() != header.names.len() {
                problems.push(crate::dataset::csvinput::field_count_problem(
                    &rec,
                    header.names.len(),
                ));
                continue;
            }
            let line = rec.line;
            let get = |k: usize| header.positions[k].and_then(|p| rec.get(p)).unwrap_or("");
            let col = |k: usize| header.positions[k].map_or(0, |p| p + 1);
            let mut bad = |k: usize, msg: String| {
                problems.push(Problem::field(line, col(k), COLUMNS[k], msg))
            };
            let node = get(0).to_string();
            if node.is_empty() {
                bad(
                    0,
                    "is empty; give the node's name exactly as in the glTF file".into(),
                );
            }
            let side = match get(1) {
                "" => Some(None),
                t => match Side::parse(t) {
                    Some(s) => Some(Some(s)),
                    None => {
                        bad(
                            1,
                            format!(
                                "unknown side {}; use left, right or leave it empty",
                                quote(t)
                            ),
                        );
                        None
                    }
                },
            };
            let finger = Finger::parse(get(2));
            if finger.is_none() {
                bad(
                    2,
                    format!(
                        "unknown finger {}; use one of {}",
                        quote(get(2)),
                        Finger::ACCEPTED
                    ),
                );
            }
            let slot = match (finger, get(3).to_ascii_lowercase().as_str()) {
                (_, "mcp") => Some(Slot::Mcp),
                (Some(Finger::Thumb), "ip") | (Some(Finger::Thumb) | None, "pip") => {
                    Some(Slot::First)
                }
                (Some(f), "pip") if f != Finger::Thumb => Some(Slot::First),
                (Some(f), "dip") if f != Finger::Thumb => Some(Slot::Second),
                (_, "tip") => Some(Slot::Tip),
                (f, t) => {
                    let allowed = if f == Some(Finger::Thumb) {
                        "MCP, IP or tip (the thumb has no PIP/DIP)"
                    } else {
                        "MCP, PIP, DIP or tip"
                    };
                    bad(3, format!("unknown joint {}; use {allowed}", quote(t)));
                    None
                }
            };
            if node.is_empty() {
                continue;
            }
            if let (Some(side), Some(finger), Some(slot)) = (side, finger, slot) {
                if let Some(first) = seen.insert((side, finger, slot), line) {
                    bad(
                        3,
                        format!(
                            "this joint is already mapped on line {first}; map each joint once"
                        ),
                    );
                } else if let Some((_, _, _, first)) = entries.get(&node) {
                    bad(
                        0,
                        format!("{} is already mapped on line {first}", quote(&node)),
                    );
                } else {
                    entries.insert(node, (side, finger, slot, line));
                }
            }
        }
        if !problems.is_empty() {
            return Err(DataError {
                file: label.to_string(),
                problems,
            });
        }
        Ok(NameMap {
            file: label.to_string(),
            entries,
        })
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
}
