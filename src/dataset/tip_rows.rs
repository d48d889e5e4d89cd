//! The fingertips of a dataset's rows: the refusal to pool rows measured to the bone
//! with rows measured to the skin, and the tips `add` records for new rows.

use super::csvinput::quote;
use super::tip::{LineRuns, TipCounts, TipKind};
use super::{Dataset, Problem, Row};

/// Lines as people read them: "2-6, 9, 12-13", at most `max` runs, then "and N more".
fn line_runs(lines: &[u64], max: usize) -> String {
    LineRuns::of(lines.iter().copied(), max).describe()
}

/// The refusal to pool rows whose fingertips differ: `None` unless some rows of `files`
/// (each a file's name and its rows) record their tips at the bone and others at the skin.
/// Rows with no recorded tip pool with either. The message names the rows of each kind,
/// why pooling them is wrong, and the way out (`option`, e.g. `--mixed-tips`).
///
/// A last segment to the bone is shorter than one to the skin by the fingertip's soft
/// tissue (3.7 to 5.7 mm on average, Buryanov and Kotiuk 2010, about 4-8% of the finger),
/// so a pooled J~3 mixes two quantities and every relative value shifts with it.
pub fn pooling_problem(files: &[(&str, &[Row])], option: &str) -> Option<String> {
    let kind = |k: TipKind| -> Vec<String> {
        files
            .iter()
            .filter_map(|(name, rows)| {
                let lines: Vec<u64> = rows
                    .iter()
                    .filter(|r| r.meta.tip == Some(k))
                    .map(|r| r.line)
                    .collect();
                (!lines.is_empty()).then(|| {
                    let n = lines.len();
                    format!(
                        "{n} row{} of {name} (line{} {})",
                        if n == 1 { "" } else { "s" },
                        if n == 1 { "" } else { "s" },
                        line_runs(&lines, 6)
                    )
                })
            })
            .collect()
    };
    let (bone, skin) = (kind(TipKind::Bone), kind(TipKind::Skin));
    if bone.is_empty() || skin.is_empty() {
        return None;
    }
    Some(format!(
        "the rows measure the last segment to different fingertips: {} at the end of the bone, {} at the skin's outline. A last segment to the skin is longer by the fingertip's soft tissue (3.7 to 5.7 mm on average, Buryanov & Kotiuk 2010), so pooled statistics would mix two quantities. Keep them in separate files and compare them with 'phalanx compare', re-measure one group to the other's tip, or give {option} to pool them anyway",
        bone.join(" and "),
        skin.join(" and ")
    ))
}

/// The new rows of an `add` with a fingertip recorded where one could be given
/// ([`record_new`]).
#[derive(Debug, Clone)]
pub(crate) struct NewTips {
    /// The new rows, tips filled in.
    pub rows: Dataset,
    /// The tip that rows giving none took from the dataset, every row of which records
    /// it, and those rows (indices into `rows.rows`).
    pub from_dataset: Option<(TipKind, Vec<usize>)>,
    /// Rows that cannot be added as they are: a tip that contradicts `--tip`, rows with
    /// no tip and none to take. Each names its line (or X-ray) and the fix.
    pub problems: Vec<Problem>,
}

/// Records a fingertip for every new row `add` writes into `current`, in this order: a
/// row's own tip stays, and must agree with `given` (`--tip`, for every row); a row
/// without one takes `given`; else a row of an X-ray `current` already records a tip for
/// takes that one (one hand has one value, see [`super::append::with_defaults`]); else it
/// takes the tip every row of `current` records. When `current`'s tips are mixed or not
/// recorded, such a row has none to take and is refused, naming the fix (`--tip`); so is
/// a row of an X-ray whose rows in `current` record no tip (the fix: record it there).
///
/// `lines` says whether the rows' lines are the user's (a file): problems then name them;
/// otherwise (one row given as options, rows made by `import`) they name the X-rays.
/// O(rows of both).
pub(crate) fn record_new(
    current: &Dataset,
    new: &Dataset,
    given: Option<TipKind>,
    lines: bool,
) -> NewTips {
    let hands = hands_of(current, new);
    let tips = current.tips();
    let shared = tips.single();
    let column = new.columns.iter().position(|c| c == "tip").map(|i| i + 1);
    let mut rows = new.clone();
    let mut taken = Vec::new();
    let mut missing: Vec<&Row> = Vec::new();
    let mut untipped_hands: Vec<&Row> = Vec::new();
    let mut problems = Vec::new();
    for (i, (r, out)) in new.rows.iter().zip(&mut rows.rows).enumerate() {
        match (r.meta.tip, given) {
            (Some(own), Some(g)) if own != g => {
                let message = format!(
                    "is {}, but --tip {} records every row of {} at the {}; leave this field \
                     empty (the row then takes --tip {}), or give no --tip",
                    quote(own.name()),
                    g.name(),
                    new.path,
                    g.name(),
                    g.name()
                );
                problems.push(match (lines, column) {
                    (true, Some(c)) => Problem::field(r.line, c, "tip", message),
                    _ => Problem::file(format!("tip of X-ray {}: {message}", quote(&r.xray))),
                });
            }
            (Some(_), _) => {}
            (None, Some(g)) => out.meta.tip = Some(g),
            (None, None) => match (hands.get(&*r.xray), shared) {
                (Some((true, _)), _) => {}
                (Some((false, _)), _) => untipped_hands.push(r),
                (None, Some(k)) => {
                    out.meta.tip = Some(k);
                    taken.push(i);
                }
                (None, None) => missing.push(r),
            },
        }
    }
    if !untipped_hands.is_empty() {
        problems.push(untipped_problem(current, &untipped_hands, &hands));
    }
    if !missing.is_empty() {
        problems.push(missing_problem(current, &tips, &missing, lines, column));
    }
    NewTips {
        rows,
        from_dataset: shared.filter(|_| !taken.is_empty()).map(|k| (k, taken)),
        problems,
    }
}

