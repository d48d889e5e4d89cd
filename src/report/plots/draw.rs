//! Shared drawing for every plot: the canvas, colours, text, interval bars,
//! legends, axes, and the accessible `<title>`/`<desc>` wrapper.
//!
//! Everything here draws in absolute pixel coordinates on the root area; a
//! plot maps its data to pixels with its chart (`ChartContext::backend_coord`)
//! and then uses these helpers, so the three plots share one look.

use super::kinds::{Plot, PlotKind};
use crate::analysis::{Analysis, Interval, Quantity, QuantityStats};
use crate::dataset::Finger;
use crate::error::Error;
use crate::format;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::fmt::Write as _;

/// The whole SVG canvas, in absolute pixels.
pub(super) type Root<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// What plotters reports when drawing on an SVG canvas fails.
pub(super) type DrawError = DrawingAreaErrorKind<std::io::Error>;
/// The result of a drawing step.
pub(super) type DrawResult = Result<(), DrawError>;
/// A pixel position `(x, y)`, y downwards.
pub(super) type Px = (i32, i32);
/// A chart with an `f64` axis on each side (either may carry fixed key points).
pub(super) type Chart<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;
/// A continuous axis.
pub(super) type Linear = RangedCoordf64;

/// Width of every plot in pixels.
pub(super) const WIDTH: u32 = 840;
/// Left and right page margin in pixels.
pub(super) const MARGIN: i32 = 16;
/// Height of the title block.
const HEADER_H: u32 = 58;

/// Text and axes.
pub(super) const INK: RGBColor = RGBColor(0x1A, 0x1A, 0x1A);
/// Secondary text.
pub(super) const MUTED: RGBColor = RGBColor(0x55, 0x55, 0x55);
/// Grid lines.
pub(super) const GRID: RGBColor = RGBColor(0xE0, 0xE0, 0xE0);
/// Background shading of alternate groups.
pub(super) const SHADE: RGBColor = RGBColor(0xF2, 0xF2, 0xF2);
/// One X-ray's value.
pub(super) const POINT: RGBColor = RGBColor(0x3A, 0x3A, 0x3A);
/// A point worth naming: flagged, outside the prediction interval, or of the newest batch.
pub(super) const NAMED: RGBColor = RGBColor(0xC2, 0x18, 0x5B);
/// The observed range (min..max) band (Okabe-Ito orange).
pub(super) const RANGE: RGBColor = RGBColor(0xE6, 0x9F, 0x00);
/// A model finger's bone.
pub(super) const BONE: RGBColor = RGBColor(0xD4, 0xD4, 0xD4);

/// Half-length of an interval bar's end caps, in pixels.
const CAP: i32 = 5;
/// Font size of legend entries, in pixels.
const LEGEND_PX: f64 = 12.0;
/// Width of a legend swatch, in pixels.
const SWATCH_W: i32 = 30;
/// Height of one legend line, in pixels.
const LEGEND_ROW: i32 = 20;

/// One of the four intervals drawn around a mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// Student-t confidence interval of the mean.
    T,
    /// Bootstrap percentile confidence interval of the mean.
    Percentile,
    /// Bootstrap BCa confidence interval of the mean.
    Bca,
    /// Prediction interval for one new X-ray.
    Prediction,
}

impl Kind {
    /// Every kind, in drawing order (top to bottom).
    pub(super) const ALL: [Kind; 4] = [Kind::T, Kind::Percentile, Kind::Bca, Kind::Prediction];

    /// This interval of a quantity, if it exists.
    pub(super) fn of(self, s: &QuantityStats) -> Option<Interval> {
        match self {
            Kind::T => s.intervals.ci_t,
            Kind::Percentile => s.intervals.ci_percentile,
            Kind::Bca => s.intervals.ci_bca,
            Kind::Prediction => s.intervals.pi,
        }
    }

    /// Colour (Okabe-Ito blue, bluish green, vermillion; Tol purple): distinct under colour blindness.
    pub(super) fn colour(self) -> RGBColor {
        match self {
            Kind::T => RGBColor(0x00, 0x72, 0xB2),
            Kind::Percentile => RGBColor(0x00, 0x9E, 0x73),
            Kind::Bca => RGBColor(0xD5, 0x5E, 0x00),
            Kind::Prediction => RGBColor(0xAA, 0x33, 0x77),
        }
    }

