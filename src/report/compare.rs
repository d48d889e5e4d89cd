//! Two cohorts compared, as text: the sentences of `phalanx compare` and the report's
//! atlas section, the terminal tables (under 100 columns) and the CSV of everything.

use super::compare_words::{Names, short};
use super::csv_out::safe_cell;
use super::layout::{Align, Give, Grid, Hidden, Width, fit_text};
use crate::analysis::Quantity;
use crate::analysis::compare::{
    CohortInfo, Cohorts, Comparison, ExternalCoverage, FingerComparison, LastSegment, TipBasis,
};
use crate::dataset::{Finger, is_pixel_unit};
use crate::error::Error;
use crate::format::{decimals, full, interval, level, num, percent, signed};

/// Decimals of a quantity's values.
fn d(q: Quantity) -> usize {
    decimals(q.is_unitless())
}

/// "0.5315 (0.0139)": a mean and its SD.
pub fn mean_sd(mean: f64, sd: Option<f64>, q: Quantity) -> String {
    match sd {
        Some(sd) => format!("{} ({})", num(mean, d(q)), num(sd, d(q))),
        None => num(mean, d(q)),
    }
}

/// "43.7% (398/910)": a share of X-rays inside a prediction interval.
pub fn coverage_cell(c: Option<&ExternalCoverage>) -> String {
    c.map_or_else(
        || "n/a".to_string(),
        |c| format!("{} ({}/{})", percent(c.share), c.inside, c.of),
    )
}

/// "+2.46 [1.57, 3.35]": Hedges' g with its interval.
pub fn hedges_cell(c: &Comparison) -> String {
    c.hedges_g.map_or_else(
        || "n/a".to_string(),
        |g| format!("{} {}", signed(g.g, 2), interval(Some(g.interval), 2)),
    )
}

/// The Welch interval of the difference, "[0.0276, 0.0620]".
pub fn welch_cell(c: &Comparison, q: Quantity) -> String {
    interval(c.welch.map(|w| w.interval), d(q))
}

/// The bootstrap interval of the difference.
pub fn bootstrap_cell(c: &Comparison, q: Quantity) -> String {
    interval(Some(c.bootstrap), d(q))
}

/// The difference B - A with its sign.
pub fn difference_cell(c: &Comparison, q: Quantity) -> String {
    signed(c.difference, d(q))
}

/// "5 X-rays, unit 'image units', fingertips not recorded".
pub fn cohort_line(c: &CohortInfo) -> String {
    let unit = match &c.unit {
        Some(u) if is_pixel_unit(u) => format!("unit '{u}' (per-image pixels)"),
        Some(u) => format!("unit '{u}'"),
        None => "no unit named".to_string(),
    };
    format!(
        "{} X-ray{}, {unit}, fingertips {}",
        c.xrays,
        if c.xrays == 1 { "" } else { "s" },
        c.tips.describe()
    )
}

/// The plain sentence of one finger: its largest differences (the quantities whose Welch
/// interval excludes 0, largest |g| first, at most two), or that there is none, and the
/// external coverage of the quantity where it is lowest.
pub fn finger_sentence(f: &FingerComparison, names: Names<'_>, confidence: f64) -> String {
    let mut clear: Vec<(Quantity, &Comparison)> = f
        .quantities
        .iter()
        .map(|q| (q.quantity, &q.comparison))
        .filter(|(_, c)| c.welch.is_some_and(|w| !w.interval.contains(0.0)))
        .collect();
    clear.sort_by(|x, y| {
        let g = |c: &Comparison| c.hedges_g.map_or(0.0, |g| g.g.abs());
        g(y.1).total_cmp(&g(x.1))
    });
    let name = finger_name(f.finger);
    let mut s = if clear.is_empty() {
        format!(
            "{name}: no clear difference (every Welch {} interval of the difference holds 0)",
            level(confidence)
        )
    } else {
        let parts: Vec<String> = clear
            .iter()
            .take(2)
            .map(|(q, c)| {
                let more = if c.difference > 0.0 {
                    "larger"
                } else {
                    "smaller"
                };
                let g = c
                    .hedges_g
                    .map_or(String::new(), |g| format!(", g = {}", signed(g.g, 2)));
                format!(
                    "{}'s {} is {more} by {} ({} of {}'s mean{g})",
                    names.b,
                    q.symbol(),
                    num(c.difference.abs(), d(*q)),
                    percent((c.difference / c.a.mean).abs()),
                    names.a
                )
            })
            .collect();
        format!(
            "{name}: the largest difference{}: {}",
            if parts.len() == 1 { "" } else { "s" },
            parts.join("; ")
        )
    };
    let lowest = f
        .quantities
        .iter()
        .filter_map(|q| q.comparison.b_in_a.map(|c| (q.quantity, c)))
        .min_by(|x, y| x.1.share.total_cmp(&y.1.share));
    if let Some((q, c)) = lowest {
        s.push_str(&format!(
            ". {} of {}'s X-rays fall inside {}'s {} prediction interval for {}",
            percent(c.share),
            names.b,
            names.a,
            level(confidence),
            q.symbol()
        ));
    }
    s.push('.');
    s
}

