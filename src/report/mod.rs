//! Everything phalanx shows: exporters that turn finished results into bytes.
//!
//! Reads analysis results only, never raw measurement rows. Every exporter and
//! renderer is pure (returns bytes or text); files are written in one place,
//! [`writer::write_all`].

pub mod csv_out;
pub mod format;
pub mod json;
pub mod plots;
pub mod render;
pub mod text;
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
    let mut files = Vec::new();
    if formats.html || formats.markdown {
        let plots = plots::all(inputs.analysis, inputs.placements)?;
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
    }
    if formats.json {
        files.push(OutputFile::new("stats.json", json::stats(inputs.analysis)?));
    }
    Ok(files)
}
