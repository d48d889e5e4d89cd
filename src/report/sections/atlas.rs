//! The paper (or a lab's X-rays) against the atlas's radiographs: the cohorts compared, the
//! external coverage, the coverage on real hands and the whole-hand proportions.

use super::common::DataName;
use super::inputs::AtlasInputs;
use super::toc::Toc;
use crate::analysis::population::PopulationStudy;
use crate::analysis::{Analysis, Quantity};
use crate::format::{decimals, level, percent};
use crate::report::phrases::pooled_rows;
use serde::Serialize;

/// The section "The paper against N atlas radiographs".
#[derive(Debug, Clone, Serialize)]
pub struct AtlasView {
    pub title: String,
    /// The Markdown anchor of the section's heading.
    pub anchor: String,
    /// The two cohorts, one line each.
    pub cohorts: Vec<String>,
    /// What differs between the cohorts, in plain words.
    pub differs: String,
    pub comparison: Vec<AtlasCompareRow>,
    /// One sentence per finger, then the fingertip sentences.
    pub sentences: Vec<String>,
    pub external: Vec<AtlasExternalRow>,
    pub external_summary: String,
    pub population_intro: String,
    pub population: Vec<AtlasPopulationRow>,
    pub proportions_intro: String,
    pub proportions: Vec<AtlasProportionRow>,
    pub notes: Vec<String>,
}

/// One finger and quantity of the comparison table.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasCompareRow {
    pub finger: String,
    pub quantity: String,
    pub paper: String,
    pub atlas: String,
    pub difference: String,
    pub welch: String,
    pub bootstrap: String,
    pub hedges: String,
}

/// One finger and quantity of the external coverage.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasExternalRow {
    pub finger: String,
    pub quantity: String,
    pub paper_pi: String,
    pub atlas_in_paper: String,
    pub atlas_pi: String,
    pub paper_in_atlas: String,
}

/// One sample size and model of the coverage on real hands.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasPopulationRow {
    pub n: String,
    pub model: String,
    pub t: String,
    pub percentile: String,
    pub bca: String,
    pub prediction: String,
    pub bootstrap: String,
}

/// One finger's whole-hand proportions from its metacarpal.
#[derive(Debug, Clone, Serialize)]
pub struct AtlasProportionRow {
    pub finger: String,
    pub n: String,
    pub mc_j: String,
    pub mc_j_pi: String,
    pub j1_mc: String,
    pub j1_mc_pi: String,
}

/// The section's title: "The paper against N atlas radiographs", or "The X-rays against ..."
/// over other data.
pub(crate) fn atlas_title(data: DataName, atlas: &AtlasInputs) -> String {
    format!(
        "{} against {} atlas radiographs",
        data.title, atlas.cohorts.b.xrays
    )
}

/// The section "The paper against N atlas radiographs" (or "The X-rays against ...") from
/// the data's analysis and the atlas's.
pub(crate) fn atlas_view(
    paper: &Analysis,
    atlas: &AtlasInputs,
    data: DataName,
    toc: &Toc,
) -> AtlasView {
    use crate::report::compare::cohort_line;
    let c = &atlas.cohorts;
    let p = &atlas.population;
    let confidence = paper.settings.confidence;
    let (comparison, external) = atlas_comparison(c);
    let (inside, tested) = c.b_inside_a();
    let external_summary = format!(
        "Over every finger and relative value, {} of the atlas's values ({inside} of {tested}) lie inside {} {} prediction interval for one new hand, which promises {}.",
        percent(inside as f64 / tested.max(1) as f64),
        data.of,
        level(confidence),
        level(confidence),
    );
    let proportions_intro = format!(
        "Where the MCP sits: {} the fingers only, the atlas also the metacarpal (CMC to MCP). mc/J is the metacarpal's length over the finger's (J1 + J2 + J3), J1/mc the first phalanx over the metacarpal: for a rig, the MCP lies (mc/J) L from the CMC for a finger of length L. Mean (SD) and the {} prediction interval for one new hand, over the atlas's X-rays.",
        if data.paper {
            "the paper measures"
        } else {
            "the X-rays measure"
        },
        level(confidence)
    );
    let title = atlas_title(data, atlas);
    AtlasView {
        anchor: toc
            .by_id
            .get("atlas")
            .map_or_else(String::new, |e| e.anchor.clone()),
        title,
        cohorts: vec![
            format!("{}: {}", data.title, cohort_line(&c.a)),
            format!("The atlas: {}", cohort_line(&c.b)),
        ],
        differs: atlas_differs(c, data, toc),
        comparison,
        sentences: atlas_sentences(c, data, confidence),
        external,
        external_summary,
        population_intro: atlas_population_intro(p, confidence),
        population: atlas_population(p),
        proportions_intro,
        proportions: atlas_proportions(&atlas.analysis),
        notes: c.notes.iter().chain(&p.notes).cloned().collect(),
    }
}

/// What differs between the cohorts besides their size, in plain words.
fn atlas_differs(c: &crate::analysis::compare::Cohorts, data: DataName, toc: &Toc) -> String {
    let atlas = format!(
        "The cohorts differ in more than their size. The atlas (the Digital Hand Atlas, {} radiographs) holds children and adolescents aged 0 to 18, all left hands, with {}; its lengths are pixels of images of different scale, so only relative values compare.",
        c.b.xrays,
        crate::dataset::landmarks::ATLAS_LANDMARKS,
    );
    let ours = if data.paper {
        format!(
            "The paper's {} X-rays are right hands, measured in Matlab, of people whose sex and age it does not give; it does not say whether its fingertips are at the bone or the skin, and its data record them at the skin because a test against published adult measurements rejects bone tips and does not reject skin tips ({}).",
            c.a.xrays,
            toc.section("literature")
        )
    } else {
        format!(
            "The data's {} X-rays are whatever hands the lab measured (the paper's among them where their rows are); their side, sex and age are what the data's notes say, and their fingertips are where the data's tip column puts them ({} tests them against published adults).",
            c.a.xrays,
            toc.section("literature")
        )
    };
    format!(
        "{atlas} {ours} A difference below may come from growth, from the side or the person, or from where the tip was clicked."
    )
}