    /// Short name for an axis row.
    pub(super) fn short(self) -> &'static str {
        match self {
            Kind::T => "t CI",
            Kind::Percentile => "percentile CI",
            Kind::Bca => "BCa CI",
            Kind::Prediction => "prediction",
        }
    }

    /// Legend text at confidence level `confidence`; `unit` is what a prediction is for.
    pub(super) fn legend(self, confidence: f64, unit: &str) -> String {
        let level = format::level(confidence);
        match self {
            Kind::T => format!("{level} CI of the mean (Student t)"),
            Kind::Percentile => format!("{level} CI (bootstrap percentile)"),
            Kind::Bca => format!("{level} CI (bootstrap BCa)"),
            Kind::Prediction => format!("{level} prediction interval (one new {unit})"),
        }
    }

    /// Name in running text (descriptions).
    pub(super) fn phrase(self) -> &'static str {
        match self {
            Kind::T => "t CI",
            Kind::Percentile => "bootstrap percentile CI",
            Kind::Bca => "BCa CI",
            Kind::Prediction => "prediction interval",
        }
    }

    /// Prediction intervals are dashed, so they differ from the CIs without colour.
    pub(super) fn dashed(self) -> bool {
        self == Kind::Prediction
    }
}

/// Which way a bar runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Dir {
    Horizontal,
    Vertical,
}

/// A categorical axis: continuous `f64` (so marks can sit between categories),
/// with ticks and grid lines only at the categories' positions.
///
/// (plotters' own `WithKeyPoints<RangedCoordf64>` cannot take a label formatter.)
pub(super) struct Categories {
    inner: RangedCoordf64,
    keys: Vec<f64>,
}

impl Categories {
    /// The axis over `lo..hi` with ticks at `keys`.
    pub(super) fn new(lo: f64, hi: f64, keys: Vec<f64>) -> Categories {
        Categories {
            inner: (lo..hi).into(),
            keys,
        }
    }
}

impl Ranged for Categories {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.keys.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
}

/// A text style in SVG pixels (plotters' sizes are 1.24 times larger than the SVG's).
#[derive(Clone, Copy)]
pub(super) struct Font {
    px: f64,
    colour: RGBColor,
    h: HPos,
    v: VPos,
    bold: bool,
}

impl Font {
    /// Regular `px`-pixel ink text, anchored left and vertically centred.
    pub(super) fn new(px: f64) -> Font {
        Font {
            px,
            colour: INK,
            h: HPos::Left,
            v: VPos::Center,
            bold: false,
        }
    }

    /// The same font in another colour.
    pub(super) fn colour(self, colour: RGBColor) -> Font {
        Font { colour, ..self }
    }

    /// The same font with another anchor.
    pub(super) fn anchor(self, h: HPos, v: VPos) -> Font {
        Font { h, v, ..self }
    }

    /// The same font in bold.
    pub(super) fn bold(self) -> Font {
        Font { bold: true, ..self }
    }

    /// The plotters text style: generic `sans-serif`, so no font file is ever needed.
    pub(super) fn style(&self) -> TextStyle<'static> {
        let weight = if self.bold {
            FontStyle::Bold
        } else {
            FontStyle::Normal
        };
        TextStyle {
            font: FontDesc::new(FontFamily::SansSerif, self.px * 1.24, weight),
            color: self.colour.to_backend_color(),
            pos: Pos::new(self.h, self.v),
        }
    }
}

/// A rough width of `text` in pixels at `px` (a generous sans-serif average).
pub(super) fn text_width(text: &str, px: f64) -> i32 {
    (text.chars().count() as f64 * px * 0.6).ceil() as i32
}

/// Draws primitives on the root canvas in absolute pixels.
pub(super) struct Pen<'r, 'a> {
    root: &'r Root<'a>,
}

impl<'r, 'a> Pen<'r, 'a> {
    /// A pen on `root`.
    pub(super) fn new(root: &'r Root<'a>) -> Self {
        Pen { root }
    }

    /// A solid line.
    pub(super) fn line(&self, a: Px, b: Px, colour: RGBColor, width: u32) -> DrawResult {
        self.root
            .draw(&PathElement::new(vec![a, b], colour.stroke_width(width)))
    }

    /// A dashed line (8 px dashes, 5 px gaps).
    pub(super) fn dashed(&self, a: Px, b: Px, colour: RGBColor, width: u32) -> DrawResult {
        self.root.draw(&DashedPathElement::new(
            vec![a, b],
            8,
            5,
            colour.stroke_width(width),
        ))
    }

