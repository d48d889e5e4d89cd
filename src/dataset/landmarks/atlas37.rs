//! The Digital Hand Atlas's 37-landmark layout: `image_id, x0, y0, ..., x36, y36`, no header.
//!
//! Landmarks 13-17 are the CMC joints of the little, ring, middle, index finger and thumb;
//! 18-20 the thumb's MCP, IP and tip; 21-24, 25-28, 29-32, 33-36 the MCP, PIP, DIP and tip
//! of the index, middle, ring and little finger (`data/atlas/README.md`). Landmarks 0-12
//! (radius, ulna, carpals) are checked as coordinates but measure nothing.

use super::hand::{Hand, Mark, Place, Slot, parse_coordinate};
use crate::dataset::csvinput::quote;
use crate::dataset::csvinput::{self, Fields};
use crate::dataset::{DataError, Finger, Problem, looks_like_formula};
use std::collections::HashMap;
use std::sync::Arc;

/// Landmarks per image.
pub const LANDMARKS: usize = 37;
/// Fields per line: the image id, then x and y of each landmark.
pub const FIELDS: usize = 1 + 2 * LANDMARKS;

/// The atlas's landmark numbers of each finger's chain (CMC, MCP, PIP, DIP, tip; thumb:
/// CMC, MCP, IP, tip).
pub const CHAINS: [(Finger, &[usize]); 5] = [
    (Finger::Thumb, &[17, 18, 19, 20]),
    (Finger::Index, &[16, 21, 22, 23, 24]),
    (Finger::Middle, &[15, 25, 26, 27, 28]),
    (Finger::Ring, &[14, 29, 30, 31, 32]),
    (Finger::Little, &[13, 33, 34, 35, 36]),
];

/// The 1-based column of landmark `k`'s x (its y is the next column).
fn x_column(k: usize) -> usize {
    2 + 2 * k
}

/// Reads every line of the atlas37 layout: checks its field count, its image id (unique)
/// and each landmark's x and y (`None` where invalid, the problem pushed), then hands the
/// line, the image and the landmarks in order to `on_line`. Cost: O(bytes).
fn each_line(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
    mut on_line: impl FnMut(&Fields<'_, '_>, Arc<str>, Vec<Option<[f64; 2]>>, &mut Vec<Problem>),
) -> Result<(String, usize), DataError> {
    let mut first_line: HashMap<Arc<str>, u64> = HashMap::new();
    let slot_of = slots();
    csvinput::read_headerless(label, input, problems, |rec: &Fields<'_, '_>, problems| {
        if rec.len() != FIELDS {
            problems.push(Problem::line(
                rec.line(),
                format!(
                    "has {} fields; the atlas37 layout has {FIELDS} on every line: an image id, then x and y of each of the {LANDMARKS} landmarks",
                    rec.len()
                ),
            ));
            return;
        }
        let Some(image) = image_id(rec, &mut first_line, problems) else {
            return;
        };
        let marks: Vec<Option<[f64; 2]>> = (0..LANDMARKS)
            .map(|k| landmark(rec, k, slot_of[k], &image, problems))
            .collect();
        on_line(rec, image, marks, problems);
    })
}

/// Reads every line into a hand; pushes the problems of each line.
pub(super) fn read(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
) -> Result<Vec<Hand>, DataError> {
    let mut hands = Vec::new();
    let slot_of = slots();
    each_line(label, input, problems, |rec, image, marks, _| {
        let line = rec.line();
        let mut hand = Hand::new(image, None, Place::csv(line, 1, "image_id"));
        for (k, (slot, xy)) in slot_of.iter().zip(marks).enumerate() {
            if let Some((finger, s)) = *slot {
                *hand.slot_mut(finger, s) = match xy {
                    Some([x, y]) => Slot::Marked(Mark {
                        x,
                        y,
                        place: Place::csv(line, x_column(k), format!("landmark {k}")),
                        label: format!("landmark {k}"),
                    }),
                    None => Slot::Invalid,
                };
            }
        }
        hands.push(hand);
    })?;
    if hands.is_empty() && problems.is_empty() {
        problems.push(Problem::file(
            "is empty; the atlas37 layout has one line per image: an image id, then x and y of 37 landmarks",
        ));
    }
    Ok(hands)
}

/// The atlas's landmark read as the wrist's centre: 10, the one carpal landmark on the
/// middle finger's ray (the head of the capitate; see `judge::WRIST_DEFINITION`).
pub const WRIST: usize = 10;

/// Per image, each finger's wrist-to-MCP distance over its length: y = |landmark [`WRIST`] -
/// MCP| / (J1 + J2 + J3), J the MCP-PIP, PIP-DIP and DIP-tip distances of the same image
/// (the tip is the bone tip), for the index, middle, ring and little finger (the thumb's
/// metacarpal swings far off the wrist, so it has none). Every line is checked as [`read`]
/// checks it; a finger of length 0 is a problem of the line. Cost: O(bytes).
pub(super) fn wrist_over_length(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
) -> Result<Vec<(Finger, Vec<f64>)>, DataError> {
    let fingers: Vec<(Finger, &[usize])> = CHAINS
        .iter()
        .filter(|(f, _)| *f != Finger::Thumb)
        .map(|&(f, marks)| (f, &marks[1..]))
        .collect();
    let mut ratios: Vec<(Finger, Vec<f64>)> =
        fingers.iter().map(|&(f, _)| (f, Vec::new())).collect();
    each_line(label, input, problems, |rec, image, marks, problems| {
        let Some(marks) = marks.into_iter().collect::<Option<Vec<[f64; 2]>>>() else {
            return;
        };
        let dist =
            |a: usize, b: usize| (marks[a][0] - marks[b][0]).hypot(marks[a][1] - marks[b][1]);
        for (k, &(finger, chain)) in fingers.iter().enumerate() {
            let mcp = chain[0];
            let length: f64 = chain.windows(2).map(|w| dist(w[0], w[1])).sum();
            if length > 0.0 {
                ratios[k].1.push(dist(WRIST, mcp) / length);
            } else {
                problems.push(Problem::field(
                    rec.line(),
                    x_column(mcp),
                    &format!("x{mcp}"),
                    format!(
                        "image {}: the {} finger's MCP, PIP, DIP and tip (landmarks {mcp}-{}) all lie on one point; correct them",
                        quote(&image),
                        finger.name(),
                        chain[chain.len() - 1]
                    ),
                ));
            }
        }
    })?;
    if ratios.iter().all(|(_, r)| r.is_empty()) && problems.is_empty() {
        problems.push(Problem::file(
            "is empty; the atlas37 layout has one line per image: an image id, then x and y of 37 landmarks",
        ));
    }
    Ok(ratios)
}

