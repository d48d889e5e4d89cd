//! The "Key results" box at the top of the report: joints as shares of the finger,
//! the misprints, which interval to use, where the fingertips are.

use super::claims::ClaimsView;
use super::common::DataName;
use super::inputs::{LiteratureInputs, ReportInputs};
use super::literature::table_name;
use crate::analysis::claims::CheckSummary;
use crate::format::{decimals, level, percent};
use crate::report::phrases::{counted, interval_advice_of};
use serde::Serialize;

/// One misprint as the key results list it.
fn key_misprint(m: &super::claims::ClaimRow) -> KeyMisprint {
    KeyMisprint {
        id: m.id.clone(),
        anchor: m.anchor.clone(),
        text: format!(
            "{}: stated {}, recomputed {}",
            m.location, m.stated, m.computed
        ),
    }
}

/// The "Key results" box at the top of the report.
#[derive(Debug, Clone, Serialize)]
pub struct KeyResults {
    /// What the X-rays count: "16 X-rays; 15 for the thumb, index, middle and little".
    pub xrays: String,
    /// Set when rows flagged as likely errors are in the data: which, and where listed.
    pub flagged: Option<String>,
    /// The confidence level, e.g. "95%".
    pub confidence: String,
    /// Each finger's inner joints as shares of the finger's length.
    pub placements: Vec<KeyPlacement>,
    pub misprints: KeyMisprints,
    /// Which interval to use, from the coverage simulation.
    pub intervals: String,
    /// Where the paper's fingertips are, from a published table (when one was compared).
    pub fingertips: Option<String>,
    /// "Where the paper's fingertips are" (or "the X-rays'").
    pub fingertips_heading: String,
}

/// One finger's joints as shares of its length, root joint (MCP) to tip.
#[derive(Debug, Clone, Serialize)]
pub struct KeyPlacement {
    pub finger: String,
    /// "PIP at 48.5% (44.5% to 52.5%); DIP at ...": the mean and the prediction interval.
    pub joints: String,
}

/// The claims that disagree with the data.
#[derive(Debug, Clone, Serialize)]
pub struct KeyMisprints {
    /// "8 of the paper's 30 numbers disagree with its Table 1 (8 recorded errata, 0 new)."
    pub summary: String,
    pub items: Vec<KeyMisprint>,
    /// The same misprints grouped by their root cause.
    pub groups: Vec<KeyMisprintGroup>,
}

/// One root cause and the misprints it explains.
#[derive(Debug, Clone, Serialize)]
pub struct KeyMisprintGroup {
    pub cause: String,
    pub items: Vec<KeyMisprint>,
}

/// One disagreeing claim, linked to its row of the claims table.
#[derive(Debug, Clone, Serialize)]
pub struct KeyMisprint {
    pub id: String,
    /// The claims table row's HTML id.
    pub anchor: String,
    /// "Sec. 2, eq. (6): stated 0.4946, recomputed 0.484636".
    pub text: String,
}

