//! The history file: one JSON line per snapshot of the statistics (`data/history.jsonl`).
//!
//! Appended by `phalanx add`, `phalanx remove` and `phalanx snapshot`, read by
//! `phalanx history` and the report's Tracking section. Lines are never rewritten.
//! A record of an addition or removal says what changed ([`ChangeRecord`]: the X-rays,
//! the file, the rows let in though flagged); any record may carry the user's note.

use super::csvinput::read_input;
use super::{DataError, Finger, Problem, Quantity};
use crate::stats::Intervals;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};

/// Statistics of one quantity at one snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema, Deserialize)]
pub struct QuantityRecord {
    pub finger: Finger,
    pub quantity: Quantity,
    pub n: usize,
    pub mean: f64,
    pub sd: Option<f64>,
    /// Keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`, as in the statistics document.
    #[serde(flatten)]
    pub intervals: Intervals,
}

/// X-rays per finger at one snapshot.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema, Deserialize)]
pub struct FingerCount {
    pub finger: Finger,
    pub n: usize,
}

/// Settings the snapshot's statistics were computed with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema, Deserialize)]
pub struct SnapshotSettings {
    pub resamples: usize,
    pub seed: u64,
    pub confidence: f64,
}

/// What made a snapshot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Event {
    /// `phalanx add` (or `import --into`): rows were added to the dataset.
    Add,
    /// `phalanx remove`: rows were taken out of the dataset.
    Remove,
    /// `phalanx snapshot`: recorded on demand.
    Snapshot,
}

impl Event {
    /// The name written to the history file: `add`, `remove` or `snapshot`.
    pub fn name(self) -> &'static str {
        match self {
            Event::Add => "add",
            Event::Remove => "remove",
            Event::Snapshot => "snapshot",
        }
    }
}

/// A row that a rule flagged as a likely error, let in with `--accept-flagged`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema, Deserialize)]
pub struct FlaggedRow {
    pub xray: String,
    pub finger: Finger,
    /// Why it was flagged, as `add` said it.
    pub reason: String,
}

/// What an addition or a removal changed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema, Deserialize)]
pub struct ChangeRecord {
    /// The file the rows came from (`add FILE`, `import FILE --into`); absent for a row
    /// given as options and for a removal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// The X-rays whose rows were added or removed, in file order.
    pub xrays: Vec<String>,
    /// Rows added or removed.
    pub rows: usize,
    /// Added: the rows let in though flagged. Removed: the rows removed that had been
    /// let in flagged.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub flagged: Vec<FlaggedRow>,
}

impl fmt::Display for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One line of the history file.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema, Deserialize)]
pub struct Snapshot {
    /// UTC time, RFC 3339.
    pub time: String,
    /// What made it.
    pub event: Event,
    /// The dataset's path as given.
    pub dataset: String,
    pub sha256: String,
    /// Distinct X-rays.
    pub xrays: usize,
    pub fingers: Vec<FingerCount>,
    pub settings: SnapshotSettings,
    pub quantities: Vec<QuantityRecord>,
    /// What an `add` or `remove` changed (absent for a `snapshot`, and in records
    /// written before phalanx recorded it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub change: Option<ChangeRecord>,
    /// The user's note (`--note`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The history file that goes with a dataset: `history.jsonl` in its directory.
pub fn default_path(data: &Path) -> PathBuf {
    match data.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join("history.jsonl"),
        _ => PathBuf::from("history.jsonl"),
    }
}

/// Reads every snapshot of a history file; a missing file is an empty history.
pub fn read(path: &Path) -> Result<Vec<Snapshot>, DataError> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let label = path.display().to_string();
    let bytes = read_input(path)?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        DataError::whole_file(
            &label,
            format!("is not UTF-8 text ({e}); it should hold JSON lines written by phalanx"),
        )
    })?;
    let mut out = Vec::new();
    let mut problems = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        match serde_json::from_str::<Snapshot>(line) {
            Ok(s) => out.push(s),
            Err(e) => problems.push(Problem {
                line: Some(i as u64 + 1),
                column: Some(e.column()),
                field: None,
                message: format!("is not a phalanx snapshot ({e}); remove or repair the line"),
            }),
        }
    }
    if problems.is_empty() {
        Ok(out)
    } else {
        Err(DataError {
            file: label,
            problems,
        })
    }
}

/// The history file's bytes with one snapshot appended as a JSON line (a
/// missing file is empty; a last line without its line end is completed).
pub(crate) fn appended_bytes(path: &Path, snapshot: &Snapshot) -> std::io::Result<Vec<u8>> {
    let mut bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(e) => return Err(e),
    };
    if !bytes.is_empty() && !bytes.ends_with(b"\n") {
        bytes.push(b'\n');
    }
    serde_json::to_writer(&mut bytes, snapshot).map_err(std::io::Error::other)?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// Appends one snapshot as a JSON line. The file is replaced atomically (old
