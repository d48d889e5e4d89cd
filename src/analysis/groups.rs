//! Statistics by group of hands: by sex, age band or side (the paper's future work).
//!
//! Groups whose value is known come first, in their natural order (sexes and sides
//! alphabetically, age bands youngest first), the "unknown" group last. Each known group
//! after the first is compared with the first as `phalanx compare` compares two cohorts
//! ([`super::compare::cohorts`]: the difference of means with its Welch and bootstrap
//! intervals, Hedges' g). A group of fewer than [`SMALL_GROUP`] X-rays carries a
//! small-sample note.

use super::compare::{self, Cohorts};
use super::{Analysis, Settings, analyse};
use crate::dataset::{Dataset, Meta};
use schemars::JsonSchema;
use serde::Serialize;

/// What to group X-rays by.
#[derive(Debug, Clone, PartialEq)]
pub enum GroupBy {
    Sex,
    Side,
    /// Age bands from these ascending edges: [e0, e1), [e1, e2), ..., [e_last, inf).
    Age(Vec<f64>),
}

/// Default age bands: children, young adults, adults, older adults.
pub const DEFAULT_AGE_BINS: [f64; 4] = [0.0, 18.0, 40.0, 65.0];

impl GroupBy {
    /// The metadata column grouped on.
    pub fn name(&self) -> &'static str {
        match self {
            GroupBy::Sex => "sex",
            GroupBy::Side => "side",
            GroupBy::Age(_) => "age",
        }
    }

    /// The group label of a hand's metadata; "unknown" when the value is missing.
    fn label(&self, meta: &Meta) -> String {
        let unknown = || UNKNOWN.to_string();
        match self {
            GroupBy::Sex => meta.sex.as_deref().map_or_else(unknown, str::to_string),
            GroupBy::Side => meta.side.as_deref().map_or_else(unknown, str::to_string),
            GroupBy::Age(edges) => meta.age.map_or_else(unknown, |a| age_band(a, edges)),
        }
    }

    /// Where a hand's group goes in the order: known groups first (age bands by their
    /// lower edge, other values alphabetically), "unknown" last.
    fn order(&self, meta: &Meta) -> (bool, usize, String) {
        let label = self.label(meta);
        match self {
            GroupBy::Age(edges) => match meta.age {
                None => (true, 0, label),
                Some(a) => (
                    false,
                    edges.iter().rposition(|&e| a >= e).map_or(0, |i| i + 1),
                    label,
                ),
            },
            _ => (label == UNKNOWN, 0, label),
        }
    }
}

/// The label of the group of hands without a value.
pub const UNKNOWN: &str = "unknown";

/// The band of an age: "18-40" for [18, 40), "65+" for the last, "under 0" below the first.
fn age_band(age: f64, edges: &[f64]) -> String {
    let fmt = crate::format::exact;
    match edges.iter().rposition(|&e| age >= e) {
        None => format!(
            "under {}",
            edges.first().map_or_else(String::new, |&e| fmt(e))
        ),
        Some(i) if i + 1 == edges.len() => format!("{}+", fmt(edges[i])),
        Some(i) => format!("{}-{}", fmt(edges[i]), fmt(edges[i + 1])),
    }
}

/// Checks age band edges: at least one, finite, strictly increasing.
pub fn validate_age_bins(edges: &[f64]) -> Result<(), String> {
    if edges.is_empty() {
        return Err("--age-bins needs at least one edge, e.g. 0,18,40,65".into());
    }
    if edges.iter().any(|e| !e.is_finite()) || edges.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!(
            "--age-bins must be finite and strictly increasing, e.g. 0,18,40,65 (got {edges:?})"
        ));
    }
    Ok(())
}

/// Why grouping by `by` would say nothing, if it would: no row has a value in
/// that column, so every X-ray would fall in one "unknown" group, a copy of the
/// whole analysis.
pub(crate) fn nothing_to_group(data: &Dataset, by: &GroupBy) -> Option<String> {
    data.hands()
        .values()
        .all(|m| by.label(m) == UNKNOWN)
        .then(|| {
            format!(
                "--group-by {0}: no row of {1} gives a value in the {0} column, so there is nothing to group by; fill the {0} column to get statistics per group",
                by.name(),
                data.path
            )
        })
}

