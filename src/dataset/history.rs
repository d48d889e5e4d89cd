//! The history file: one JSON line per snapshot of the statistics (`data/history.jsonl`).
//!
//! Appended by `phalanx add` and `phalanx snapshot`, read by `phalanx history`
//! and the report's Tracking section. Lines are never rewritten.

use super::csvinput::read_input;
use super::{DataError, Problem};
use crate::stats::Intervals;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Statistics of one quantity at one snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QuantityRecord {
    pub finger: String,
    pub quantity: String,
    pub n: usize,
    pub mean: f64,
    pub sd: Option<f64>,
    /// Keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`, as in the statistics document.
    #[serde(flatten)]
    pub intervals: Intervals,
}

/// X-rays per finger at one snapshot.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FingerCount {
    pub finger: String,
    pub n: usize,
}

/// Settings the snapshot's statistics were computed with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SnapshotSettings {
    pub resamples: usize,
    pub seed: u64,
    pub confidence: f64,
}

/// One line of the history file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// UTC time, RFC 3339.
    pub time: String,
    /// What made it: `add` or `snapshot`.
    pub event: String,
    /// The dataset's path as given.
    pub dataset: String,
    pub sha256: String,
    /// Distinct X-rays.
    pub xrays: usize,
    pub fingers: Vec<FingerCount>,
    pub settings: SnapshotSettings,
    pub quantities: Vec<QuantityRecord>,
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
pub fn appended_bytes(path: &Path, snapshot: &Snapshot) -> std::io::Result<Vec<u8>> {
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
pub fn append(path: &Path, snapshot: &Snapshot) -> std::io::Result<()> {
    crate::atomic::replace(path, &appended_bytes(path, snapshot)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Interval;

    fn snap(n: usize) -> Snapshot {
        Snapshot {
            time: "2026-01-01T00:00:00Z".into(),
            event: "add".into(),
            dataset: "d.csv".into(),
            sha256: "00".into(),
            xrays: n,
            fingers: vec![FingerCount {
                finger: "index".into(),
                n,
            }],
            settings: SnapshotSettings {
                resamples: 10,
                seed: 1,
                confidence: 0.95,
            },
            quantities: vec![QuantityRecord {
                finger: "index".into(),
                quantity: "rel_j1".into(),
                n,
                mean: 0.5,
                sd: None,
                intervals: Intervals {
                    ci_t: Some(Interval::new(0.4, 0.6)),
                    ..Intervals::NONE
                },
            }],
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
}
