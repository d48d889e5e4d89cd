//! Section 8, how far to trust each interval: the simulated coverage per method, and
//! the coverage measured on real hands beside it.

use super::inputs::{AtlasInputs, ReportInputs};
use crate::analysis::coverage::{CoverageSettings, CurvePoint};
use crate::format::{num, percent, xrays};
use crate::report::phrases::{interval_advice_of, method, pooled_rows};
use serde::Serialize;

/// Simulated coverage per method, one row per sample size.
#[derive(Debug, Clone, Serialize)]
pub struct CoverageView {
    pub sims: String,
    /// Resamples per simulated dataset at the data's own n and elsewhere, in words.
    pub resamples: String,
    /// Why the simulations take the resamples they take, for the methods.
    pub method: String,
    /// What the simulation says at the data's n, and which interval to use.
    pub summary: String,
    /// Sample sizes of the data not simulated (n = 1, or beyond the report's limit).
    pub notes: Vec<String>,
    pub rows: Vec<CoverageRow>,
    /// Coverage measured on real hands, beside the simulation (set when an
    /// atlas of measured hands is given; `None` otherwise).
    pub real: Option<RealCoverageView>,
}

/// The coverage of every method at one sample size.
#[derive(Debug, Clone, Serialize)]
pub struct CoverageRow {
    /// "5 X-rays".
    pub n: String,
    pub t: String,
    pub percentile: String,
    pub bca: String,
    pub prediction: String,
    /// True for the data's own n.
    pub this_data: bool,
}

/// Coverage measured on real hands (an atlas of X-ray measurements) rather
/// than simulated from a normal model.
#[derive(Debug, Clone, Serialize)]
pub struct RealCoverageView {
    /// Where the hands come from.
    pub source: String,
    /// How the coverage was measured.
    pub note: String,
    pub rows: Vec<CoverageRow>,
}

/// A method's coverage as a percentage, "n/a" when not simulated.
fn coverage_cell(p: &CurvePoint, name: &str) -> String {
    method(p, name).map_or_else(|| "n/a".to_string(), |m| percent(m.coverage))
}

/// Why the coverage simulations take fewer resamples than the statistics: the Monte-Carlo
/// error of the printed figures (see [`crate::analysis::coverage::SIM_RESAMPLES`]).
fn simulation_method(s: &CoverageSettings, asked: usize) -> String {
    let se = |p: f64| 100.0 * s.mc_se(p);
    let curve = crate::analysis::coverage::CURVE_RESAMPLES;
    let b = s.resamples.min(curve);
    let bias = crate::analysis::coverage::bootstrap_bias_points(b);
    let measured = if b == curve {
        " (measured against 10000 resamples: 0.3 to 0.5 points at 10 to 50 X-rays)"
    } else {
        ""
    };
    format!(
        "each simulated dataset is bootstrapped with {b} resamples{} (the statistics above use the {asked} asked for), chosen by the Monte-Carlo error of the printed coverage. From {} simulated datasets a coverage near 95% has a Monte-Carlo SE of {} points, one near 85% of {}; the bootstrap's own noise lowers the percentile and BCa coverage by about 70 / B points at B resamples, {} here{measured}, {} times the SE near 95%. More resamples would move no printed figure beyond that noise, at a cost that grows with them. The t and prediction intervals do not use the bootstrap.",
        if s.resamples > curve {
            format!(", {} at this data's n", s.resamples)
        } else {
            String::new()
        },
        s.sims,
        num(se(0.95), 2),
        num(se(0.85), 2),
        num(bias, 2),
        num(bias / se(0.95).max(1e-9), 1),
    )
}

pub(crate) fn coverage(inputs: &ReportInputs<'_>) -> CoverageView {
    let s = inputs.coverage_settings;
    let points = inputs.coverage;
    let data: Vec<String> = points
        .iter()
        .filter(|p| p.in_data)
        .map(|p| xrays(p.n))
        .collect();
    let notes = crate::analysis::coverage::not_simulated(inputs.analysis, s);
    let summary = interval_advice_of(points, Some(inputs.analysis)).unwrap_or_else(|| {
        "Coverage could not be simulated at this data's size (fewer than 2 X-rays, or more than the report simulates).".to_string()
    });
    CoverageView {
        sims: s.sims.to_string(),
        resamples: {
            let data = if data.is_empty() {
                "not simulated".to_string()
            } else {
                data.join(", ")
            };
            let curve = crate::analysis::coverage::CURVE_RESAMPLES;
            if s.resamples <= curve {
                format!(
                    "{} bootstrap resamples per simulated dataset at every size, this data's n ({data}) included, or the exact enumeration where it needs fewer",
                    s.resamples
                )
            } else {
                format!(
                    "{} bootstrap resamples per simulated dataset at this data's n ({data}), at most {curve} at the other sizes",
                    s.resamples
                )
            }
        },
        method: simulation_method(s, inputs.analysis.settings.resamples),
        summary,
        notes,
        rows: points
            .iter()
            .map(|p| CoverageRow {
                n: xrays(p.n),
                t: coverage_cell(p, "t"),
                percentile: coverage_cell(p, "percentile"),
                bca: coverage_cell(p, "bca"),
                prediction: coverage_cell(p, "prediction"),
                this_data: p.in_data,
            })
            .collect(),
        real: inputs.atlas.map(real_coverage),
    }
}

/// The coverage of each method measured on the atlas's hands (the mean over its
/// relative values per sample size), for the coverage section, beside the simulation.
fn real_coverage(atlas: &AtlasInputs) -> RealCoverageView {
    let p = &atlas.population;
    let rows = pooled_rows(p)
        .into_iter()
        .filter(|r| !r.normal)
        .map(|r| {
            let [t, percentile, bca, prediction] = r.cells;
            CoverageRow {
                n: xrays(r.n),
                t,
                percentile,
                bca,
                prediction,
                this_data: false,
            }
        })
        .collect();
    let population = p.quantities.first().map_or(0, |q| q.population);
    RealCoverageView {
        source: format!("samples drawn from the {population} X-rays of the atlas"),
        note: format!(
            "Each figure is the mean over the atlas's {} relative values of how often the interval held the atlas's mean (the prediction interval: one further atlas X-ray), from {} samples per size; the atlas section below has the details.",
            p.quantities.len(),
            p.settings.sims
        ),
        rows,
    }
}
