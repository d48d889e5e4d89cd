//! JSON Schemas of the documents phalanx writes, generated from the Rust types
//! that write them (schemars reads the same `#[serde]` attributes serde does).
//!
//! [`DOCUMENTS`] is the one list: `phalanx schema --out docs/schema` writes
//! `<name>.schema.json` for each entry, CI fails when the committed files
//! differ, and the integration tests validate real output against them. A new
//! JSON document is one line there: derive `JsonSchema` next to `Serialize` on
//! its type (and on the types it holds) and add `("name", of::<Type>)`.

use super::json;
use super::writer::OutputFile;
use crate::dataset::history::Snapshot;
use crate::error::Error;
use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema};

/// A document's schema generator.
pub(crate) type Generator = fn() -> Schema;

/// Every JSON document phalanx writes: its name (the schema file is
/// `<name>.schema.json`) and the schema of the type that writes it.
pub(crate) const DOCUMENTS: &[(&str, Generator)] = &[
    ("stats", of::<json::StatsDocument<'static>>),
    ("check", of::<json::CheckDocument<'static>>),
    ("coverage", of::<json::CoverageDocument<'static>>),
    (
        "coverage-population",
        of::<json::PopulationDocument<'static>>,
    ),
    ("compare", of::<json::CompareDocument<'static>>),
    ("place", of::<json::PlacementDocument<'static>>),
    ("audit", of::<json::AuditDocument<'static>>),
    ("deform", of::<super::deform::DeformDocument<'static>>),
    ("rig", of::<super::rig::RigDocument>),
    ("history", of::<json::HistoryDocument<'static>>),
    ("history-record", of::<Snapshot>),
];

/// The JSON Schema (draft 2020-12) of what serialising a `T` writes: a field
/// serde may skip is optional, every other field required.
pub(crate) fn of<T: JsonSchema>() -> Schema {
    SchemaSettings::draft2020_12()
        .for_serialize()
        .into_generator()
        .into_root_schema_for::<T>()
}

/// The schema files, `<name>.schema.json` for each of [`DOCUMENTS`]: pretty
/// JSON ending in a newline.
pub(crate) fn files() -> Result<Vec<OutputFile>, Error> {
    DOCUMENTS
        .iter()
        .map(|(name, schema)| {
            let mut bytes = serde_json::to_vec_pretty(&schema())
                .map_err(|e| Error::render("cannot serialise a JSON Schema", e))?;
            bytes.push(b'\n');
            Ok(OutputFile::new(format!("{name}.schema.json"), bytes))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{Value, json};

    #[test]
    fn names_are_unique_file_names() {
        let mut names: Vec<&str> = DOCUMENTS.iter().map(|(n, _)| *n).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), DOCUMENTS.len());
        assert!(
            names
                .iter()
                .all(|n| n.chars().all(|c| c.is_ascii_lowercase() || c == '-'))
        );
    }

    /// An interval is a two-number array; the flattened intervals are four
    /// required keys at the level of the struct that holds them.
    #[test]
    fn intervals_flatten_into_required_pairs() {
        let s = serde_json::to_value(of::<crate::dataset::history::QuantityRecord>()).unwrap();
        let interval = &s["$defs"]["Interval"];
        assert_eq!(interval["type"], "array");
        assert_eq!(interval["minItems"], 2);
        assert_eq!(interval["maxItems"], 2);
        let required = s["required"].as_array().unwrap();
        for key in ["ci_t", "ci_percentile", "ci_bca", "pi", "finger", "mean"] {
            assert!(required.contains(&json!(key)), "{key} not required: {s}");
        }
        let ci_t = &s["properties"]["ci_t"];
        assert!(
            ci_t.to_string().contains("#/$defs/Interval") && ci_t.to_string().contains("null"),
            "ci_t should be an Interval or null: {ci_t}"
        );
    }

    /// A rig position (glam's DVec3) is an array of three numbers.
    #[test]
    fn positions_are_three_numbers() {
        let s = serde_json::to_value(of::<crate::rig::RigJoint>()).unwrap();
        let p = &s["properties"]["position"];
        assert_eq!(p["type"], "array");
        assert_eq!(p["minItems"], 3);
        assert_eq!(p["maxItems"], 3);
        assert_eq!(p["items"]["type"], "number");
    }

    #[test]
    fn schema_version_is_pinned_in_every_document() {
        for (name, schema) in DOCUMENTS {
            let s: Value = serde_json::to_value(schema()).unwrap();
            if *name == "history-record" {
                continue;
            }
            assert_eq!(
                s["properties"]["schema_version"]["const"],
                json::SCHEMA_VERSION,
                "{name}"
            );
        }
    }
}
