//! What is wrong with a CSV file's first line or a record, said with its fix: a field count
//! that differs from the header's (a quote left open, a decimal comma, fields missing or
//! extra), a first line that is data or uses another separator, no header at all.

use super::columns::{Columns, Header, required_names};
use super::scan::Record;
use crate::dataset::Finger;
use crate::dataset::error::{Problem, quote};

/// The problem of a record whose field count differs from the header's: most
/// often a quote left open (the field then runs on over commas and line ends),
/// a number written with an unquoted decimal comma (`346,65`, read as two fields:
/// [`decimal_commas`]), else fields missing or extra.
pub(super) fn field_count_problem<C: Columns>(rec: &Record<'_>, header: &Header<C>) -> Problem {
    let width = header.names.len();
    let runaway = (0..rec.len()).any(|i| rec.get(i).is_some_and(|f| f.contains([',', '\n', '\r'])));
    let field = |i: usize| rec.get(i).unwrap_or("");
    let commas = decimal_commas(rec, header);
    let hint = if runaway {
        "a quoted field is not closed, so it runs on over commas or line ends; close the quote (\") or remove it".to_string()
    } else if !commas.is_empty() {
        let each: Vec<String> = commas
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                format!(
                    "{} {} looks like a number with a decimal comma",
                    header.names[i - k],
                    quote(&format!("{},{}", field(i), field(i + 1)))
                )
            })
            .collect();
        let fixed: Vec<String> = commas
            .iter()
            .map(|&i| format!("{}.{}", field(i), field(i + 1)))
            .collect();
        format!(
            "{}: unquoted, the comma splits it in two fields; write it with a point ({})",
            each.join(", "),
            fixed.join(", ")
        )
    } else if rec.len() > width {
        "remove the extra fields, or quote a value that contains a comma".to_string()
    } else {
        "add the missing fields (an empty value still needs its comma)".to_string()
    };
    Problem::line(
        rec.line,
        format!(
            "has {} fields but the header has {width}; {hint}",
            rec.len()
        ),
    )
}

/// Where a record with k more fields than the header holds k numbers written with an
/// unquoted decimal comma: the positions i of the fields (i, i + 1) that join into one
/// (a whole number, then digits only: `346` and `65` from `346,65`). Such a reading
/// counts only when it is the one way to join k pairs (none overlapping) so that every
/// joined number lands in a numeric column ([`Columns::numeric`]) and every numeric
/// column then holds a number or nothing; otherwise (several ways, or none) the record
/// is not said to hold a decimal comma. Empty for none. Cost: O(C(p, k)) for p
/// candidate pairs, at most 3 joins tried.
fn decimal_commas<C: Columns>(rec: &Record<'_>, header: &Header<C>) -> Vec<usize> {
    let width = header.names.len();
    let extra = rec.len().saturating_sub(width);
    if extra == 0 || extra > 3 {
        return Vec::new();
    }
    let field = |i: usize| rec.get(i).unwrap_or("");
    let digits = |f: &str| !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit());
    let whole = |f: &str| digits(f.strip_prefix('-').unwrap_or(f));
    let candidates: Vec<usize> = (0..rec.len().saturating_sub(1))
        .filter(|&i| whole(field(i)) && digits(field(i + 1)))
        .collect();
    let numeric: Vec<bool> = header
        .names
        .iter()
        .map(|n| C::ALL.iter().any(|c| c.name() == n && c.numeric()))
        .collect();
    // The record's fields with the pairs at `joins` (ascending) joined.
    let reads = |joins: &[usize]| -> bool {
        let mut out: Vec<String> = Vec::with_capacity(width);
        let mut i = 0;
        while i < rec.len() {
            if joins.contains(&i) {
                if !numeric.get(out.len()).copied().unwrap_or(false) {
                    return false;
                }
                out.push(format!("{}.{}", field(i), field(i + 1)));
                i += 2;
            } else {
                out.push(field(i).to_string());
                i += 1;
            }
        }
        out.len() == width
            && out
                .iter()
                .zip(&numeric)
                .all(|(v, &num)| !num || v.is_empty() || v.parse::<f64>().is_ok())
    };
    let mut found: Vec<Vec<usize>> = Vec::new();
    let mut pick: Vec<usize> = Vec::new();
    fn choose(
        candidates: &[usize],
        k: usize,
        pick: &mut Vec<usize>,
        found: &mut Vec<Vec<usize>>,
        reads: &dyn Fn(&[usize]) -> bool,
    ) {
        if found.len() > 1 {
            return;
        }
        if pick.len() == k {
            if reads(pick) {
                found.push(pick.clone());
            }
            return;
        }
        for (n, &c) in candidates.iter().enumerate() {
            if pick.last().is_some_and(|&p| c < p + 2) {
                continue;
            }
            pick.push(c);
            choose(&candidates[n + 1..], k, pick, found, reads);
            pick.pop();
        }
    }
    choose(&candidates, extra, &mut pick, &mut found, &reads);
    match found.as_slice() {
        [one] => one.clone(),
        _ => Vec::new(),
    }
}

