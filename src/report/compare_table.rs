//! Two cohorts compared where one is a published summary table, as text: the conclusion
//! (a sentence per finger and one overall), how the cohorts differ, the fingertip finding,
//! then the tables; the CSV of everything. Also the lines on how two cohorts differ
//! ([`Profile`], [`differences`]), which `phalanx compare` and the report share.

use super::compare_words::{Names, short};
use super::csv_out::safe_cell;
use super::layout::{Align, Give, Grid, Hidden, Width, fit_text};
use crate::analysis::Quantity;
use crate::analysis::compare::CohortInfo;
use crate::analysis::literature::{
    Correlation, Difference, Estimate, Fit, SideInfo, TableCohorts, TableFinger, TipFinding,
    TipVerdict,
};
use crate::dataset::{CohortNotes, Finger, TipCounts, TipKind, is_pixel_unit};
use crate::error::Error;
use crate::format::{count, decimals, full, interval, level, num, signed};

/// What is known of a cohort, each line for people; "not recorded" where nothing is.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// A short name: the description's, else the file.
    pub name: String,
    pub age: String,
    pub side: String,
    pub tip: String,
    pub landmarks: String,
}

const UNKNOWN: &str = "not recorded";

fn age_of(ages: Option<(f64, f64)>, about: Option<&CohortNotes>) -> String {
    match (ages, about.and_then(|a| a.age.clone())) {
        (Some((lo, hi)), _) if lo == hi => format!("aged {}", num(lo, 0)),
        (Some((lo, hi)), _) => format!("aged {} to {}", num(lo, 0), num(hi, 0)),
        (None, Some(a)) => a,
        (None, None) => UNKNOWN.to_string(),
    }
}

fn side_of(sides: &[String], about: Option<&CohortNotes>) -> String {
    match (sides, about.and_then(|a| a.side.clone())) {
        ([], Some(s)) => format!("{s} hands"),
        ([], None) => UNKNOWN.to_string(),
        ([one], _) => format!("{one} hands"),
        (many, _) => format!("{} hands", many.join(" and ")),
    }
}

fn tip_of(recorded: Option<&TipCounts>, about: Option<&CohortNotes>) -> String {
    let known = recorded.filter(|t| t.bone + t.skin > 0);
    match (known, about.and_then(|a| a.tip)) {
        (Some(t), _) => format!("fingertips {}", t.describe()),
        (None, Some(t)) => format!("fingertips {}", t.phrase()),
        (None, None) => format!("fingertips {UNKNOWN}"),
    }
}

impl Profile {
    /// A dataset's profile: its rows first, its description where the rows are silent.
    pub fn of_data(c: &CohortInfo) -> Profile {
        let about = c.about.as_ref();
        Profile {
            name: about
                .and_then(|a| a.name.clone())
                .unwrap_or_else(|| c.path.clone()),
            age: age_of(c.ages, about),
            side: side_of(&c.sides, about),
            tip: tip_of(Some(&c.tips), about),
            landmarks: about
                .and_then(|a| a.landmarks.clone())
                .unwrap_or_else(|| UNKNOWN.to_string()),
        }
    }

    /// A side of a comparison with a table.
    pub fn of_side(s: &SideInfo) -> Profile {
        let about = s.about.as_ref();
        let tip = match s.table_tip {
            Some(TipKind::Skin) => {
                "last phalanx plus the fingertip's soft tissue (tip at the skin)".to_string()
            }
            Some(TipKind::Bone) => tip_of(None, about),
            None => tip_of(s.tips.as_ref(), about),
        };
        Profile {
            name: about
                .and_then(|a| a.name.clone())
                .unwrap_or_else(|| s.path.clone()),
            age: age_of(s.ages, about),
            side: side_of(&s.sides, about),
            tip,
            landmarks: about
                .and_then(|a| a.landmarks.clone())
                .unwrap_or_else(|| UNKNOWN.to_string()),
        }
    }
}

