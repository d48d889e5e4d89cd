//! Section 5, reproducing the paper: the claim-by-claim check and the misprints.

use crate::analysis::claims::{CheckSummary, ClaimResult, Verdict};
use crate::format::num;
use serde::Serialize;

/// The claim-by-claim check.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimsView {
    pub file: String,
    /// Why the claims were not checked, when they were not.
    pub note: Option<String>,
    pub summary: String,
    pub rows: Vec<ClaimRow>,
    /// Claims that disagree, with their causes.
    pub misprints: Vec<ClaimRow>,
    /// The same claims grouped by their root cause: one slip and every number it carries into.
    pub misprint_groups: Vec<MisprintGroup>,
}

/// One root cause of misprints and the claims it explains, in the claims' order.
#[derive(Debug, Clone, Serialize)]
pub struct MisprintGroup {
    /// The cause, in the words of the claim that explains it best.
    pub cause: String,
    pub claims: Vec<ClaimRow>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ClaimRow {
    pub id: String,
    /// HTML id of the claim's table row (`claim-` and the id, other characters as `-`).
    pub anchor: String,
    pub location: String,
    pub refers_to: String,
    pub stated: String,
    pub computed: String,
    pub verdict: String,
    /// CSS class: `match`, `rounded`, `erratum`, `mismatch`.
    pub class: String,
    pub cause: String,
    pub erratum_note: String,
}

pub(crate) fn claims(file: &str, results: &[ClaimResult], note: Option<&str>) -> ClaimsView {
    let rows: Vec<ClaimRow> = results
        .iter()
        .map(|r| {
            let computed = match (r.verdict, r.computed_rounded) {
                (Verdict::MatchesRounded, Some(x)) => format!(
                    "{} (from rounded values: {})",
                    num(r.computed, r.decimals + 2),
                    num(x, r.decimals)
                ),
                // Counts (printed without decimals) stay whole numbers.
                _ if r.decimals == 0 && r.computed.fract() == 0.0 => num(r.computed, 0),
                _ => num(r.computed, r.decimals + 2),
            };
            ClaimRow {
                id: r.id.clone(),
                anchor: claim_anchor(&r.id),
                location: r.location.clone(),
                // The paper's "grooming" finger is named once, in the key results.
                refers_to: plain_index(&r.refers_to),
                stated: r.stated_text.clone(),
                computed,
                verdict: r.verdict.label().to_string(),
                class: match r.verdict {
                    Verdict::Matches => "match",
                    Verdict::MatchesRounded => "rounded",
                    Verdict::KnownErratum => "erratum",
                    Verdict::Mismatch => "mismatch",
                }
                .to_string(),
                cause: r.cause.clone().unwrap_or_default(),
                erratum_note: plain_index(r.erratum_note.as_deref().unwrap_or_default()),
            }
        })
        .collect();
    let s = CheckSummary::of(results);
    ClaimsView {
        file: file.to_string(),
        note: note.map(str::to_string),
        summary: format!(
            "{} claims: {} match, {} match from rounded values (as the paper computes), {} known errata, {} new mismatches.",
            s.claims, s.matches, s.matches_rounded, s.known_errata, s.mismatches
        ),
        misprints: rows
            .iter()
            .filter(|r| !r.cause.is_empty())
            .cloned()
            .collect(),
        misprint_groups: misprint_groups(&rows),
        rows,
    }
}

/// The disagreeing claims grouped by root cause. A claim "carried over from claim 'X'"
/// joins X's group; claims whose causes name the same decimal numbers (the same slipped
/// digit, told from either side) share a group. Each group is told by its longest cause
/// that is not a carry-over.
pub(crate) fn misprint_groups(rows: &[ClaimRow]) -> Vec<MisprintGroup> {
    let misprints: Vec<&ClaimRow> = rows.iter().filter(|r| !r.cause.is_empty()).collect();
    let root = |r: &ClaimRow| -> String {
        let mut cause = r.cause.clone();
        // A chain of carry-overs is short; the bound keeps a cycle finite.
        for _ in 0..misprints.len() {
            let Some(m) = carried_from(&cause).and_then(|f| misprints.iter().find(|m| m.id == f))
            else {
                break;
            };
            cause = m.cause.clone();
        }
        cause
    };
    let mut groups: Vec<(Vec<String>, MisprintGroup)> = Vec::new();
    for r in &misprints {
        let key = decimals_named(&root(r));
        let at = groups
            .iter()
            .position(|(k, _)| !key.is_empty() && *k == key);
        match at {
            Some(i) => groups[i].1.claims.push((*r).clone()),
            None => groups.push((
                key,
                MisprintGroup {
                    cause: String::new(),
                    claims: vec![(*r).clone()],
                },
            )),
        }
    }
    groups
        .into_iter()
        .map(|(_, mut g)| {
            g.cause = g
                .claims
                .iter()
                .filter(|c| carried_from(&c.cause).is_none())
                .map(|c| c.cause.as_str())
                .max_by_key(|c| c.len())
                .unwrap_or(&g.claims[0].cause)
                .to_string();
            g
        })
        .collect()
}

/// The claim a cause says it was carried over from: "carried over from claim 'X': ...".
fn carried_from(cause: &str) -> Option<&str> {
    let rest = cause.split("carried over from claim '").nth(1)?;
    rest.split('\'').next()
}

/// The numbers with a decimal point a cause names, sorted and without repeats.
fn decimals_named(cause: &str) -> Vec<String> {
    let mut v: Vec<String> = cause
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .map(|w| w.trim_matches('.'))
        .filter(|w| w.contains('.') && w.chars().any(|c| c.is_ascii_digit()))
        .map(str::to_string)
        .collect();
    v.sort();
    v.dedup();
    v
}

/// The claims file's words with the paper's "grooming" finger called the index (the key
/// results name the paper's term once).
fn plain_index(text: &str) -> String {
    text.replace("grooming-finger", "index-finger")
        .replace("grooming finger", "index finger")
}

/// The HTML id of a claim's table row: `claim-` and its id, characters other
/// than ASCII letters, digits, `-` and `_` written as `-`.
fn claim_anchor(id: &str) -> String {
    let slug: String = id
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    format!("claim-{slug}")
}
