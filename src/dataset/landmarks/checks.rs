//! From a hand's landmarks to its rows, refusing geometry that cannot be a finger.
//!
//! Per finger, in this order (the first that fails is reported; the finger is not measured):
//!
//! 1. completeness: a finger needs every joint from the MCP to the tip. A finger with none
//!    of them, or with one marked as not labelled, is left out with a note; a finger with
//!    some but not all of them is a problem (a missing landmark). The CMC is optional.
//! 2. zero-length segments: two consecutive joints (CMC included) at the same point.
//! 3. order along the finger: each joint from the PIP (thumb: IP) on must lie farther from
//!    the MCP than the one before it; a DIP nearer the MCP than the PIP is the mark of
//!    swapped landmarks.
//! 4. folds: consecutive segments (CMC -> MCP included) may not turn by more than 90
//!    degrees (their dot product is negative), which no finger lying on a detector does.
//! 5. proportions: no phalanx over [`MAX_SEGMENT_RATIO`] times another. The metacarpal is
//!    left out: it is naturally up to about 6.4 times the distal phalanx (the Digital Hand
//!    Atlas's largest ratio, little finger).

use super::hand::{Hand, LandmarkRow, Mark, Side, Slot};
use super::names::{Joint, chain};
use crate::dataset::TipKind;
use crate::dataset::csvinput::quote;
use crate::dataset::{Finger, MAX_LENGTH, Problem};
use crate::format::num;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Largest ratio of the longest to the shortest phalanx of a finger. The Digital Hand
/// Atlas's largest is 3.8 (910 hands, little finger J1/J3); the paper's is 2.3.
pub const MAX_SEGMENT_RATIO: f64 = 5.0;

/// Largest turn, in degrees, between consecutive segments of a finger.
pub const MAX_FOLD_DEGREES: f64 = 90.0;

/// What every row of an import shares.
pub(super) struct RowMeta {
    /// Multiplies pixel lengths (the pixel spacing, or 1).
    pub scale: f64,
    pub unit: Arc<str>,
    pub source: Option<Arc<str>>,
    pub tip: Option<TipKind>,
    /// The side of hands whose file gives none.
    pub side: Option<Side>,
}

/// Notes collected over a file, gathered per finger so a finger absent from every image
/// makes one note, not one per image.
#[derive(Default)]
pub(super) struct Notes {
    /// Images without any landmark of a finger.
    absent: BTreeMap<Finger, Vec<Arc<str>>>,
    /// Images where a joint of a finger is marked as not labelled, with where.
    unlabelled: BTreeMap<Finger, Vec<String>>,
    /// Other notes, in order.
    other: Vec<String>,
}

/// Most images named in one note.
const NOTE_NAMES: usize = 10;

impl Notes {
    /// Adds a note of its own.
    pub fn push(&mut self, note: String) {
        self.other.push(note);
    }

    /// The notes as sentences: other notes first, then per finger.
    pub fn finish(self) -> Vec<String> {
        let list = |items: &[String]| {
            let mut s = items
                .iter()
                .take(NOTE_NAMES)
                .cloned()
                .collect::<Vec<_>>()
                .join(", ");
            if items.len() > NOTE_NAMES {
                s.push_str(&format!(" and {} more", items.len() - NOTE_NAMES));
            }
            s
        };
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let mut out = self.other;
        for (f, images) in &self.absent {
            let named: Vec<String> = images.iter().map(|i| quote(i)).collect();
            out.push(format!(
                "{} finger: not annotated in {} image{} ({}); imported the fingers they have",
                f.name(),
                images.len(),
                plural(images.len()),
                list(&named)
            ));
        }
        for (f, places) in &self.unlabelled {
            out.push(format!(
                "{} finger: not imported from {} image{} where a joint is marked as not labelled ({})",
                f.name(),
                places.len(),
                plural(places.len()),
                list(places)
            ));
        }
        out
    }
}

