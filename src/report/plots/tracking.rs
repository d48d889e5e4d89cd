//! The tracking plot: how one finger's mean relative segment lengths and their
//! Student t confidence intervals moved as X-rays were added, snapshot by snapshot.
//!
//! One panel per relative quantity (J~1, J~2[, J~3]), stacked, each with its own
//! y range (J~1 is near 0.48, J~3 near 0.24) and all with the same x range (the
//! snapshot's number in the history, integer ticks), so a removal and a re-addition
//! stay in time order: the mean as a line with a diamond per snapshot, the interval
//! as a vertical bar per snapshot over a shaded band joining neighbouring intervals.
//! A snapshot that removed rows is marked with a ring, one that added rows flagged
//! as likely errors with a square; the legend names both.

use super::draw::{
    Axes, Categories, Chart, Dir, DrawResult, Font, Frame, INK, Kind, LegendItem, Linear, MARGIN,
    MUTED, NAMED, Pen, Px, RANGE, Root, WIDTH, clip, draw_axes, extent, finish, padded, render,
    text_width, tick_format, xrays,
};
use super::kinds::{Plot, PlotKind, TrackPoint, TrackSeries, finger_phrase};
use crate::dataset::Finger;
use crate::error::Error;
use crate::format::{self, level};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Pixels above a panel's plotting area (its heading).
const PANEL_TOP_PX: u32 = 30;
/// Height of a panel's plotting area in pixels.
const CHART_PX: u32 = 140;
/// Pixels below a panel's plotting area (tick labels and axis description).
const X_AXIS_PX: u32 = 46;
/// Height of the legend block in pixels.
const LEGEND_BLOCK_PX: u32 = 30;
/// Font size of legend entries, in pixels.
const LEGEND_FONT_PX: f64 = 12.0;
/// Width of a legend swatch, in pixels.
const SWATCH_W: i32 = 30;
/// Opacity of the shaded confidence band.
const BAND_OPACITY: f64 = 0.18;
/// Half-size of a mean marker (diamond), in pixels.
const MARKER: i32 = 4;
/// At most about this many ticks on the x axis.
const MAX_TICKS: f64 = 8.0;
/// Decimals of relative values in the description.
const DECIMALS: usize = 4;
/// The x range when there is no snapshot at all.
const EMPTY_X: (f64, f64) = (0.0, 10.0);

/// One series, ready to draw.
struct Panel<'s> {
    label: &'s str,
    /// The snapshots with a finite mean, in snapshot order.
    points: Vec<TrackPoint>,
}