/// lines, then the new one), so an interrupted append leaves the old history,
/// never a torn line. Cost: O(size of the history).
pub(crate) fn append(path: &Path, snapshot: &Snapshot) -> std::io::Result<()> {
    crate::atomic::replace(path, &appended_bytes(path, snapshot)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Interval;

    fn snap(n: usize) -> Snapshot {
        Snapshot {
            time: "2026-01-01T00:00:00Z".into(),
            event: Event::Add,
            dataset: "d.csv".into(),
            sha256: "00".into(),
            xrays: n,
            fingers: vec![FingerCount {
                finger: Finger::Index,
                n,
            }],
            settings: SnapshotSettings {
                resamples: 10,
                seed: 1,
                confidence: 0.95,
            },
            quantities: vec![QuantityRecord {
                finger: Finger::Index,
                quantity: Quantity::RelJ1,
                n,
                mean: 0.5,
                sd: None,
                intervals: Intervals {
                    ci_t: Some(Interval::new(0.4, 0.6)),
                    ..Intervals::NONE
                },
            }],
            change: None,
            note: None,
        }
    }

    #[test]
    fn round_trips_and_reports_bad_lines() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("history.jsonl");
        assert!(read(&p).unwrap().is_empty());
        append(&p, &snap(5)).unwrap();
        append(&p, &snap(6)).unwrap();
        assert_eq!(read(&p).unwrap(), vec![snap(5), snap(6)]);
        std::fs::write(
            &p,
            format!("{}\n{{oops\n", serde_json::to_string(&snap(5)).unwrap()),
        )
        .unwrap();
        let e = read(&p).unwrap_err();
        assert_eq!(e.problems[0].line, Some(2));
        // A line without a final line end (edited by hand) is terminated before the next append.
        std::fs::write(&p, "{\"torn\":").unwrap();
        append(&p, &snap(7)).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.starts_with("{\"torn\":\n{"), "{text}");
        assert_eq!(
            default_path(Path::new("data/m.csv")),
            PathBuf::from("data/history.jsonl")
        );
        assert_eq!(
            default_path(Path::new("m.csv")),
            PathBuf::from("history.jsonl")
        );
    }

    #[test]
    fn the_committed_history_reads_and_writes_back_unchanged() {
        // data/history.jsonl was written before the records were typed.
        let path = Path::new("data/history.jsonl");
        let snaps = read(path).unwrap();
        assert!(!snaps.is_empty());
        assert_eq!(snaps[0].event, Event::Snapshot);
        assert_eq!(snaps[0].quantities[0].finger, Finger::Thumb);
        assert_eq!(snaps[0].quantities[0].quantity, Quantity::RelJ1);
        // Written back, every key and value is as read. (serde_json parses floats to
        // within an ulp, not always exactly, so the lines are compared as parsed JSON.)
        let text = std::fs::read_to_string(path).unwrap();
        assert_eq!(text.lines().count(), snaps.len());
        for (line, snap) in text.lines().zip(&snaps) {
            let read: serde_json::Value = serde_json::from_str(line).unwrap();
            assert_eq!(serde_json::to_value(snap).unwrap(), read);
        }
    }

    #[test]
    fn unknown_names_are_reported_with_their_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("history.jsonl");
        let good = serde_json::to_string(&snap(5)).unwrap();
        let lines = [
            good.clone(),
            good.replace("\"event\":\"add\"", "\"event\":\"merge\""),
            good.replace("\"finger\":\"index\"", "\"finger\":\"toe\""),
            good.replace("\"quantity\":\"rel_j1\"", "\"quantity\":\"rel_j9\""),
        ];
        std::fs::write(&p, lines.join("\n")).unwrap();
        let e = read(&p).unwrap_err();
        let got: Vec<(Option<u64>, &str)> = e
            .problems
            .iter()
            .map(|p| (p.line, p.message.as_str()))
            .collect();
        assert_eq!(got.len(), 3, "{got:?}");
        assert_eq!(got[0].0, Some(2));
        assert!(got[0].1.contains("unknown variant `merge`"), "{got:?}");
        assert_eq!(got[1].0, Some(3));
        assert!(got[1].1.contains("unknown finger 'toe'"), "{got:?}");
        assert_eq!(got[2].0, Some(4));
        assert!(got[2].1.contains("unknown quantity 'rel_j9'"), "{got:?}");
        assert!(e.to_string().contains("history.jsonl"), "{e}");
    }
}
