//! The report's part on the joint region the rigs are judged against: its
//! shape per finger (the X-rays' own correlation, the prior's, the one used)
//! and its calibration table (false alarms and power by simulation), as
//! strings made by [`crate::format`]. It reads finished results
//! ([`crate::analysis::region::calibration::simulate`], run by `cmd/report`).

use crate::analysis::Analysis;
use crate::analysis::region::calibration::{
    self, CORRELATIONS, Cell, FINGER_MM, JOINTS, MOVES_MM, Setup, fisher_interval,
};
use crate::analysis::region::{FIX_LEVEL, ShapePriors};
use crate::format::{level, num, percent};
use serde::Serialize;

/// The region's part of the report's methods.
#[derive(Debug, Clone, Serialize)]
pub struct RegionView {
    /// How a finger is judged, in a paragraph.
    pub text: String,
    /// Each finger with two positions: its correlations.
    pub shapes: Vec<ShapeRow>,
    /// The false alarms' table caption.
    pub caption: String,
    /// The table's column heads: the true correlations.
    pub correlations: Vec<String>,
    /// One row per number of X-rays.
    pub false_alarms: Vec<CalibrationRow>,
    /// The power table's caption.
    pub power_caption: String,
    /// The power table's column heads: the numbers of X-rays.
    pub sizes: Vec<String>,
    /// One row per joint and move.
    pub power: Vec<CalibrationRow>,
    /// What the tables show, in sentences.
    pub notes: Vec<String>,
}

/// One finger's shape: the X-rays' correlation of u with its Fisher interval,
/// the prior's, and the one the verdicts use.
#[derive(Debug, Clone, Serialize)]
pub struct ShapeRow {
    pub finger: String,
    pub own: String,
    pub prior: String,
    pub used: String,
}

/// A table row: its label and cells.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationRow {
    pub label: String,
    pub cells: Vec<String>,
}

/// The region's view, `None` without a calibration table (`rigs`: where the rigs'
/// section is, "section 13").
pub fn region_view(
    a: &Analysis,
    shape: Option<&ShapePriors>,
    calibration: Option<(&Setup, &[Cell])>,
    rigs: &str,
) -> Option<RegionView> {
    let (setup, cells) = calibration?;
    if cells.is_empty() {
        return None;
    }
    let c = a.settings.confidence;
    let shapes = shape_rows(a, shape);
    let sizes: Vec<usize> = {
        let mut v: Vec<usize> = cells.iter().map(|c| c.n).collect();
        v.dedup();
        v
    };
    Some(RegionView {
        text: region_text(a, shape, rigs),
        caption: format!(
            "False alarms: the share of normal index fingers outside the {} joint region, by the \
             number of X-rays (rows) and the true correlation of u (columns).",
            level(c)
        ),
        correlations: CORRELATIONS.iter().map(|r| num(*r, 3)).collect(),
        false_alarms: false_alarm_rows(&sizes, cells),
        power_caption: format!(
            "Power: the share of index fingers with one joint moved towards the tip on a {} mm \
             finger (the MCP with the tip held) found outside the region, lowest to highest over \
             the true correlations above; in parentheses, on the X-rays' own S.",
            num(FINGER_MM, 0)
        ),
        sizes: sizes.iter().map(|&n| crate::format::xrays(n)).collect(),
        power: power_rows(&sizes, cells),
        notes: region_notes(a, setup, cells, &shapes),
        shapes,
    })
}