    /// A filled rectangle between two corners.
    pub(super) fn rect(&self, a: Px, b: Px, colour: RGBColor, opacity: f64) -> DrawResult {
        self.root
            .draw(&Rectangle::new([a, b], colour.mix(opacity).filled()))
    }

    /// A filled circle.
    pub(super) fn dot(&self, c: Px, r: i32, colour: RGBColor, opacity: f64) -> DrawResult {
        self.root
            .draw(&Circle::new(c, r, colour.mix(opacity).filled()))
    }

    /// The mean marker: a filled diamond.
    pub(super) fn diamond(&self, c: Px, r: i32) -> DrawResult {
        let points = vec![
            (c.0, c.1 - r),
            (c.0 + r, c.1),
            (c.0, c.1 + r),
            (c.0 - r, c.1),
        ];
        self.root.draw(&Polygon::new(points, INK.filled()))
    }

    /// The marker of the k-th rig: circle, square, triangle, then the cycle again
    /// in other colours, so shape alone tells the first three apart.
    pub(super) fn marker(&self, c: Px, k: usize) -> DrawResult {
        let colour = MARKER_COLOURS[k % MARKER_COLOURS.len()];
        let r = 5;
        match k % 3 {
            0 => self.dot(c, r, colour, 1.0),
            1 => self.rect((c.0 - r, c.1 - r), (c.0 + r, c.1 + r), colour, 1.0),
            _ => self.root.draw(&Polygon::new(
                vec![
                    (c.0, c.1 - r - 1),
                    (c.0 + r + 1, c.1 + r),
                    (c.0 - r - 1, c.1 + r),
                ],
                colour.filled(),
            )),
        }
    }

    /// Text anchored at `at`; plotters escapes it for XML.
    pub(super) fn text(&self, at: Px, text: &str, font: Font) -> DrawResult {
        self.root.draw_text(&plain(text), &font.style(), at)
    }

    /// An interval bar from `a` to `b` (pixels) with end caps, in the style of `kind`.
    pub(super) fn interval(&self, a: Px, b: Px, dir: Dir, kind: Kind) -> DrawResult {
        let colour = kind.colour();
        if kind.dashed() {
            self.dashed(a, b, colour, 2)?;
        } else {
            self.line(a, b, colour, 3)?;
        }
        let (cx, cy) = match dir {
            Dir::Horizontal => (0, CAP),
            Dir::Vertical => (CAP, 0),
        };
        for p in [a, b] {
            self.line((p.0 - cx, p.1 - cy), (p.0 + cx, p.1 + cy), colour, 2)?;
        }
        Ok(())
    }

    /// A grey note (e.g. why an interval is missing) starting at `at`.
    pub(super) fn note(&self, at: Px, text: &str) -> DrawResult {
        self.text(at, text, Font::new(11.0).colour(MUTED))
    }
}

/// What a legend entry shows next to its text.
#[derive(Debug, Clone, Copy)]
pub(super) enum Swatch {
    /// One X-ray's value.
    Point,
    /// An X-ray worth naming (flagged, outside the prediction interval, newest).
    Named,
    /// X-rays binned into a histogram.
    Histogram,
    /// The mean.
    Mean,
    /// An interval bar.
    Interval(Kind),
    /// The observed range band.
    Range,
    /// A joint at the root or the tip.
    Joint,
    /// The marker of the k-th rig.
    Marker(usize),
}

/// One legend entry.
#[derive(Debug, Clone)]
pub(super) struct LegendItem {
    pub swatch: Swatch,
    pub label: String,
}

impl LegendItem {
    /// An entry.
    pub(super) fn new(swatch: Swatch, label: impl Into<String>) -> LegendItem {
        LegendItem {
            swatch,
            label: label.into(),
        }
    }

    /// The entries of the four intervals.
    pub(super) fn intervals(confidence: f64, unit: &str) -> Vec<LegendItem> {
        Kind::ALL
            .iter()
            .map(|&k| LegendItem::new(Swatch::Interval(k), k.legend(confidence, unit)))
            .collect()
    }
}

