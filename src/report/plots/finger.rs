//! The per-finger plot: one panel per relative quantity (J~1, J~2[, J~3]), each
//! with every X-ray's value, the mean, and the four intervals on their own rows.
//!
//! X-rays are drawn one by one while there are few (labelled with their ids up
//! to [`LABELLED_MAX`], deterministically jittered up to [`POINTS_MAX`]) and as a
//! histogram beyond, so the SVG stays small whatever the number of X-rays. Beyond
//! [`LABELLED_MAX`] only the X-rays worth naming carry their id, at most
//! [`NAMED_MAX`] per panel, each on a lane of its own so the labels stay legible:
//! rows added though flagged, X-rays outside the panel's prediction interval (the
//! farthest first), and the newest addition when it has at most [`NEWEST_NAMED`] X-rays.

use super::draw::{
    Axes, Categories, Chart, Dir, DrawResult, Font, Frame, INK, Kind, LegendItem, Linear, MARGIN,
    MUTED, NAMED, POINT, Pen, Px, Root, Swatch, WIDTH, clip, draw_axes, extent, finish, padded,
    render, stats_values, text_width, tick_format,
};
use super::kinds::{Named, Plot, PlotKind, finger_phrase};
use crate::analysis::{FingerAnalysis, Quantity, QuantityStats};
use crate::error::Error;
use crate::format;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Up to this many X-rays, each point carries its X-ray's id.
pub(super) const LABELLED_MAX: usize = 12;
/// Beyond [`LABELLED_MAX`], at most this many X-rays per panel carry their id.
pub(super) const NAMED_MAX: usize = 8;
/// The newest addition is named when it has at most this many X-rays.
pub(super) const NEWEST_NAMED: usize = 4;
/// Rows of the strip per named X-ray (its lane).
const NAMED_LANE: f64 = 0.6;
/// Beyond this many X-rays, values are binned instead of drawn one by one.
pub(super) const POINTS_MAX: usize = 2000;
/// Up to this many X-rays, the description lists every value.
const LISTED_MAX: usize = 30;
/// Bins of the histogram strip.
const BINS: usize = 120;
/// Pixels per row of the panel's y axis.
const ROW_PX: f64 = 24.0;
/// Pixels below a panel's plotting area (tick labels and axis description).
const X_AXIS_PX: u32 = 46;
/// Pixels above a panel's plotting area.
const PANEL_TOP_PX: u32 = 10;
/// Y of the bottom of the X-ray strip, in rows (the intervals sit at 0..=3).
const STRIP_LOW: f64 = 3.7;
/// The inverse golden ratio: a low-discrepancy sequence for deterministic jitter.
const GOLDEN: f64 = 0.618_033_988_749_895;

/// How the X-rays of a panel are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Strip {
    /// One lane per X-ray, each point labelled with its id.
    Labelled,
    /// Points jittered vertically by a fixed sequence.
    Jittered,
    /// A histogram of the values.
    Binned,
}

impl Strip {
    /// The strip for `n` X-rays.
    fn for_count(n: usize) -> Strip {
        if n <= LABELLED_MAX {
            Strip::Labelled
        } else if n <= POINTS_MAX {
            Strip::Jittered
        } else {
            Strip::Binned
        }
    }
}

/// The vertical layout of a panel, in rows: intervals at 0 (prediction) to 3 (t),
/// the X-ray strip from [`STRIP_LOW`] to `strip_high`.
#[derive(Debug, Clone, Copy)]
struct Rows {
    strip_high: f64,
    y0: f64,
    y1: f64,
}

impl Rows {
    /// The layout for `n` X-rays drawn as `strip`, `named` of them on lanes of their own.
    fn new(strip: Strip, n: usize, named: usize) -> Rows {
        let height = match strip {
            Strip::Labelled => (0.55 * n as f64).max(1.2),
            Strip::Jittered | Strip::Binned => 2.5 + NAMED_LANE * named as f64,
        };
        let strip_high = STRIP_LOW + height;
        Rows {
            strip_high,
            y0: -0.6,
            y1: strip_high + 0.3,
        }
    }

    /// Y of an interval's row.
    fn of(kind: Kind) -> f64 {
        match kind {
            Kind::T => 3.0,
            Kind::Percentile => 2.0,
            Kind::Bca => 1.0,
            Kind::Prediction => 0.0,
        }
    }

    /// Middle of the X-ray strip (where its axis label goes).
    fn strip_mid(&self) -> f64 {
        (STRIP_LOW + self.strip_high) / 2.0
    }