/// Measures every finger of `hand` that passes the checks (module docs), appending its
/// row to `rows`; pushes a problem per failed check and a note per finger left out.
pub(super) fn measure(
    hand: &Hand,
    meta: &RowMeta,
    rows: &mut Vec<LandmarkRow>,
    problems: &mut Vec<Problem>,
    notes: &mut Notes,
) {
    for finger in Finger::ALL {
        let joints = chain(finger);
        let slots = &hand.slots[finger.index()][..joints.len()];
        if slots.iter().any(|s| matches!(s, Slot::Invalid)) {
            continue; // a coordinate is bad; its problem is reported
        }
        let phalanx_slots = &slots[1..];
        if let Some(place) = phalanx_slots.iter().find_map(|s| match s {
            Slot::Unlabelled(p) => Some(p),
            _ => None,
        }) {
            let at = place
                .field
                .clone()
                .or(place.line.map(|l| format!("line {l}")));
            let at = at.map_or(String::new(), |a| format!(" at {a}"));
            notes
                .unlabelled
                .entry(finger)
                .or_default()
                .push(format!("{}{at}", quote(&hand.image)));
            continue;
        }
        let marks: Vec<&Mark> = phalanx_slots
            .iter()
            .filter_map(|s| match s {
                Slot::Marked(m) => Some(m),
                _ => None,
            })
            .collect();
        if marks.is_empty() {
            notes
                .absent
                .entry(finger)
                .or_default()
                .push(hand.image.clone());
            continue;
        }
        if marks.len() < phalanx_slots.len() {
            missing(hand, finger, phalanx_slots, problems);
            continue;
        }
        let cmc = match &slots[0] {
            Slot::Marked(m) => Some(m),
            _ => None,
        };
        if let Some(row) = geometry(hand, finger, cmc, &marks, meta, problems) {
            rows.push(row);
        }
    }
}

/// Reports each missing joint of a partly annotated finger.
fn missing(hand: &Hand, finger: Finger, phalanx_slots: &[Slot], problems: &mut Vec<Problem>) {
    let joints = &chain(finger)[1..];
    let have: Vec<&str> = joints
        .iter()
        .zip(phalanx_slots)
        .filter(|(_, s)| matches!(s, Slot::Marked(_)))
        .map(|(j, _)| j.name())
        .collect();
    for (joint, _) in joints
        .iter()
        .zip(phalanx_slots)
        .filter(|(_, s)| matches!(s, Slot::Empty))
    {
        let landmark = super::Landmark::Joint(finger, *joint);
        problems.push(hand.place.problem(format!(
            "image {}: the {landmark} is missing, but the {} finger has its {}; add the {landmark} (named e.g. '{}') or remove the finger's other landmarks",
            quote(&hand.image),
            finger.name(),
            have.join(", "),
            landmark.plain_name()
        )));
    }
}

fn dist(a: &Mark, b: &Mark) -> f64 {
    (b.x - a.x).hypot(b.y - a.y)
}

/// "index PIP (landmark 22)".
fn name(finger: Finger, joint: Joint, m: &Mark) -> String {
    format!("{} {} ({})", finger.name(), joint.name(), m.label)
}

/// Checks 2-5 of the module docs on a complete finger and measures it.
fn geometry(
    hand: &Hand,
    finger: Finger,
    cmc: Option<&Mark>,
    marks: &[&Mark],
    meta: &RowMeta,
    problems: &mut Vec<Problem>,
) -> Option<LandmarkRow> {
    let image = quote(&hand.image);
    let joints = chain(finger);
    // The chain from the CMC (when marked) or the MCP, with each point's joint.
    let mut full: Vec<(Joint, &Mark)> = Vec::with_capacity(5);
    if let Some(c) = cmc {
        full.push((Joint::Cmc, c));
    }
    full.extend(joints[1..].iter().copied().zip(marks.iter().copied()));
    let before = problems.len();
    check_distinct(&image, finger, &full, problems);
    if problems.len() > before {
        return None;
    }
    check_outwards(&image, finger, joints, marks, problems);
    if problems.len() > before {
        return None;
    }
    check_folds(&image, finger, &full, problems);
    if problems.len() > before {
        return None;
    }
    let segs: Vec<f64> = marks.windows(2).map(|w| dist(w[0], w[1])).collect();
    if let Some(problem) = implausible_proportions(hand, &image, finger, &segs) {
        problems.push(problem);
        return None;
    }
    let (lengths, mc) = match scaled(hand, &image, finger, cmc, marks[0], &segs, meta) {
        Ok(scaled) => scaled,
        Err(problem) => {
            problems.push(problem);
            return None;
        }
    };
    Some(LandmarkRow {
        image: hand.image.clone(),
        finger,
        lengths,
        mc,
        side: hand.side.or(meta.side),
        unit: meta.unit.clone(),
        source: meta.source.clone(),
        tip: meta.tip,
    })
}

/// Check 2: no two consecutive joints (CMC included) at the same point.
fn check_distinct(
    image: &str,
    finger: Finger,
    full: &[(Joint, &Mark)],
    problems: &mut Vec<Problem>,
) {
    for w in full.windows(2) {
        let ((ja, a), (jb, b)) = (w[0], w[1]);
        if a.x == b.x && a.y == b.y {
            problems.push(b.place.problem(format!(
                "image {image}: the {} is at the same point ({}, {}) as the {}, so the segment between them has zero length; one of them is misplaced",
                name(finger, jb, b),
                b.x,
                b.y,
                name(finger, ja, a)
            )));
        }
    }
}

