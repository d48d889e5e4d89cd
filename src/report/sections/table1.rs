//! Section 2, Table 1 of the paper: one row per X-ray, J1..J3 per finger.

use super::common::{MAX_LISTED_XRAYS, is_paper, truncation};
use crate::analysis::Analysis;
use crate::dataset::Finger;
use crate::format::num;
use serde::Serialize;

/// Table 1 of the paper: one row per X-ray, J1..J3 per finger.
#[derive(Debug, Clone, Serialize)]
pub struct Table1View {
    /// Column groups: finger display names with their segment headers.
    pub groups: Vec<Table1Group>,
    pub rows: Vec<Table1Row>,
    /// Set when only the first [`MAX_LISTED_XRAYS`] X-rays are listed.
    pub truncated: Option<String>,
    pub unit: String,
    /// True when the rows give different units: each row then names its own.
    pub units: bool,
    /// "Table 1: the measurements" over the paper's X-rays, "The measurements" otherwise.
    pub heading: String,
    /// Where the lengths come from, ending the section's first sentence.
    pub source: String,
    /// The Markdown anchor of the heading.
    pub anchor: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct Table1Group {
    pub finger: String,
    pub segments: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Table1Row {
    pub xray: String,
    /// The row's unit, when the dataset mixes units (else empty: the unit is `Table1View::unit`).
    pub unit: String,
    /// Every length, group by group; "-" where the X-ray lacks that finger.
    pub cells: Vec<String>,
}

/// The report's finger order, thumb first as in every other table (the paper's Table 1
/// prints the thumb last).
const TABLE1_ORDER: [Finger; 5] = [
    Finger::Thumb,
    Finger::Index,
    Finger::Middle,
    Finger::Ring,
    Finger::Little,
];

pub(crate) fn table1(a: &Analysis, paper_xrays: (usize, usize)) -> Table1View {
    let (named, xrays) = paper_xrays;
    let (heading, source) = if is_paper(paper_xrays) {
        (
            "Table 1: the measurements".to_string(),
            "as printed in the paper's Table 1".to_string(),
        )
    } else if named == 0 {
        (
            "The measurements".to_string(),
            format!("as in the dataset ({xrays} X-rays, none of them the paper's)"),
        )
    } else {
        (
            "The measurements".to_string(),
            format!(
                "as in the dataset: the {named} X-rays of the paper's Table 1 and {} added since",
                xrays - named
            ),
        )
    };
    let fingers: Vec<_> = TABLE1_ORDER.iter().filter_map(|&f| a.finger(f)).collect();
    let groups = fingers
        .iter()
        .map(|f| Table1Group {
            finger: f.finger.name().to_string(),
            segments: (1..=f.finger.segments()).map(|k| format!("J{k}")).collect(),
        })
        .collect();
    // X-rays in order of first appearance across the fingers.
    let mut ids: Vec<&str> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for f in &fingers {
        for x in &f.xrays {
            if seen.insert(&*x.xray) {
                ids.push(&x.xray);
            }
        }
    }
    let lookup: Vec<std::collections::HashMap<&str, &[f64]>> = fingers
        .iter()
        .map(|f| {
            f.xrays
                .iter()
                .map(|x| (&*x.xray, x.lengths.as_slice()))
                .collect()
        })
        .collect();
    let units: std::collections::HashMap<&str, &str> = fingers
        .iter()
        .flat_map(|f| f.xrays.iter())
        .filter_map(|x| Some((&*x.xray, x.unit.as_deref()?)))
        .collect();
    let mixed = a.mixed_units();
    let rows = ids
        .iter()
        .take(MAX_LISTED_XRAYS)
        .map(|id| Table1Row {
            xray: id.to_string(),
            unit: if mixed {
                units.get(id).map_or("none named", |u| u).to_string()
            } else {
                String::new()
            },
            cells: fingers
                .iter()
                .zip(&lookup)
                .flat_map(|(f, map)| match map.get(id) {
                    Some(ls) => ls.iter().map(|l| num(*l, 2)).collect::<Vec<_>>(),
                    None => vec!["-".to_string(); f.finger.segments()],
                })
                .collect(),
        })
        .collect();
    Table1View {
        groups,
        rows,
        truncated: truncation(ids.len()),
        unit: match (&a.unit, mixed) {
            (_, true) => "the unit each row names (its column 'unit')".to_string(),
            (Some(u), _) if u == "image units" => {
                "image units (pixels of the X-ray images, not millimetres)".to_string()
            }
            (Some(u), _) => u.clone(),
            (None, _) => "the dataset's unit (its rows name none)".to_string(),
        },
        units: mixed,
        anchor: format!(
            "2-{}",
            heading
                .to_ascii_lowercase()
                .replace(':', "")
                .replace(' ', "-")
        ),
        heading,
        source,
    }
}