/// The "Key results" box: joints as shares of the finger, the misprints, which interval to use.
pub(crate) fn key_results(inputs: &ReportInputs<'_>, claims: &ClaimsView) -> KeyResults {
    let a = inputs.analysis;
    let c = level(a.settings.confidence);
    let placements = inputs
        .placements
        .iter()
        .map(|p| {
            let share = |x: f64| percent(x / p.length);
            let joints: Vec<String> = p
                .joints
                .iter()
                .map(|j| {
                    let pi = j.position.intervals.pi.map_or_else(
                        || "no prediction interval with one X-ray".to_string(),
                        |i| format!("{} to {}", share(i.low), share(i.high)),
                    );
                    format!("{} at {} ({pi})", j.joint.name(), share(j.position.mean))
                })
                .collect();
            KeyPlacement {
                finger: p.finger.display_name().to_string(),
                joints: joints.join("; "),
            }
        })
        .collect();
    let s = CheckSummary::of(inputs.claims);
    let misprints = KeyMisprints {
        summary: if let Some(note) = &claims.note {
            note.clone()
        } else if claims.misprints.is_empty() {
            format!(
                "All {} numbers the paper states agree with its Table 1.",
                s.claims
            )
        } else {
            format!(
                "{} of the paper's {} stated numbers disagree with its Table 1 ({} recorded errata, {} new); the causes are in section 5.",
                claims.misprints.len(),
                s.claims,
                s.known_errata,
                s.mismatches
            )
        },
        items: claims.misprints.iter().map(key_misprint).collect(),
        groups: claims
            .misprint_groups
            .iter()
            .map(|g| KeyMisprintGroup {
                cause: g.cause.clone(),
                items: g.claims.iter().map(key_misprint).collect(),
            })
            .collect(),
    };
    let flagged = match a.flagged.as_slice() {
        [] => None,
        rows => {
            let list: Vec<String> = rows
                .iter()
                .map(|f| format!("{} {}", f.xray, f.finger.name()))
                .collect();
            Some(format!(
                "{} of the data {} added though flagged as a likely measurement or typing error: {}. The numbers below include {}; check {} (section 4 lists why each was flagged, and how to take it out).",
                if rows.len() == 1 {
                    "1 row".to_string()
                } else {
                    format!("{} rows", rows.len())
                },
                if rows.len() == 1 { "was" } else { "were" },
                list.join(", "),
                if rows.len() == 1 { "it" } else { "them" },
                if rows.len() == 1 { "it" } else { "them" },
            ))
        }
    };
    KeyResults {
        xrays: counted(a),
        flagged,
        confidence: c,
        placements,
        misprints,
        intervals: interval_advice_of(inputs.coverage, Some(a)).unwrap_or_else(|| {
            "The coverage of the intervals could not be simulated at this data's size.".to_string()
        }),
        fingertips: inputs
            .literature
            .and_then(|l| key_fingertips(l, DataName::of(inputs.paper_xrays))),
        fingertips_heading: format!(
            "Where {} fingertips are",
            DataName::of(inputs.paper_xrays).of
        ),
    }
}

/// The key result on the fingertips: where the paper's are taken, and what the test does
/// and does not show, in one paragraph.
fn key_fingertips(l: &LiteratureInputs, data: DataName) -> Option<String> {
    let v = l.paper.tips.as_ref()?;
    let name = table_name(&l.paper.b);
    let ranges = |pick: fn(&crate::analysis::literature::TipFinding) -> f64| {
        let xs: Vec<f64> = v.fingers.iter().map(pick).collect();
        let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (slo, shi) = ranges(|t| t.soft_share);
    let nearest = v.nearest_to_rejection().map_or(String::new(), |(t, i)| {
        format!(
            "; the {}'s interval ends at {}",
            t.finger.name(),
            crate::format::signed(i.high, decimals(true))
        )
    });
    Some(match v.overall {
        Some(crate::analysis::literature::Fit::Skin) => format!(
            "{} fingertips are taken at the skin, not at the end of the bone. Against {name}, a Welch test of each finger's last segment rejects bone alone on all {} fingers at every assumed correlation from 0 to 0.9, and does not reject bone plus the fingertip's soft tissue (not rejected is not shown equal{nearest}). {} The soft tissue is {} to {} of a finger measured to the skin, so a rig's tip at the skin compares with {} as it is, and a tip at the bone needs that share added.",
            capital(data.of),
            v.fingers.len(),
            if data.paper {
                "The paper does not say where its tips are; its rows record the skin because of this test."
            } else {
                "The data's tip column says where each row's tip is; the paper's rows record the skin because of this test."
            },
            percent(slo),
            percent(shi),
            data.the,
        ),
        Some(crate::analysis::literature::Fit::Bone) => format!(
            "{} fingertips are taken at the end of the bone: against {name}, its last segment rejects bone plus soft tissue on all {} fingers and does not reject bone alone (not rejected is not shown equal).",
            capital(data.of),
            v.fingers.len()
        ),
        _ => format!(
            "Where {} fingertips are is not settled by {name}: the fingers do not reject one tip and leave the other at every assumed correlation from 0 to 0.9.",
            data.of
        ),
    })
}

/// "The paper's" from "the paper's".
fn capital(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or(String::new(), |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}
