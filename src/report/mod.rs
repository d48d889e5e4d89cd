//! Everything phalanx shows: exporters that turn finished results into bytes.
//!
//! Reads analysis results only, never raw measurement rows. Two layers: the
//! report's [`sections`] (each its view and builder) and the [`phrases`] the
//! terminal shares sit below the exporters (html/md through [`view`] and
//! [`render`], text, json, csv, audit, compare, deform, rig). Every exporter and
//! renderer is pure (returns bytes or text); nothing here writes but
//! [`writer::write_all`], which `cmd` calls for the report's, the schemas' and
//! `deform`'s files (the other commands write their one file through `crate::atomic`).

pub(crate) mod audit;
pub(crate) mod compare;
pub(crate) mod compare_table;
pub(crate) mod compare_words;
pub(crate) mod csv_out;
pub(crate) mod deform;
pub(crate) mod inputs;
pub mod json;
pub mod layout;
pub(crate) mod phrases;
pub mod plots;
pub(crate) mod progress;
pub mod render;
pub mod render3d;
pub(crate) mod rig;
pub(crate) mod schema;
pub mod sections;
pub(crate) mod text;
pub(crate) mod track_words;
pub mod view;
pub mod writer;

use crate::error::Error;
use render::Templates;
use view::ReportInputs;
use writer::OutputFile;

/// Which report files to produce.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Formats {
    /// `index.html` (self-contained, plots inline).
    pub html: bool,
    /// `report.md`, with plots linked from `plots/`.
    pub markdown: bool,
    /// `stats.json`, the same document as `phalanx stats --format json`.
    pub json: bool,
}

impl Formats {
    /// Every format.
    pub const ALL: Formats = Formats {
        html: true,
        markdown: true,
        json: true,
    };
}

/// Renders the report files in memory: nothing is written here.
pub fn render(
    inputs: &ReportInputs<'_>,
    formats: Formats,
    templates: &Templates,
) -> Result<Vec<OutputFile>, Error> {
    // The pages and plots, and stats.json (at 100,000 X-rays 150 MB of JSON, about 0.3 s),
    // are made side by side; the files keep their order.
    let (pages, json) = rayon::join(
        || pages(inputs, formats, templates),
        || {
            formats
                .json
                .then(|| json::stats(inputs.analysis, inputs.groups))
                .transpose()
        },
    );
    let mut files = pages?;
    if let Some(json) = json? {
        files.push(OutputFile::new("stats.json", json));
    }
    Ok(files)
}

/// The HTML and Markdown pages with their plots and figures, as `formats` asks.
fn pages(
    inputs: &ReportInputs<'_>,
    formats: Formats,
    templates: &Templates,
) -> Result<Vec<OutputFile>, Error> {
    let mut files = Vec::new();
    if formats.html || formats.markdown {
        let mut plots = plots::all_named(inputs.analysis, inputs.placements, &named(inputs))?;
        plots.extend(tracking_plots(inputs)?);
        if !inputs.rigs.is_empty() {
            plots.push(plots::rigs_plot(inputs.analysis, &rig_ratios(inputs.rigs))?);
        }
        if !inputs.coverage.is_empty() {
            plots.push(plots::coverage_plot(
                inputs.coverage,
                inputs.coverage_settings.confidence,
            )?);
        }
        if let Some(atlas) = inputs.atlas {
            for f in &inputs.analysis.fingers {
                if let Some(g) = atlas.analysis.finger(f.finger) {
                    plots.push(plots::atlas_plot(
                        f,
                        g,
                        "atlas",
                        inputs.analysis.settings.confidence,
                    )?);
                }
            }
        }
        let view = view::build(inputs, &plots);
        if formats.html {
            files.push(OutputFile::new("index.html", templates.html(&view)?));
        }
        if formats.markdown {
            files.push(OutputFile::new("report.md", templates.markdown(&view)?));
        }
        for p in &plots {
            files.push(OutputFile::new(
                format!("plots/{}.svg", p.id),
                p.svg.clone().into_bytes(),
            ));
        }
        if let Some(d) = inputs.deform {
            files.extend(d.figures.iter().cloned());
        }
        if let Some(m) = inputs.made {
            files.extend(m.figures.iter().cloned());
        }
    }
    Ok(files)
}

/// The X-rays worth naming in the plots: the rows added though flagged, and the X-rays of
/// the history's last addition (when they are still in the data).
fn named(inputs: &ReportInputs<'_>) -> plots::Named {
    let a = inputs.analysis;
    let newest = inputs
        .history
        .iter()
        .rev()
        .find(|s| s.event == crate::dataset::history::Event::Add)
        .and_then(|s| s.change.as_ref())
        .map(|c| {
            c.xrays
                .iter()
                .filter(|x| {
                    a.fingers
                        .iter()
                        .any(|f| f.xrays.iter().any(|v| *v.xray == ***x))
                })
                .cloned()
                .collect()
        })
        .unwrap_or_default();
    plots::Named {
        flagged: a
            .flagged
            .iter()
            .map(|f| (f.xray.to_string(), f.finger))
            .collect(),
        newest,
    }
}

/// The ratios of each reference rig, for the rig plot.
fn rig_ratios(rigs: &[view::ReferenceAudit]) -> Vec<plots::RigRatios> {
    rigs.iter()
        .map(|r| plots::RigRatios {
            name: r.rig.name.clone(),
            values: r
                .audit
                .fingers
                .iter()
                .flat_map(|f| {
                    f.audit
                        .values
                        .iter()
                        .filter(|v| !v.quantity.is_relative())
                        .map(move |v| (f.chain.finger, v.quantity, v.measured))
                })
                .collect(),
        })
        .collect()
}

/// One tracking plot per finger with history (two snapshots or more), in the analysis's finger order.
fn tracking_plots(inputs: &ReportInputs<'_>) -> Result<Vec<plots::Plot>, Error> {
    // One snapshot is a single point per quantity: nothing moves yet.
    if inputs.history.len() < 2 {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for f in &inputs.analysis.fingers {
        let series = plots::track_series(inputs.history, f.finger);
        if !series.is_empty() {
            out.push(plots::tracking_plot(
                f.finger,
                &series,
                inputs.analysis.settings.confidence,
            )?);
        }
    }
    Ok(out)
}
