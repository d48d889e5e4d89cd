//! The rig plot: popular rigs' adjacent-segment ratios against the X-rays.
//!
//! One row per finger and ratio (J2/J1; J3/J2 for index to little): the
//! X-rays' observed range as a band, their prediction interval as a dashed
//! bar, their mean as a diamond, and each rig as a marker (its own shape and
//! colour), spread vertically within the row. Ratios need no fingertip, so
//! every rig with two segments appears.

use super::draw::{
    Dir, DrawResult, Frame, Kind, LegendItem, Pen, QuantityRow, RANGE, Root, Swatch, WIDTH, extent,
    finish, padded, quantity_rows, render, row_chart,
};
use super::kinds::{Plot, PlotKind};
use crate::analysis::{Analysis, Quantity};
use crate::dataset::Finger;
use crate::error::Error;
use crate::format::{level, trimmed};

const ROW_PX: u32 = 50;
const AXIS_PX: u32 = 46;
const TOP_PX: u32 = 10;

/// One rig's ratios: (finger, quantity, value).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RigRatios {
    pub name: String,
    pub values: Vec<(Finger, Quantity, f64)>,
}

/// One row per finger and ratio.
type Row<'a> = QuantityRow<'a>;

fn rows(a: &Analysis) -> Vec<Row<'_>> {
    quantity_rows(a, |q| {
        matches!(q, Quantity::RatioJ2J1 | Quantity::RatioJ3J2)
    })
}

/// Draws the rig plot (id `rigs`).
pub(super) fn plot(a: &Analysis, rigs: &[RigRatios]) -> Result<Plot, Error> {
    let confidence = a.settings.confidence;
    let rows = rows(a);
    let mut legend = vec![
        LegendItem::new(Swatch::Mean, "X-ray mean"),
        LegendItem::new(Swatch::Range, "X-ray observed range"),
        LegendItem::new(
            Swatch::Interval(Kind::Prediction),
            Kind::Prediction.legend(confidence, "hand"),
        ),
    ];
    legend.extend(
        rigs.iter()
            .enumerate()
            .map(|(k, r)| LegendItem::new(Swatch::Marker(k), r.name.clone())),
    );
    let title = "Popular rigs against the X-rays: ratios of adjacent segments".to_string();
    let subtitle = "One row per finger and ratio. A rig's marker inside the dashed bar is as \
                    plausible as a new hand; outside it, the rig's joints are spaced unlike the X-rays."
        .to_string();
    let frame = Frame::new(&title, &subtitle, &legend);
    let chart_px = ROW_PX * rows.len().max(1) as u32 + AXIS_PX + TOP_PX;
    let height = frame.height() + chart_px + 8;
    let svg = render((WIDTH, height), "drawing the rig plot", |root| {
        let pen = Pen::new(root);
        let top = frame.draw(&pen)?;
        let area = root.clone().shrink((0, top), (WIDTH, chart_px));
        draw_chart(&pen, &area, &rows, rigs)
    })?;
    finish(
        "rigs".to_string(),
        PlotKind::Rigs,
        title,
        description(&rows, rigs, confidence),
        svg,
    )
}

fn value_of(r: &RigRatios, row: &Row) -> Option<f64> {
    r.values
        .iter()
        .find(|(f, q, _)| *f == row.finger && *q == row.stats.name)
        .map(|v| v.2)
        .filter(|v| v.is_finite())
}

fn draw_chart(pen: &Pen, area: &Root<'_>, rows: &[Row], rigs: &[RigRatios]) -> DrawResult {
    let count = rows.len();
    let values = rows.iter().flat_map(|r| {
        let s = r.stats;
        let mut v = vec![s.min, s.max, s.mean];
        if let Some(pi) = s.intervals.pi {
            v.extend([pi.low, pi.high]);
        }
        v.extend(rigs.iter().filter_map(|g| value_of(g, r)));
        v
    });
    let (x0, x1) = extent(values).map_or((0.0, 1.0), |(lo, hi)| padded(lo, hi, 0.04));
    let chart = row_chart(
        pen,
        area,
        rows,
        (x0, x1),
        (TOP_PX, AXIS_PX),
        (
            "ratio of adjacent segment lengths (unitless)",
            "finger and ratio",
            "no ratios in the data",
        ),
    )?;
    let y_of = |r: usize| (count - 1 - r) as f64;
    let at = |x: f64, y: f64| chart.backend_coord(&(x, y));
    if rows.is_empty() {
        return Ok(());
    }
    let n = rigs.len() as i32;
    for (r, row) in rows.iter().enumerate() {
        let y = y_of(r);
        let s = row.stats;
        let (a, b) = (at(s.min, y), at(s.max, y));
        pen.rect((a.0, a.1 - 8), (b.0.max(a.0 + 2), b.1 + 8), RANGE, 0.55)?;
        if let Some(pi) = s.intervals.pi {
            let (a, b) = (at(pi.low, y), at(pi.high, y));
            pen.interval(
                (a.0, a.1 + 14),
                (b.0, b.1 + 14),
                Dir::Horizontal,
                Kind::Prediction,
            )?;
        }
        pen.diamond(at(s.mean, y), 5)?;
        for (k, rig) in rigs.iter().enumerate() {
            if let Some(v) = value_of(rig, row) {
                let p = at(v, y);
                // Spread the rigs over -14..+2 px so they do not hide one another.
                let dy = if n > 1 {
                    -14 + 16 * k as i32 / (n - 1)
                } else {
                    -6
                };
                pen.marker((p.0, p.1 + dy), k)?;
            }
        }
    }
    Ok(())
}

fn description(rows: &[Row], rigs: &[RigRatios], confidence: f64) -> String {
    let mut out = format!(
        "Ratios of adjacent finger segments of {} popular rigs against the X-rays: per finger and ratio, \
         the X-rays' mean, observed range and {} prediction interval, and each rig's value.",
        rigs.len(),
        level(confidence)
    );
    for row in rows {
        let s = row.stats;
        out.push_str(&format!(
            " {}: X-ray mean {}, range {} to {}",
            row.label,
            trimmed(s.mean, 3),
            trimmed(s.min, 3),
            trimmed(s.max, 3)
        ));
        if let Some(pi) = s.intervals.pi {
            out.push_str(&format!(
                ", prediction {} to {}",
                trimmed(pi.low, 3),
                trimmed(pi.high, 3)
            ));
        }
        let named: Vec<String> = rigs
            .iter()
            .filter_map(|g| value_of(g, row).map(|v| format!("{} {}", g.name, trimmed(v, 3))))
            .collect();
        if !named.is_empty() {
            out.push_str(&format!("; {}", named.join(", ")));
        }
        out.push('.');
    }
    out
}
