//! Sentences and table cells shared by the terminal ([`super::text`]) and the report
//! ([`super::sections`]).

use crate::analysis::coverage::{CurvePoint, MethodCoverage, holds};
use crate::analysis::population::PopulationStudy;
use crate::analysis::{Analysis, Quantity};
use crate::dataset::history::Snapshot;
use crate::format::{level, percent, xrays};

/// What a dataset whose rows are in several units means for its statistics, when it is:
/// the rows per unit, that relative values and ratios pool, and which fingers lose their
/// total J.
pub fn units_note(a: &Analysis) -> Option<String> {
    if !a.mixed_units() {
        return None;
    }
    let units: Vec<String> = a
        .units
        .iter()
        .map(|(u, n)| {
            format!(
                "{} ({n} row{})",
                u.as_deref().map_or("no unit named", |u| u),
                if *n == 1 { "" } else { "s" }
            )
        })
        .collect();
    let without: Vec<&str> = a
        .fingers
        .iter()
        .filter(|f| f.quantity(Quantity::Total).is_none())
        .map(|f| f.finger.name())
        .collect();
    Some(format!(
        "the rows give their lengths in {} units: {}. The relative values and ratios have no unit and pool across them; lengths in different units are never averaged, so the total length J is left out for {} (measured in more than one unit). For J in one unit, run phalanx on a file of that unit's rows",
        a.units.len(),
        units.join(", "),
        if without.is_empty() {
            "no finger".to_string()
        } else {
            without.join(", ")
        }
    ))
}

/// What one history record changed, in words: the rows and X-rays added or removed, the
/// file, the rows let in flagged, the note. Empty for a snapshot without a note.
pub(crate) fn record_change(s: &Snapshot) -> String {
    let mut parts: Vec<String> = Vec::new();
    if let Some(c) = &s.change {
        let ids = if c.xrays.len() <= 4 {
            c.xrays.join(", ")
        } else {
            format!(
                "{} ... {}",
                c.xrays[..2].join(", "),
                c.xrays[c.xrays.len() - 1]
            )
        };
        let sign = match s.event {
            crate::dataset::history::Event::Remove => "-",
            _ => "+",
        };
        let of = match c.xrays.len() {
            1 => format!("X-ray {ids}"),
            n => format!("{n} X-rays: {ids}"),
        };
        let what = format!(
            "{sign}{} row{} ({of})",
            c.rows,
            if c.rows == 1 { "" } else { "s" }
        );
        parts.push(match (&c.file, s.event) {
            (Some(f), _) => format!("{what} from {f}"),
            (None, crate::dataset::history::Event::Remove) => what,
            (None, _) => format!("{what} typed as options"),
        });
        if !c.flagged.is_empty() {
            let rows: Vec<String> = c
                .flagged
                .iter()
                .map(|f| format!("{} {}", f.xray, f.finger.name()))
                .collect();
            parts.push(match s.event {
                crate::dataset::history::Event::Remove => {
                    format!("had been added flagged: {}", rows.join(", "))
                }
                _ => format!("added though flagged: {}", rows.join(", ")),
            });
        }
    }
    if let Some(n) = &s.note {
        parts.push(format!("note: {n}"));
    }
    parts.join("; ")
}

/// The coverage of method `name` at one point, if simulated.
pub(crate) fn method<'c>(p: &'c CurvePoint, name: &str) -> Option<&'c MethodCoverage> {
    p.coverage.methods.iter().find(|m| m.method == name)
}

/// A note as a sentence: capitalised, ending in a full stop.
pub(crate) fn sentence(note: &str) -> String {
    let mut c = note.chars();
    let mut s: String = match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    };
    if !s.ends_with('.') {
        s.push('.');
    }
    s
}