impl<'s> Panel<'s> {
    /// The drawable snapshots of `s`.
    fn new(s: &'s TrackSeries) -> Panel<'s> {
        let mut points: Vec<TrackPoint> = s
            .points
            .iter()
            .filter(|p| p.mean.is_finite())
            .copied()
            .collect();
        points.sort_by_key(|p| p.snapshot);
        Panel {
            label: &s.label,
            points,
        }
    }

    /// The y range: every mean and interval end, padded.
    fn y_range(&self) -> (f64, f64) {
        let values = self.points.iter().flat_map(|p| {
            let (lo, hi) = ci(p).unwrap_or((p.mean, p.mean));
            [p.mean, lo, hi]
        });
        extent(values).map_or((0.0, 1.0), |(lo, hi)| padded(lo, hi, 0.08))
    }
}

/// A snapshot's interval as `(low, high)`, if both ends are finite.
fn ci(p: &TrackPoint) -> Option<(f64, f64)> {
    p.ci.filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
        .map(|(lo, hi)| (lo.min(hi), lo.max(hi)))
}

/// Draws the tracking plot of one finger.
pub(super) fn plot(finger: Finger, series: &[TrackSeries], confidence: f64) -> Result<Plot, Error> {
    let placeholder = TrackSeries {
        label: String::new(),
        points: Vec::new(),
    };
    let mut panels: Vec<Panel> = series.iter().map(Panel::new).collect();
    if panels.is_empty() {
        panels.push(Panel::new(&placeholder));
    }
    let (x0, x1) = x_range(&panels);
    let keys = integer_ticks(x0, x1);
    let title = format!("Tracking the means of {}", finger_phrase(finger));
    let subtitle = format!(
        "Each relative segment length's mean snapshot by snapshot (the history's records in \
         order), one panel per segment with its own y range. Per snapshot: the mean (diamonds, \
         joined by a line) and its {} Student t confidence interval (bars, with a band between \
         neighbouring snapshots); rings mark removals, squares additions of flagged rows.",
        level(confidence)
    );
    // The legend is drawn here: its swatches (a line with a marker, a band) are this plot's own.
    let no_legend: Vec<LegendItem> = Vec::new();
    let frame = Frame::new(&title, &subtitle, &no_legend);
    let panel_px = PANEL_TOP_PX + CHART_PX + X_AXIS_PX;
    let body = panel_px * panels.len() as u32;
    let height = frame.height() + LEGEND_BLOCK_PX + body + 8;
    let context = format!("drawing the tracking plot for {}", finger.name());
    let svg = render((WIDTH, height), &context, |root| {
        let pen = Pen::new(root);
        let mut top = frame.draw(&pen)?;
        draw_legend(root, &pen, top, confidence)?;
        top += LEGEND_BLOCK_PX as i32;
        for panel in &panels {
            let area = root.clone().shrink((0, top), (WIDTH, panel_px));
            draw_panel(root, &pen, &area, top, panel, (x0, x1), &keys)?;
            top += panel_px as i32;
        }
        Ok(())
    })?;
    finish(
        format!("tracking-{}", finger.name()),
        PlotKind::Tracking,
        title,
        description(finger, series, confidence),
        svg,
    )
}

/// The shared x range: every snapshot's number, padded by at least one on each
/// side so a single snapshot sits inside the axis.
fn x_range(panels: &[Panel]) -> (f64, f64) {
    let all = panels
        .iter()
        .flat_map(|p| p.points.iter().map(|q| q.snapshot as f64));
    match extent(all) {
        Some((lo, hi)) => {
            let pad = ((hi - lo) * 0.04).max(1.0);
            (lo - pad, hi + pad)
        }
        None => EMPTY_X,
    }
}

/// Integer ticks in `[lo, hi]` (non-negative only), spaced 1, 2 or 5 times a power of ten.
fn integer_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return Vec::new();
    }
    let raw = (hi - lo) / MAX_TICKS;
    let step = (0..400)
        .map(|k| [1.0, 2.0, 5.0][k % 3] * 10f64.powi((k / 3) as i32))
        .find(|&s| s >= raw)
        .unwrap_or(f64::INFINITY);
    if !step.is_finite() {
        return Vec::new();
    }
    let first = (lo.max(0.0) / step).ceil();
    (0..)
        .map(|i| (first + i as f64) * step)
        .take_while(|&v| v <= hi)
        .collect()
}

/// The legend at `top`: the mean (a line with a marker), the interval (a band with a
/// bar), and the marks of removals and of flagged rows added.
fn draw_legend(root: &Root<'_>, pen: &Pen, top: i32, confidence: f64) -> DrawResult {
    let mid = top + LEGEND_BLOCK_PX as i32 / 2 - 4;
    let font = Font::new(LEGEND_FONT_PX);
    let mut x = MARGIN;
    pen.line((x + 2, mid), (x + SWATCH_W - 2, mid), INK, 2)?;
    pen.diamond((x + SWATCH_W / 2, mid), MARKER)?;
    x += SWATCH_W + 6;
    pen.text((x, mid), "mean", font)?;
    x += text_width("mean", LEGEND_FONT_PX) + 18;
    let t = Kind::T.colour();
    pen.rect(
        (x + 2, mid - 8),
        (x + SWATCH_W - 2, mid + 8),
        t,
        BAND_OPACITY,
    )?;
    let c = x + SWATCH_W / 2;
    pen.interval((c, mid - 7), (c, mid + 7), Dir::Vertical, Kind::T)?;
    x += SWATCH_W + 6;
    let label = format!("{} t confidence interval", level(confidence));
    pen.text((x, mid), &label, font)?;
    x += text_width(&label, LEGEND_FONT_PX) + 18;
    removal_mark(root, (x + SWATCH_W / 2, mid))?;
    x += SWATCH_W + 6;
    pen.text((x, mid), "removal (rows taken out)", font)?;
    x += text_width("removal (rows taken out)", LEGEND_FONT_PX) + 18;
    flagged_mark(root, (x + SWATCH_W / 2, mid))?;
    x += SWATCH_W + 6;
    pen.text((x, mid), "flagged rows added", font)
}