/// "the index finger", "the thumb".
fn finger_name(f: Finger) -> String {
    match f {
        Finger::Thumb => "thumb".to_string(),
        other => format!("{} finger", other.name()),
    }
}

/// Whether a finger's soft-tissue sentence says anything: not when the fingertip
/// offset that would explain the difference rounds to 0.0% of the finger, nor when it
/// is under one pixel of per-image pixel data (pixels or image units: below what the
/// measurements can tell).
/// A shorter last segment (no offset explains it) is always worth saying.
pub fn tip_worth_saying(last: &LastSegment, cohorts: &Cohorts) -> bool {
    let o = &last.offset;
    if o.share_of_a < 0.0 {
        return true;
    }
    let skin = if last.skin == "a" {
        &cohorts.a
    } else {
        &cohorts.b
    };
    // Pixels, or the paper's "image units" (pixels of X-ray images).
    let pixels = |u: &str| is_pixel_unit(u) || u.trim() == "image units";
    let sub_pixel = skin.unit.as_deref().is_some_and(pixels) && o.in_a_units < 1.0;
    percent(o.share_of_a) != percent(0.0) && !sub_pixel
}

/// The soft-tissue sentence of a finger's last segment: how much longer one cohort's is,
/// and the fingertip offset (as a share of the finger) that would explain it.
pub fn tip_sentence(last: &LastSegment, cohorts: &Cohorts, names: Names<'_>) -> String {
    let (skin, bone, skin_info) = if last.skin == "a" {
        (names.a, names.b, &cohorts.a)
    } else {
        (names.b, names.a, &cohorts.b)
    };
    let why = match last.basis {
        TipBasis::Recorded => format!(
            "{bone}'s fingertips are recorded at the bone, {skin}'s {}",
            if skin_info.tips.single().is_some() {
                "at the skin"
            } else {
                "not recorded"
            }
        ),
        TipBasis::LongerLastSegment => format!(
            "neither cohort's recorded tips tell them apart; {skin}'s last segment is the longer"
        ),
    };
    let o = &last.offset;
    let units = match &skin_info.unit {
        Some(u) if !is_pixel_unit(u) => format!(", {} {u}", num(o.in_a_units, 1)),
        _ => String::new(),
    };
    if o.share_of_a < 0.0 {
        return format!(
            "{}: {skin}'s last segment ({}) is the shorter, so no soft tissue at its tips explains the difference ({why}).",
            last.quantity.symbol(),
            signed(last.difference, 4),
        );
    }
    format!(
        "{} differs by {} (B - A). If {skin} measured to the skin and {bone} to the bone ({why}), a fingertip {} of the finger's length ({} of the length to the bone tip{units}) beyond the bone would explain it.",
        last.quantity.symbol(),
        signed(last.difference, 4),
        percent(o.share_of_a),
        percent(o.share_of_bone),
    )
}

/// The overall sentence of two datasets compared: how many quantities differ clearly (a
/// Welch interval without 0), the largest effect, and the last segment on every finger.
pub fn overall_sentence(c: &Cohorts, names: Names<'_>) -> String {
    let all: Vec<(Finger, Quantity, &Comparison)> = c
        .fingers
        .iter()
        .flat_map(|f| {
            f.quantities
                .iter()
                .map(move |q| (f.finger, q.quantity, &q.comparison))
        })
        .collect();
    let clear: Vec<&(Finger, Quantity, &Comparison)> = all
        .iter()
        .filter(|(_, _, x)| x.welch.is_some_and(|w| !w.interval.contains(0.0)))
        .collect();
    let mut s = format!(
        "Overall: {} of {} quantities over {} finger{} differ clearly (their Welch {} interval of B - A excludes 0)",
        clear.len(),
        all.len(),
        c.fingers.len(),
        if c.fingers.len() == 1 { "" } else { "s" },
        level(c.settings.confidence)
    );
    let g = |x: &Comparison| x.hedges_g.map_or(0.0, |g| g.g.abs());
    if let Some((f, q, x)) = clear.iter().max_by(|a, b| g(a.2).total_cmp(&g(b.2))) {
        s.push_str(&format!(
            "; the largest is the {} {} (g = {})",
            f.name(),
            q.symbol(),
            x.hedges_g.map_or("n/a".to_string(), |g| signed(g.g, 2))
        ));
    }
    let lasts: Vec<&LastSegment> = c
        .fingers
        .iter()
        .filter_map(|f| f.last_segment.as_ref())
        .collect();
    if !lasts.is_empty() && lasts.len() == c.fingers.len() {
        let shorter_b = lasts.iter().all(|l| l.difference < 0.0);
        let shorter_a = lasts.iter().all(|l| l.difference > 0.0);
        if shorter_a || shorter_b {
            let (short, long) = if shorter_b {
                (names.b, names.a)
            } else {
                (names.a, names.b)
            };
            let lo = lasts
                .iter()
                .map(|l| l.difference.abs())
                .fold(f64::INFINITY, f64::min);
            let hi = lasts.iter().map(|l| l.difference.abs()).fold(0.0, f64::max);
            s.push_str(&format!(
                ". On every finger {short}'s last segment is the shorter (by {} to {} of the finger): fingertips at the bone in {short} and at the skin in {long} would explain it",
                num(lo, 4),
                num(hi, 4)
            ));
        }
    }
    s.push('.');
    s
}