/// One line per kind of difference (age, side, fingertips, landmarks): "age: A (the paper's
/// X-rays) not given; B (...) adults aged 19 to 78". A kind on which both say the same is
/// one line ending "(the same)".
pub fn differences(a: &Profile, b: &Profile, names: Names<'_>) -> Vec<String> {
    [
        ("age", &a.age, &b.age),
        ("side", &a.side, &b.side),
        ("tip", &a.tip, &b.tip),
        ("landmarks", &a.landmarks, &b.landmarks),
    ]
    .into_iter()
    .map(|(what, x, y)| {
        if x == y {
            format!("{what}: {x} in both (the same)")
        } else {
            format!("{what}: {} {x}; {} {y}", names.a, names.b)
        }
    })
    .collect()
}

/// The short form for a report's line on why one cohort differs from another: "children
/// and adolescents aged 0 to 18 against not given (age), left hands against right hands
/// (side), ...", the kinds that differ only.
pub fn differs_in(a: &Profile, b: &Profile) -> String {
    let parts: Vec<String> = [
        ("age", &a.age, &b.age),
        ("side", &a.side, &b.side),
        ("tip", &a.tip, &b.tip),
        ("landmarks", &a.landmarks, &b.landmarks),
    ]
    .into_iter()
    .filter(|(_, x, y)| x != y)
    .map(|(what, x, y)| format!("{what}: {y}, against {x}"))
    .collect();
    if parts.is_empty() {
        "no recorded difference of age, side, fingertip or landmarks".to_string()
    } else {
        parts.join("; ")
    }
}

fn d(q: Quantity) -> usize {
    decimals(q.is_unitless())
}

/// "0.2428 [0.2242, 0.2614]": an estimate with its t interval, or the reason it has none.
pub fn estimate_cell(e: &Estimate, q: Quantity) -> String {
    match e.ci {
        Some(ci) => format!("{} {}", num(e.mean, d(q)), interval(Some(ci), d(q))),
        None => format!("{} (no interval)", num(e.mean, d(q))),
    }
}

/// The verdict on equal means: "differs" (the interval excludes 0), "not rejected" (it holds
/// 0: no difference shown, which is not equality shown), "n/a" (no interval).
fn verdict(not_rejected: Option<bool>) -> &'static str {
    match not_rejected {
        Some(true) => "not rejected",
        Some(false) => "differs",
        None => "n/a",
    }
}

/// "differs at 0, 0.85 and 0.9" or "not rejected at 0; differs at 0.85, 0.9".
pub fn sweep_cell(sweep: &[Difference]) -> String {
    let mut groups: Vec<(&'static str, Vec<String>)> = Vec::new();
    for x in sweep {
        let v = verdict(x.not_rejected);
        let r = trim_rho(x.rho);
        match groups.last_mut() {
            Some((w, rs)) if *w == v => rs.push(r),
            _ => groups.push((v, vec![r])),
        }
    }
    groups
        .into_iter()
        .map(|(v, rs)| format!("{v} at {}", rs.join(", ")))
        .collect::<Vec<_>>()
        .join("; ")
}

/// "not rejected" or "differs" when the verdict is the same at every correlation of the
/// sweep, else each correlation's ([`sweep_cell`]).
pub fn verdict_cell(sweep: &[Difference]) -> String {
    match sweep.first() {
        Some(first) if sweep.iter().all(|d| d.not_rejected == first.not_rejected) => {
            verdict(first.not_rejected).to_string()
        }
        _ => sweep_cell(sweep),
    }
}

/// A correlation with 2 decimals, trailing zeros dropped: 0 -> "0", 0.9 -> "0.9", 0.853 -> "0.85".
pub fn trim_rho(r: f64) -> String {
    crate::format::trimmed(r, 2)
}

fn finger_name(f: Finger) -> String {
    match f {
        Finger::Thumb => "thumb".to_string(),
        other => format!("{} finger", other.name()),
    }
}

/// What the test leaves standing, in words: "bone plus soft tissue (tip at the skin); bone
/// alone rejected".
pub fn fit_words(f: Option<Fit>) -> &'static str {
    match f {
        Some(Fit::Skin) => "bone plus soft tissue (tip at the skin); bone alone rejected",
        Some(Fit::Bone) => "bone alone (tip at the bone); bone plus soft tissue rejected",
        Some(Fit::Both) => "both: neither rejected, the data cannot tell",
        Some(Fit::Neither) => "neither: both rejected",
        None => "n/a (no interval)",
    }
}

