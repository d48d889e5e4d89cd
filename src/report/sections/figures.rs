//! Section 7 and the plots of every section: inline SVG for HTML, a file link for Markdown.

use crate::report::plots::{Plot, PlotKind};
use serde::Serialize;

/// One plot: inline SVG for HTML, a file link for Markdown.
#[derive(Debug, Clone, Serialize)]
pub struct PlotView {
    pub id: String,
    pub kind: PlotKind,
    pub title: String,
    pub description: String,
    /// Path relative to the report directory, e.g. `plots/hand.svg`.
    pub file: String,
    pub svg: String,
    /// The description's first sentence, shown under the plot.
    pub caption: String,
    /// The rest of the description (every value in words), folded away in HTML.
    pub details: String,
}

pub(crate) fn plot(p: &Plot) -> PlotView {
    let (caption, details) = match p.description.split_once(". ") {
        Some((first, rest)) => (format!("{first}."), rest.to_string()),
        None => (p.description.clone(), String::new()),
    };
    PlotView {
        caption,
        details,
        id: p.id.clone(),
        kind: p.kind,
        title: p.title.clone(),
        description: p.description.clone(),
        file: format!("plots/{}.svg", p.id),
        svg: p.svg.clone(),
    }
}