/// The terminal output of `phalanx compare`: the cohorts, the conclusion (one sentence
/// overall, one per finger with its fingertip offset), how the cohorts differ, then per
/// finger two tables (means and differences; effect size and external coverage), then
/// what was not compared. Fitted to `width` ([`super::layout`]).
pub fn text(c: &Cohorts, width: Width) -> String {
    let conf = level(c.settings.confidence);
    let mut hidden = Hidden::new();
    let mut out = String::new();
    out.push_str(&format!("A: {} ({})\n", c.a.path, cohort_line(&c.a)));
    out.push_str(&format!("B: {} ({})\n", c.b.path, cohort_line(&c.b)));
    out.push_str("\nConclusion\n");
    out.push_str(&overall_sentence(c, Names::AB));
    out.push('\n');
    for f in &c.fingers {
        out.push_str(&format!(
            "- {}",
            finger_sentence(f, Names::AB, c.settings.confidence)
        ));
        if let Some(last) = f.last_segment.as_ref().filter(|l| tip_worth_saying(l, c)) {
            out.push(' ');
            out.push_str(&tip_sentence(last, c, Names::AB));
        }
        out.push('\n');
    }
    out.push_str("\nHow the cohorts differ\n");
    let (pa, pb) = (
        super::compare_table::Profile::of_data(&c.a),
        super::compare_table::Profile::of_data(&c.b),
    );
    for l in super::compare_table::differences(&pa, &pb, Names::AB) {
        out.push_str(&format!("- {l}\n"));
    }
    out.push_str(&format!(
        "\nThe tables: differences are B - A, with {conf} Welch and bootstrap intervals (each cohort resampled on its own: {} resamples, seed {}). PI: the {conf} prediction interval for one new X-ray.\n",
        c.settings.resamples, c.settings.seed
    ));
    for f in &c.fingers {
        let mut head = Grid::new()
            .col("", Align::Left, Give::Keep)
            .col("A mean (SD)", Align::Right, Give::Keep)
            .col("B mean (SD)", Align::Right, Give::Keep)
            .col("B - A", Align::Right, Give::Keep)
            .col("Welch", Align::Right, Give::Keep)
            .col("bootstrap", Align::Right, Give::Drop(1));
        let mut cov = Grid::new()
            .col("", Align::Left, Give::Keep)
            .col("Hedges' g", Align::Right, Give::Keep)
            .col("B inside A's PI", Align::Right, Give::Keep)
            .col("A inside B's PI", Align::Right, Give::Keep);
        for q in &f.quantities {
            let (k, x) = (q.quantity, &q.comparison);
            head.row(vec![
                short(k).to_string(),
                mean_sd(x.a.mean, x.a.sd, k),
                mean_sd(x.b.mean, x.b.sd, k),
                difference_cell(x, k),
                welch_cell(x, k),
                bootstrap_cell(x, k),
            ]);
            cov.row(vec![
                short(k).to_string(),
                hedges_cell(x),
                coverage_cell(x.b_in_a.as_ref()),
                coverage_cell(x.a_in_b.as_ref()),
            ]);
        }
        out.push_str(&format!(
            "\n{} (A: {} X-rays, B: {})\n",
            f.finger.display_name(),
            f.n_a,
            f.n_b
        ));
        out.push_str(&head.render(width, 0, &mut hidden));
        out.push('\n');
        out.push_str(&cov.render(width, 0, &mut hidden));
    }
    if !c.notes.is_empty() {
        out.push('\n');
        for n in &c.notes {
            out.push_str(&format!("not compared: {n}\n"));
        }
    }
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// Header of the comparison CSV.
pub const CSV_COLUMNS: [&str; 28] = [
    "finger",
    "quantity",
    "n_a",
    "mean_a",
    "sd_a",
    "n_b",
    "mean_b",
    "sd_b",
    "difference",
    "welch_se",
    "welch_df",
    "welch_low",
    "welch_high",
    "bootstrap_low",
    "bootstrap_high",
    "hedges_g",
    "hedges_g_low",
    "hedges_g_high",
    "pi_a_low",
    "pi_a_high",
    "b_inside_a",
    "b_share_inside_a",
    "pi_b_low",
    "pi_b_high",
    "a_inside_b",
    "a_share_inside_b",
    "confidence",
    "notes",
];

/// The comparison as CSV: one row per finger and quantity, full precision, empty cells where
/// a value is undefined.
pub fn csv(c: &Cohorts) -> Result<Vec<u8>, Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e| Error::render("cannot write CSV", e);
    w.write_record(CSV_COLUMNS).map_err(err)?;
    for f in &c.fingers {
        for q in &f.quantities {
            let x = &q.comparison;
            let ext = |e: Option<ExternalCoverage>| {
                [
                    full(e.map(|e| e.interval.low)),
                    full(e.map(|e| e.interval.high)),
                    e.map_or(String::new(), |e| e.inside.to_string()),
                    full(e.map(|e| e.share)),
                ]
            };
            let mut row = vec![
                f.finger.name().to_string(),
                q.quantity.name().to_string(),
                x.a.n.to_string(),
                full(Some(x.a.mean)),
                full(x.a.sd),
                x.b.n.to_string(),
                full(Some(x.b.mean)),
                full(x.b.sd),
                full(Some(x.difference)),
                full(x.welch.map(|w| w.se)),
                full(x.welch.map(|w| w.df)),
                full(x.welch.map(|w| w.interval.low)),
                full(x.welch.map(|w| w.interval.high)),
                full(Some(x.bootstrap.low)),
                full(Some(x.bootstrap.high)),
                full(x.hedges_g.map(|g| g.g)),
                full(x.hedges_g.map(|g| g.interval.low)),
                full(x.hedges_g.map(|g| g.interval.high)),
            ];
            row.extend(ext(x.b_in_a));
            row.extend(ext(x.a_in_b));
            row.push(full(Some(x.confidence)));
            row.push(safe_cell(&x.notes.join("; ")));
            w.write_record(&row).map_err(err)?;
        }
    }
    w.into_inner()
        .map_err(|e| Error::render("cannot write CSV", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Settings;
    use crate::analysis::compare::cohorts;
    use crate::dataset::Dataset;

    fn cohort(unit: &str, rows: &[[f64; 3]]) -> Dataset {
        let mut text = String::from("xray,finger,j1,j2,j3,unit\n");
        for (i, r) in rows.iter().enumerate() {
            text.push_str(&format!("x{i},index,{},{},{},{unit}\n", r[0], r[1], r[2]));
        }
        Dataset::from_bytes("d.csv", text.as_bytes()).unwrap()
    }

    #[test]
    fn no_fingertip_sentence_below_what_the_data_tell() {
        let rows = [[40.0, 22.0, 19.0], [42.0, 23.0, 20.0], [41.0, 22.5, 19.0]];
        let longer = [[40.0, 22.0, 21.0], [42.0, 23.0, 22.0], [41.0, 22.5, 21.5]];
        let settings = Settings {
            resamples: 200,
            ..Settings::default()
        };
        let c = cohorts(&cohort("mm", &rows), &cohort("mm", &longer), &settings);
        let last = c.fingers[0].last_segment.clone().expect("a last segment");
        assert!(tip_worth_saying(&last, &c), "{last:?}");
        assert!(text(&c, Width::Fit(400)).contains("a fingertip"));
        // An offset that rounds to 0.0% of the finger says nothing.
        let mut tiny = c.clone();
        let l = tiny.fingers[0].last_segment.as_mut().unwrap();
        l.offset.share_of_a = 0.0004;
        assert!(!tip_worth_saying(l, &c));
        tiny.fingers[0]
            .last_segment
            .as_mut()
            .unwrap()
            .offset
            .share_of_a = 0.0004;
        assert!(!text(&tiny, Width::Fit(400)).contains("a fingertip"));
        // Nor under one pixel of pixel data.
        let px = cohorts(
            &cohort("image units", &rows),
            &cohort("image units", &longer),
            &settings,
        );
        let mut l = px.fingers[0].last_segment.clone().unwrap();
        l.offset.in_a_units = 0.8;
        l.offset.share_of_a = 0.002;
        assert!(!tip_worth_saying(&l, &px));
        l.offset.in_a_units = 1.5;
        assert!(tip_worth_saying(&l, &px));
    }
}