/// How a rig's finger is judged, in a paragraph: with the atlas's shape prior when there is one.
fn region_text(a: &Analysis, shape: Option<&ShapePriors>, rigs: &str) -> String {
    let c = a.settings.confidence;
    let m = shape.map_or(0.0, |s| s.hands);
    match shape {
        Some(s) if m > 0.0 => format!(
            "A rig's finger ({rigs}, phalanx audit) is judged on its relative joint \
             positions u = (J~1, J~1 + J~2) as one vector, T² = (u − ū)′ [S* (1 + 1/n)]⁻¹ (u − ū) \
             at most p (n − 1) / (n − p) F({c}; p, n − p). The region's shape is the correlation \
             of the two positions, which {n} X-rays hardly fix, so S* keeps the X-rays' variances \
             and pools their correlation r_S with {src}'s r0 ({hands} hands) weighted as {m} \
             hands: r* = (m r0 + (n − 1) r_S) / (m + n − 1), the posterior mean of a \
             Normal–Inverse-Wishart model whose prior scale is the atlas's correlation set to the \
             X-rays' variances. The prior carries nothing about the variances, so the bound stays \
             Hotelling's at the X-rays' n (a bound on n + m hands, as the full posterior \
             predictive gives, flags 12% of normal fingers at n = 5). Assumed: normal \
             proportions, independent hands, and a correlation like the atlas's (children's \
             left hands, bone tips; a tip's soft tissue in proportion to the finger leaves the \
             correlation unchanged). Every verdict also gives T² on the X-rays' own S, and the \
             JSON both. A fix places a moved joint where the finger is most likely given the \
             joints that stay, and only when that lies inside the {inner} region.",
            c = level(c),
            n = a.dataset.xrays,
            src = s.source,
            hands = s.n,
            m = num(m, 0),
            inner = level(FIX_LEVEL),
        ),
        _ => format!(
            "A rig's finger ({rigs}, phalanx audit) is judged on its relative joint \
             positions u = (J~1, J~1 + J~2) as one vector, T² = (u − ū)′ [S (1 + 1/n)]⁻¹ (u − ū) \
             at most p (n − 1) / (n − p) F({}; p, n − p), S the X-rays' own covariance (no atlas \
             to borrow the shape from).",
            level(c)
        ),
    }
}

/// The false alarms' rows: one per number of X-rays, one cell per true correlation.
fn false_alarm_rows(sizes: &[usize], cells: &[Cell]) -> Vec<CalibrationRow> {
    let at = |n: usize, r: f64| cells.iter().find(|c| c.n == n && c.correlation == r);
    sizes
        .iter()
        .map(|&n| CalibrationRow {
            label: format!("{n}"),
            cells: CORRELATIONS
                .iter()
                .map(|&r| at(n, r).map_or("n/a".into(), |c| percent(c.false_alarms.model)))
                .collect(),
        })
        .collect()
}

/// The power rows: one per joint and move, each cell the range over the true correlations
/// (on the X-rays' own S in parentheses).
fn power_rows(sizes: &[usize], cells: &[Cell]) -> Vec<CalibrationRow> {
    // A range of rates in whole percentage points: "9–10%", or "100%".
    let range = |values: &[f64]| -> String {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = (num(lo * 100.0, 0), num(hi * 100.0, 0));
        if lo == hi {
            format!("{lo}%")
        } else {
            format!("{lo}–{hi}%")
        }
    };
    let mut power = Vec::new();
    for (j, joint) in JOINTS.iter().enumerate() {
        for (k, mm) in MOVES_MM.iter().enumerate() {
            let cells_of = |own: bool| -> Vec<String> {
                sizes
                    .iter()
                    .map(|&n| {
                        let rates: Vec<f64> = cells
                            .iter()
                            .filter(|c| c.n == n)
                            .map(|c| {
                                let r = c.power[j][k];
                                if own { r.own } else { r.model }
                            })
                            .collect();
                        range(&rates)
                    })
                    .collect()
            };
            let (model, own) = (cells_of(false), cells_of(true));
            power.push(CalibrationRow {
                label: format!("{} {} mm", joint.name(), num(*mm, 0)),
                cells: model
                    .into_iter()
                    .zip(own)
                    .map(|(m, o)| format!("{m} ({o})"))
                    .collect(),
            });
        }
    }
    power
}