/// Where each legend entry goes, relative to the legend's top-left, and the legend's height.
/// Entries flow left to right and wrap at `width`.
fn legend_layout(items: &[LegendItem], width: i32) -> (Vec<Px>, i32) {
    let (mut x, mut y) = (0, 0);
    let mut at = Vec::with_capacity(items.len());
    for item in items {
        let w = SWATCH_W + 6 + text_width(&item.label, LEGEND_PX) + 18;
        if x > 0 && x + w > width {
            x = 0;
            y += LEGEND_ROW;
        }
        at.push((x, y));
        x += w;
    }
    let rows = if items.is_empty() { 0 } else { y + LEGEND_ROW };
    (at, rows)
}

/// Height of the legend block of `items` (with padding), in pixels.
fn legend_height(items: &[LegendItem]) -> u32 {
    let (_, h) = legend_layout(items, legend_width());
    if h == 0 { 0 } else { (h + 10) as u32 }
}

/// Usable legend width.
fn legend_width() -> i32 {
    WIDTH as i32 - 2 * MARGIN
}

/// Draws a legend whose top-left corner is at `(MARGIN, top)`.
fn draw_legend(pen: &Pen, top: i32, items: &[LegendItem]) -> DrawResult {
    let (at, _) = legend_layout(items, legend_width());
    for (item, (x, y)) in items.iter().zip(at) {
        let (x, mid) = (MARGIN + x, top + y + LEGEND_ROW / 2);
        draw_swatch(pen, (x, mid), item.swatch)?;
        let font = Font::new(LEGEND_PX).colour(INK);
        pen.text((x + SWATCH_W + 6, mid), &item.label, font)?;
    }
    Ok(())
}

/// One swatch whose left edge is at `left.0`, vertically centred on `left.1`.
fn draw_swatch(pen: &Pen, left: Px, swatch: Swatch) -> DrawResult {
    let (x, y) = left;
    let mid = (x + SWATCH_W / 2, y);
    match swatch {
        Swatch::Point => pen.dot(mid, 4, POINT, 0.85),
        Swatch::Named => pen.dot(mid, 5, NAMED, 1.0),
        Swatch::Histogram => {
            for (i, h) in [4, 9, 6].into_iter().enumerate() {
                let x0 = x + 6 + 6 * i as i32;
                pen.rect((x0, y + 6 - h), (x0 + 5, y + 6), POINT, 0.6)?;
            }
            Ok(())
        }
        Swatch::Mean => {
            pen.line((mid.0, y - 8), (mid.0, y + 8), INK, 1)?;
            pen.diamond(mid, 5)
        }
        Swatch::Interval(kind) => {
            pen.interval((x + 3, y), (x + SWATCH_W - 3, y), Dir::Horizontal, kind)
        }
        Swatch::Range => pen.rect((x + 2, y - 6), (x + SWATCH_W - 2, y + 6), RANGE, 0.55),
        Swatch::Joint => pen.dot(mid, 5, INK, 1.0),
        Swatch::Marker(k) => pen.marker(mid, k),
    }
}

/// Colours of rig markers (Okabe-Ito blue, vermillion, bluish green, reddish purple, sky blue).
const MARKER_COLOURS: [RGBColor; 5] = [
    RGBColor(0x00, 0x72, 0xB2),
    RGBColor(0xD5, 0x5E, 0x00),
    RGBColor(0x00, 0x9E, 0x73),
    RGBColor(0xCC, 0x79, 0xA7),
    RGBColor(0x56, 0xB4, 0xE9),
];

/// The top of every plot: a bold title, a wrapped subtitle and the legend.
pub(super) struct Frame<'t> {
    title: &'t str,
    subtitle: Vec<String>,
    legend: &'t [LegendItem],
}

/// Height of one subtitle line, in pixels.
const SUBTITLE_LINE: i32 = 16;
/// Font size of the subtitle, in pixels.
const SUBTITLE_PX: f64 = 12.0;

impl<'t> Frame<'t> {
    /// A frame; the subtitle is wrapped to the plot's width.
    pub(super) fn new(title: &'t str, subtitle: &str, legend: &'t [LegendItem]) -> Frame<'t> {
        Frame {
            title,
            subtitle: wrap(subtitle, SUBTITLE_PX, legend_width()),
            legend,
        }
    }

    /// Height of the title, subtitle and legend in pixels.
    pub(super) fn height(&self) -> u32 {
        self.legend_top() as u32 + legend_height(self.legend)
    }

    /// Top of the legend, below the last subtitle line.
    fn legend_top(&self) -> i32 {
        let extra = self.subtitle.len().saturating_sub(1) as i32;
        HEADER_H as i32 + SUBTITLE_LINE * extra
    }

    /// Draws the frame; returns the y pixel where the plot body starts.
    pub(super) fn draw(&self, pen: &Pen) -> Result<i32, DrawError> {
        pen.text((MARGIN, 20), self.title, Font::new(17.0).bold())?;
        let font = Font::new(SUBTITLE_PX).colour(MUTED);
        for (i, line) in self.subtitle.iter().enumerate() {
            pen.text((MARGIN, 44 + SUBTITLE_LINE * i as i32), line, font)?;
        }
        draw_legend(pen, self.legend_top(), self.legend)?;
        Ok(self.height() as i32)
    }
}