/// The X-rays of `new`'s rows that `current` has: whether their rows there record a tip,
/// and their lines there.
type Hands<'a> = std::collections::HashMap<&'a str, (bool, Vec<u64>)>;

/// [`Hands`] of `new` in `current`. O(rows of both).
fn hands_of<'a>(current: &'a Dataset, new: &Dataset) -> Hands<'a> {
    let wanted: std::collections::HashSet<&str> = new.rows.iter().map(|r| &*r.xray).collect();
    let mut hands = Hands::new();
    for r in &current.rows {
        if wanted.contains(&*r.xray) {
            let h = hands.entry(&r.xray).or_default();
            h.0 |= r.meta.tip.is_some();
            h.1.push(r.line);
        }
    }
    hands
}

/// The refusal of new rows without a tip whose X-rays `current` has, recording none
/// there: their lines in `current` and the fix (record the tip there first).
fn untipped_problem(current: &Dataset, untipped: &[&Row], hands: &Hands<'_>) -> Problem {
    let ids = xray_ids(untipped);
    let mut old_lines: Vec<u64> = ids
        .iter()
        .filter_map(|x| hands.get(x))
        .flat_map(|h| h.1.iter().copied())
        .collect();
    old_lines.sort_unstable();
    let n = untipped.len();
    Problem::file(format!(
        "{} of {} give{} no tip, and {} rows in {} ({}) record none; one hand has one \
         tip, so record it in their tip column there first (bone or skin), and the new \
         rows take it; nothing was added",
        crate::format::count(n, "row", "rows"),
        xrays_named(&ids),
        if n == 1 { "s" } else { "" },
        if ids.len() == 1 {
            "the X-ray's"
        } else {
            "those X-rays'"
        },
        current.path,
        LineRuns::of(old_lines, 6).with_word()
    ))
}

/// The refusal of new rows without a tip when `current` (whose fingertips are `tips`)
/// has no one tip to take: the rows by line (`lines`) or X-ray, and the fix (`--tip`, or
/// the tip column, `column`, of the file).
fn missing_problem(
    current: &Dataset,
    tips: &TipCounts,
    missing: &[&Row],
    lines: bool,
    column: Option<usize>,
) -> Problem {
    let n = missing.len();
    let subject = if lines {
        format!(
            "{} ({})",
            crate::format::count(n, "row", "rows"),
            LineRuns::of(missing.iter().map(|r| r.line), 6).with_word()
        )
    } else {
        format!(
            "{} of {}",
            crate::format::count(n, "row", "rows"),
            xrays_named(&xray_ids(missing))
        )
    };
    let (verb, their) = if n == 1 {
        ("gives", "its fingertip was")
    } else {
        ("give", "their fingertips were")
    };
    let fill = match (lines, column) {
        (false, _) => String::new(),
        (true, Some(_)) => " (or fill in the tip column)".to_string(),
        (true, None) => " (or add a tip column)".to_string(),
    };
    Problem::file(format!(
        "{subject} {verb} no tip, and {} has no one tip for {} to take (its fingertips: {}). \
         Give --tip skin or --tip bone: where {their} measured{fill}; nothing was added",
        current.path,
        if n == 1 { "it" } else { "them" },
        tips.describe()
    ))
}

/// The distinct X-ray ids of rows, in order of first appearance.
fn xray_ids<'r>(rows: &[&'r Row]) -> Vec<&'r str> {
    let mut seen = std::collections::HashSet::new();
    rows.iter()
        .map(|r| &*r.xray)
        .filter(|x| seen.insert(*x))
        .collect()
}