/// "a", "a and b", "a, b and c".
pub(crate) fn and_list(items: &[&str]) -> String {
    match items.split_last() {
        None => String::new(),
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// What the X-rays count, said once for the report: "16 X-rays" when every finger has
/// them all, else "16 X-rays; 15 for the thumb, index, middle and little" (each smaller
/// count with its fingers).
pub fn counted(a: &Analysis) -> String {
    let total = a.dataset.xrays;
    let mut out = xrays(total);
    let mut sizes: Vec<usize> = a
        .fingers
        .iter()
        .map(|f| f.n)
        .filter(|&n| n != total)
        .collect();
    sizes.sort_unstable_by(|x, y| y.cmp(x));
    sizes.dedup();
    let parts: Vec<String> = sizes
        .iter()
        .map(|&n| {
            let names: Vec<&str> = a
                .fingers
                .iter()
                .filter(|f| f.n == n)
                .map(|f| f.finger.name())
                .collect();
            format!("{n} for the {}", and_list(&names))
        })
        .collect();
    if !parts.is_empty() {
        out.push_str("; ");
        out.push_str(&parts.join(", "));
    }
    out
}

/// Which interval to use, read off the simulation at the data's smallest n:
/// which methods hold their nominal level there ([`holds`]) and which fall
/// short. `None` when the data's n was not simulated.
pub fn interval_advice(points: &[CurvePoint]) -> Option<String> {
    interval_advice_of(points, None)
}

/// [`interval_advice`], naming the fingers whose n it is when `a` says some fingers
/// have more X-rays ("At n = 15 X-rays (the thumb, index, middle and little; the ring
/// has 16)").
pub fn interval_advice_of(points: &[CurvePoint], a: Option<&Analysis>) -> Option<String> {
    let p = points.iter().filter(|p| p.in_data).min_by_key(|p| p.n)?;
    let whose = a
        .filter(|a| a.fingers.iter().any(|f| f.n != p.n))
        .map(|a| {
            let at: Vec<&str> = a
                .fingers
                .iter()
                .filter(|f| f.n == p.n)
                .map(|f| f.finger.name())
                .collect();
            let mut others: Vec<usize> = a
                .fingers
                .iter()
                .map(|f| f.n)
                .filter(|&n| n != p.n)
                .collect();
            others.sort_unstable();
            others.dedup();
            let more = match others.as_slice() {
                [one] => format!("{one}"),
                [lo, .., hi] => format!("{lo} to {hi}"),
                [] => String::new(),
            };
            format!(
                " (the n of the {}; the other fingers have {more})",
                and_list(&at)
            )
        })
        .unwrap_or_default();
    let t = method(p, "t")?;
    let pi = method(p, "prediction")?;
    let name = |m: &str| match m {
        "t" => "t",
        "percentile" => "bootstrap percentile",
        "bca" => "BCa",
        _ => "prediction",
    };
    let short: Vec<String> = p
        .coverage
        .methods
        .iter()
        .filter(|m| !holds(m))
        .map(|m| format!("{} ({})", name(m.method), percent(m.coverage)))
        .collect();
    let mut s = format!(
        "At n = {}{whose}, the t interval covers the mean {} of the time and the prediction interval holds {} of new hands, against a nominal {}",
        xrays(p.n),
        percent(t.coverage),
        percent(pi.coverage),
        level(t.nominal)
    );
    match short.as_slice() {
        [] => s.push_str("; every method holds its level at this size."),
        [one] => s.push_str(&format!("; the {one} interval under-covers.")),
        many => s.push_str(&format!(
            "; the {} intervals under-cover.",
            match many.split_last() {
                Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
                None => String::new(),
            }
        )),
    }
    s.push(' ');
    s.push_str(match (holds(t), holds(pi)) {
        (true, true) => {
            "Use the t interval for the mean of all hands and the prediction interval for where a new hand falls."
        }
        (true, false) => {
            "Use the t interval for the mean of all hands; the prediction interval is too narrow at this size."
        }
        (false, true) => {
            "Use the prediction interval for where a new hand falls; no confidence interval of the mean holds its level at this size."
        }
        (false, false) => "No interval holds its level at this size: read them as rough guides.",
    });
    Some(s)
}

/// One row of a pooled coverage table: at one sample size, the coverage on the
/// population's hands (each method's mean over the quantities), or the normal model's
/// coverage in the row beneath it.
pub(crate) struct PooledRow {
    pub n: usize,
    /// The normal model's row, beneath its size's row of real hands.
    pub normal: bool,
    /// t, percentile, BCa and prediction as percentages ("n/a" where none was measured).
    pub cells: [String; 4],
    /// The bootstrap at this size ("exact (126)", "random (10000)"; empty when unknown).
    pub bootstrap: String,
}

/// The pooled coverage rows of a population study, per size in order: the real hands'
/// row, then the normal model's when it was simulated at that size.
pub(crate) fn pooled_rows(p: &PopulationStudy) -> Vec<PooledRow> {
    const METHODS: [&str; 4] = ["t", "percentile", "bca", "prediction"];
    let pooled = p.pooled();
    let mut rows = Vec::new();
    for (k, &n) in p.sizes.iter().enumerate() {
        let bootstrap = p
            .normal
            .get(k)
            .map_or_else(String::new, |c| crate::format::plan_short(c.bootstrap));
        rows.push(PooledRow {
            n,
            normal: false,
            cells: METHODS.map(|m| {
                pooled
                    .iter()
                    .find(|x| x.n == n && x.method == m)
                    .map_or_else(|| "n/a".to_string(), |x| percent(x.mean))
            }),
            bootstrap: bootstrap.clone(),
        });
        if let Some(normal) = p.normal.iter().find(|c| c.n == n) {
            rows.push(PooledRow {
                n,
                normal: true,
                cells: METHODS.map(|m| {
                    normal
                        .methods
                        .iter()
                        .find(|x| x.method == m)
                        .map_or_else(|| "n/a".to_string(), |x| percent(x.coverage))
                }),
                bootstrap,
            });
        }
    }
    rows
}
