//! The atlas plot of one finger: an atlas's distribution of each relative value as a
//! binned strip (a histogram in the row), with the paper's X-rays and its prediction
//! interval over it, so a reader sees how many atlas hands the paper's interval holds.

use super::draw::{
    Dir, DrawResult, Frame, Kind, LegendItem, POINT, Pen, QuantityRow, RANGE, Root, Swatch, WIDTH,
    extent, finish, padded, render, row_chart,
};
use super::kinds::{Plot, PlotKind, finger_phrase};
use crate::analysis::FingerAnalysis;
use crate::error::Error;
use crate::format::{level, percent, trimmed};

const ROW_PX: u32 = 78;
const AXIS_PX: u32 = 46;
const TOP_PX: u32 = 10;
/// Bins of the atlas's strip over the plot's x range.
const BINS: usize = 60;

/// One row: a relative quantity with the paper's statistics and both cohorts' values.
struct AtlasRow<'s> {
    row: QuantityRow<'s>,
    paper: Vec<f64>,
    atlas: Vec<f64>,
}

/// The values of quantity `k` (J~k+1) of every X-ray of a finger.
fn relative(f: &FingerAnalysis, k: usize) -> Vec<f64> {
    f.xrays
        .iter()
        .filter_map(|x| x.relative.get(k).copied())
        .filter(|v| v.is_finite())
        .collect()
}

/// Draws the atlas plot of one finger (id `atlas-<finger>`): `paper` and `atlas` are the
/// same finger's analyses in each cohort; `atlas_name` names the atlas in the text.
pub(super) fn plot(
    paper: &FingerAnalysis,
    atlas: &FingerAnalysis,
    atlas_name: &str,
    confidence: f64,
) -> Result<Plot, Error> {
    let rows: Vec<AtlasRow<'_>> = paper
        .quantities
        .iter()
        .filter(|s| s.name.is_relative())
        .enumerate()
        .map(|(k, s)| AtlasRow {
            row: QuantityRow {
                label: s.name.symbol().to_string(),
                finger: paper.finger,
                group: 0,
                stats: s,
            },
            paper: relative(paper, k),
            atlas: relative(atlas, k),
        })
        .collect();
    let legend = vec![
        LegendItem::new(
            Swatch::Histogram,
            format!("{atlas_name} radiographs per bin"),
        ),
        LegendItem::new(Swatch::Point, "the paper's X-rays"),
        LegendItem::new(
            Swatch::Interval(Kind::Prediction),
            Kind::Prediction.legend(confidence, "hand"),
        ),
    ];
    let title = format!(
        "{}: the paper's X-rays against {} {atlas_name} radiographs",
        paper.finger.name(),
        atlas.n
    );
    let subtitle = format!(
        "One row per relative value. Bars: the {atlas_name}'s hands, binned. Dots: the paper's {} X-rays; dashed: the paper's {} prediction interval for one new hand.",
        paper.n,
        level(confidence)
    );
    let frame = Frame::new(&title, &subtitle, &legend);
    let chart_px = ROW_PX * rows.len().max(1) as u32 + AXIS_PX + TOP_PX;
    let height = frame.height() + chart_px + 8;
    let id = format!("atlas-{}", paper.finger.name());
    let svg = render((WIDTH, height), "drawing an atlas plot", |root| {
        let pen = Pen::new(root);
        let top = frame.draw(&pen)?;
        let area = root.clone().shrink((0, top), (WIDTH, chart_px));
        draw_chart(&pen, &area, &rows)
    })?;
    finish(
        id,
        PlotKind::Atlas,
        title,
        description(paper, &rows, atlas_name, confidence),
        svg,
    )
}

fn draw_chart(pen: &Pen, area: &Root<'_>, rows: &[AtlasRow]) -> DrawResult {
    let count = rows.len();
    let values = rows.iter().flat_map(|r| {
        let mut v: Vec<f64> = r.atlas.iter().chain(&r.paper).copied().collect();
        if let Some(pi) = r.row.stats.intervals.pi {
            v.extend([pi.low, pi.high]);
        }
        v
    });
    let (x0, x1) = extent(values).map_or((0.0, 1.0), |(lo, hi)| padded(lo, hi, 0.03));
    let quantity_rows: Vec<QuantityRow> = rows
        .iter()
        .map(|r| QuantityRow {
            label: r.row.label.clone(),
            finger: r.row.finger,
            group: r.row.group,
            stats: r.row.stats,
        })
        .collect();
    let chart = row_chart(
        pen,
        area,
        &quantity_rows,
        (x0, x1),
        (TOP_PX, AXIS_PX),
        (
            "relative value (share of the finger's length)",
            "relative value",
            "no relative values",
        ),
    )?;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    let width = (x1 - x0) / BINS as f64;
    for (r, row) in rows.iter().enumerate() {
        let y = (count - 1 - r) as f64;
        let mut bins = [0usize; BINS];
        for &v in &row.atlas {
            let b = ((v - x0) / width).floor();
            if b >= 0.0 && b < BINS as f64 {
                bins[b as usize] += 1;
            }
        }
        let most = bins.iter().copied().max().unwrap_or(0).max(1) as f64;
        for (b, &c) in bins.iter().enumerate().filter(|(_, c)| **c > 0) {
            let lo = x0 + width * b as f64;
            let h = 0.8 * c as f64 / most;
            pen.rect(at(lo, y - 0.45 + h), at(lo + width, y - 0.45), RANGE, 0.7)?;
        }
        if let Some(pi) = row.row.stats.intervals.pi {
            let (a, b) = (at(pi.low, y + 0.3), at(pi.high, y + 0.3));
            pen.interval(a, b, Dir::Horizontal, Kind::Prediction)?;
        }
        for (i, &v) in row.paper.iter().enumerate() {
            // Spread the paper's dots a little so equal values stay visible.
            let p = at(v, y + 0.3);
            pen.dot((p.0, p.1 - 9 + 4 * (i as i32 % 3)), 4, POINT, 0.9)?;
        }
    }
    Ok(())
}

fn description(
    paper: &FingerAnalysis,
    rows: &[AtlasRow],
    atlas_name: &str,
    confidence: f64,
) -> String {
    let mut out = format!(
        "For {}, each relative value of the {atlas_name}'s radiographs as a binned strip, with the paper's {} X-rays as dots and the paper's {} prediction interval as a dashed bar.",
        finger_phrase(paper.finger),
        paper.n,
        level(confidence)
    );
    for row in rows {
        let s = row.row.stats;
        out.push_str(&format!(
            " {}: paper mean {}",
            row.row.label,
            trimmed(s.mean, 4)
        ));
        if let Some(pi) = s.intervals.pi {
            let inside = row.atlas.iter().filter(|v| pi.contains(**v)).count();
            out.push_str(&format!(
                ", prediction {} to {}, holding {} of the {atlas_name}'s {} hands",
                trimmed(pi.low, 4),
                trimmed(pi.high, 4),
                percent(inside as f64 / row.atlas.len().max(1) as f64),
                row.atlas.len()
            ));
        }
        out.push('.');
    }
    out
}
