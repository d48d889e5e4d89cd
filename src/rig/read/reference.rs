//! Reference rigs: the default finger joints of widely used rigs (`data/rigs/*.json`).
//!
//! One JSON file per rig: `name`, `source`, `url`, `side`, `units`, `notes`, and
//! `fingers` mapping thumb/index/middle/ring/little to joints (`MCP`, `PIP`,
//! `DIP` or `IP`, optional `tip`) given as `[x, y, z]`. See `data/rigs/README.md`.

use super::naming::Side;
use super::{FingerChain, RigJoint};
use crate::analysis::placement::Joint;
use crate::dataset::{DataError, Finger, Problem};
use glam::DVec3;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RigJson {
    name: String,
    source: String,
    url: String,
    side: String,
    units: String,
    #[serde(default)]
    notes: String,
    fingers: BTreeMap<String, BTreeMap<String, [f64; 3]>>,
}

/// A reference rig with its provenance.
#[derive(Debug, Clone)]
pub struct ReferenceRig {
    /// File stem, e.g. `rigify-human`.
    pub id: String,
    pub name: String,
    pub source: String,
    pub url: String,
    pub units: String,
    pub notes: String,
    pub chains: Vec<FingerChain>,
}

/// Parses one reference rig; `label` names it in errors. Every problem is reported.
pub(crate) fn parse(label: &str, id: &str, bytes: &[u8]) -> Result<ReferenceRig, DataError> {
    let doc: RigJson = serde_json::from_slice(bytes).map_err(|e| DataError {
        file: label.to_string(),
        problems: vec![Problem {
            line: Some(e.line() as u64),
            column: Some(e.column()),
            field: None,
            message: format!("{e}; see data/rigs/README.md for the format"),
        }],
    })?;
    let mut problems = Vec::new();
    let side = check_provenance(&doc, &mut problems);
    let mut chains: Vec<FingerChain> = Vec::new();
    for (fname, joints) in &doc.fingers {
        let Some(finger) = Finger::parse(fname) else {
            problems.push(Problem::file(format!(
                "unknown finger '{fname}'; use {}",
                Finger::ACCEPTED
            )));
            continue;
        };
        if chains.iter().any(|c| c.finger == finger) {
            problems.push(Problem::file(format!(
                "{fname}: the {finger} is given twice (under two of its names); keep one"
            )));
            continue;
        }
        chains.push(read_chain(fname, finger, joints, side, &mut problems));
    }
    if !problems.is_empty() {
        return Err(DataError {
            file: label.to_string(),
            problems,
        });
    }
    chains.sort_by_key(|c| c.finger);
    Ok(ReferenceRig {
        id: id.to_string(),
        name: doc.name,
        source: doc.source,
        url: doc.url,
        units: doc.units,
        notes: doc.notes,
        chains,
    })
}

/// Checks the rig's url, side and units; returns the side.
fn check_provenance(doc: &RigJson, problems: &mut Vec<Problem>) -> Option<Side> {
    if !doc.url.starts_with("https://")
        || doc
            .url
            .contains(|c: char| c.is_whitespace() || c.is_control() || c == '>' || c == '<')
    {
        problems.push(Problem::file(format!(
            "url '{}' is not a plain https:// address; give the source's web address",
            doc.url
        )));
    }
    let side = Side::parse(&doc.side);
    if side.is_none() {
        problems.push(Problem::file(format!(
            "side '{}' is neither left nor right",
            doc.side
        )));
    }
    let units = doc.units.to_ascii_lowercase();
    if !(units == "m" || units.contains("metre") || units.contains("meter")) {
        problems.push(Problem::file(format!(
            "units '{}' are not metres; give the coordinates in metres (e.g. \"Blender units (metres)\")",
            doc.units
        )));
    }
    side
}

/// One finger's joints (`joints` by name) as a chain: MCP, the inner joints,
/// then the tip when given. Unknown, missing and non-finite joints are problems.
fn read_chain(
    fname: &str,
    finger: Finger,
    joints: &BTreeMap<String, [f64; 3]>,
    side: Option<Side>,
    problems: &mut Vec<Problem>,
) -> FingerChain {
    let mut order = vec![Joint::Mcp];
    order.extend_from_slice(Joint::inner(finger));
    let has_tip = joints.contains_key("tip");
    if has_tip {
        order.push(Joint::Tip);
    }
    for key in joints.keys() {
        if !order.iter().any(|j| j.name() == key) {
            let mut allowed: Vec<&str> = order.iter().map(|j| j.name()).collect();
            if !has_tip {
                allowed.push("tip");
            }
            problems.push(Problem::file(format!(
                "{fname}: unknown joint '{key}'; use {}",
                allowed.join(", ")
            )));
        }
    }
    let mut chain = Vec::new();
    for j in order {
        match joints.get(j.name()) {
            Some(p) if p.iter().all(|v| v.is_finite()) => chain.push(RigJoint {
                joint: j,
                node: None,
                name: format!("{fname} {}", j.name()),
                position: DVec3::from_array(*p),
                weighted: None,
            }),
            Some(_) => problems.push(Problem::file(format!(
                "{fname} {}: not a finite point",
                j.name()
            ))),
            None => problems.push(Problem::file(format!(
                "{fname}: joint {} is missing",
                j.name()
            ))),
        }
    }
    FingerChain {
        side,
        finger,
        joints: chain,
        has_tip,
        metacarpal: None,
        wrist: None,
        hierarchy: true,
    }
}

