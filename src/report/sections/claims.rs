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
                refers_to: r.refers_to.clone(),
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
                erratum_note: r.erratum_note.clone().unwrap_or_default(),
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
        rows,
    }
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