/// Check 3: each joint from the PIP (thumb: IP) on lies farther from the MCP than the one
/// before it.
fn check_outwards(
    image: &str,
    finger: Finger,
    joints: &[Joint],
    marks: &[&Mark],
    problems: &mut Vec<Problem>,
) {
    let mcp = marks[0];
    for k in 2..marks.len() {
        let (near, far) = (dist(mcp, marks[k - 1]), dist(mcp, marks[k]));
        if far <= near {
            let (jp, jk) = (joints[k], joints[k + 1]);
            problems.push(marks[k].place.problem(format!(
                "image {image}: the {} is no farther from the {} MCP ({} px) than the {} is ({} px); the joints run {} from the MCP outwards: are two landmarks swapped?",
                name(finger, jk, marks[k]),
                finger.name(),
                num(far, 1),
                name(finger, jp, marks[k - 1]),
                num(near, 1),
                joints[1..]
                    .iter()
                    .map(|j| j.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
}

/// Check 4: consecutive segments turn by at most [`MAX_FOLD_DEGREES`].
fn check_folds(image: &str, finger: Finger, full: &[(Joint, &Mark)], problems: &mut Vec<Problem>) {
    for w in full.windows(3) {
        let ((ja, a), (jb, b), (jc, c)) = (w[0], w[1], w[2]);
        let (ux, uy, vx, vy) = (b.x - a.x, b.y - a.y, c.x - b.x, c.y - b.y);
        let cos = (ux * vx + uy * vy) / (ux.hypot(uy) * vx.hypot(vy));
        let turn = cos.clamp(-1.0, 1.0).acos().to_degrees();
        if turn > MAX_FOLD_DEGREES {
            problems.push(b.place.problem(format!(
                "image {image}: the {} finger folds back by {} degrees at the {} (between its {}-{} and {}-{} segments); no finger on a radiograph bends over {} degrees: are landmarks swapped or misplaced?",
                finger.name(),
                num(turn, 0),
                name(finger, jb, b),
                ja.name(),
                jb.name(),
                jb.name(),
                jc.name(),
                num(MAX_FOLD_DEGREES, 0)
            )));
        }
    }
}

/// Check 5: the problem when one phalanx is over [`MAX_SEGMENT_RATIO`] times another.
fn implausible_proportions(
    hand: &Hand,
    image: &str,
    finger: Finger,
    segs: &[f64],
) -> Option<Problem> {
    let (lo, hi) =
        segs.iter()
            .enumerate()
            .fold(((0, f64::INFINITY), (0, 0.0f64)), |(lo, hi), (i, &s)| {
                (
                    if s < lo.1 { (i, s) } else { lo },
                    if s > hi.1 { (i, s) } else { hi },
                )
            });
    if hi.1 <= MAX_SEGMENT_RATIO * lo.1 {
        return None;
    }
    let shown: Vec<String> = segs
        .iter()
        .enumerate()
        .map(|(i, s)| format!("J{} = {}", i + 1, num(*s, 1)))
        .collect();
    Some(hand.place.problem(format!(
        "image {image}: the {} finger's segments ({} px) make no plausible finger: J{} is {} times J{} (over {} times); check its landmarks",
        finger.name(),
        shown.join(", "),
        hi.0 + 1,
        num(hi.1 / lo.1, 1),
        lo.0 + 1,
        num(MAX_SEGMENT_RATIO, 0)
    )))
}

/// The phalanx lengths and the metacarpal's (from the CMC, when marked) scaled by the pixel
/// spacing; the problem when one falls outside (0, [`MAX_LENGTH`]].
fn scaled(
    hand: &Hand,
    image: &str,
    finger: Finger,
    cmc: Option<&Mark>,
    mcp: &Mark,
    segs: &[f64],
    meta: &RowMeta,
) -> Result<([f64; 3], Option<f64>), Problem> {
    let mut lengths = [0.0; 3];
    for (l, s) in lengths.iter_mut().zip(segs) {
        *l = s * meta.scale;
    }
    let mc = cmc.map(|c| dist(c, mcp) * meta.scale);
    let in_range = |l: &f64| *l > 0.0 && *l <= MAX_LENGTH;
    if !(lengths[..segs.len()].iter().all(in_range) && mc.iter().all(in_range)) {
        return Err(hand.place.problem(format!(
            "image {image}: the {} finger's lengths scaled by the pixel spacing {} fall outside (0, {MAX_LENGTH:e}]; check the pixel spacing",
            finger.name(),
            meta.scale
        )));
    }
    Ok((lengths, mc))
}