/// The finding of one finger as a clause: "bone alone is rejected and bone plus soft tissue
/// is not".
fn fit_clause(f: Option<Fit>) -> &'static str {
    match f {
        Some(Fit::Skin) => "Bone alone is rejected and bone plus soft tissue is not",
        Some(Fit::Bone) => "Bone plus soft tissue is rejected and bone alone is not",
        Some(Fit::Both) => "Neither is rejected, so the data cannot tell",
        Some(Fit::Neither) => "Both are rejected",
        None => "Without an interval neither is tested",
    }
}

/// The fingertip sentence of one finger: the data's last segment against the table's bone
/// only and bone plus soft tissue, and which the test rejects. `names.a` is the data,
/// `names.b` the table; differences are the table's value minus the data's.
pub fn tip_finding_sentence(t: &TipFinding, names: Names<'_>, confidence: f64) -> String {
    let q = t.quantity;
    let inside = |e: &Estimate| t.data.ci.is_some_and(|ci| ci.contains(e.mean));
    let where_ = |e: &Estimate| {
        if inside(e) { "inside" } else { "outside" }
    };
    let diff = |x: &Difference| match x.interval {
        Some(i) => format!(
            "difference {} {}",
            signed(x.difference, d(q)),
            interval(Some(i), d(q))
        ),
        None => format!("difference {}", signed(x.difference, d(q))),
    };
    let holds = t.sweep.iter().all(|(_, f)| *f == t.fit);
    format!(
        "{}: {} {} is {} ({} t CI {}); {}'s bone only gives {}, {} that interval ({}), bone plus soft tissue {}, {} it ({}). {}{}.",
        finger_name(t.finger),
        possessive(names.a),
        q.symbol(),
        num(t.data.mean, d(q)),
        level(confidence),
        interval(t.data.ci, d(q)),
        names.b,
        num(t.bone.mean, d(q)),
        where_(&t.bone),
        diff(&t.bone_difference),
        num(t.skin.mean, d(q)),
        where_(&t.skin),
        diff(&t.skin_difference),
        fit_clause(t.fit),
        if holds {
            " at every correlation from 0 to 0.9"
        } else {
            " at the assumed correlation, not at every one from 0 to 0.9"
        }
    )
}

/// The overall fingertip sentence: which tip the test rejects and which it does not, the
/// weakest "not rejected" with its interval, and the rows' record beside it (consistent
/// with it or not; never "confirmed": the record may rest on this very test).
pub fn tip_overall(v: &TipVerdict, names: Names<'_>) -> String {
    let (data, table) = if v.data == "a" {
        (names.a, names.b)
    } else {
        (names.b, names.a)
    };
    let n = v.fingers.len();
    let (rejected, kept, tip) = match v.overall {
        Some(Fit::Skin) => ("bone alone", "bone plus soft tissue", TipKind::Skin),
        Some(Fit::Bone) => ("bone plus soft tissue", "bone alone", TipKind::Bone),
        _ => {
            let record = match v.recorded {
                Some(t) => format!("its rows record the tips at the {}", t.name()),
                None => "its rows do not record where the tips are".to_string(),
            };
            return format!(
                "Against {table}, the fingers do not reject one tip and leave the other at every correlation from 0 to 0.9, so where {} fingertips are is not settled ({record}).",
                possessive(data)
            );
        }
    };
    let nearest = v.nearest_to_rejection().map_or(String::new(), |(t, i)| {
        format!(
            " (the interval nearest to rejecting it: the {}'s, {}, at the assumed correlation)",
            finger_name(t.finger),
            interval(Some(i), d(t.quantity))
        )
    });
    let record = match v.recorded {
        Some(r) if r == tip => format!(
            "Its rows record the tips at the {}: consistent with this test, not confirmed by it.",
            r.name()
        ),
        Some(r) => format!(
            "Its rows record the tips at the {}, which this test rejects: record tip = {}.",
            r.name(),
            tip.name()
        ),
        None => format!(
            "Its rows do not record where the tips are: record tip = {}.",
            tip.name()
        ),
    };
    format!(
        "Against {table}, {of} last segment rejects {rejected} on all {n} fingers at every correlation from 0 to 0.9 (each Welch interval of the difference excludes 0) and does not reject {kept} on any{nearest}. So {of} fingertips are taken {}: not rejected is not shown equal. {record}",
        tip.phrase(),
        of = possessive(data)
    )
}