/// What the calibration tables show, in sentences.
fn region_notes(a: &Analysis, setup: &Setup, cells: &[Cell], shapes: &[ShapeRow]) -> Vec<String> {
    let c = a.settings.confidence;
    let own_alarms: Vec<f64> = cells.iter().map(|c| c.false_alarms.own).collect();
    let max_model = cells
        .iter()
        .map(|c| c.false_alarms.model)
        .fold(0.0, f64::max);
    let max_own = own_alarms.iter().copied().fold(0.0, f64::max);
    let min_own = own_alarms.iter().copied().fold(1.0, f64::min);
    // The target: at most the region's own miss rate, 1 - c (5% at 95%).
    let target = 1.0 - c;
    let se = calibration::monte_carlo_se(target, setup.simulations);
    // The largest of 28 cells lies about 2 SEs above its mean by chance
    // alone, so the target is read within 3.
    let goal = format!("the target, at most {}", level(target));
    let verdict = if max_model <= target {
        format!("{goal}, is met in every cell")
    } else if max_model <= target + 3.0 * se {
        format!(
            "{goal}, is met in every cell within Monte Carlo error (3 SEs, {} points, for the \
             largest of {} cells)",
            num(3.0 * se * 100.0, 2),
            cells.len()
        )
    } else {
        format!("{goal}, is not met")
    };
    vec![
        format!(
            "Each cell is {} simulations (seed {}, one ChaCha8 stream per cell): n reference hands \
             drawn from a normal population of u with the paper's index SDs ({} and {}) and the \
             true correlation of the column (the ends of the Fisher {} interval of the paper's \
             r = {} from its 5 index fingers, and points between), one new normal hand judged \
             against their region; the Monte Carlo SE of a rate near {} is {} points. The rule \
             does not change when either position is rescaled (S*'s variances are S's), so the \
             false alarms depend on the correlation alone.",
            setup.simulations,
            setup.seed,
            num(setup.sd[0], 4),
            num(setup.sd[1], 4),
            level(c),
            shapes
                .iter()
                .find(|s| s.finger == "index")
                .map_or("n/a".to_string(), |s| s.own.clone()),
            level(target),
            num(se * 100.0, 2),
        ),
        format!(
            "The most false alarms in any cell: {} ({verdict}; Hotelling's region on the X-rays' \
             own S, exact for normal hands, gives {} to {} across the table).{} \
             tests/independent/region_calibration.py draws the same table without phalanx's code.",
            percent(max_model),
            percent(min_own),
            percent(max_own),
            if setup.prior.is_some() {
                format!(
                    " Where the true correlation is high the prior costs power at small n, the \
                     price of not hanging the region's shape on one correlation from {} hands; \
                     at 910 X-rays the two agree.",
                    a.dataset.xrays
                )
            } else {
                String::new()
            },
        ),
    ]
}

/// Each finger with two positions: the X-rays' correlation of u with its
/// Fisher interval, the prior's, and the one the verdicts use.
fn shape_rows(a: &Analysis, shape: Option<&ShapePriors>) -> Vec<ShapeRow> {
    a.fingers
        .iter()
        .filter_map(|f| {
            let prior = shape.and_then(|s| s.of(f.finger));
            let region = f.joint_region(a.settings.confidence, prior)?;
            let (own, used) = (region.own_correlation?, region.correlation?);
            let interval = fisher_interval(own, region.n, a.settings.confidence)
                .map_or(String::new(), |(lo, hi)| {
                    format!(" [{}, {}]", num(lo, 2), num(hi, 3))
                });
            Some(ShapeRow {
                finger: f.finger.name().to_string(),
                own: format!("{}{interval}", num(own, 3)),
                prior: prior.map_or("none".into(), |p| num(p.correlation, 3)),
                used: num(used, 3),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse_without_bootstrap};
    use crate::dataset::{Dataset, Finger};
    use std::path::Path;

    #[test]
    fn the_shapes_are_the_regions_and_the_table_has_every_cell() {
        let paper = analyse_without_bootstrap(
            &Dataset::load(Path::new("data/measurements.csv")).unwrap(),
            &Settings::default(),
        );
        let atlas = analyse_without_bootstrap(
            &Dataset::load(Path::new("data/atlas/measurements.csv")).unwrap(),
            &Settings::default(),
        );
        let shape = atlas.shape_priors(10.0);
        let setup = Setup::of(&paper, Finger::Index, shape.of(Finger::Index), 200).unwrap();
        let cells = calibration::simulate(&setup);
        let v = region_view(&paper, Some(&shape), Some((&setup, &cells)), "section 13").unwrap();
        // The index: r_S 0.969 [0.60, 0.998], the atlas's 0.643, r* 0.736
        // (tests/independent/region_calibration.py prints the same).
        let index = v.shapes.iter().find(|s| s.finger == "index").unwrap();
        assert_eq!(index.own, "0.969 [0.60, 0.998]");
        assert_eq!(index.prior, "0.643");
        assert_eq!(index.used, "0.736");
        let r = paper
            .finger(Finger::Index)
            .unwrap()
            .joint_region(0.95, shape.of(Finger::Index))
            .unwrap();
        assert_eq!(num(r.correlation.unwrap(), 3), index.used);
        assert_eq!(v.false_alarms.len(), calibration::SIZES.len());
        assert!(
            v.false_alarms
                .iter()
                .all(|r| r.cells.len() == CORRELATIONS.len())
        );
        assert_eq!(v.power.len(), 9);
        assert!(v.text.contains("weighted as 10 hands"), "{}", v.text);
        // Without a calibration, no part.
        assert!(region_view(&paper, Some(&shape), None, "section 13").is_none());
    }
}