/// The statistics of one group.
#[derive(Debug, Clone)]
pub struct Group {
    /// The column grouped on (`sex`, `age`, `side`).
    pub by: &'static str,
    pub label: String,
    pub xrays: usize,
    pub analysis: Analysis,
    /// Set for groups too small for intervals, or small enough to read them with care.
    pub note: Option<String>,
}

/// Fewest X-rays a group needs for spreads and intervals.
pub const MIN_GROUP: usize = 2;

/// Below this many X-rays a group's intervals carry a small-sample note: at n = 3 and 4
/// the bootstrap percentile and BCa intervals of a 95% level cover the mean only 72-80% of
/// the time (`phalanx coverage`), and the t and prediction intervals, though they keep
/// their level, are several times wider than at n = 10.
pub const SMALL_GROUP: usize = 5;

/// One known group compared with the first known group (the reference).
#[derive(Debug, Clone)]
pub struct GroupDifference {
    /// The reference group (A) and the group compared with it (B); differences are B - A.
    pub a: String,
    pub b: String,
    pub cohorts: Cohorts,
}

/// The groups of a dataset and the differences between its known groups.
#[derive(Debug, Clone)]
pub struct Groups {
    pub by: &'static str,
    /// Known groups first, "unknown" last (see the module's doc).
    pub groups: Vec<Group>,
    /// Each known group after the first against the first; empty with fewer than two
    /// known groups.
    pub differences: Vec<GroupDifference>,
}

/// The seed of group `i`'s own bootstrap: `seed + 0x9E3779B97F4A7C15 * (i + 1)` (wrapping),
/// so groups do not share random streams.
fn group_seed(seed: u64, i: usize) -> u64 {
    seed.wrapping_add(0x9E37_79B9_7F4A_7C15u64.wrapping_mul(i as u64 + 1))
}

/// Splits the X-rays into groups by their hand's value (rows of one X-ray may leave it
/// empty: [`Dataset::hand`]), known groups first, and analyses each with its own seed
/// ([`group_seed`]). Groups with fewer than [`MIN_GROUP`] X-rays are kept, with a note;
/// those under [`SMALL_GROUP`] get a small-sample note. Then each known group after the
/// first is compared with the first ([`compare::cohorts`], seeded with the later group's
/// seed). Cost: one analysis per group and one comparison per known group after the first.
pub fn analyse_groups(data: &Dataset, by: &GroupBy, settings: &Settings) -> Groups {
    let hands = data.hands();
    let mut keys: Vec<((bool, usize, String), Dataset)> = Vec::new();
    for row in &data.rows {
        let key = by.order(&hands[&*row.xray]);
        let i = match keys.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                keys.push((
                    key,
                    Dataset {
                        path: data.path.clone(),
                        sha256: data.sha256.clone(),
                        columns: data.columns.clone(),
                        rows: Vec::new(),
                    },
                ));
                keys.len() - 1
            }
        };
        keys[i].1.rows.push(row.clone());
    }
    keys.sort_by(|(x, _), (y, _)| x.cmp(y));
    let groups: Vec<Group> = keys
        .iter()
        .enumerate()
        .map(|(i, ((_, _, label), subset))| {
            let seed = group_seed(settings.seed, i);
            let analysis = analyse(subset, &Settings { seed, ..*settings });
            let xrays = subset.xray_count();
            let note = if xrays < MIN_GROUP {
                Some(format!(
                    "only {xrays} X-ray: no spread or interval can be estimated; add X-rays of this group"
                ))
            } else if xrays < SMALL_GROUP {
                Some(format!(
                    "only {xrays} X-rays, fewer than {SMALL_GROUP}: at this size the bootstrap (percentile and BCa) intervals cover the mean far less often than their level says, and the t and prediction intervals, though honest, are wide; read this group as a first look"
                ))
            } else {
                None
            };
            Group {
                by: by.name(),
                label: label.clone(),
                xrays,
                analysis,
                note,
            }
        })
        .collect();
    let known: Vec<usize> = (0..groups.len())
        .filter(|&i| groups[i].label != UNKNOWN)
        .collect();
    let differences = match known.split_first() {
        Some((&first, rest)) => rest
            .iter()
            .map(|&i| {
                let seed = group_seed(settings.seed, i);
                GroupDifference {
                    a: groups[first].label.clone(),
                    b: groups[i].label.clone(),
                    cohorts: compare::cohorts(
                        &keys[first].1,
                        &keys[i].1,
                        &Settings { seed, ..*settings },
                    ),
                }
            })
            .collect(),
        None => Vec::new(),
    };
    Groups {
        by: by.name(),
        groups,
        differences,
    }
}