/// The ring around a snapshot that removed rows.
fn removal_mark(root: &Root<'_>, c: Px) -> DrawResult {
    root.draw(&Circle::new(c, MARKER + 4, NAMED.stroke_width(2)))?;
    Ok(())
}

/// The square around a snapshot that added rows flagged as likely errors.
fn flagged_mark(root: &Root<'_>, (x, y): Px) -> DrawResult {
    let r = MARKER + 4;
    root.draw(&Rectangle::new(
        [(x - r, y - r), (x + r, y + r)],
        RANGE.stroke_width(2),
    ))?;
    Ok(())
}

/// Draws one series' panel into `area` (a full-width slice of `root` starting at
/// pixel row `top`) over the shared x range with ticks at `keys`.
fn draw_panel(
    root: &Root<'_>,
    pen: &Pen,
    area: &Root<'_>,
    top: i32,
    panel: &Panel,
    (x0, x1): (f64, f64),
    keys: &[f64],
) -> DrawResult {
    draw_heading(pen, top, panel)?;
    let (y0, y1) = panel.y_range();
    let mut chart: Chart<'_, '_, Categories, Linear> = ChartBuilder::on(area)
        .margin_top(PANEL_TOP_PX)
        .margin_left(MARGIN)
        .margin_right(MARGIN + 8)
        .x_label_area_size(X_AXIS_PX)
        .y_label_area_size(84)
        .build_cartesian_2d(Categories::new(x0, x1, keys.to_vec()), y0..y1)?;
    let x_format = |x: &f64| format::num(*x, 0);
    let y_format = tick_format(y1 - y0);
    let axes = Axes {
        x_desc: "snapshot (record of the history, in order)".to_string(),
        y_desc: "fraction of total length J".to_string(),
        x_grid: true,
        x_format: &x_format,
        y_format: &y_format,
    };
    draw_axes(&mut chart, &axes)?;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    if panel.points.is_empty() {
        let font = Font::new(14.0)
            .colour(MUTED)
            .anchor(HPos::Center, VPos::Center);
        return pen.text(
            at((x0 + x1) / 2.0, (y0 + y1) / 2.0),
            "no snapshots yet",
            font,
        );
    }
    draw_snapshots(root, pen, &at, &panel.points)
}

/// The panel's heading: the series label and how many snapshots it has.
fn draw_heading(pen: &Pen, top: i32, panel: &Panel) -> DrawResult {
    if panel.label.is_empty() {
        return Ok(());
    }
    let y = top + PANEL_TOP_PX as i32 / 2 + 2;
    let label = clip(panel.label, 60);
    pen.text((MARGIN, y), &label, Font::new(13.0).bold())?;
    let n = panel.points.len();
    let missing = panel.points.iter().filter(|p| ci(p).is_none()).count();
    let removals = panel.points.iter().filter(|p| p.removal).count();
    let flagged = panel.points.iter().filter(|p| p.flagged > 0).count();
    let mut info = match n {
        0 => return Ok(()),
        1 => "1 snapshot".to_string(),
        n => format!("{n} snapshots"),
    };
    if let Some((lo, hi)) = extent(panel.points.iter().map(|p| p.xrays as f64)) {
        info.push_str(&if lo == hi {
            format!(", {}", xrays(lo as usize))
        } else {
            format!(", {} to {} X-rays", format::num(lo, 0), format::num(hi, 0))
        });
    }
    if removals > 0 {
        info.push_str(&format!(", {removals} with a removal"));
    }
    if flagged > 0 {
        info.push_str(&format!(", {flagged} adding flagged rows"));
    }
    if missing > 0 {
        info.push_str(&format!(", {missing} without an interval"));
    }
    let x = MARGIN + text_width(&label, 13.0) + 12;
    pen.note((x, y), &info)
}