/// "A's", "the paper's", "the X-rays'": a name's possessive.
fn possessive(name: &str) -> String {
    if name.ends_with('s') {
        format!("{name}'")
    } else {
        format!("{name}'s")
    }
}

/// The sentence of one finger: which quantities differ, on which equality is not rejected,
/// which cannot be tested, and whether the verdicts depend on the correlation.
pub fn table_finger_sentence(f: &TableFinger, names: Names<'_>) -> String {
    let mut differ: Vec<String> = Vec::new();
    let mut not_rejected: Vec<&str> = Vec::new();
    let mut none: Vec<&str> = Vec::new();
    let mut moved: Vec<&str> = Vec::new();
    for q in &f.quantities {
        let s = q.quantity.symbol();
        match q.difference.not_rejected {
            Some(false) => differ.push(format!(
                "{s} ({} {} by {})",
                names.b,
                if q.difference.difference > 0.0 {
                    "larger"
                } else {
                    "smaller"
                },
                num(q.difference.difference.abs(), d(q.quantity))
            )),
            Some(true) => not_rejected.push(s),
            None => none.push(s),
        }
        if !q.verdict_holds() {
            moved.push(s);
        }
    }
    let mut s = format!("{}: ", finger_name(f.finger));
    let mut parts = Vec::new();
    if !differ.is_empty() {
        parts.push(format!(
            "{} and {} differ on {}",
            names.a,
            names.b,
            differ.join(", ")
        ));
    }
    if !not_rejected.is_empty() {
        parts.push(format!(
            "equality not rejected on {}",
            not_rejected.join(", ")
        ));
    }
    if !none.is_empty() {
        parts.push(format!("cannot test {} (no interval)", none.join(", ")));
    }
    s.push_str(&parts.join("; "));
    if differ.is_empty() && not_rejected.is_empty() {
        s.push('.');
    } else if moved.is_empty() {
        s.push_str(&format!(
            " (correlation {}; the same verdicts at 0 and 0.9).",
            trim_rho(f.rho)
        ));
    } else {
        s.push_str(&format!(
            " (correlation {}; the verdict on {} changes between 0 and 0.9).",
            trim_rho(f.rho),
            moved.join(", ")
        ));
    }
    s
}

