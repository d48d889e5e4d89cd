//! What `add`, `import` and `remove` say of a change to a dataset: the
//! warnings and notes on the new rows, and the counts of the summary line.

use crate::dataset::tip::TipKind;
use crate::format::count;

/// What an addition has to say, as the tracking returns it.
pub(crate) struct Added<'a> {
    /// The new rows' file (its label, `<command line>` for one row given as options).
    pub new_file: &'a str,
    /// Whether the new row was given as options.
    pub from_options: bool,
    /// The dataset added to.
    pub dataset: &'a str,
    /// Each row added though flagged: its line (when it has one) and why.
    pub accepted: &'a [(Option<u64>, String)],
    /// Each finger whose segments look swapped: the new rows' lines and the warning.
    pub swapped: &'a [(Vec<u64>, String)],
    /// The tip new rows giving none took from the dataset: kind, rows, first ids.
    pub taken_tip: Option<&'a (TipKind, usize, Vec<String>)>,
    /// Fingers whose new rows could not be checked fully, one sentence each.
    pub limits: &'a [String],
    /// Header columns the dataset gained.
    pub added_columns: &'a [&'static str],
}

/// The warnings and notes of an addition, one line each, for standard
/// error: `warning: ...`, `note: ...`, and the columns the header gained.
pub(crate) fn added_messages(added: &Added<'_>) -> Vec<String> {
    // Where a message about new rows points: `FILE:LINE,LINE` for rows of a
    // file the user wrote, the file alone for rows given as options or made
    // by the program.
    let file = added.new_file;
    let at = |lines: &[u64]| {
        if lines.is_empty() {
            file.to_string()
        } else {
            let lines: Vec<String> = lines.iter().map(u64::to_string).collect();
            format!("{file}:{}", lines.join(","))
        }
    };
    let mut out = Vec::new();
    for (line, reason) in added.accepted {
        let lines: Vec<u64> = line.iter().copied().collect();
        out.push(format!(
            "warning: {}: added though flagged (--accept-flagged): {reason}",
            at(&lines)
        ));
    }
    for (lines, w) in added.swapped {
        out.push(format!("warning: {}: {w}", at(lines)));
    }
    if let Some((kind, rows, ids)) = added.taken_tip {
        out.push(format!(
            "note: {}",
            taken_tip(
                (!added.from_options).then_some(file),
                added.dataset,
                *kind,
                *rows,
                ids
            )
        ));
    }
    for n in added.limits {
        out.push(format!("note: {n}"));
    }
    if !added.added_columns.is_empty() {
        out.push(format!(
            "note: the dataset's header gained the column{} {} (empty on its existing rows)",
            if added.added_columns.len() == 1 {
                ""
            } else {
                "s"
            },
            added.added_columns.join(", ")
        ));
    }
    out
}

/// What `add` says of new rows that gave no tip and took the one every row of the dataset
/// records: "50 rows of new.csv give no tip: recorded at the skin, as every row of
/// data/measurements.csv is; give --tip bone if these were measured to the bone (take them
/// out first: phalanx remove --xray n1,n2)". `new_file` is `None` for a row given as options.
fn taken_tip(
    new_file: Option<&str>,
    dataset: &str,
    kind: TipKind,
    n: usize,
    ids: &[String],
) -> String {
    let other = match kind {
        TipKind::Bone => TipKind::Skin,
        TipKind::Skin => TipKind::Bone,
    };
    // Ids a shell and the option parser take as they are.
    let plain = |x: &String| {
        x.starts_with(|c: char| c.is_ascii_alphanumeric())
            && x.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
    };
    let (subject, these, them) = match new_file {
        None => ("the new row gives".to_string(), "it was", "it"),
        Some(file) => (
            format!(
                "{} of {file} give{}",
                count(n, "row", "rows"),
                if n == 1 { "s" } else { "" }
            ),
            if n == 1 { "it was" } else { "these were" },
            if n == 1 { "it" } else { "them" },
        ),
    };
    let remove = if ids.len() <= 10 && ids.iter().all(plain) {
        format!("phalanx remove --xray {}", ids.join(","))
    } else {
        "phalanx remove --xray with their ids".to_string()
    };
    format!(
        "{subject} no tip: recorded at the {}, as every row of {dataset} is; give --tip {} if \
         {these} measured to the {} (take {them} out first: {remove})",
        kind.name(),
        other.name(),
        other.name()
    )
}

/// "1 row", "50 rows".
pub(crate) fn rows(n: usize) -> String {
    count(n, "row", "rows")
}

/// ", 1 of them recorded as flagged", or nothing.
pub(crate) fn flagged(n: usize) -> String {
    match n {
        0 => String::new(),
        1 => ", 1 of them recorded as flagged".to_string(),
        n => format!(", {n} of them recorded as flagged"),
    }
}
