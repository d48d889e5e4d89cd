//! What is known about a cohort beyond its rows: who the hands are and how they were
//! measured, from a `key,value` file beside the data (`X.cohort.csv` for `X.csv`).
//!
//! Keys: `name`, `citation`, `age`, `sex`, `side`, `tip` (`bone` or `skin`), `landmarks`
//! and `sample`; every key is optional and appears at most once. A measurement file's own
//! columns (`side`, `tip`, `age`) say what its rows record; these notes fill in what rows
//! cannot say (an atlas's age range, the landmark type, a table's sample).

use super::csvinput::{self, Columns, quote};
use super::{DataError, TipKind};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The description of a cohort; `None` where the notes say nothing.
#[derive(Debug, Clone, Default, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CohortNotes {
    /// A short name for sentences ("the Digital Hand Atlas").
    pub name: Option<String>,
    pub citation: Option<String>,
    /// Who the hands are by age ("adults aged 19 to 78").
    pub age: Option<String>,
    pub sex: Option<String>,
    /// `left`, `right` or a description.
    pub side: Option<String>,
    /// Where the last segment ends.
    pub tip: Option<TipKind>,
    /// Where the lengths were measured from and to ("joint centres", "bone ends").
    pub landmarks: Option<String>,
    /// How many hands, how imaged, in which unit.
    pub sample: Option<String>,
}

/// The notes file beside `path`: `X.cohort.csv` for `X.csv` (or for `X`).
pub fn notes_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    let name = format!("{}.cohort.csv", stem.unwrap_or_default());
    path.with_file_name(name)
}

impl CohortNotes {
    /// The notes beside `path`, if that file exists; its problems are reported with their
    /// lines and columns.
    pub fn beside(path: &Path) -> Result<Option<CohortNotes>, DataError> {
        let notes = notes_path(path);
        if !notes.is_file() {
            return Ok(None);
        }
        let bytes = csvinput::read_input(&notes)?;
        CohortNotes::from_bytes(&notes.display().to_string(), &bytes).map(Some)
    }

    /// Validates a notes file's bytes; `label` names it in errors.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<CohortNotes, DataError> {
        let mut notes = CohortNotes::default();
        let mut seen: Vec<(String, u64)> = Vec::new();
        csvinput::read_table(label, bytes, |cells| {
            let (Some(key), Some(value)) =
                (cells.text(NoteColumn::Key), cells.text(NoteColumn::Value))
            else {
                return;
            };
            let key = key.to_ascii_lowercase();
            if let Some((_, first)) = seen.iter().find(|(k, _)| *k == key) {
                cells.bad(
                    NoteColumn::Key,
                    format!(
                        "{} is already given on line {first}; keep one of them",
                        quote(&key)
                    ),
                );
                return;
            }
            seen.push((key.clone(), cells.line()));
            if value.is_empty() {
                return;
            }
            let text = Some(value.to_string());
            match key.as_str() {
                "name" => notes.name = text,
                "citation" => notes.citation = text,
                "age" => notes.age = text,
                "sex" => notes.sex = text,
                "side" => notes.side = text,
                "landmarks" => notes.landmarks = text,
                "sample" => notes.sample = text,
                "tip" => match TipKind::parse(value) {
                    Some(t) => notes.tip = Some(t),
                    None => cells.bad(
                        NoteColumn::Value,
                        format!("{} is not a fingertip kind; use bone or skin", quote(value)),
                    ),
                },
                _ => cells.bad(
                    NoteColumn::Key,
                    format!(
                        "unknown key {}; use name, citation, age, sex, side, tip, landmarks or sample",
                        quote(&key)
                    ),
                ),
            }
        })?;
        Ok(notes)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NoteColumn {
    Key,
    Value,
}

impl Columns for NoteColumn {
    const ALL: &'static [NoteColumn] = &[NoteColumn::Key, NoteColumn::Value];
    const EMPTY: &'static str = "is empty; a cohort description needs the header key,value";
    const NO_ROWS: Option<&'static str> = None;

    fn name(self) -> &'static str {
        match self {
            NoteColumn::Key => "key",
            NoteColumn::Value => "value",
        }
    }

    fn required(self) -> bool {
        true
    }

    fn index(self) -> usize {
        self as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_notes_read() {
        for (data, tip) in [
            ("data/measurements.csv", TipKind::Skin),
            ("data/atlas/measurements.csv", TipKind::Bone),
            ("data/literature/buryanov-kotiuk-2010.csv", TipKind::Bone),
        ] {
            if data.starts_with("data/atlas/") && !Path::new(data).is_file() {
                crate::dataset::vendored::skip(format!("{data} is absent"));
                continue;
            }
            let n = CohortNotes::beside(Path::new(data)).unwrap().unwrap();
            assert_eq!(n.tip, Some(tip), "{data}");
            assert!(n.name.is_some() && n.age.is_some() && n.landmarks.is_some());
        }
        assert_eq!(
            notes_path(Path::new("a/b.csv")),
            PathBuf::from("a/b.cohort.csv")
        );
        // One statement of the atlas's landmark type: its notes say what the report's
        // other sections say (crate::dataset::landmarks::ATLAS_LANDMARKS).
        let atlas = CohortNotes::beside(Path::new(crate::dataset::vendored::ATLAS)).unwrap();
        let Some(atlas) = atlas else {
            crate::dataset::vendored::skip("data/atlas/measurements.cohort.csv is absent");
            return;
        };
        let said = crate::dataset::landmarks::ATLAS_LANDMARKS
            .replace(" and at the tips", ", and the tips");
        assert_eq!(
            atlas.landmarks.as_deref().map(|l| format!("landmarks {l}")),
            Some(said)
        );
    }

    #[test]
    fn bad_notes_name_their_lines() {
        let e =
            CohortNotes::from_bytes("n.csv", b"key,value\nage,1\nage,2\ncolour,red\ntip,nail\n")
                .unwrap_err();
        let places: Vec<_> = e.problems.iter().map(|p| (p.line, p.column)).collect();
        assert_eq!(
            places,
            [(Some(3), Some(1)), (Some(4), Some(1)), (Some(5), Some(2))],
            "{e}"
        );
    }
}