    /// The y tick positions: the four interval rows and the strip.
    fn keys(&self) -> Vec<f64> {
        let mut keys: Vec<f64> = Kind::ALL.iter().map(|&k| Rows::of(k)).collect();
        keys.push(self.strip_mid());
        keys
    }

    /// The y tick label at `y`.
    fn label(&self, y: f64) -> String {
        if (y - self.strip_mid()).abs() < 0.05 {
            return "X-rays".to_string();
        }
        Kind::ALL
            .iter()
            .find(|&&k| (Rows::of(k) - y).abs() < 0.05)
            .map_or_else(String::new, |k| k.short().to_string())
    }

    /// Height of a panel in pixels.
    fn panel_px(&self) -> u32 {
        ((self.y1 - self.y0) * ROW_PX).round() as u32 + X_AXIS_PX + PANEL_TOP_PX
    }
}

/// Why an X-ray is named in a panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Why {
    Flagged,
    Outside,
    Newest,
}

/// One relative quantity of the finger with its per-X-ray values.
struct Panel<'f> {
    stats: &'f QuantityStats,
    /// `(X-ray id, value)` in X-ray order.
    values: Vec<(&'f str, f64)>,
    /// Indices into `values` of the X-rays worth naming (beyond [`LABELLED_MAX`]),
    /// ordered by value, at most [`NAMED_MAX`].
    named: Vec<usize>,
}