/// One group as it appears in JSON.
#[derive(Serialize, JsonSchema)]
pub(crate) struct GroupSummary<'a> {
    pub group: &'a str,
    pub xrays: usize,
    pub seed: u64,
    pub note: Option<&'a str>,
    pub fingers: &'a [super::FingerAnalysis],
}

impl Group {
    /// The JSON view of this group.
    pub(crate) fn summary(&self) -> GroupSummary<'_> {
        GroupSummary {
            group: &self.label,
            xrays: self.xrays,
            seed: self.analysis.settings.seed,
            note: self.note.as_deref(),
            fingers: &self.analysis.fingers,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data() -> Dataset {
        let text = "xray,finger,j1,j2,j3,sex,age,side\n\
                    a,index,4,3,3,f,30,left\na,thumb,4,3,,f,30,left\n\
                    b,index,5,3,3,m,70,right\n\
                    c,index,6,3,3,f,17,right\n\
                    d,index,6,3.5,3,,,\n";
        Dataset::from_bytes("g.csv", text.as_bytes()).unwrap()
    }

    #[test]
    fn groups_have_the_right_sizes_known_first() {
        let g = analyse_groups(&data(), &GroupBy::Sex, &Settings::default());
        let sizes: Vec<(&str, usize)> = g
            .groups
            .iter()
            .map(|g| (g.label.as_str(), g.xrays))
            .collect();
        assert_eq!(sizes, vec![("female", 2), ("male", 1), ("unknown", 1)]);
        // Two X-rays (under SMALL_GROUP) get the small-sample note, one the no-spread note.
        assert!(
            g.groups[0]
                .note
                .as_deref()
                .unwrap()
                .contains("only 2 X-rays, fewer than 5"),
            "{:?}",
            g.groups[0].note
        );
        assert!(
            g.groups[1]
                .note
                .as_deref()
                .unwrap()
                .contains("only 1 X-ray:")
        );
        // The female group: index n = 2 (a, c), thumb n = 1 (a).
        let f = &g.groups[0].analysis;
        assert_eq!(f.finger(crate::dataset::Finger::Index).unwrap().n, 2);
        assert_eq!(f.finger(crate::dataset::Finger::Thumb).unwrap().n, 1);
        assert_ne!(
            g.groups[0].analysis.settings.seed,
            g.groups[1].analysis.settings.seed
        );
        // "unknown" is listed first in the file (d has no sex) but goes last anyway.
        let d = Dataset::from_bytes(
            "u.csv",
            b"xray,finger,j1,j2,j3,sex\nd,index,6,3.5,3,\na,index,4,3,3,m\nb,index,5,3,3,f\n",
        )
        .unwrap();
        let g = analyse_groups(&d, &GroupBy::Sex, &Settings::default());
        let labels: Vec<&str> = g.groups.iter().map(|g| g.label.as_str()).collect();
        assert_eq!(labels, vec!["female", "male", "unknown"]);
    }

    #[test]
    fn an_x_ray_with_its_sex_on_one_row_only_is_of_that_sex() {
        // a's thumb row leaves sex empty; its index row says f.
        let d = Dataset::from_bytes(
            "h.csv",
            b"xray,finger,j1,j2,j3,sex\na,thumb,4,3,,\na,index,4,3,3,f\nb,index,5,3,3,m\n",
        )
        .unwrap();
        let g = analyse_groups(&d, &GroupBy::Sex, &Settings::default());
        let labels: Vec<(&str, usize)> = g
            .groups
            .iter()
            .map(|g| (g.label.as_str(), g.analysis.dataset.rows))
            .collect();
        assert_eq!(labels, vec![("female", 2), ("male", 1)]);
    }

    #[test]
    fn the_difference_of_two_groups_is_compare_s() {
        // Six hands per sex; the males' J~1 is larger.
        let mut text = String::from("xray,finger,j1,j2,j3,sex\n");
        for (i, (j1, j2, j3)) in [
            (40.0, 25.0, 20.0),
            (41.0, 24.0, 20.5),
            (39.5, 25.5, 19.5),
            (40.5, 24.5, 21.0),
            (42.0, 25.0, 20.0),
            (39.0, 26.0, 20.5),
        ]
        .into_iter()
        .enumerate()
        {
            text.push_str(&format!("f{i},index,{j1},{j2},{j3},f\n"));
            text.push_str(&format!("m{i},index,{},{j2},{j3},m\n", j1 + 6.0));
        }
        let d = Dataset::from_bytes("s.csv", text.as_bytes()).unwrap();
        let s = Settings {
            resamples: 500,
            ..Settings::default()
        };
        let g = analyse_groups(&d, &GroupBy::Sex, &s);
        assert_eq!(g.differences.len(), 1);
        let diff = &g.differences[0];
        assert_eq!((diff.a.as_str(), diff.b.as_str()), ("female", "male"));
        // The same numbers as comparing the two groups' rows as cohorts (the later
        // group's seed).
        let female = Dataset {
            rows: d
                .rows
                .iter()
                .filter(|r| r.xray.starts_with('f'))
                .cloned()
                .collect(),
            ..d.clone()
        };
        let male = Dataset {
            rows: d
                .rows
                .iter()
                .filter(|r| r.xray.starts_with('m'))
                .cloned()
                .collect(),
            ..d.clone()
        };
        let seed = group_seed(s.seed, 1);
        let direct = compare::cohorts(&female, &male, &Settings { seed, ..s });
        assert_eq!(diff.cohorts, direct);
        let j1 = diff.cohorts.fingers[0]
            .quantity(crate::dataset::Quantity::RelJ1)
            .unwrap();
        assert!(j1.difference > 0.0, "{}", j1.difference);
        let w = j1.welch.unwrap().interval;
        assert!(w.low > 0.0, "{w:?}");
        assert!(j1.hedges_g.unwrap().g > 1.0);
        // No difference without two known groups.
        let one = analyse_groups(&female, &GroupBy::Sex, &s);
        assert!(one.differences.is_empty());
    }

    #[test]
    fn no_values_no_groups() {
        let d = Dataset::from_bytes(
            "n.csv",
            b"xray,finger,j1,j2,j3,sex
a,index,4,3,3,
b,index,5,3,3,
",
        )
        .unwrap();
        let note = nothing_to_group(&d, &GroupBy::Sex).unwrap();
        assert!(
            note.contains("no row of n.csv gives a value in the sex column"),
            "{note}"
        );
        assert!(nothing_to_group(&data(), &GroupBy::Sex).is_none());
        assert!(nothing_to_group(&d, &GroupBy::Age(DEFAULT_AGE_BINS.to_vec())).is_some());
    }

    #[test]
    fn age_bands() {
        let g = analyse_groups(
            &data(),
            &GroupBy::Age(DEFAULT_AGE_BINS.to_vec()),
            &Settings::default(),
        );
        let labels: Vec<&str> = g.groups.iter().map(|g| g.label.as_str()).collect();
        // Youngest band first, "unknown" last (the file lists 18-40 first).
        assert_eq!(labels, vec!["0-18", "18-40", "65+", "unknown"]);
        assert_eq!(age_band(-1.0, &[0.0, 10.0]), "under 0");
        assert_eq!(age_band(10.0, &[0.0, 10.0]), "10+");
        assert!(validate_age_bins(&[0.0, 18.0, 18.0]).is_err());
        assert!(validate_age_bins(&[]).is_err());
        let sides = analyse_groups(&data(), &GroupBy::Side, &Settings::default());
        assert_eq!(
            sides
                .groups
                .iter()
                .map(|g| (g.label.as_str(), g.xrays))
                .collect::<Vec<_>>(),
            vec![("left", 1), ("right", 2), ("unknown", 1)]
        );
    }
}