/// Reads every `*.json` in `dir`, in file-name order; an absent directory is no rigs.
pub fn load_dir(dir: &Path) -> Result<Vec<ReferenceRig>, DataError> {
    let label = dir.display().to_string();
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => {
            return Err(DataError::whole_file(
                &label,
                format!("cannot be listed ({e})"),
            ));
        }
    };
    let mut paths: Vec<_> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| {
            let bytes = crate::dataset::csvinput::read_input(p)?;
            let id = p
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
            parse(&p.display().to_string(), &id, &bytes)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_committed_rigs_load_with_their_sources() {
        let rigs = load_dir(Path::new("data/rigs")).unwrap();
        assert!(rigs.len() >= 2);
        for r in &rigs {
            assert!(r.url.starts_with("https://"), "{}", r.id);
            assert!(!r.source.is_empty());
            assert_eq!(r.chains.len(), 5, "{}", r.id);
        }
    }

    #[test]
    fn bad_rigs_name_their_problems() {
        let e = parse("x.json", "x", br#"{"name":"a","source":"b","url":"c","side":"up","units":"m","fingers":{"toe":{},"index":{"MCP":[0,0,0],"PIP":[1,0,0]}}}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("side 'up'"), "{e}");
        assert!(e.contains("unknown finger 'toe'"), "{e}");
        assert!(e.contains("index: joint DIP is missing"), "{e}");
        let e = parse(
            "x.json",
            "x",
            br#"{"name":"a","source":"b","url":"https://e.org/\u0007","side":"left","units":"cm","fingers":{"little":{"MCP":[0,0,0],"PIP":[1,0,0],"DIP":[2,0,0]},"pinky":{"MCP":[0,0,0],"PIP":[1,0,0],"DIP":[2,0,0]}}}"#,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("is not a plain https:// address"), "{e}");
        assert!(e.contains("units 'cm' are not metres"), "{e}");
        assert!(e.contains("given twice"), "{e}");
        let e = parse("x.json", "x", b"{\n  \"name\": 3\n}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.json:2:"), "{e}");
    }
}

#[cfg(test)]
mod values {
    use super::*;
    use crate::analysis::{Quantity, Settings, analyse};
    use crate::dataset::Dataset;

    /// Relative values and ratios of the committed rigs, computed independently
    /// with NumPy from the same JSON files when they were written (data/rigs/README.md).
    #[test]
    fn committed_rigs_give_the_independently_computed_proportions() {
        let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
        let a = analyse(&d, &Settings::default());
        let rigs = load_dir(Path::new("data/rigs")).unwrap();
        let value = |id: &str, finger: Finger, q: Quantity| {
            let r = rigs.iter().find(|r| r.id == id).unwrap();
            let c = r.chains.iter().find(|c| c.finger == finger).unwrap();
            // The rig's own proportions: its tips compared as they are.
            let opts = crate::rig::judge::JudgeOptions::new(
                crate::rig::judge::data_tip_of(&a.tips),
                crate::rig::judge::SoftTissue::Unknown,
                &a,
            );
            let audit = crate::rig::judge::audit_with(&a, &c.input(), &opts).unwrap();
            audit
                .values
                .iter()
                .find(|v| v.quantity == q)
                .map(|v| v.measured)
        };
        let cases = [
            ("rigify-human", Finger::Index, Quantity::RelJ1, 0.468766),
            ("rigify-human", Finger::Index, Quantity::RatioJ2J1, 0.626630),
            ("rigify-human", Finger::Thumb, Quantity::RelJ1, 0.616671),
            ("rigify-human", Finger::Little, Quantity::RelJ3, 0.229325),
            (
                "godot-humanoid-profile",
                Finger::Middle,
                Quantity::RatioJ2J1,
                0.333333,
            ),
        ];
        for (id, f, q, want) in cases {
            let got = value(id, f, q).unwrap_or_else(|| panic!("{id} {f} {q:?}"));
            assert!((got - want).abs() < 1e-6, "{id} {f} {q:?}: {got} vs {want}");
        }
        // Godot has no tips: no relative values, and its thumb is not judged.
        assert_eq!(
            value("godot-humanoid-profile", Finger::Index, Quantity::RelJ1),
            None
        );
    }
}