/// The band, the mean line, the interval bars and the mean markers of sorted
/// `points`; `at` maps a value to pixels.
fn draw_snapshots(
    root: &Root<'_>,
    pen: &Pen,
    at: &dyn Fn(f64, f64) -> Px,
    points: &[TrackPoint],
) -> DrawResult {
    let t = Kind::T.colour();
    for run in points.chunk_by(|a, b| ci(a).is_some() == ci(b).is_some()) {
        if run.len() < 2 || ci(&run[0]).is_none() {
            continue;
        }
        let ends: Vec<(f64, (f64, f64))> = run
            .iter()
            .filter_map(|p| ci(p).map(|i| (p.snapshot as f64, i)))
            .collect();
        let upper = ends.iter().map(|&(x, (_, hi))| at(x, hi));
        let lower = ends.iter().rev().map(|&(x, (lo, _))| at(x, lo));
        let outline: Vec<Px> = upper.chain(lower).collect();
        root.draw(&Polygon::new(outline, t.mix(BAND_OPACITY).filled()))?;
    }
    if points.len() > 1 {
        let line: Vec<Px> = points
            .iter()
            .map(|p| at(p.snapshot as f64, p.mean))
            .collect();
        root.draw(&PathElement::new(line, INK.stroke_width(2)))?;
    }
    for p in points {
        if let Some((lo, hi)) = ci(p) {
            let x = p.snapshot as f64;
            pen.interval(at(x, lo), at(x, hi), Dir::Vertical, Kind::T)?;
        }
    }
    for p in points {
        let c = at(p.snapshot as f64, p.mean);
        pen.diamond(c, MARKER)?;
        if p.removal {
            removal_mark(root, c)?;
        }
        if p.flagged > 0 {
            flagged_mark(root, c)?;
        }
    }
    Ok(())
}

/// The screen-reader description: per series, its first and last snapshot.
fn description(finger: Finger, series: &[TrackSeries], confidence: f64) -> String {
    let mut d = format!(
        "Tracking plot of {}: the mean of each relative segment length (fraction of the \
         finger's total length J) snapshot by snapshot, in the history's order, one point \
         per snapshot, with its {} Student t confidence interval; snapshots that removed rows \
         and that added rows flagged as likely errors are marked.",
        finger_phrase(finger),
        level(confidence)
    );
    if series.is_empty() {
        d.push_str(" No snapshots yet.");
    }
    for s in series {
        d.push(' ');
        d.push_str(&series_sentence(s, confidence));
    }
    d
}

/// "J~1 = J1/J: 4 snapshots; first at 3 X-rays: mean 0.4846, 95% t confidence
/// interval from 0.4712 to 0.4980; last at ...".
fn series_sentence(s: &TrackSeries, confidence: f64) -> String {
    let label = &s.label;
    match s.points.as_slice() {
        [] => format!("{label}: no snapshots yet."),
        [only] => format!("{label}: 1 snapshot {}.", point_words(only, confidence)),
        [first, .., last] => format!(
            "{label}: {} snapshots; first {}; last {}.",
            s.points.len(),
            point_words(first, confidence),
            point_words(last, confidence)
        ),
    }
}

/// "at snapshot 2 (3 X-rays): mean 0.4846, 95% t confidence interval from 0.4712 to 0.4980".
fn point_words(p: &TrackPoint, confidence: f64) -> String {
    let interval = match p.ci {
        Some((lo, hi)) => format!(
            "{} t confidence interval from {} to {}",
            level(confidence),
            format::num(lo, DECIMALS),
            format::num(hi, DECIMALS)
        ),
        None => "no confidence interval".to_string(),
    };
    let mark = match (p.removal, p.flagged) {
        (true, _) => ", a removal",
        (false, 0) => "",
        (false, _) => ", adding flagged rows",
    };
    format!(
        "at snapshot {} ({}{mark}): mean {}, {interval}",
        p.snapshot,
        xrays(p.xrays),
        format::num(p.mean, DECIMALS)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_ticks_are_few_and_whole() {
        assert_eq!(integer_ticks(0.0, 2.0), [0.0, 1.0, 2.0]);
        assert_eq!(integer_ticks(4.5, 5.5), [5.0]);
        assert_eq!(integer_ticks(-1.0, 3.0), [0.0, 1.0, 2.0, 3.0]);
        let wide = integer_ticks(-34.8, 1039.8);
        assert_eq!(wide, [0.0, 200.0, 400.0, 600.0, 800.0, 1000.0]);
        assert!(integer_ticks(f64::NAN, 1.0).is_empty());
        assert!(integer_ticks(0.0, f64::INFINITY).is_empty());
    }

    #[test]
    fn a_single_snapshot_sits_inside_the_x_range() {
        let s = TrackSeries {
            label: "J~1".to_string(),
            points: vec![TrackPoint {
                snapshot: 1,
                removal: false,
                flagged: 0,
                xrays: 1,
                mean: 0.5,
                ci: None,
            }],
        };
        assert_eq!(x_range(&[Panel::new(&s)]), (0.0, 2.0));
        assert_eq!(x_range(&[]), EMPTY_X);
    }
}
