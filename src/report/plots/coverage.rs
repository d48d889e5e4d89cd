//! The coverage plot: how often each interval method covers, against the
//! number of X-rays, with the nominal level as a line.
//!
//! The x axis is logarithmic (ln n, ticks at the simulated sizes), so the small
//! studies where the methods differ get the room; the y axis is the share of
//! simulated datasets covered, in per cent. One line per method in the
//! colours of the other plots (the prediction interval dashed); the data's own
//! size is marked with a vertical line.

use super::draw::{
    Axes, Categories, Chart, DrawResult, Font, Frame, INK, Kind, LegendItem, Linear, MARGIN, MUTED,
    Pen, Px, Root, Swatch, WIDTH, draw_axes, finish, render, xrays,
};
use super::kinds::{Plot, PlotKind};
use crate::analysis::coverage::CurvePoint;
use crate::error::Error;
use crate::format::{self, level, percent};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Height of the chart area (plot, ticks and axis descriptions) in pixels.
const CHART_PX: u32 = 360;
/// Half-size of a point marker, in pixels.
const MARKER: i32 = 4;

/// The method of each line, in legend order, with its name in the simulation.
const METHODS: [(Kind, &str); 4] = [
    (Kind::T, "t"),
    (Kind::Percentile, "percentile"),
    (Kind::Bca, "bca"),
    (Kind::Prediction, "prediction"),
];

/// Draws the coverage plot of `points` (ascending n) at confidence `confidence`.
pub(super) fn plot(points: &[CurvePoint], confidence: f64) -> Result<Plot, Error> {
    let legend: Vec<LegendItem> = METHODS
        .iter()
        .map(|&(k, _)| LegendItem::new(Swatch::Interval(k), k.legend(confidence, "X-ray")))
        .collect();
    let title = "How often each interval covers, by the number of X-rays".to_string();
    let sims = points.first().map_or(0, |p| p.coverage.sims);
    let subtitle = format!(
        "Share of {sims} simulated datasets per size (normal model) whose interval held its target: the mean for \
         the confidence intervals, one new X-ray for the prediction interval. The dashed grey line is the nominal {}; \
         the vertical line marks this data's size. The x axis is logarithmic.",
        level(confidence)
    );
    let frame = Frame::new(&title, &subtitle, &legend);
    let height = frame.height() + CHART_PX + 8;
    let svg = render((WIDTH, height), "drawing the coverage plot", |root| {
        let pen = Pen::new(root);
        let top = frame.draw(&pen)?;
        let area = root.clone().shrink((0, top), (WIDTH, CHART_PX));
        draw_chart(root, &pen, &area, points, confidence)
    })?;
    finish(
        "coverage".to_string(),
        PlotKind::Coverage,
        title,
        description(points, confidence),
        svg,
    )
}

/// The coverage of method `name` at `p`, in per cent.
fn coverage_of(p: &CurvePoint, name: &str) -> Option<f64> {
    p.coverage
        .methods
        .iter()
        .find(|m| m.method == name)
        .map(|m| 100.0 * m.coverage)
        .filter(|c| c.is_finite())
}

/// The y range in per cent: every coverage and the nominal level, padded, at most 100.
fn y_range(points: &[CurvePoint], confidence: f64) -> (f64, f64) {
    let nominal = 100.0 * confidence;
    let low = points
        .iter()
        .flat_map(|p| METHODS.iter().filter_map(|&(_, m)| coverage_of(p, m)))
        .fold(nominal, f64::min);
    let lo = ((low - 2.0) / 5.0).floor() * 5.0;
    (lo.max(0.0), 100.0)
}

/// Draws the axes, the nominal line, the data's size and one line per method.
fn draw_chart(
    root: &Root<'_>,
    pen: &Pen,
    area: &Root<'_>,
    points: &[CurvePoint],
    confidence: f64,
) -> DrawResult {
    let ln = |n: usize| (n.max(1) as f64).ln();
    let keys: Vec<f64> = points.iter().map(|p| ln(p.n)).collect();
    let (x0, x1) = match (keys.first(), keys.last()) {
        (Some(&a), Some(&b)) if b > a => (a - 0.08 * (b - a), b + 0.08 * (b - a)),
        (Some(&a), _) => (a - 0.5, a + 0.5),
        _ => (0.0, 1.0),
    };
    let (y0, y1) = y_range(points, confidence);
    let mut chart: Chart<'_, '_, Categories, Linear> = ChartBuilder::on(area)
        .margin_top(10)
        .margin_left(MARGIN)
        .margin_right(MARGIN + 8)
        .x_label_area_size(46)
        .y_label_area_size(64)
        .build_cartesian_2d(Categories::new(x0, x1, keys), y0..y1)?;
    let x_format = |x: &f64| format::num(x.exp(), 0);
    let y_format = |y: &f64| format!("{}%", format::num(*y, 0));
    let axes = Axes {
        x_desc: "number of X-rays n (logarithmic)".to_string(),
        y_desc: "coverage".to_string(),
        x_grid: true,
        x_format: &x_format,
        y_format: &y_format,
    };
    draw_axes(&mut chart, &axes)?;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    let nominal = 100.0 * confidence;
    pen.dashed(at(x0, nominal), at(x1, nominal), MUTED, 1)?;
    // Labelled at the left end, where the lines of the smallest sizes spread apart below it.
    let left = at(x0, nominal);
    pen.text(
        (left.0 + 6, left.1 - 4),
        &format!("nominal {}", level(confidence)),
        Font::new(11.0)
            .colour(MUTED)
            .anchor(HPos::Left, VPos::Bottom),
    )?;
    for p in points.iter().filter(|p| p.in_data) {
        let x = ln(p.n);
        pen.line(at(x, y0), at(x, y1), INK, 1)?;
        pen.text(
            (at(x, y1).0 + 4, at(x, y1).1 + 10),
            &format!("this data: {}", xrays(p.n)),
            Font::new(11.0).colour(INK),
        )?;
    }
    for &(kind, name) in &METHODS {
        let line: Vec<Px> = points
            .iter()
            .filter_map(|p| coverage_of(p, name).map(|c| at(ln(p.n), c)))
            .collect();
        let colour = kind.colour();
        if kind.dashed() {
            for pair in line.windows(2) {
                pen.dashed(pair[0], pair[1], colour, 2)?;
            }
        } else {
            root.draw(&PathElement::new(line.clone(), colour.stroke_width(2)))?;
        }
        for &c in &line {
            pen.dot(c, MARKER, colour, 1.0)?;
        }
    }
    Ok(())
}

/// The screen-reader description: each method's coverage at the smallest and
/// largest size and at the data's own.
fn description(points: &[CurvePoint], confidence: f64) -> String {
    let mut d = format!(
        "Line chart of the simulated coverage of nominal {} intervals against the number of X-rays.",
        level(confidence)
    );
    if points.is_empty() {
        d.push_str(" Nothing was simulated.");
        return d;
    }
    for &(kind, name) in &METHODS {
        let at: Vec<String> = points
            .iter()
            .filter_map(|p| {
                coverage_of(p, name).map(|c| format!("{} at {}", percent(c / 100.0), xrays(p.n)))
            })
            .collect();
        d.push_str(&format!(" {}: {}.", kind.phrase(), at.join(", ")));
    }
    if let Some(p) = points.iter().find(|p| p.in_data) {
        d.push_str(&format!(" This data has {}.", xrays(p.n)));
    }
    d
}
