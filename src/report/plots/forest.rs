//! The forest plot: every relative quantity of every finger on one row, its
//! mean and its four intervals stacked within the row, on one shared x axis.

use super::draw::{
    Dir, DrawResult, Font, Frame, INK, Kind, LegendItem, MUTED, Pen, Px, QuantityRow, Root, Swatch,
    WIDTH, extent, finish, padded, quantity_rows, render, row_chart, stats_values, text_width,
};
use super::finger::quantity_sentence;
use super::kinds::{Plot, PlotKind};
use crate::analysis::{Analysis, Quantity, QuantityStats};
use crate::error::Error;
use crate::format::level;
use plotters::style::text_anchor::{HPos, VPos};

/// Height of one row in pixels.
const ROW_PX: u32 = 44;
/// Pixels below the rows (tick labels and axis description) and above them.
const AXIS_PX: u32 = 46;
const TOP_PX: u32 = 10;
/// Vertical offsets of the four bars within a row, in pixels (t at the top).
const OFFSETS: [i32; 4] = [-12, -4, 4, 12];

/// One row per finger and relative quantity.
type Row<'a> = QuantityRow<'a>;

/// The rows, top to bottom: fingers in order, their relative quantities in order.
fn rows(a: &Analysis) -> Vec<Row<'_>> {
    quantity_rows(a, Quantity::is_relative)
}

/// Draws the forest plot.
pub(super) fn plot(a: &Analysis) -> Result<Plot, Error> {
    let confidence = a.settings.confidence;
    let rows = rows(a);
    let mut legend = vec![LegendItem::new(Swatch::Mean, "mean")];
    legend.extend(LegendItem::intervals(confidence, "X-ray"));
    let chart_px = ROW_PX * rows.len().max(1) as u32 + AXIS_PX + TOP_PX;
    let title = "Relative segment lengths of every finger: means and intervals".to_string();
    let subtitle = format!(
        "One row per finger and segment. Bars from the top: t, bootstrap percentile and BCa {} \
         CIs of the mean, then the prediction interval.",
        level(confidence)
    );
    let frame = Frame::new(&title, &subtitle, &legend);
    let height = frame.height() + chart_px + 8;
    let svg = render((WIDTH, height), "drawing the forest plot", |root| {
        let pen = Pen::new(root);
        let top = frame.draw(&pen)?;
        let area = root.clone().shrink((0, top), (WIDTH, chart_px));
        draw_chart(&pen, &area, &rows)
    })?;
    finish(
        "forest".to_string(),
        PlotKind::Forest,
        title,
        description(&rows, confidence),
        svg,
    )
}

/// Draws the axes, the shading of alternate fingers and every row into `area`.
fn draw_chart(pen: &Pen, area: &Root<'_>, rows: &[Row]) -> DrawResult {
    let count = rows.len();
    let (x0, x1) = extent(rows.iter().flat_map(|r| stats_values(r.stats)))
        .map_or((0.0, 1.0), |(lo, hi)| padded(lo, hi, 0.04));
    let chart = row_chart(
        pen,
        area,
        rows,
        (x0, x1),
        (TOP_PX, AXIS_PX),
        (
            "relative value J~k = Jk/J (fraction of the finger's total length J, unitless)",
            "finger and segment",
            "no finger in the data",
        ),
    )?;
    let y_of = |r: usize| (count - 1 - r) as f64;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    if rows.is_empty() {
        return Ok(());
    }
    let right_px = at(x1, 0.0).0;
    for (r, row) in rows.iter().enumerate() {
        draw_row(pen, &|x| at(x, y_of(r)), row.stats, right_px)?;
    }
    Ok(())
}

/// One row: the four bars at their offsets and the mean, and a note naming any
/// missing interval. `at` maps a value to the pixel on the row's centre line;
/// `right_px` is the plotting area's right edge.
fn draw_row(pen: &Pen, at: &dyn Fn(f64) -> Px, s: &QuantityStats, right_px: i32) -> DrawResult {
    let mean = at(s.mean);
    pen.line((mean.0, mean.1 - 18), (mean.0, mean.1 + 18), INK, 1)?;
    let mut right = mean.0 + 6;
    let mut missing = Vec::new();
    for (kind, dy) in Kind::ALL.into_iter().zip(OFFSETS) {
        match kind.of(s) {
            Some(i) => {
                let (a, b) = (at(i.low), at(i.high));
                pen.interval((a.0, a.1 + dy), (b.0, b.1 + dy), Dir::Horizontal, kind)?;
                right = right.max(b.0 + 6);
            }
            None => missing.push(kind.short()),
        }
    }
    pen.diamond(mean, 5)?;
    if missing.is_empty() {
        return Ok(());
    }
    let note = if missing.len() == Kind::ALL.len() {
        let why = if s.n < 2 { " (1 X-ray)" } else { "" };
        format!("no intervals{why}")
    } else {
        format!("not available: {}", missing.join(", "))
    };
    let font = Font::new(11.0).colour(MUTED);
    if right + 4 + text_width(&note, 11.0) > right_px {
        pen.text(
            (mean.0 - 10, mean.1),
            &note,
            font.anchor(HPos::Right, VPos::Center),
        )
    } else {
        pen.text((right + 4, mean.1), &note, font)
    }
}

/// The screen-reader description: every row's statistics.
fn description(rows: &[Row], confidence: f64) -> String {
    let mut out = format!(
        "Forest plot of the relative segment lengths of every finger: per finger and segment, \
         the mean with its {} t, bootstrap percentile and BCa confidence intervals and its \
         prediction interval for one new X-ray.",
        level(confidence)
    );
    for row in rows {
        let finger = row.finger.name();
        out.push_str(&format!(
            " {finger} {}",
            quantity_sentence(row.stats, confidence)
        ));
    }
    out
}