/// Splits `text` into lines at spaces so each fits `width` pixels at `px` (a
/// single over-long word keeps its own line).
fn wrap(text: &str, px: f64, width: i32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if !line.is_empty() && text_width(&candidate, px) > width {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// One row of a row chart: a quantity of a finger.
pub(super) struct QuantityRow<'s> {
    /// "index J~1", "ring J2/J1".
    pub label: String,
    pub finger: Finger,
    /// Position of the finger in the analysis (alternate fingers are shaded).
    pub group: usize,
    pub stats: &'s QuantityStats,
}

/// The rows of the quantities `keep` accepts, top to bottom: fingers in the
/// analysis's order, their quantities in order.
pub(super) fn quantity_rows(a: &Analysis, keep: impl Fn(Quantity) -> bool) -> Vec<QuantityRow<'_>> {
    a.fingers
        .iter()
        .enumerate()
        .flat_map(|(group, f)| {
            f.quantities
                .iter()
                .filter(|s| keep(s.name))
                .map(move |s| QuantityRow {
                    label: format!("{} {}", f.finger.name(), s.name.symbol()),
                    finger: f.finger,
                    group,
                    stats: s,
                })
        })
        .collect()
}

/// A chart of quantity rows over a linear x axis from `x.0` to `x.1`: row r
/// (from the top) at y = count - 1 - r; rows of odd groups are shaded; the
/// axes are drawn, and without rows `empty` is written in the middle. Shared
/// by the forest and rig plots.
pub(super) fn row_chart<'a, 'b>(
    pen: &Pen,
    area: &'a Root<'b>,
    rows: &[QuantityRow<'_>],
    x: (f64, f64),
    (top_px, axis_px): (u32, u32),
    (x_desc, y_desc, empty): (&str, &str, &str),
) -> Result<Chart<'a, 'b, Linear, Categories>, DrawError> {
    let count = rows.len();
    let (x0, x1) = x;
    let keys: Vec<f64> = (0..count).map(|i| i as f64).collect();
    let y_top = count.max(1) as f64 - 0.5;
    let mut chart: Chart<'a, 'b, Linear, Categories> = ChartBuilder::on(area)
        .margin_top(top_px)
        .margin_left(MARGIN)
        .margin_right(MARGIN + 8)
        .x_label_area_size(axis_px)
        .y_label_area_size(104)
        .build_cartesian_2d(x0..x1, Categories::new(-0.5, y_top, keys))?;
    let y_of = |r: usize| (count - 1 - r) as f64;
    {
        let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
        for (r, _) in rows
            .iter()
            .enumerate()
            .filter(|(_, row)| row.group % 2 == 1)
        {
            pen.rect(at(x0, y_of(r) + 0.5), at(x1, y_of(r) - 0.5), SHADE, 1.0)?;
        }
    }
    let x_format = tick_format(x1 - x0);
    let y_format = |y: &f64| {
        let r = count as f64 - 1.0 - y.round();
        if r >= 0.0 {
            rows.get(r as usize).map_or("", |row| row.label.as_str())
        } else {
            ""
        }
        .to_string()
    };
    let axes = Axes {
        x_desc: x_desc.to_string(),
        y_desc: y_desc.to_string(),
        x_grid: true,
        x_format: &x_format,
        y_format: &y_format,
    };
    draw_axes(&mut chart, &axes)?;
    if rows.is_empty() {
        let font = Font::new(14.0)
            .colour(MUTED)
            .anchor(HPos::Center, VPos::Center);
        pen.text(chart.backend_coord(&((x0 + x1) / 2.0, 0.0)), empty, font)?;
    }
    Ok(chart)
}

/// Texts and tick formats of a chart's two axes.
pub(super) struct Axes<'f> {
    pub x_desc: String,
    pub y_desc: String,
    /// Draw grid lines across the plot at the x ticks.
    pub x_grid: bool,
    pub x_format: &'f dyn Fn(&f64) -> String,
    pub y_format: &'f dyn Fn(&f64) -> String,
}