/// Per image, the thumb's CMC in the hand's own frame: (a, b) with CMC = W + D (a d + b r),
/// W the wrist (landmark [`WRIST`]), D = |M - W| and d = (M - W) / D for M the middle
/// finger's MCP (landmark 25), r the unit direction square to d in the image towards the
/// index finger's MCP (landmark 21), i.e. towards the thumb's side. The CMC sits on the
/// carpus, so (a, b) does not move with the thumb. Images whose landmarks are not all
/// valid, or whose middle MCP lies on the wrist, are passed over (the checks of
/// [`wrist_over_length`] report them). Cost: O(bytes).
pub(super) fn thumb_cmc_in_hand(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
) -> Result<Vec<[f64; 2]>, DataError> {
    const THUMB_CMC: usize = 17;
    const INDEX_MCP: usize = 21;
    const MIDDLE_MCP: usize = 25;
    let mut out = Vec::new();
    each_line(label, input, problems, |_, _, marks, _| {
        let Some(marks) = marks.into_iter().collect::<Option<Vec<[f64; 2]>>>() else {
            return;
        };
        let sub = |a: usize, b: usize| [marks[a][0] - marks[b][0], marks[a][1] - marks[b][1]];
        let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
        let m = sub(MIDDLE_MCP, WRIST);
        let big_d = m[0].hypot(m[1]);
        if big_d <= 0.0 {
            return;
        }
        let d = [m[0] / big_d, m[1] / big_d];
        let mut r = [-d[1], d[0]];
        if dot(sub(INDEX_MCP, WRIST), r) < 0.0 {
            r = [d[1], -d[0]];
        }
        let c = sub(THUMB_CMC, WRIST);
        out.push([dot(c, d) / big_d, dot(c, r) / big_d]);
    })?;
    Ok(out)
}

/// Which chain slot (finger, index along [`CHAINS`]) each landmark fills, if any.
fn slots() -> [Option<(Finger, usize)>; LANDMARKS] {
    let mut slot_of: [Option<(Finger, usize)>; LANDMARKS] = [None; LANDMARKS];
    for (finger, marks) in CHAINS {
        for (k, &m) in marks.iter().enumerate() {
            slot_of[m] = Some((finger, k));
        }
    }
    slot_of
}

/// The line's image id, recorded in `first_line`; `None` after a problem (empty, a formula,
/// or repeated).
fn image_id(
    rec: &Fields<'_, '_>,
    first_line: &mut HashMap<Arc<str>, u64>,
    problems: &mut Vec<Problem>,
) -> Option<Arc<str>> {
    let line = rec.line();
    let id = rec.get(0)?;
    if id.is_empty() {
        problems.push(Problem::field(
            line,
            1,
            "image_id",
            "is empty; give every line the id of its image",
        ));
        return None;
    }
    if looks_like_formula(id) {
        problems.push(Problem::field(
            line,
            1,
            "image_id",
            format!(
                "{} starts like a spreadsheet formula; remove the leading '{}'",
                quote(id),
                id.chars().next().unwrap_or('=')
            ),
        ));
        return None;
    }
    let image: Arc<str> = Arc::from(id);
    if let Some(first) = first_line.get(&image) {
        problems.push(Problem::field(
            line,
            1,
            "image_id",
            format!(
                "image {} is repeated: line {first} has it already; give each image one line, or correct the id",
                quote(id)
            ),
        ));
        return None;
    }
    first_line.insert(image.clone(), line);
    Some(image)
}

/// Landmark `k`'s x and y; `None` when either is not a coordinate (a problem is pushed for
/// each, naming the finger and joint of `slot`) or not UTF-8 (reported by the scanner).
fn landmark(
    rec: &Fields<'_, '_>,
    k: usize,
    slot: Option<(Finger, usize)>,
    image: &str,
    problems: &mut Vec<Problem>,
) -> Option<[f64; 2]> {
    let mut xy = [0.0; 2];
    let mut ok = true;
    for (axis, v) in xy.iter_mut().enumerate() {
        let column = x_column(k) + axis;
        let Some(text) = rec.get(column - 1) else {
            ok = false; // not UTF-8: reported by the scanner
            continue;
        };
        match parse_coordinate(text) {
            Ok(c) => *v = c,
            Err(why) => {
                ok = false;
                let axis_name = if axis == 0 { "x" } else { "y" };
                let what = slot.map_or(String::new(), |(f, s)| {
                    format!(" ({} {})", f.name(), super::names::chain(f)[s].name())
                });
                problems.push(Problem::field(
                    rec.line(),
                    column,
                    &format!("{axis_name}{k}"),
                    format!(
                        "image {}, landmark {k}{what}: {axis_name} {why}",
                        quote(image)
                    ),
                ));
            }
        }
    }
    ok.then_some(xy)
}
