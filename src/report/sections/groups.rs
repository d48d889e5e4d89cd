//! Section 4 by group (`--group-by`): each group's statistics and each group against the first.

use super::statistics::StatsFinger;
use super::statistics::stats;
use crate::analysis::groups::{GroupDifference, Groups};
use crate::format::{level, xrays};
use serde::Serialize;

/// Statistics per group of X-rays.
#[derive(Debug, Clone, Serialize)]
pub struct GroupsView {
    /// The column grouped on.
    pub by: String,
    /// Known groups first, "unknown" last.
    pub groups: Vec<GroupView>,
    /// Each known group after the first against the first.
    pub differences: Vec<GroupDifferenceView>,
    /// The confidence level, e.g. "95%".
    pub confidence: String,
}

/// One known group against the reference group, as `compare` puts two cohorts.
#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceView {
    /// "male against female".
    pub title: String,
    pub id: String,
    pub a: String,
    pub b: String,
    pub fingers: Vec<GroupDifferenceFinger>,
    pub notes: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceFinger {
    pub finger: String,
    /// What differs, as `compare` says it.
    pub sentence: String,
    pub counts: String,
    pub rows: Vec<GroupDifferenceRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupDifferenceRow {
    pub quantity: String,
    pub a: String,
    pub b: String,
    pub difference: String,
    pub welch: String,
    pub bootstrap: String,
    pub hedges: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct GroupView {
    pub label: String,
    pub id: String,
    pub xrays: String,
    pub note: Option<String>,
    pub stats: Vec<StatsFinger>,
}

pub(crate) fn groups_view(groups: Option<&Groups>, confidence: f64) -> Option<GroupsView> {
    let all = groups?;
    Some(GroupsView {
        by: all.by.to_string(),
        confidence: level(confidence),
        differences: all
            .differences
            .iter()
            .enumerate()
            .map(|(i, d)| group_difference(d, i))
            .collect(),
        groups: all
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| GroupView {
                label: g.label.clone(),
                id: format!("group-{}", i + 1),
                xrays: g.xrays.to_string(),
                note: g.note.clone(),
                stats: g
                    .analysis
                    .fingers
                    .iter()
                    .map(|f| {
                        let mut v = stats(f);
                        v.id = format!("group-{}-{}", i + 1, v.id);
                        v
                    })
                    .collect(),
            })
            .collect(),
    })
}

/// The view of one group difference: per finger `compare`'s sentence and its table.
fn group_difference(d: &GroupDifference, i: usize) -> GroupDifferenceView {
    use crate::report::compare as cmp;
    use crate::report::compare_words::Names;
    let c = &d.cohorts;
    let names = Names { a: &d.a, b: &d.b };
    GroupDifferenceView {
        title: format!("{} against {}", d.b, d.a),
        id: format!("group-difference-{}", i + 1),
        a: d.a.clone(),
        b: d.b.clone(),
        fingers: c
            .fingers
            .iter()
            .map(|f| GroupDifferenceFinger {
                finger: f.finger.name().to_string(),
                sentence: cmp::finger_sentence(f, names, c.settings.confidence),
                counts: format!("{}: {}, {}: {}", d.a, xrays(f.n_a), d.b, xrays(f.n_b)),
                rows: f
                    .quantities
                    .iter()
                    .map(|q| {
                        let (k, x) = (q.quantity, &q.comparison);
                        GroupDifferenceRow {
                            quantity: k.label().to_string(),
                            a: cmp::mean_sd(x.a.mean, x.a.sd, k),
                            b: cmp::mean_sd(x.b.mean, x.b.sd, k),
                            difference: cmp::difference_cell(x, k),
                            welch: cmp::welch_cell(x, k),
                            bootstrap: cmp::bootstrap_cell(x, k),
                            hedges: cmp::hedges_cell(x),
                        }
                    })
                    .collect(),
            })
            .collect(),
        notes: c.notes.clone(),
    }
}
