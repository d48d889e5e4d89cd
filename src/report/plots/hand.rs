//! The hand diagram: what an animator rigs from. Every finger is drawn upright
//! at the model length L, root joint (MCP) at 0 and tip at L, each inner joint
//! at its mean position with its observed range and its prediction interval.

use super::draw::{
    Axes, BONE, Categories, Chart, Dir, DrawResult, Font, Frame, INK, Kind, LegendItem, Linear,
    MARGIN, MUTED, Pen, Px, RANGE, Swatch, WIDTH, draw_axes, extent, finish, padded, render,
    tick_format,
};
use super::kinds::{Plot, PlotKind};
use crate::analysis::placement::{FingerPlacement, JointPosition};
use crate::error::Error;
use crate::format::{self, label_decimals, level, trimmed};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Height of the chart (axes included) in pixels.
const CHART_PX: u32 = 560;
/// Half-width of a bone in pixels.
const BONE_HALF: i32 = 6;
/// Half-width of a range band in pixels.
const BAND_HALF: i32 = 11;
/// Shift of a bone left of its finger's tick, in categories.
const BONE_SHIFT: f64 = 0.12;
/// Offset of the prediction bar left of the bone, in pixels.
const PI_OFFSET: i32 = 19;

/// Draws the hand diagram.
pub(super) fn plot(placements: &[FingerPlacement], confidence: f64) -> Result<Plot, Error> {
    let length = model_length(placements);
    let legend = legend(confidence);
    let title = format!(
        "Joint positions on a model hand (L = {} model units)",
        trimmed(length, 4)
    );
    let subtitle = format!(
        "Every finger from its root joint (MCP, at 0) to its tip (at L); inner joints at their mean \
         position with the observed range and the {} prediction interval.",
        level(confidence)
    );
    let frame = Frame::new(&title, &subtitle, &legend);
    let height = frame.height() + CHART_PX + 8;
    let svg = render((WIDTH, height), "drawing the hand diagram", |root| {
        let pen = Pen::new(root);
        let top = frame.draw(&pen)?;
        let area = root.clone().shrink((0, top), (WIDTH, CHART_PX));
        draw_chart(&pen, &area, placements, length)
    })?;
    finish(
        "hand".to_string(),
        PlotKind::Hand,
        title,
        description(placements, length, confidence),
        svg,
    )
}

/// The common model length L (the largest finite one; 1 when there is none).
fn model_length(placements: &[FingerPlacement]) -> f64 {
    extent(placements.iter().map(|p| p.length))
        .map(|(_, hi)| hi)
        .filter(|&l| l > 0.0)
        .unwrap_or(1.0)
}

/// The legend: joints, mean, range, prediction interval.
fn legend(confidence: f64) -> Vec<LegendItem> {
    vec![
        LegendItem::new(Swatch::Joint, "root (MCP) and tip"),
        LegendItem::new(Swatch::Mean, "mean joint position"),
        LegendItem::new(Swatch::Range, "observed range (min to max)"),
        LegendItem::new(
            Swatch::Interval(Kind::Prediction),
            Kind::Prediction.legend(confidence, "hand"),
        ),
    ]
}

/// Draws the axes and every finger into `area`.
fn draw_chart(
    pen: &Pen,
    area: &super::draw::Root<'_>,
    placements: &[FingerPlacement],
    length: f64,
) -> DrawResult {
    let k = placements.len().max(1);
    let keys: Vec<f64> = (0..placements.len()).map(|i| i as f64).collect();
    let (y0, y1) = y_range(placements, length);
    let mut chart: Chart<'_, '_, Categories, Linear> = ChartBuilder::on(area)
        .margin_top(8)
        .margin_left(MARGIN)
        .margin_right(MARGIN + 8)
        .x_label_area_size(46)
        .y_label_area_size(76)
        .build_cartesian_2d(Categories::new(-0.5, k as f64 - 0.5, keys), y0..y1)?;
    let names: Vec<&str> = placements.iter().map(|p| p.finger.name()).collect();
    let x_format = |x: &f64| {
        let i = x.round();
        if i >= 0.0 {
            names.get(i as usize).copied().unwrap_or("")
        } else {
            ""
        }
        .to_string()
    };
    let y_format = tick_format(y1 - y0);
    let axes = Axes {
        x_desc: format!(
            "finger (each drawn at the model length L = {})",
            trimmed(length, 4)
        ),
        y_desc: "distance from the root joint MCP (model units)".to_string(),
        x_grid: false,
        x_format: &x_format,
        y_format: &y_format,
    };
    draw_axes(&mut chart, &axes)?;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    if placements.is_empty() {
        let font = Font::new(14.0)
            .colour(MUTED)
            .anchor(HPos::Center, VPos::Center);
        return pen.text(at(0.0, (y0 + y1) / 2.0), "no finger in the data", font);
    }
    for (i, p) in placements.iter().enumerate() {
        // The bone sits left of the tick so that bone and labels centre on it.
        draw_finger(
            pen,
            &|y| at(i as f64 - BONE_SHIFT, y),
            p,
            label_decimals(length),
        )?;
    }
    Ok(())
}