/// Draws a chart's grid, ticks, tick labels and axis descriptions in the shared style.
pub(super) fn draw_axes<X, Y>(chart: &mut Chart<'_, '_, X, Y>, axes: &Axes) -> DrawResult
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut mesh = chart.configure_mesh();
    if !axes.x_grid {
        mesh.disable_x_mesh();
    }
    mesh.x_desc(plain(&axes.x_desc))
        .y_desc(plain(&axes.y_desc))
        .x_label_formatter(axes.x_format)
        .y_label_formatter(axes.y_format)
        .x_labels(8)
        .y_labels(8)
        .label_style(Font::new(12.0).style())
        .axis_desc_style(Font::new(12.0).style())
        .axis_style(MUTED.stroke_width(1))
        .bold_line_style(GRID.stroke_width(1))
        .light_line_style(TRANSPARENT)
        .draw()
}

/// A tick formatter with enough decimals for ticks spaced over `span` (about 8 ticks).
pub(super) fn tick_format(span: f64) -> impl Fn(&f64) -> String {
    let decimals = format::step_decimals(span / 8.0);
    move |v: &f64| format::num(*v, decimals)
}

/// `[lo, hi]` widened by `frac` of its span on each side; a point or an empty or
/// non-finite range becomes a small window, so the axis always has extent.
pub(super) fn padded(lo: f64, hi: f64, frac: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        span * frac
    } else {
        (lo.abs() * 0.05).max(1e-3)
    };
    (lo - pad, hi + pad)
}

/// The smallest and largest finite values, if any.
pub(super) fn extent(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// Every end of every interval, and the mean, min and max, of a quantity.
pub(super) fn stats_values(s: &QuantityStats) -> Vec<f64> {
    let mut v = vec![s.mean, s.min, s.max];
    for kind in Kind::ALL {
        if let Some(i) = kind.of(s) {
            v.extend([i.low, i.high]);
        }
    }
    v
}

/// "1 X-ray", "5 X-rays".
pub(super) fn xrays(n: usize) -> String {
    format::xrays(n)
}

/// Text without control characters (XML 1.0 cannot carry most of them).
pub(super) fn plain(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// At most `max` characters of `text`, with an ellipsis when cut.
pub(super) fn clip(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(max.saturating_sub(1)).collect();
        s.push('\u{2026}');
        s
    }
}

/// Escapes text for XML content and attribute values.
pub(super) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in plain(text).chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            other => out.push(other),
        }
    }
    out
}

/// Draws on a fresh white `size` canvas and returns the SVG text.
/// `context` names the plot in errors ("drawing the hand diagram").
pub(super) fn render<F>(size: (u32, u32), context: &str, draw: F) -> Result<String, Error>
where
    F: FnOnce(&Root<'_>) -> DrawResult,
{
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)
            .and_then(|()| draw(&root))
            .and_then(|()| root.present())
            .map_err(|e| Error::render(context.to_string(), e.to_string()))?;
    }
    Ok(svg)
}

/// Makes a finished [`Plot`]: gives the root `<svg>` `role="img"`, labels it with a
/// `<title>` and a `<desc>` (its first children, ids prefixed with the plot's id).
pub(super) fn finish(
    id: String,
    kind: PlotKind,
    title: String,
    description: String,
    svg: String,
) -> Result<Plot, Error> {
    let end = svg
        .starts_with("<svg")
        .then(|| svg.find('>'))
        .flatten()
        .ok_or_else(|| {
            Error::render(
                format!("labelling the {id} plot"),
                "the SVG backend wrote no root <svg> element",
            )
        })?;
    let idx = escape(&id);
    let mut out = String::with_capacity(svg.len() + title.len() + description.len() + 200);
    out.push_str(&svg[..end]);
    // Writing into a String cannot fail.
    let _ = write!(
        out,
        " role=\"img\" aria-labelledby=\"{idx}-title\" aria-describedby=\"{idx}-desc\">\n\
         <title id=\"{idx}-title\">{}</title>\n<desc id=\"{idx}-desc\">{}</desc>",
        escape(&title),
        escape(&description),
    );
    out.push_str(&svg[end + 1..]);
    Ok(Plot {
        id,
        kind,
        title,
        description,
        svg: out,
    })
}
