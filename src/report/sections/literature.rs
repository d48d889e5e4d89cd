//! The paper (or a lab's X-rays) against published measurements: where its fingertips are,
//! and every quantity beside the published table.

use super::common::DataName;
use super::inputs::LiteratureInputs;
use super::toc::Toc;
use crate::format::{level, percent, xrays};
use serde::Serialize;

/// The section "The paper against published measurements".
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureView {
    pub title: String,
    /// The Markdown anchor of the section's heading.
    pub anchor: String,
    /// The published table: its citation and sample.
    pub source: String,
    /// One line per cohort on why it differs from the paper.
    pub cohorts: Vec<String>,
    /// Where the fingertips are: the table of the issue, with intervals.
    pub tips: Vec<LiteratureTipRow>,
    pub tip_finding: String,
    /// One sentence per finger: the evidence.
    pub tip_evidence: Vec<String>,
    /// What it changes for a rig audit.
    pub audit: String,
    /// The correlation assumed between the table's segments, and the verdicts at 0 and 0.9.
    pub correlation: String,
    /// The paper beside the table to the skin, the atlas beside it to the bone.
    pub side: Vec<LiteratureSideRow>,
    pub side_intro: String,
    /// One sentence per finger of the paper against the table.
    pub sentences: Vec<String>,
    pub notes: Vec<String>,
}

/// One finger's last segment: the paper's, the table's bone only and bone plus soft tissue.
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureTipRow {
    pub finger: String,
    pub paper: String,
    pub bone: String,
    pub skin: String,
    /// "bone plus soft tissue (tip at the skin)".
    pub fits: String,
    /// The fit at each correlation: "0: skin; 0.85: skin; 0.9: skin".
    pub sweep: String,
}

/// One finger and quantity: the paper and the table to the skin, the atlas and the table
/// to the bone, with the verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct LiteratureSideRow {
    pub finger: String,
    pub quantity: String,
    pub paper: String,
    pub table_skin: String,
    /// The verdict at 0, the assumed correlation and 0.9.
    pub paper_verdict: String,
    pub atlas: String,
    pub table_bone: String,
    pub atlas_verdict: String,
}

/// The section's title: "The paper against published measurements", or "The X-rays
/// against ..." over other data.
pub(crate) fn literature_title(data: DataName) -> String {
    format!("{} against published measurements", data.title)
}

/// The section "The paper (or the X-rays) against published measurements".
pub(crate) fn literature_view(l: &LiteratureInputs, data: DataName, toc: &Toc) -> LiteratureView {
    use crate::report::compare_table::{correlation_line, table_finger_sentence};
    use crate::report::compare_words::Names;
    let p = &l.paper;
    let name = table_name(&p.b);
    let names = Names {
        a: data.the,
        b: &name,
    };
    let about = p.b.about.clone().unwrap_or_default();
    let source = format!(
        "{}: {}. What was measured: {}.",
        about.citation.clone().unwrap_or_else(|| p.b.path.clone()),
        about
            .sample
            .clone()
            .unwrap_or_else(|| "sample not described".to_string()),
        about
            .landmarks
            .clone()
            .unwrap_or_else(|| "not described".to_string()),
    );
    let cohorts = cohort_lines(l, &name, data);
    let conf = level(p.confidence);
    let (tips, tip_finding, tip_evidence) = tip_parts(p, names, data, &conf);
    let soft: Vec<String> = p
        .tips
        .iter()
        .flat_map(|v| &v.fingers)
        .map(|t| format!("{} {}", t.finger.name(), percent(t.soft_share)))
        .collect();
    let audit = format!(
        "What it changes for a rig audit: {} last segment is taken to end at the skin, so a rig's last segment is compared with it as it is when the rig's tips are at the skin (the end of the finger's mesh), and no soft tissue is to be trimmed off. A rig whose tips sit at the end of the bone needs the fingertip's soft tissue added before it is compared: {name} measures it at {} of a finger measured to the skin, a share that scales with the rig's finger in any unit. A fixed offset in millimetres does not: a rig in the wrong unit would lose most of a segment to it. The audits of {} follow this: they read each dataset's tips from its tip column, compare skin tips with skin tips as they are, and where one side's tips are at the bone (the atlas's, for the MCP judged from its CMC or the wrist) correct the last segment by that finger's share.",
        data.of,
        soft.join(", "),
        toc.section("rigs")
    );
    let side = side_rows(l);
    let tip_word = match p.b.table_tip {
        Some(crate::dataset::TipKind::Skin) => {
            format!(
                "to the skin (its soft tissue added), as {} rows record skin tips",
                data.of
            )
        }
        _ => "to the end of the bone".to_string(),
    };
    let data_xrays = if data.paper {
        "the paper's X-rays"
    } else {
        "the X-rays"
    };
    let side_intro = format!(
        "Each cohort beside {name} measured to the same fingertip: {data_xrays} (mean and {conf} t interval) against {name}'s ratios of means {tip_word}; the atlas (bone tips) against {name} to the bone. A verdict says whether the {conf} interval of the difference excludes 0 (differs) or holds it (not rejected: no difference shown, which is not equality shown), the same at correlations 0, the assumed one and 0.9 unless each is named."
    );
    LiteratureView {
        title: literature_title(data),
        anchor: toc
            .by_id
            .get("literature")
            .map_or_else(String::new, |e| e.anchor.clone()),
        source,
        cohorts,
        tips,
        tip_finding,
        tip_evidence,
        audit,
        correlation: correlation_line(&p.correlation),
        side,
        side_intro,
        sentences: p
            .fingers
            .iter()
            .map(|f| data.possessive_in(table_finger_sentence(f, names)))
            .collect(),
        notes: p.notes.clone(),
    }
}