/// The overall sentence of a comparison with a table: how many quantities could be tested
/// and how many of those differ; for the untestable ones, how many of the table's point
/// values lie outside the data's t intervals ([`Untestable`]).
pub fn table_overall(c: &TableCohorts, names: Names<'_>) -> String {
    let all: Vec<_> = c.fingers.iter().flat_map(|f| &f.quantities).collect();
    let tested: Vec<_> = all
        .iter()
        .filter(|q| q.difference.not_rejected.is_some())
        .collect();
    let differ = tested
        .iter()
        .filter(|q| q.difference.not_rejected == Some(false))
        .count();
    let moved = tested.iter().filter(|q| !q.verdict_holds()).count();
    let u = &c.untestable;
    // Who lacks the spread, and how the point values sit against the other side's intervals.
    let (why, points) = match u.intervals_of.filter(|_| u.checked > 0) {
        Some(side) => {
            let (with_ci, without) = if side == "a" {
                (names.a, names.b)
            } else {
                (names.b, names.a)
            };
            (
                format!("{without} gives no SD or no n for the segments they need"),
                format!(
                    "; {} of {without}'s {} point values{} lie outside {with_ci}'s {} t intervals",
                    u.outside,
                    u.checked,
                    if tested.is_empty() { "" } else { " for them" },
                    level(c.confidence)
                ),
            )
        }
        None => (
            "no SD or no n for the segments they need".to_string(),
            String::new(),
        ),
    };
    let mut s = if tested.is_empty() {
        format!(
            "Overall: 0 of {} quantities can be tested ({why}){points}.",
            all.len()
        )
    } else {
        let mut s = format!(
            "Overall: {differ} of {} quantities {} differ between {} and {} at the assumed correlation",
            tested.len(),
            if u.quantities > 0 {
                "tested"
            } else {
                "compared"
            },
            names.a,
            names.b
        );
        let rest = tested.len() - differ;
        if rest > 0 {
            s.push_str(&format!(
                "; on the other {rest} equality is not rejected, which is not equality shown"
            ));
        }
        if moved == 0 {
            s.push_str(", and no verdict changes between correlations 0 and 0.9.");
        } else {
            s.push_str(&format!(
                "; {moved} verdict{} change{} between correlations 0 and 0.9, so those rest on the assumption.",
                if moved == 1 { "" } else { "s" },
                if moved == 1 { "s" } else { "" }
            ));
        }
        if u.quantities > 0 {
            s.push_str(&format!(
                " {} cannot be tested ({why}){points}.",
                count(u.quantities, "more quantity", "more quantities")
            ));
        }
        s
    };
    if let Some(v) = &c.tips {
        s.push(' ');
        s.push_str(&tip_overall(v, names));
    }
    s
}

/// The correlation statement: what is assumed, from where, and why it matters.
pub fn correlation_line(c: &Correlation) -> String {
    let values: Vec<String> = c
        .fingers
        .iter()
        .map(|f| format!("{} {}", f.finger.name(), trim_rho(f.rho)))
        .collect();
    match &c.from {
        Some(path) => {
            let hands = c.fingers.iter().filter_map(|f| f.hands).max().unwrap_or(0);
            format!(
                "A summary table gives no correlations between its segments, so a ratio of its means has a standard error only under an assumed one. Assumed: the mean correlation of the segment lengths (J1, J2, J3, mc) of each finger over {path} ({hands} hands with per-hand values): {}. Differences of scale between those images (age, pixel spacing) raise them. Every verdict is also given at correlations 0 and 0.9.",
                values.join(", ")
            )
        }
        None => format!(
            "A summary table gives no correlations between its segments, so a ratio of its means has a standard error only under an assumed one. Assumed (given with --correlation): {} for every finger. Every verdict is also given at correlations 0 and 0.9.",
            c.fingers
                .first()
                .map_or("0".to_string(), |f| trim_rho(f.rho))
        ),
    }
}

/// "5 X-rays, unit 'image units', fingertips at the skin" or "a published summary table,
/// 66 hands, unit 'mm'".
fn side_line(s: &SideInfo) -> String {
    let unit = match &s.unit {
        Some(u) if is_pixel_unit(u) => format!("unit '{u}' (per-image pixels)"),
        Some(u) => format!("unit '{u}'"),
        None => "no unit named".to_string(),
    };
    let name = s
        .about
        .as_ref()
        .and_then(|a| a.name.clone())
        .map_or(String::new(), |n| format!("{n}: "));
    match s.kind {
        "table" => format!(
            "{name}a published summary table, {}, {unit}; its last segments taken {}",
            s.n.map_or("n not given".to_string(), |n| format!("{n} hands")),
            match s.table_tip {
                Some(TipKind::Skin) =>
                    "to the skin (the soft tissue added), as the other side's rows record skin tips",
                _ => "to the end of the bone",
            }
        ),
        _ => format!(
            "{name}{} X-ray{}, {unit}, fingertips {}",
            s.n.unwrap_or(0),
            if s.n == Some(1) { "" } else { "s" },
            s.tips.map_or("not recorded".to_string(), |t| t.describe())
        ),
    }
}