/// The y range: 0..L and every joint's range and prediction interval, padded.
fn y_range(placements: &[FingerPlacement], length: f64) -> (f64, f64) {
    let ends = placements.iter().flat_map(|p| {
        p.joints.iter().flat_map(|j| {
            let pos = &j.position;
            let pi = pos.intervals.pi.map_or([pos.mean; 2], |i| [i.low, i.high]);
            [pos.min, pos.max, pi[0], pi[1]]
        })
    });
    let (lo, hi) = extent([0.0, length].into_iter().chain(ends)).unwrap_or((0.0, length));
    padded(lo, hi, 0.04)
}

/// One finger: bone, root and tip, and every inner joint. `at` maps a distance to pixels.
fn draw_finger(pen: &Pen, at: &dyn Fn(f64) -> Px, p: &FingerPlacement, d: usize) -> DrawResult {
    let (root, tip) = (at(0.0), at(p.length));
    pen.rect(
        (root.0 - BONE_HALF, tip.1),
        (root.0 + BONE_HALF, root.1),
        BONE,
        1.0,
    )?;
    for j in &p.joints {
        draw_joint(pen, at, j, d)?;
    }
    let label = Font::new(12.0).colour(MUTED);
    for (at_px, name) in [(root, "MCP"), (tip, "tip")] {
        pen.dot(at_px, 5, INK, 1.0)?;
        pen.text((at_px.0 + BAND_HALF + 4, at_px.1), name, label)?;
    }
    Ok(())
}

/// One inner joint: range band, prediction bar, mean marker and label.
fn draw_joint(pen: &Pen, at: &dyn Fn(f64) -> Px, j: &JointPosition, d: usize) -> DrawResult {
    let pos = &j.position;
    let x = at(0.0).0;
    let (low, high) = (at(pos.min).1, at(pos.max).1);
    pen.rect((x - BAND_HALF, high), (x + BAND_HALF, low), RANGE, 0.6)?;
    if let Some(pi) = pos.intervals.pi {
        let bar_x = x - PI_OFFSET;
        pen.interval(
            (bar_x, at(pi.low).1),
            (bar_x, at(pi.high).1),
            Dir::Vertical,
            Kind::Prediction,
        )?;
    }
    let m = at(pos.mean);
    pen.line((x - BAND_HALF - 2, m.1), (x + BAND_HALF + 2, m.1), INK, 2)?;
    pen.diamond(m, 5)?;
    let text = format!("{} {}", j.joint.name(), format::num(pos.mean, d));
    pen.text((x + BAND_HALF + 4, m.1), &text, Font::new(12.0).bold())
}

/// The screen-reader description: every joint's mean, range and prediction interval.
fn description(placements: &[FingerPlacement], length: f64, confidence: f64) -> String {
    let d = label_decimals(length);
    let mut out = format!(
        "Model hand: every finger drawn at length L = {} model units, from its root joint \
         (MCP, at 0) to its tip (at {}).",
        trimmed(length, 4),
        trimmed(length, 4)
    );
    if placements.is_empty() {
        out.push_str(" The data has no finger.");
    }
    for p in placements {
        let joints: Vec<String> = p
            .joints
            .iter()
            .map(|j| {
                let pos = &j.position;
                format!(
                    "{} at mean {} (observed {} to {}; {} prediction interval {})",
                    j.joint.name(),
                    format::num(pos.mean, d),
                    format::num(pos.min, d),
                    format::num(pos.max, d),
                    level(confidence),
                    format::interval(pos.intervals.pi, d)
                )
            })
            .collect();
        out.push_str(&format!(
            " {} ({}): {}.",
            p.finger.name(),
            super::draw::xrays(p.n),
            joints.join("; ")
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_fingers_the_model_length_is_one() {
        // The label decimals per model length are tested with `format::label_decimals`.
        assert_eq!(model_length(&[]), 1.0);
    }
}