/// How the published table and the atlas differ from the data, one line each.
fn cohort_lines(l: &LiteratureInputs, name: &str, data: DataName) -> Vec<String> {
    use crate::report::compare_table::{Profile, differs_in};
    let p = &l.paper;
    let paper_profile = Profile::of_side(&p.a);
    let table_profile = Profile::of_side(&crate::analysis::literature::SideInfo {
        table_tip: None,
        ..p.b.clone()
    });
    let mut cohorts = vec![format!(
        "{name} differs from {} in {}.",
        data.the,
        differs_in(&paper_profile, &table_profile)
    )];
    if let Some(info) = &l.atlas_info {
        cohorts.push(format!(
            "{} differs from {} in {}.",
            info.about
                .as_ref()
                .and_then(|a| a.name.clone())
                .map(|n| {
                    let mut c = n.chars();
                    c.next().map_or(String::new(), |f| {
                        f.to_uppercase().collect::<String>() + c.as_str()
                    })
                })
                .unwrap_or_else(|| "The atlas".to_string()),
            data.the,
            differs_in(&paper_profile, &Profile::of_data(info))
        ));
    }
    cohorts
}

/// The fingertips' part: one row per finger's last segment, the overall finding, and the
/// evidence finger by finger (`conf`: the confidence level in words).
fn tip_parts(
    p: &crate::analysis::literature::TableCohorts,
    names: crate::report::compare_words::Names<'_>,
    data: DataName,
    conf: &str,
) -> (Vec<LiteratureTipRow>, String, Vec<String>) {
    use crate::report::compare_table::{
        estimate_cell, fit_words, tip_finding_sentence, tip_overall, trim_rho,
    };
    let name = names.b;
    match &p.tips {
        Some(v) => (
            v.fingers
                .iter()
                .map(|t| LiteratureTipRow {
                    finger: format!("{} {}", t.finger.name(), t.quantity.symbol()),
                    paper: estimate_cell(&t.data, t.quantity),
                    bone: estimate_cell(&t.bone, t.quantity),
                    skin: estimate_cell(&t.skin, t.quantity),
                    fits: fit_words(t.fit).to_string(),
                    sweep: t
                        .sweep
                        .iter()
                        .map(|(r, f)| {
                            format!(
                                "{}: {}",
                                trim_rho(*r),
                                f.and_then(|f| f.tip()).map_or("n/a", |t| t.name())
                            )
                        })
                        .collect::<Vec<_>>()
                        .join("; "),
                })
                .collect(),
            tip_overall(v, names),
            v.fingers
                .iter()
                .map(|t| tip_finding_sentence(t, names, p.confidence))
                .chain(std::iter::once(format!(
                    "Each difference is {name}'s ratio minus {} mean, with its {conf} Welch-type interval (both uncertainties): a tip is rejected when that interval excludes 0, and not rejected when it holds 0, which at {} is not a finding that the two are equal.",
                    data.of,
                    xrays(p.a.n.unwrap_or(0))
                )))
                .collect(),
        ),
        None => (
            Vec::new(),
            format!(
                "{name} gives no fingertip soft tissue, so {} tips cannot be placed.",
                data.of
            ),
            Vec::new(),
        ),
    }
}

/// Every finger and quantity: the paper beside the table to the skin, the atlas beside
/// it to the bone (when the atlas is there), with the verdicts.
fn side_rows(l: &LiteratureInputs) -> Vec<LiteratureSideRow> {
    use crate::report::compare_table::{estimate_cell, verdict_cell};
    use crate::report::compare_words::short;
    let p = &l.paper;
    let mut side = Vec::new();
    for f in &p.fingers {
        let atlas_f = l
            .atlas
            .as_ref()
            .and_then(|a| a.fingers.iter().find(|g| g.finger == f.finger));
        for q in &f.quantities {
            let aq = atlas_f.and_then(|g| g.quantities.iter().find(|x| x.quantity == q.quantity));
            side.push(LiteratureSideRow {
                finger: f.finger.name().to_string(),
                quantity: short(q.quantity).to_string(),
                paper: estimate_cell(&q.a, q.quantity),
                table_skin: estimate_cell(&q.b, q.quantity),
                paper_verdict: verdict_cell(&q.sweep),
                atlas: aq.map_or("n/a".into(), |x| estimate_cell(&x.a, q.quantity)),
                table_bone: aq.map_or("n/a".into(), |x| estimate_cell(&x.b, q.quantity)),
                atlas_verdict: aq.map_or("n/a".into(), |x| verdict_cell(&x.sweep)),
            });
        }
    }
    side
}

/// "Buryanov & Kotiuk 2010", or the table's file.
pub(crate) fn table_name(s: &crate::analysis::literature::SideInfo) -> String {
    s.about
        .as_ref()
        .and_then(|a| a.name.clone())
        .unwrap_or_else(|| s.path.clone())
}
