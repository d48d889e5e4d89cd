//! Section 1, provenance, and the settings the prose quotes; how to cite the paper.

use super::common::is_paper;
use super::inputs::ReportInputs;
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::format::{decimals, exact, level, num};
use crate::stats::rng;
use serde::Serialize;

/// A label and its value.
#[derive(Debug, Clone, Serialize)]
pub struct Item {
    pub label: String,
    pub value: String,
}

fn item(label: &str, value: impl Into<String>) -> Item {
    Item {
        label: label.to_string(),
        value: value.into(),
    }
}

/// The provenance table: the data, the claims, the version and the settings.
pub(crate) fn provenance(inputs: &ReportInputs<'_>, settings: &SettingsText) -> Vec<Item> {
    let a = inputs.analysis;
    let mut provenance = vec![
        item("Dataset", a.dataset.path.clone()),
        item("SHA-256", a.dataset.sha256.clone()),
        item("X-rays", a.dataset.xrays.to_string()),
        item("Measurement rows", a.dataset.rows.to_string()),
        item("Claims file", inputs.claims_file),
        item("phalanx version", env!("CARGO_PKG_VERSION")),
        item("Seed", a.settings.seed.to_string()),
        item("Resamples asked for", a.settings.resamples.to_string()),
        item("Bootstrap", settings.bootstrap.clone()),
        item("Confidence", settings.confidence.clone()),
        item("Random number generator", rng::RNG_NAME),
    ];
    if let Some(t) = &inputs.timestamp {
        provenance.push(item("Generated", t.clone()));
    }
    provenance
}

/// Settings as the prose of the report quotes them.
#[derive(Debug, Clone, Serialize)]
pub struct SettingsText {
    /// e.g. "95%".
    pub confidence: String,
    pub resamples: String,
    pub seed: String,
    pub rng: String,
    /// e.g. "5".
    pub xrays: String,
    /// How the bootstrap was done, per distinct plan (e.g. "exact: all 126 ...").
    pub bootstrap: String,
    pub model_length: String,
    /// Why the intervals are wide at this n (the t quantile against the normal one).
    pub width_reason: String,
    /// What unit the totals J are in, as a sentence ending the statistics intro.
    pub length_unit: String,
}

pub(crate) fn settings_text(inputs: &ReportInputs<'_>) -> SettingsText {
    let a = inputs.analysis;
    let mut plans: Vec<String> = a
        .fingers
        .iter()
        .map(|f| crate::format::plan(f.bootstrap))
        .collect();
    plans.dedup();
    SettingsText {
        confidence: level(a.settings.confidence),
        resamples: a.settings.resamples.to_string(),
        seed: a.settings.seed.to_string(),
        rng: rng::RNG_NAME.to_string(),
        xrays: a.dataset.xrays.to_string(),
        bootstrap: plans.join("; "),
        model_length: exact(inputs.model_length),
        width_reason: width_reason(a),
        length_unit: length_unit(a, is_paper(inputs.paper_xrays)),
    }
}

/// "With n = 5 the 95% t quantile is 2.78 (4 degrees of freedom), not the normal 1.96."
fn width_reason(a: &Analysis) -> String {
    let crate::analysis::WidthReason { n, t, z } = a.width_reason();
    let c = a.settings.confidence;
    match t {
        Some(t) => format!(
            "With n = {n} X-rays the {} t quantile is {} ({} degrees of freedom), not the normal {}.",
            level(c),
            num(t, 2),
            n - 1,
            num(z, 2)
        ),
        None => format!(
            "With n = {n} X-ray{} no interval can be estimated.",
            if n == 1 { "" } else { "s" }
        ),
    }
}

/// What unit the totals J are in, as the statistics section says it. In image units
/// (pixels of images of no common scale) it says that J's spread, intervals and
/// prediction interval describe no physical length, and where that is seen; `paper`: the
/// data are the paper's X-rays, whose sources its section 2 names.
fn length_unit(a: &Analysis, paper: bool) -> String {
    if a.mixed_units() {
        "The rows give their lengths in more than one unit: J is shown only for a finger whose X-rays share one.".to_string()
    } else if a.pixel_lengths() {
        "The lengths are per-image pixels, so J is not averaged.".to_string()
    } else {
        match &a.unit {
            Some(u) if u == "image units" => {
                let sources = if paper {
                    "the paper took its X-ray images \"from internet and hospitals\" (its section 2) and gives no scale"
                } else {
                    "the rows give no scale"
                };
                // The spread of one finger's J, as the table below prints it.
                let seen = a
                    .fingers
                    .iter()
                    .find(|f| f.finger == Finger::Index)
                    .or(a.fingers.first())
                    .and_then(|f| {
                        let q = f.quantities.iter().find(|q| q.name == Quantity::Total)?;
                        Some(format!(
                            "; the {}'s J runs from {} to {}",
                            f.finger.name(),
                            num(q.min, decimals(false)),
                            num(q.max, decimals(false))
                        ))
                    })
                    .unwrap_or_default();
                format!(
                    "J is in image units, pixels of each X-ray as published: {sources}, so an image unit need not be the same length on two X-rays{seen}. J's spread therefore pools the images' scales with the hands' sizes, and its SD, t interval and prediction interval describe no physical length: they are shown because the paper gives J, not as sizes of hands. The relative values are ratios within one image, so the scale cancels from them."
                )
            }
            Some(u) => format!("J is in {u}."),
            None => "J is in the dataset's unit (the rows name none).".to_string(),
        }
    }
}

/// How to cite the paper and phalanx.
#[derive(Debug, Clone, Serialize)]
pub struct CitationView {
    /// Authors of the paper.
    pub paper_authors: String,
    pub paper_title: String,
    /// Where it appeared, as far as the paper's text says.
    pub paper_venue: String,
    /// phalanx, its version and where its citation metadata are.
    pub phalanx: String,
}

/// The paper's authors, as its title page gives them.
pub const PAPER_AUTHORS: &str = "E. Chaudhry, L. H. You, X. Jin and Jian J. Zhang";

/// The paper's title.
pub const PAPER_TITLE: &str =
    "Statistical Analysis of Joint Determination for Skeleton Driven Animation of Human Hands";
/// The paper's venue: its text names none.
pub const PAPER_VENUE: &str = "conference paper (National Centre for Computer Animation, Bournemouth University, UK; State Key Lab of CAD & CG, Zhejiang University, China); the paper's text names no venue, year or pages";

/// How to cite the paper and phalanx.
pub(crate) fn citation() -> CitationView {
    CitationView {
        paper_authors: PAPER_AUTHORS.to_string(),
        paper_title: PAPER_TITLE.to_string(),
        paper_venue: PAPER_VENUE.to_string(),
        phalanx: format!(
            "phalanx {}, finger-joint statistics from hand X-rays (MIT OR Apache-2.0); citation metadata in CITATION.cff",
            env!("CARGO_PKG_VERSION")
        ),
    }
}