/// What a first line that is not a header of `C` looks like, and what to do,
/// as one problem: a file of another separator (one field holding semicolons
/// or tabs: Excel's "CSV" in locales with a decimal comma, a TSV export), or
/// a file without a header line (no field names a column of `C`, and one
/// looks like data: a number, a finger, a side or a joint). `None` when the
/// line is a header with mistakes in it, which are reported column by column.
fn sniff<C: Columns>(record: &Record<'_>) -> Option<Problem> {
    let fields: Vec<&str> = (0..record.len())
        .map(|i| record.get(i).unwrap_or(""))
        .collect();
    let line = fields.join(",");
    let save = "save it as 'CSV UTF-8 (Comma delimited)'";
    if let [only] = fields.as_slice() {
        let semicolons = only.matches(';').count();
        let tabs = only.matches('\t').count();
        let message = if semicolons > 0 && semicolons >= tabs {
            format!(
                "the file looks semicolon-separated ({}), as Excel saves CSV in many locales; phalanx reads \
                 comma-separated files: {save}, or replace each ';' with ',' and any decimal comma with a point \
                 (339,96 -> 339.96)",
                quote(only)
            )
        } else if tabs > 0 {
            format!(
                "the file looks tab-separated ({}), as a TSV export or cells pasted from a spreadsheet; phalanx \
                 reads comma-separated files: {save}, or replace each tab with ','",
                quote(&only.replace('\t', "\\t"))
            )
        } else {
            return None;
        };
        return Some(Problem::line(record.line, message));
    }
    let names_a_column = fields
        .iter()
        .any(|f| C::ALL.iter().any(|c| c.name().eq_ignore_ascii_case(f)));
    let data_like = |f: &&str| {
        f.parse::<f64>().is_ok()
            || Finger::parse(f).is_some()
            || ["left", "right", "mcp", "pip", "dip", "ip", "tip"]
                .iter()
                .any(|v| v.eq_ignore_ascii_case(f))
    };
    if names_a_column || !fields.iter().any(data_like) {
        return None;
    }
    let optional: Vec<&str> = C::ALL
        .iter()
        .filter(|c| !c.required())
        .map(|c| c.name())
        .collect();
    let optional = if optional.is_empty() {
        String::new()
    } else {
        format!(" (and any of the optional columns {})", optional.join(","))
    };
    Some(Problem::line(
        record.line,
        format!(
            "the file has no header line: its first line, {}, is data; add the header line {}{optional} above it",
            quote(&line),
            required_names::<C>()
        ),
    ))
}

/// The problem of a file without a header record: empty (`content` false, only white
/// space), or the table's own message, or which columns to start it with.
pub(super) fn no_header_problem<C: Columns>(content: bool) -> Problem {
    Problem::file(match (content, C::NO_HEADER) {
        (false, _) => C::EMPTY.to_string(),
        (true, Some(message)) => message.to_string(),
        (true, None) => format!(
            "has no header line; start it with {}",
            required_names::<C>()
        ),
    })
}

/// The header of `record`; when it has problems and the record shows what kind of file
/// this is ([`sniff`]), one message saying so replaces one per header column.
pub(super) fn read_header<C: Columns>(
    record: &Record<'_>,
    problems: &mut Vec<Problem>,
) -> Header<C> {
    let before_header = problems.len();
    let header = Header::<C>::parse(record, problems);
    if problems.len() > before_header
        && let Some(shape) = sniff::<C>(record)
    {
        problems.truncate(before_header);
        problems.push(shape);
    }
    header
}

/// Byte-level problems (non-UTF-8, NUL) after the header know their column; names its field.
pub(super) fn name_fields<C: Columns>(problems: &mut [Problem], header: &Header<C>) {
    for p in problems {
        if let (None, Some(c), Some(l)) = (&p.field, p.column, p.line)
            && l > header.line
        {
            p.field = header.names.get(c - 1).filter(|n| !n.is_empty()).cloned();
        }
    }
}