/// The comparison rows of every finger and quantity, and the external-validity rows of the
/// relative ones.
fn atlas_comparison(
    c: &crate::analysis::compare::Cohorts,
) -> (Vec<AtlasCompareRow>, Vec<AtlasExternalRow>) {
    use crate::report::compare::{
        bootstrap_cell, coverage_cell, difference_cell, hedges_cell, mean_sd, welch_cell,
    };
    use crate::report::compare_words::short;
    let d = |q: Quantity| decimals(q.is_unitless());
    let mut comparison = Vec::new();
    let mut external = Vec::new();
    for f in &c.fingers {
        for qc in &f.quantities {
            let (q, cmp) = (qc.quantity, &qc.comparison);
            comparison.push(AtlasCompareRow {
                finger: f.finger.name().to_string(),
                quantity: short(q).to_string(),
                paper: mean_sd(cmp.a.mean, cmp.a.sd, q),
                atlas: mean_sd(cmp.b.mean, cmp.b.sd, q),
                difference: difference_cell(cmp, q),
                welch: welch_cell(cmp, q),
                bootstrap: bootstrap_cell(cmp, q),
                hedges: hedges_cell(cmp),
            });
            if q.is_relative() {
                external.push(AtlasExternalRow {
                    finger: f.finger.name().to_string(),
                    quantity: short(q).to_string(),
                    paper_pi: crate::format::interval(cmp.b_in_a.map(|e| e.interval), d(q)),
                    atlas_in_paper: coverage_cell(cmp.b_in_a.as_ref()),
                    atlas_pi: crate::format::interval(cmp.a_in_b.map(|e| e.interval), d(q)),
                    paper_in_atlas: coverage_cell(cmp.a_in_b.as_ref()),
                });
            }
        }
    }
    (comparison, external)
}

/// One sentence per finger, then one per finger's last segment (the tip).
fn atlas_sentences(
    c: &crate::analysis::compare::Cohorts,
    data: DataName,
    confidence: f64,
) -> Vec<String> {
    use crate::report::compare::{finger_sentence, tip_sentence};
    use crate::report::compare_words::Names;
    let names = Names {
        a: data.the,
        b: "the atlas",
    };
    let mut sentences: Vec<String> = c
        .fingers
        .iter()
        .map(|f| data.possessive_in(finger_sentence(f, names, confidence)))
        .collect();
    for f in &c.fingers {
        if let Some(last) = &f.last_segment {
            sentences.push(format!(
                "{}: {}",
                f.finger.name(),
                data.possessive_in(tip_sentence(last, c, names))
            ));
        }
    }
    sentences
}

/// The text above the coverage on real hands: what was drawn and the Monte-Carlo SE.
fn atlas_population_intro(p: &PopulationStudy, confidence: f64) -> String {
    let xrays = p.quantities.first().map_or(0, |q| q.population);
    format!(
        "The atlas taken as the population of hands ({xrays} X-rays): {} samples of each size n drawn from its X-rays with replacement, every interval built as the statistics build it, and counted when it holds the atlas's mean (the prediction interval: one further atlas X-ray). Each figure is the mean over the {} relative values; beside it, the normal model's figure. Monte-Carlo SE about {} per value at {}.",
        p.settings.sims,
        p.quantities.len(),
        percent(p.settings.mc_se(confidence)),
        level(confidence),
    )
}

/// Per sample size, the coverage on atlas hands and, below it, the normal model's.
fn atlas_population(p: &PopulationStudy) -> Vec<AtlasPopulationRow> {
    pooled_rows(p)
        .into_iter()
        .map(|r| {
            let [t, percentile, bca, prediction] = r.cells;
            let (n, model) = if r.normal {
                (String::new(), "normal model")
            } else {
                (r.n.to_string(), "atlas hands")
            };
            AtlasPopulationRow {
                n,
                model: model.to_string(),
                t,
                percentile,
                bca,
                prediction,
                bootstrap: r.bootstrap,
            }
        })
        .collect()
}

/// Each finger's mc/J and J1/mc over the atlas's X-rays (fingers without both are left out).
fn atlas_proportions(analysis: &Analysis) -> Vec<AtlasProportionRow> {
    use crate::report::compare::mean_sd;
    let mut proportions = Vec::new();
    for f in &analysis.fingers {
        let get = |q: Quantity| f.quantities.iter().find(|s| s.name == q);
        let (Some(mc_j), Some(j1_mc)) = (get(Quantity::RatioMcJ), get(Quantity::RatioJ1Mc)) else {
            continue;
        };
        proportions.push(AtlasProportionRow {
            finger: f.finger.name().to_string(),
            n: mc_j.n.to_string(),
            mc_j: mean_sd(mc_j.mean, mc_j.sd, Quantity::RatioMcJ),
            mc_j_pi: crate::format::interval(mc_j.intervals.pi, 4),
            j1_mc: mean_sd(j1_mc.mean, j1_mc.sd, Quantity::RatioJ1Mc),
            j1_mc_pi: crate::format::interval(j1_mc.intervals.pi, 4),
        });
    }
    proportions
}
