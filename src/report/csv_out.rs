//! CSV output of the statistics: one row per finger and quantity, every number
//! to 15 significant digits ([`crate::format::readable`]).

use crate::analysis::Analysis;
use crate::analysis::groups::Groups;
use crate::error::Error;
use crate::format::{interval_bounds, readable};

/// Header of the statistics CSV.
pub(crate) const STATS_COLUMNS: [&str; 22] = [
    "finger",
    "quantity",
    "n",
    "mean",
    "sd",
    "se",
    "median",
    "min",
    "max",
    "range",
    "cv",
    "ci_t_low",
    "ci_t_high",
    "ci_percentile_low",
    "ci_percentile_high",
    "ci_bca_low",
    "ci_bca_high",
    "pi_low",
    "pi_high",
    "bootstrap",
    "confidence",
    "notes",
];

/// Neutralises a text cell against spreadsheet formula injection: a cell that
/// starts with `=`, `+`, `-`, `@`, tab or carriage return gets a leading `'`.
pub(crate) fn safe_cell(text: &str) -> String {
    if text.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{text}")
    } else {
        text.to_string()
    }
}

/// `audit --moves`: one row per moved node ([`crate::rig::fix::moves::HEADER`]),
/// nine decimals (a nanometre in metres). Node names are written exactly as
/// the file has them (no spreadsheet guard): scripts look the nodes up by them.
pub(crate) fn moves(moves: &[crate::rig::fix::moves::Move]) -> Result<Vec<u8>, Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e| Error::render("cannot write CSV", e);
    w.write_record(crate::rig::fix::moves::HEADER)
        .map_err(err)?;
    for m in moves {
        let mut row = vec![m.name.clone()];
        for v in [m.old_world, m.new_world, m.new_local] {
            row.extend(v.to_array().map(|x| crate::format::num(x, 9)));
        }
        w.write_record(&row).map_err(err)?;
    }
    w.into_inner()
        .map_err(|e| Error::render("cannot write CSV", e.to_string()))
}

/// `audit --moves`' second file: one row per influence of each vertex whose
/// skin weights the fix changed ([`crate::rig::fix::moves::WEIGHTS_HEADER`]),
/// weights to nine decimals, names as the file has them.
pub(crate) fn weight_changes(
    changes: &[crate::rig::fix::moves::WeightChange],
) -> Result<Vec<u8>, Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e| Error::render("cannot write CSV", e);
    w.write_record(crate::rig::fix::moves::WEIGHTS_HEADER)
        .map_err(err)?;
    for c in changes {
        for (node, weight) in &c.influences {
            w.write_record([
                c.mesh.clone(),
                c.primitive.to_string(),
                c.vertex.to_string(),
                node.clone(),
                crate::format::num(*weight, 9),
            ])
            .map_err(err)?;
        }
    }
    w.into_inner()
        .map_err(|e| Error::render("cannot write CSV", e.to_string()))
}

/// The statistics as CSV bytes; empty cells where a value is null. With groups
/// (`--group-by`), two leading columns `group_by` and `group` name each row's
/// group (`all` for the whole dataset).
pub(crate) fn stats(a: &Analysis, groups: Option<&Groups>) -> Result<Vec<u8>, Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e| Error::render("cannot write CSV", e);
    let by = groups.map(|g| g.by);
    let groups = groups.map_or(&[][..], |g| &g.groups);
    let mut header: Vec<&str> = Vec::new();
    if by.is_some() {
        header.extend(["group_by", "group"]);
    }
    header.extend(STATS_COLUMNS);
    w.write_record(&header).map_err(err)?;
    let mut sets: Vec<(&str, &Analysis)> = vec![("all", a)];
    sets.extend(groups.iter().map(|g| (g.label.as_str(), &g.analysis)));
    for (label, a) in sets {
        let lead: Vec<String> = match by {
            Some(b) => vec![b.to_string(), safe_cell(label)],
            None => Vec::new(),
        };
        write_analysis(&mut w, a, &lead)?;
    }
    w.into_inner()
        .map_err(|e| Error::render("cannot write CSV", e.to_string()))
}

fn write_analysis(
    w: &mut csv::Writer<Vec<u8>>,
    a: &Analysis,
    lead: &[String],
) -> Result<(), Error> {
    let err = |e| Error::render("cannot write CSV", e);
    for fa in &a.fingers {
        let method = crate::format::plan_kind(fa.bootstrap);
        for q in &fa.quantities {
            let mut rec = lead.to_vec();
            rec.extend([
                fa.finger.name().to_string(),
                q.name.name().to_string(),
                q.n.to_string(),
                readable(Some(q.mean)),
                readable(q.sd),
                readable(q.se),
                readable(Some(q.median)),
                readable(Some(q.min)),
                readable(Some(q.max)),
                readable(Some(q.range)),
                readable(q.cv),
            ]);
            rec.extend(interval_bounds(&q.intervals));
            rec.push(method.to_string());
            rec.push(readable(Some(a.settings.confidence)));
            rec.push(safe_cell(&q.notes.join("; ")));
            w.write_record(&rec).map_err(err)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formulas_are_neutralised() {
        assert_eq!(safe_cell("=HYPERLINK(\"x\")"), "'=HYPERLINK(\"x\")");
        assert_eq!(safe_cell("@SUM(A1)"), "'@SUM(A1)");
        assert_eq!(safe_cell("plain"), "plain");
    }
}