impl<'f> Panel<'f> {
    /// The panels of a finger: its relative quantities, in order.
    fn all(f: &'f FingerAnalysis, named: &Named) -> Vec<Panel<'f>> {
        f.quantities
            .iter()
            .filter_map(|s| {
                let k = segment_index(s.name)?;
                let values: Vec<(&str, f64)> = f
                    .xrays
                    .iter()
                    .filter_map(|x| x.relative.get(k).map(|&v| (&*x.xray, v)))
                    .collect();
                let named = if values.len() > LABELLED_MAX {
                    worth_naming(&values, s, f.finger, named)
                } else {
                    Vec::new()
                };
                Some(Panel {
                    stats: s,
                    values,
                    named,
                })
            })
            .collect()
    }

    /// The x range: every value and every interval, padded.
    fn x_range(&self, strip: Strip) -> (f64, f64) {
        let all = self
            .values
            .iter()
            .map(|&(_, v)| v)
            .chain(stats_values(self.stats));
        let (lo, hi) = extent(all).unwrap_or((0.0, 1.0));
        // Labelled points need room for their ids.
        let frac = if strip == Strip::Labelled { 0.12 } else { 0.06 };
        padded(lo, hi, frac)
    }
}

/// The X-rays of a panel worth naming, by index into `values`, ordered by value: the
/// flagged rows of the finger, then those outside the prediction interval (farthest
/// first), then the newest addition if it is small, at most [`NAMED_MAX`] in all. O(n log n).
fn worth_naming(
    values: &[(&str, f64)],
    s: &QuantityStats,
    finger: crate::dataset::Finger,
    named: &Named,
) -> Vec<usize> {
    let small_newest = named.newest.len() <= NEWEST_NAMED;
    let mut picks: Vec<(Why, f64, usize)> = values
        .iter()
        .enumerate()
        .filter_map(|(i, &(id, v))| {
            let beyond = s
                .intervals
                .pi
                .map_or(0.0, |pi| (pi.low - v).max(v - pi.high).max(0.0));
            let why = if named.flagged.iter().any(|(x, f)| x == id && *f == finger) {
                Why::Flagged
            } else if beyond > 0.0 {
                Why::Outside
            } else if small_newest && named.newest.iter().any(|x| x == id) {
                Why::Newest
            } else {
                return None;
            };
            Some((why, -beyond, i))
        })
        .collect();
    picks.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut out: Vec<usize> = picks.into_iter().take(NAMED_MAX).map(|p| p.2).collect();
    out.sort_by(|&a, &b| values[a].1.total_cmp(&values[b].1).then(a.cmp(&b)));
    out
}

/// The index into `XrayValues::relative` of a relative quantity.
fn segment_index(q: Quantity) -> Option<usize> {
    match q {
        Quantity::RelJ1 => Some(0),
        Quantity::RelJ2 => Some(1),
        Quantity::RelJ3 => Some(2),
        Quantity::RatioJ2J1
        | Quantity::RatioJ3J2
        | Quantity::Total
        | Quantity::RatioMcJ
        | Quantity::RatioJ1Mc => None,
    }
}

/// Draws the plot of one finger.
pub(super) fn plot(f: &FingerAnalysis, confidence: f64, named: &Named) -> Result<Plot, Error> {
    let n = f.xrays.len();
    let strip = Strip::for_count(n);
    let panels = Panel::all(f, named);
    let most_named = panels.iter().map(|p| p.named.len()).max().unwrap_or(0);
    let rows = Rows::new(strip, n, most_named);
    let legend = legend(strip, confidence, most_named > 0);
    let panel_px = rows.panel_px();
    let body = panel_px * panels.len() as u32;
    let title = format!("Relative segment lengths of {}", finger_phrase(f.finger));
    let subtitle = subtitle(strip, n, confidence);
    let context = format!("drawing the finger plot for {}", f.finger.name());
    let frame = Frame::new(&title, &subtitle, &legend);
    let height = frame.height() + body + 8;
    let svg = render((WIDTH, height), &context, |root| {
        let pen = Pen::new(root);
        let mut top = frame.draw(&pen)?;
        for panel in &panels {
            let area = root.clone().shrink((0, top), (WIDTH, panel_px));
            draw_panel(&pen, &area, panel, strip, rows)?;
            top += panel_px as i32;
        }
        Ok(())
    })?;
    let id = format!("finger-{}", f.finger.name());
    finish(
        id,
        PlotKind::Finger,
        title,
        description(f, &panels, confidence),
        svg,
    )
}

/// The legend: how X-rays are drawn, the named ones, the mean, the four intervals.
fn legend(strip: Strip, confidence: f64, named: bool) -> Vec<LegendItem> {
    let xray = match strip {
        Strip::Binned => LegendItem::new(Swatch::Histogram, "X-rays per bin (histogram)"),
        Strip::Labelled | Strip::Jittered => LegendItem::new(Swatch::Point, "one X-ray"),
    };
    let mut items = vec![xray];
    if named {
        items.push(LegendItem::new(
            Swatch::Named,
            "named: flagged, outside the prediction interval, or newest",
        ));
    }
    items.push(LegendItem::new(Swatch::Mean, "mean"));
    items.extend(LegendItem::intervals(confidence, "X-ray"));
    items
}

/// The line under the title.
fn subtitle(strip: Strip, n: usize, confidence: f64) -> String {
    let xrays = match strip {
        Strip::Labelled => "one labelled point per X-ray",
        Strip::Jittered => "one point per X-ray (spread vertically only for visibility)",
        Strip::Binned => "X-rays binned into a histogram (too many to draw one by one)",
    };
    format!(
        "n = {}. Per segment: {xrays}; the mean with its {} intervals.",
        super::draw::xrays(n),
        format::level(confidence)
    )
}

/// Draws one quantity's panel into `area` (a full-width horizontal slice).
fn draw_panel(pen: &Pen, area: &Root<'_>, panel: &Panel, strip: Strip, rows: Rows) -> DrawResult {
    let (x0, x1) = panel.x_range(strip);
    let mut chart: Chart<'_, '_, Linear, Categories> = ChartBuilder::on(area)
        .margin_top(PANEL_TOP_PX)
        .margin_left(MARGIN)
        .margin_right(MARGIN + 8)
        .x_label_area_size(X_AXIS_PX)
        .y_label_area_size(118)
        .build_cartesian_2d(x0..x1, Categories::new(rows.y0, rows.y1, rows.keys()))?;
    let x_format = tick_format(x1 - x0);
    let y_format = |y: &f64| rows.label(*y);
    let axes = Axes {
        x_desc: format!(
            "{}: relative value (fraction of the finger's total length J, unitless)",
            panel.stats.name.label()
        ),
        y_desc: String::new(),
        x_grid: true,
        x_format: &x_format,
        y_format: &y_format,
    };
    draw_axes(&mut chart, &axes)?;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    let s = panel.stats;
    pen.line(
        at(s.mean, rows.y0 + 0.1),
        at(s.mean, rows.strip_high),
        INK,
        1,
    )?;
    match strip {
        Strip::Labelled => draw_labelled(pen, &at, panel, rows, at(x1, 0.0).0)?,
        Strip::Jittered => draw_jittered(pen, &at, panel, rows)?,
        Strip::Binned => draw_binned(pen, &at, panel, rows, (x0, x1))?,
    }
    draw_named(pen, &at, panel, rows, at(x1, 0.0).0)?;
    draw_intervals(pen, &at, s, x0)
}

/// Every interval of `s` on its row, with the mean marked on each; a missing
/// interval says why at the left edge `left` of its row.
fn draw_intervals(
    pen: &Pen,
    at: &dyn Fn(f64, f64) -> Px,
    s: &QuantityStats,
    left: f64,
) -> DrawResult {
    for kind in Kind::ALL {
        let y = Rows::of(kind);
        match kind.of(s) {
            Some(i) => {
                pen.interval(at(i.low, y), at(i.high, y), Dir::Horizontal, kind)?;
                pen.diamond(at(s.mean, y), 4)?;
            }
            None => {
                let why = if s.n < 2 { "1 X-ray" } else { "see notes" };
                let p = at(left, y);
                pen.note((p.0 + 8, p.1), &format!("not available ({why})"))?;
            }
        }
    }
    Ok(())
}

/// One lane per X-ray, top to bottom in X-ray order, each point with its id
/// beside it (on the left near the right edge `right_px`).
fn draw_labelled(
    pen: &Pen,
    at: &dyn Fn(f64, f64) -> Px,
    panel: &Panel,
    rows: Rows,
    right_px: i32,
) -> DrawResult {
    let n = panel.values.len().max(1) as f64;
    let lane = (rows.strip_high - STRIP_LOW) / n;
    for (i, &(id, v)) in panel.values.iter().enumerate() {
        let p = at(v, rows.strip_high - (i as f64 + 0.5) * lane);
        pen.dot(p, 4, POINT, 0.85)?;
        let label = clip(id, 16);
        let font = Font::new(11.0).colour(MUTED);
        if p.0 + 8 + text_width(&label, 11.0) > right_px {
            pen.text(
                (p.0 - 8, p.1),
                &label,
                font.anchor(HPos::Right, VPos::Center),
            )?;
        } else {
            pen.text((p.0 + 8, p.1), &label, font)?;
        }
    }
    Ok(())
}

/// A label beside point `p`, on its right or, near the right edge `right_px`, its left.
fn label_at(pen: &Pen, p: Px, label: &str, font: Font, right_px: i32) -> DrawResult {
    if p.0 + 8 + text_width(label, 11.0) > right_px {
        pen.text(
            (p.0 - 8, p.1),
            label,
            font.anchor(HPos::Right, VPos::Center),
        )
    } else {
        pen.text((p.0 + 8, p.1), label, font)
    }
}

/// The named X-rays (beyond [`LABELLED_MAX`]), each on a lane of its own above the
/// other points, by value, highlighted and labelled with its id.
fn draw_named(
    pen: &Pen,
    at: &dyn Fn(f64, f64) -> Px,
    panel: &Panel,
    rows: Rows,
    right_px: i32,
) -> DrawResult {
    for (lane, &i) in panel.named.iter().enumerate() {
        let (id, v) = panel.values[i];
        let y = rows.strip_high - NAMED_LANE * (lane as f64 + 0.5);
        let p = at(v, y);
        pen.dot(p, 5, NAMED, 1.0)?;
        label_at(
            pen,
            p,
            &clip(id, 16),
            Font::new(11.0).colour(NAMED),
            right_px,
        )?;
    }
    Ok(())
}

/// The height of the strip left to the unnamed points (below the named lanes).
fn unnamed_height(panel: &Panel, rows: Rows) -> f64 {
    rows.strip_high - STRIP_LOW - NAMED_LANE * panel.named.len() as f64
}

/// One point per X-ray, spread vertically over the strip (below the named lanes) by
/// the golden-ratio sequence; the named ones are drawn by [`draw_named`].
fn draw_jittered(pen: &Pen, at: &dyn Fn(f64, f64) -> Px, panel: &Panel, rows: Rows) -> DrawResult {
    let height = unnamed_height(panel, rows);
    for (i, &(_, v)) in panel.values.iter().enumerate() {
        if panel.named.contains(&i) {
            continue;
        }
        let jitter = ((i as f64 + 1.0) * GOLDEN).fract();
        let y = STRIP_LOW + height * (0.08 + 0.84 * jitter);
        pen.dot(at(v, y), 3, POINT, 0.45)?;
    }
    Ok(())
}

/// A histogram of the values over the panel's x range, bars rising from the strip's bottom.
fn draw_binned(
    pen: &Pen,
    at: &dyn Fn(f64, f64) -> Px,
    panel: &Panel,
    rows: Rows,
    (x0, x1): (f64, f64),
) -> DrawResult {
    let counts = histogram(panel.values.iter().map(|&(_, v)| v), x0, x1, BINS);
    let most = counts.iter().copied().max().unwrap_or(0).max(1) as f64;
    let width = (x1 - x0) / BINS as f64;
    let height = unnamed_height(panel, rows);
    for (b, &c) in counts.iter().enumerate().filter(|(_, c)| **c > 0) {
        let left = x0 + b as f64 * width;
        let top = STRIP_LOW + height * c as f64 / most;
        pen.rect(at(left, STRIP_LOW), at(left + width, top), POINT, 0.6)?;
    }
    Ok(())
}

/// Counts of finite `values` in `bins` equal bins over `[x0, x1]` (the ends clamp).
fn histogram(values: impl Iterator<Item = f64>, x0: f64, x1: f64, bins: usize) -> Vec<usize> {
    let mut counts = vec![0usize; bins];
    let span = x1 - x0;
    if bins == 0 || span.is_nan() || span <= 0.0 {
        return counts;
    }
    for v in values.filter(|v| v.is_finite()) {
        let b = ((v - x0) / span * bins as f64)
            .floor()
            .clamp(0.0, (bins - 1) as f64);
        counts[b as usize] += 1;
    }
    counts
}

/// The screen-reader description: every statistic, and every value when there are few.
fn description(f: &FingerAnalysis, panels: &[Panel], confidence: f64) -> String {
    let n = f.xrays.len();
    let mut d = format!(
        "Relative segment lengths (fractions of the finger's total length J) of {}, from {}.",
        finger_phrase(f.finger),
        super::draw::xrays(n)
    );
    for p in panels {
        d.push(' ');
        d.push_str(&quantity_sentence(p.stats, confidence));
    }
    for p in panels.iter().filter(|p| !p.named.is_empty()) {
        let names: Vec<String> = p
            .named
            .iter()
            .map(|&i| format!("{} {}", p.values[i].0, format::num(p.values[i].1, 4)))
            .collect();
        d.push_str(&format!(
            " Named in the {} panel: {}.",
            p.stats.name.symbol(),
            names.join(", ")
        ));
    }
    if n <= LISTED_MAX {
        d.push_str(" Values per X-ray: ");
        let per_xray: Vec<String> = f
            .xrays
            .iter()
            .map(|x| {
                let values: Vec<String> = panels
                    .iter()
                    .zip(&x.relative)
                    .map(|(p, v)| format!("{} {}", p.stats.name.symbol(), format::num(*v, 4)))
                    .collect();
                format!("{}: {}", x.xray, values.join(", "))
            })
            .collect();
        d.push_str(&per_xray.join("; "));
        d.push('.');
    }
    d
}

/// "J~1 = J1/J: mean 0.4846, observed 0.4728 to 0.5047; 95% t CI [...], ...".
pub(super) fn quantity_sentence(s: &QuantityStats, confidence: f64) -> String {
    let intervals: Vec<String> = Kind::ALL
        .iter()
        .map(|&k| format!("{} {}", k.phrase(), format::interval(k.of(s), 4)))
        .collect();
    format!(
        "{}: mean {}, observed {} to {}; {} {}.",
        s.name.label(),
        format::num(s.mean, 4),
        format::num(s.min, 4),
        format::num(s.max, 4),
        format::level(confidence),
        intervals.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_clamps_and_skips_non_finite() {
        let c = histogram(
            [0.0, 0.5, 1.0, 2.0, -1.0, f64::NAN].into_iter(),
            0.0,
            1.0,
            4,
        );
        assert_eq!(c, vec![2, 0, 1, 2]);
        assert_eq!(histogram([1.0].into_iter(), 1.0, 1.0, 4), vec![0; 4]);
    }

    #[test]
    fn strips_switch_at_their_limits() {
        assert_eq!(Strip::for_count(LABELLED_MAX), Strip::Labelled);
        assert_eq!(Strip::for_count(LABELLED_MAX + 1), Strip::Jittered);
        assert_eq!(Strip::for_count(POINTS_MAX), Strip::Jittered);
        assert_eq!(Strip::for_count(POINTS_MAX + 1), Strip::Binned);
    }

    #[test]
    fn row_labels_name_every_tick() {
        let rows = Rows::new(Strip::Labelled, 5, 0);
        let labels: Vec<String> = rows.keys().iter().map(|&y| rows.label(y)).collect();
        assert_eq!(
            labels,
            ["t CI", "percentile CI", "BCa CI", "prediction", "X-rays"]
        );
        assert_eq!(Quantity::RelJ3.symbol(), "J~3");
    }
}