/// The terminal output of `phalanx compare` when a side is a summary table.
pub fn text(c: &TableCohorts, width: Width) -> String {
    let names = Names::AB;
    let conf = level(c.confidence);
    let mut hidden = Hidden::new();
    let mut out = String::new();
    out.push_str(&format!("A: {} ({})\n", c.a.path, side_line(&c.a)));
    out.push_str(&format!("B: {} ({})\n", c.b.path, side_line(&c.b)));
    out.push_str("\nConclusion\n");
    out.push_str(&table_overall(c, names));
    out.push('\n');
    for f in &c.fingers {
        out.push_str(&format!("- {}\n", table_finger_sentence(f, names)));
    }
    out.push_str("\nHow the cohorts differ\n");
    for l in differences(&Profile::of_side(&c.a), &Profile::of_side(&c.b), names) {
        out.push_str(&format!("- {l}\n"));
    }
    out.push_str(&format!("\n{}\n", correlation_line(&c.correlation)));
    if let Some(v) = &c.tips {
        out.push_str(&tips_text(c, v, width, &mut hidden));
    }
    out.push_str(&format!(
        "\nThe tables: A's and B's estimates with {conf} t intervals (a dataset: its mean over X-rays; a table: its ratio of means, delta-method SE at the assumed correlation), B - A with a Welch-type {conf} interval, and the verdict at the assumed correlation: differs when that interval excludes 0, not rejected when it holds 0 (no difference shown, which is not equality shown). A verdict marked * changes between correlations 0 and 0.9 (--format csv gives each).\n"
    ));
    out.push_str(&finger_tables(c, width, &mut hidden));
    out.push_str(&unanswered(c));
    hidden.append_to(&mut out, width);
    fit_text(&out, width)
}

/// The fingertips' part of [`text`]: the data side's last segment against the table's,
/// bone only and with soft tissue, then one sentence per finger.
fn tips_text(
    c: &TableCohorts,
    v: &crate::analysis::literature::TipVerdict,
    width: Width,
    hidden: &mut Hidden,
) -> String {
    let names = Names::AB;
    let conf = level(c.confidence);
    let mut out = String::new();
    let (dn, tn) = if v.data == "a" {
        ("A", "B")
    } else {
        ("B", "A")
    };
    out.push_str(&format!(
    "\nWhere {dn}'s fingertips are: its last segment against {tn}'s, bone only and bone plus soft tissue ({conf} intervals; differences {tn} - {dn}; kept: the tip not rejected where the other is)\n"
));
    let mut g = Grid::new()
        .col("finger", Align::Left, Give::Keep)
        .col(format!("{dn}, mean [t CI]"), Align::Right, Give::Keep)
        .col(format!("{tn} bone only"), Align::Right, Give::Keep)
        .col(format!("{tn} bone + soft tissue"), Align::Right, Give::Keep)
        .col("kept", Align::Left, Give::Keep);
    for t in &v.fingers {
        g.row(vec![
            format!("{} {}", t.finger.name(), t.quantity.symbol()),
            estimate_cell(&t.data, t.quantity),
            estimate_cell(&t.bone, t.quantity),
            estimate_cell(&t.skin, t.quantity),
            match t.fit {
                Some(Fit::Skin) => "skin".into(),
                Some(Fit::Bone) => "bone".into(),
                Some(Fit::Both) => "both".into(),
                Some(Fit::Neither) => "neither".into(),
                None => "n/a".into(),
            },
        ]);
    }
    out.push_str(&g.render(width, 0, hidden));
    let tip_names = if v.data == "a" {
        names
    } else {
        Names { a: "B", b: "A" }
    };
    for t in &v.fingers {
        out.push_str(&format!(
            "- {}\n",
            tip_finding_sentence(t, tip_names, c.confidence)
        ));
    }
    out
}