/// "X-ray 'a'", "X-rays 'a', 'b'", the first 10 named, then "and 3 more".
fn xrays_named(ids: &[&str]) -> String {
    let shown: Vec<String> = ids.iter().take(10).map(|x| quote(x)).collect();
    format!(
        "X-ray{} {}{}",
        if ids.len() == 1 { "" } else { "s" },
        shown.join(", "),
        if ids.len() > shown.len() {
            format!(" and {} more", ids.len() - shown.len())
        } else {
            String::new()
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bone_with_skin_is_refused_naming_the_rows() {
        let skin = Dataset::from_bytes(
            "data.csv",
            b"xray,finger,j1,j2,j3,tip\na,index,4,2,2,skin\nb,index,4,2,2,skin\nc,index,4,2,2,\n",
        )
        .unwrap();
        let bone = Dataset::from_bytes(
            "new.csv",
            b"xray,finger,j1,j2,j3,tip\nd,index,4,2,2,bone\ne,index,4,2,2,bone\nf,index,4,2,2,bone\ng,index,4,2,2,skin\n",
        )
        .unwrap();
        let m = pooling_problem(
            &[("data.csv", &skin.rows), ("new.csv", &bone.rows)],
            "--mixed-tips",
        )
        .unwrap();
        assert!(
            m.contains("3 rows of new.csv (lines 2-4) at the end of the bone"),
            "{m}"
        );
        assert!(
            m.contains("2 rows of data.csv (lines 2-3) and 1 row of new.csv (line 5) at the skin"),
            "{m}"
        );
        assert!(m.contains("give --mixed-tips"), "{m}");
        // Unrecorded tips pool with either; one kind alone is fine.
        assert_eq!(
            pooling_problem(&[("data.csv", &skin.rows)], "--mixed-tips"),
            None
        );
        assert_eq!(line_runs(&[1, 2, 3, 5, 7, 8], 2), "1-3, 5 and 1 more");
    }

    fn ds(label: &str, text: &str) -> Dataset {
        Dataset::from_bytes(label, text.as_bytes()).unwrap()
    }

    #[test]
    fn new_rows_take_the_one_tip_of_the_dataset_or_are_refused() {
        let skin = ds(
            "d.csv",
            "xray,finger,j1,j2,j3,tip\na,index,4,2,2,skin\nb,index,4,2,2,skin\n",
        );
        let new = ds(
            "n.csv",
            "xray,finger,j1,j2,j3\nc,index,4,2,2\nc,ring,4,2,2\nd,index,4,2,2\n",
        );
        let t = record_new(&skin, &new, None, true);
        assert!(t.problems.is_empty(), "{:?}", t.problems);
        assert_eq!(t.from_dataset, Some((TipKind::Skin, vec![0, 1, 2])));
        assert!(
            t.rows
                .rows
                .iter()
                .all(|r| r.meta.tip == Some(TipKind::Skin))
        );
        // --tip sets the rows without one, and nothing is said to have been taken.
        let t = record_new(&skin, &new, Some(TipKind::Bone), true);
        assert_eq!(t.from_dataset, None);
        assert!(
            t.rows
                .rows
                .iter()
                .all(|r| r.meta.tip == Some(TipKind::Bone))
        );
        // Into a dataset without one tip: refused, naming the lines and the fix.
        let unknown = ds("d.csv", "xray,finger,j1,j2,j3\na,index,4,2,2\n");
        let t = record_new(&unknown, &new, None, true);
        assert_eq!(t.problems.len(), 1);
        assert_eq!(
            t.problems[0].message,
            "3 rows (lines 2-4) give no tip, and d.csv has no one tip for them to take (its \
             fingertips: not recorded). Give --tip skin or --tip bone: where their fingertips \
             were measured (or add a tip column); nothing was added"
        );
        // Rows of an X-ray whose rows record a tip take it later (one hand, one value).
        let mixed = ds(
            "d.csv",
            "xray,finger,j1,j2,j3,tip\nc,index,4,2,2,bone\nz,index,4,2,2,\n",
        );
        let t = record_new(
            &mixed,
            &ds(
                "n.csv",
                "xray,finger,j1,j2,j3\nc,ring,4,2,2\nd,ring,4,2,2\n",
            ),
            None,
            false,
        );
        assert_eq!(t.problems.len(), 1);
        assert!(
            t.problems[0].message.starts_with(
                "1 row of X-ray 'd' gives no tip, and d.csv has no one tip for it to take (its \
                 fingertips: mixed: 1 row at the bone, 1 row not recorded)"
            ),
            "{}",
            t.problems[0].message
        );
        // A row's own tip that contradicts --tip: at its field.
        let own = ds(
            "n.csv",
            "xray,finger,j1,j2,j3,tip\nc,index,4,2,2,\nd,index,4,2,2,skin\n",
        );
        let t = record_new(&skin, &own, Some(TipKind::Bone), true);
        assert_eq!(t.problems.len(), 1);
        let p = &t.problems[0];
        assert_eq!(
            (p.line, p.column, p.field.as_deref()),
            (Some(3), Some(6), Some("tip"))
        );
        assert!(
            p.message
                .starts_with("is 'skin', but --tip bone records every row of n.csv at the bone"),
            "{}",
            p.message
        );
    }
}
