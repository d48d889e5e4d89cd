//! The table of contents: the sections present, numbered in order without gaps.
//!
//! The atlas and the published measurements are there only when their files are;
//! every section after them takes the next number, so the numbers run 1, 2, 3, ...

use super::common::md_anchor;
use serde::Serialize;
use std::collections::BTreeMap;

/// One section: its HTML id, number, title and Markdown anchor.
#[derive(Debug, Clone, Serialize)]
pub struct TocEntry {
    pub id: String,
    pub number: String,
    pub title: String,
    /// The anchor GitHub gives the Markdown heading "N. title".
    pub anchor: String,
}

/// The sections in order, and each by its id (for the templates and cross-references).
#[derive(Debug, Clone, Serialize)]
pub struct Toc {
    pub entries: Vec<TocEntry>,
    pub by_id: BTreeMap<String, TocEntry>,
}

impl Toc {
    /// Numbers the sections given as (id, title), the absent ones (`None`) left out.
    pub(crate) fn new(sections: &[(&str, Option<String>)]) -> Toc {
        let entries: Vec<TocEntry> = sections
            .iter()
            .filter_map(|(id, title)| title.as_ref().map(|t| (*id, t)))
            .enumerate()
            .map(|(i, (id, title))| {
                let number = (i + 1).to_string();
                TocEntry {
                    id: id.to_string(),
                    anchor: md_anchor(&format!("{number}. {title}")),
                    number,
                    title: title.clone(),
                }
            })
            .collect();
        let by_id = entries.iter().map(|e| (e.id.clone(), e.clone())).collect();
        Toc { entries, by_id }
    }

    /// "section N" for the section `id`, or "below" when it is absent.
    pub(crate) fn section(&self, id: &str) -> String {
        self.by_id
            .get(id)
            .map_or_else(|| "below".to_string(), |e| format!("section {}", e.number))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_run_without_gaps() {
        let toc = Toc::new(&[
            ("a", Some("A".into())),
            ("b", None),
            ("c", Some("C: the end".into())),
        ]);
        let numbers: Vec<&str> = toc.entries.iter().map(|e| e.number.as_str()).collect();
        assert_eq!(numbers, ["1", "2"]);
        assert_eq!(toc.by_id["c"].anchor, "2-c-the-end");
        assert_eq!(toc.section("c"), "section 2");
        assert_eq!(toc.section("b"), "below");
    }
}