/// One table per finger: A's and B's estimates, B - A and the verdict.
fn finger_tables(c: &TableCohorts, width: Width, hidden: &mut Hidden) -> String {
    let mut out = String::new();
    for f in &c.fingers {
        let mut g = Grid::new()
            .col("", Align::Left, Give::Keep)
            .col("A [CI]", Align::Right, Give::Keep)
            .col("B [CI]", Align::Right, Give::Keep)
            .col("B - A [interval]", Align::Right, Give::Keep)
            .col("verdict", Align::Left, Give::Keep);
        for q in &f.quantities {
            let k = q.quantity;
            g.row(vec![
                short(k).to_string(),
                estimate_cell(&q.a, k),
                estimate_cell(&q.b, k),
                format!(
                    "{} {}",
                    signed(q.difference.difference, d(k)),
                    interval(q.difference.interval, d(k))
                ),
                format!(
                    "{}{}",
                    verdict(q.difference.not_rejected),
                    if q.verdict_holds() { "" } else { " *" }
                ),
            ]);
        }
        out.push_str(&format!(
            "\n{} (correlation {})\n",
            f.finger.display_name(),
            trim_rho(f.rho)
        ));
        out.push_str(&g.render(width, 0, hidden));
    }
    out
}

/// The values without an interval and the quantities not compared, with why.
fn unanswered(c: &TableCohorts) -> String {
    let mut out = String::new();
    let whys: Vec<String> = c
        .fingers
        .iter()
        .flat_map(|f| &f.quantities)
        .flat_map(|q| [q.a.why.clone(), q.b.why.clone()])
        .flatten()
        .fold(Vec::new(), |mut acc, w| {
            if !acc.contains(&w) {
                acc.push(w);
            }
            acc
        });
    if !whys.is_empty() || !c.notes.is_empty() {
        out.push('\n');
        for w in whys {
            out.push_str(&format!("no interval: {w}\n"));
        }
        for n in &c.notes {
            out.push_str(&format!("not compared: {n}\n"));
        }
    }
    out
}

/// Header of the CSV of a comparison with a table.
pub const CSV_COLUMNS: [&str; 20] = [
    "finger",
    "quantity",
    "rho",
    "mean_a",
    "se_a",
    "ci_a_low",
    "ci_a_high",
    "mean_b",
    "se_b",
    "ci_b_low",
    "ci_b_high",
    "difference",
    "se",
    "df",
    "low",
    "high",
    "not_rejected",
    "not_rejected_at_0",
    "not_rejected_at_0.9",
    "notes",
];

/// The comparison with a table as CSV: one row per finger and quantity, full precision.
pub fn csv(c: &TableCohorts) -> Result<Vec<u8>, Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let err = |e| Error::render("cannot write CSV", e);
    w.write_record(CSV_COLUMNS).map_err(err)?;
    let b = |x: Option<bool>| x.map_or(String::new(), |x| x.to_string());
    for f in &c.fingers {
        for q in &f.quantities {
            let at = |r: f64| {
                q.sweep
                    .iter()
                    .find(|s| (s.rho - r).abs() < 1e-12)
                    .and_then(|s| s.not_rejected)
            };
            let notes: Vec<String> = [q.a.why.clone(), q.b.why.clone()]
                .into_iter()
                .flatten()
                .collect();
            let row = vec![
                f.finger.name().to_string(),
                q.quantity.name().to_string(),
                full(Some(f.rho)),
                full(Some(q.a.mean)),
                full(q.a.se),
                full(q.a.ci.map(|i| i.low)),
                full(q.a.ci.map(|i| i.high)),
                full(Some(q.b.mean)),
                full(q.b.se),
                full(q.b.ci.map(|i| i.low)),
                full(q.b.ci.map(|i| i.high)),
                full(Some(q.difference.difference)),
                full(q.difference.se),
                full(q.difference.df),
                full(q.difference.interval.map(|i| i.low)),
                full(q.difference.interval.map(|i| i.high)),
                b(q.difference.not_rejected),
                b(at(0.0)),
                b(at(0.9)),
                safe_cell(&notes.join("; ")),
            ];
            w.write_record(&row).map_err(err)?;
        }
    }
    w.into_inner()
        .map_err(|e| Error::render("cannot write CSV", e.to_string()))
}
