//! COCO keypoints JSON, as CVAT, Label Studio and COCO-WholeBody export it.
//!
//! `images` (each with an `id` and usually a `file_name`), `annotations` (each with an
//! `image_id`, a `category_id` and `keypoints`, a flat list `[x, y, v, x, y, v, ...]`) and
//! `categories` (each with the `keypoints` names). Keypoints are matched by their category's
//! names ([`super::names`]); a category without names means the standard 21-point order
//! ([`super::names::STANDARD_21`]). An annotation with COCO-WholeBody's `lefthand_kpts` or
//! `righthand_kpts` (21 x 3 numbers in the standard order) gives a hand per side, and its
//! `keypoints` (the body) are ignored; `lefthand_valid: false` skips that hand.
//!
//! A keypoint whose visibility `v` is 0 is not labelled. An image is named by its
//! `file_name`, else its `id`; hands from COCO-WholeBody's keys are named `NAME:left` and
//! `NAME:right`, since one image holds both. One hand per image (and side) is read: a
//! second annotation of the same image is a problem.

use super::checks::Notes;
use super::hand::{Hand, Mark, Place, Side, Slot, coordinate};
use super::names::{self, Landmark, STANDARD_21, chain};
use crate::dataset::csvinput::quote;
use crate::dataset::{DataError, Finger, Problem, looks_like_formula};
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::sync::Arc;

/// Keypoint names of a category: `None` for the standard 21-point order.
type Names = Option<Vec<(Landmark, String)>>;

/// The names of a category that has none: the standard order.
static NO_NAMES: Names = None;

/// A hand found in an annotation, before its keypoints are read.
struct Found<'v> {
    hand: Hand,
    /// The flat list `[x, y, v, ...]`, 3 numbers per name.
    kpts: &'v [Value],
    names: Vec<(Landmark, String)>,
    /// JSON path of the list.
    path: String,
}

/// Reads the hands of a COCO file. With `side` set, COCO-WholeBody hands of the other
/// side are skipped.
pub(super) fn read(
    label: &str,
    input: &[u8],
    side: Option<Side>,
    problems: &mut Vec<Problem>,
    notes: &mut Notes,
) -> Result<Vec<Hand>, DataError> {
    let root = parse_json(label, input)?;
    let Value::Object(root) = &root else {
        problems.push(Problem::file(
            "is not a COCO keypoints file: its top level must be an object with 'images', 'annotations' and 'categories'",
        ));
        return Ok(Vec::new());
    };
    let images = images(root, problems);
    let mut categories = Categories::new(root, problems);
    let Some(annotations) = list(root, "annotations", problems) else {
        return Ok(Vec::new());
    };
    let mut hands: Vec<Hand> = Vec::new();
    let mut first: HashMap<Arc<str>, usize> = HashMap::new();
    let mut annotated = vec![false; images.order.len()];
    let mut other_side = 0usize;
    for (k, ann) in annotations.iter().enumerate() {
        let here = format!("annotations[{k}]");
        let Some((i, ann)) = annotated_image(ann, &here, &images, problems) else {
            continue;
        };
        annotated[i] = true;
        let name = &images.order[i];
        let found = if ann.contains_key("lefthand_kpts") || ann.contains_key("righthand_kpts") {
            whole_body_hands(ann, &here, name, side, &mut other_side, problems)
        } else {
            plain_hand(ann, &here, name, &mut categories, problems)
                .into_iter()
                .collect()
        };
        for found in found {
            if let Some(hand) = claim(found, k, &here, &mut first, problems) {
                hands.push(hand);
            }
        }
    }
    note_unannotated(&images.order, &annotated, notes);
    note_other_side(other_side, side, notes);
    Ok(hands)
}

/// The annotation as an object and the index of the image it annotates; `None` after a problem.
fn annotated_image<'v>(
    ann: &'v Value,
    here: &str,
    images: &Images,
    problems: &mut Vec<Problem>,
) -> Option<(usize, &'v Map<String, Value>)> {
    let Value::Object(ann) = ann else {
        problems.push(Place::json(here).problem(
            "is not an object; each annotation is {\"image_id\": ..., \"keypoints\": [...], ...}",
        ));
        return None;
    };
    let Some(id) = ann.get("image_id") else {
        problems.push(
            Place::json(here)
                .problem("has no image_id; give the id of the image (from 'images') it annotates"),
        );
        return None;
    };
    let Some(&i) = id_text(id).and_then(|t| images.by_id.get(&t)) else {
        problems.push(Place::json(format!("{here}.image_id")).problem(format!(
            "{} points at no image: no entry of 'images' has this id; add the image or correct the id",
            short(id)
        )));
        return None;
    };
    Some((i, ann))
}

/// The labelled COCO-WholeBody hands of an annotation (`lefthand_kpts`, `righthand_kpts`),
/// counting those of the side not asked for in `other_side`.
fn whole_body_hands<'v>(
    ann: &'v Map<String, Value>,
    here: &str,
    name: &str,
    side: Option<Side>,
    other_side: &mut usize,
    problems: &mut Vec<Problem>,
) -> Vec<Found<'v>> {
    let mut found: Vec<Found> = Vec::new();
    for (key, valid, s) in [
        ("lefthand_kpts", "lefthand_valid", Side::Left),
        ("righthand_kpts", "righthand_valid", Side::Right),
    ] {
        let Some(kpts) = ann.get(key) else { continue };
        if ann.get(valid) == Some(&Value::Bool(false)) {
            continue;
        }
        let path = format!("{here}.{key}");
        let Value::Array(kpts) = kpts else {
            problems.push(
                Place::json(&path).problem(
                    "is not a list; give 21 x 3 numbers: x, y, visibility of each keypoint",
                ),
            );
            continue;
        };
        if kpts.len() != 3 * STANDARD_21.len() {
            problems.push(Place::json(&path).problem(format!(
                "has {} numbers; a COCO-WholeBody hand has 21 keypoints x 3 (x, y, visibility) = 63",
                kpts.len()
            )));
            continue;
        }
        if kpts
            .iter()
            .skip(2)
            .step_by(3)
            .all(|v| v.as_f64() == Some(0.0))
        {
            continue; // no keypoint labelled: the person's hand is not annotated
        }
        if side.is_some_and(|want| want != s) {
            *other_side += 1;
            continue;
        }
        let image: Arc<str> = Arc::from(format!("{name}:{}", s.name()));
        found.push(Found {
            hand: Hand::new(image, Some(s), Place::json(here)),
            kpts,
            names: standard_names(),
            path,
        });
    }
    found
}

/// The hand of a plain COCO annotation (`keypoints` named by its category); `None` after a
/// problem.
fn plain_hand<'v>(
    ann: &'v Map<String, Value>,
    here: &str,
    name: &str,
    categories: &mut Categories,
    problems: &mut Vec<Problem>,
) -> Option<Found<'v>> {
    let path = format!("{here}.keypoints");
    let kpts = match ann.get("keypoints") {
        Some(Value::Array(a)) => a,
        Some(_) => {
            problems.push(
                Place::json(&path).problem(
                    "is not a list; give x, y, visibility of each keypoint in one flat list",
                ),
            );
            return None;
        }
        None => {
            problems.push(Place::json(here).problem(
                "has no keypoints (nor COCO-WholeBody's lefthand_kpts or righthand_kpts); add the hand's keypoints",
            ));
            return None;
        }
    };
    let names = categories.names_for(ann, here, problems)?;
    let names = names.clone().unwrap_or_else(standard_names);
    if kpts.len() != 3 * names.len() {
        problems.push(Place::json(&path).problem(format!(
            "has {} numbers, but its category has {} keypoints of 3 numbers each (x, y, visibility): {} expected",
            kpts.len(),
            names.len(),
            3 * names.len()
        )));
        return None;
    }
    let image: Arc<str> = Arc::from(name);
    Some(Found {
        hand: Hand::new(image, None, Place::json(here)),
        kpts,
        names,
        path,
    })
}

/// Reads a found hand's keypoints unless its image (and side) already has a hand from an
/// earlier annotation, which is a problem.
fn claim(
    found: Found,
    k: usize,
    here: &str,
    first: &mut HashMap<Arc<str>, usize>,
    problems: &mut Vec<Problem>,
) -> Option<Hand> {
    let Found {
        mut hand,
        kpts,
        names,
        path,
    } = found;
    if let Some(j) = first.get(&hand.image) {
        problems.push(Place::json(here).problem(format!(
            "image {} already has a hand in annotations[{j}]; phalanx reads one hand per image (and side): remove one, or give each hand its own image",
            quote(&hand.image)
        )));
        return None;
    }
    first.insert(hand.image.clone(), k);
    fill(&mut hand, kpts, &names, &path, problems);
    Some(hand)
}

/// Notes the images no annotation points at (the first 10 by name).
fn note_unannotated(order: &[String], annotated: &[bool], notes: &mut Notes) {
    let lonely: Vec<String> = order
        .iter()
        .zip(annotated)
        .filter(|(_, a)| !**a)
        .map(|(n, _)| quote(n))
        .collect();
    if !lonely.is_empty() {
        let shown: Vec<&str> = lonely.iter().take(10).map(String::as_str).collect();
        notes.push(format!(
            "{} image{} without any annotation: {}{}",
            lonely.len(),
            if lonely.len() == 1 { "" } else { "s" },
            shown.join(", "),
            if lonely.len() > 10 { ", ..." } else { "" }
        ));
    }
}

/// Notes how many COCO-WholeBody hands of the side not asked for were skipped.
fn note_other_side(other_side: usize, side: Option<Side>, notes: &mut Notes) {
    if other_side > 0 {
        notes.push(format!(
            "{other_side} COCO-WholeBody hand{} of the other side skipped (only {} hands asked for)",
            if other_side == 1 { "" } else { "s" },
            side.map_or("", Side::name)
        ));
    }
}

/// Parses the whole file as JSON; syntax errors name their line and column.
fn parse_json(label: &str, input: &[u8]) -> Result<Value, DataError> {
    if input.starts_with(b"\xFF\xFE") || input.starts_with(b"\xFE\xFF") {
        return Err(DataError::whole_file(
            label,
            "is UTF-16 text; save it as UTF-8",
        ));
    }
    let input = input.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(input);
    serde_json::from_slice(input).map_err(|e| {
        let text = e.to_string();
        let what = text.split(" at line ").next().unwrap_or(&text);
        DataError {
            file: label.to_string(),
            problems: vec![Problem {
                line: Some(e.line() as u64),
                column: Some(e.column()),
                field: None,
                message: format!(
                    "is not valid JSON ({what}); a COCO keypoints file is one JSON object"
                ),
            }],
        }
    })
}

/// `root[key]` as a list; a problem when absent or not a list.
fn list<'v>(
    root: &'v Map<String, Value>,
    key: &str,
    problems: &mut Vec<Problem>,
) -> Option<&'v Vec<Value>> {
    match root.get(key) {
        Some(Value::Array(a)) => Some(a),
        Some(_) => {
            problems.push(Place::json(key).problem("is not a list"));
            None
        }
        None => {
            problems.push(Problem::file(format!(
                "has no '{key}' list; a COCO keypoints file has 'images', 'annotations' and 'categories'"
            )));
            None
        }
    }
}

/// An id as text: numbers as written (7), strings as they are.
fn id_text(v: &Value) -> Option<String> {
    match v {
        Value::Number(n) => Some(n.to_string()),
        Value::String(s) => Some(s.clone()),
        _ => None,
    }
}

/// A JSON value for a message: text quoted, anything else as JSON; long values shortened.
fn short(v: &Value) -> String {
    match v {
        Value::String(s) => quote(s),
        other => {
            let json = other.to_string();
            if json.chars().count() <= 40 {
                json
            } else {
                quote(&json)
            }
        }
    }
}

/// The images: their names in file order, and the index of each id.
struct Images {
    order: Vec<String>,
    by_id: HashMap<String, usize>,
}

fn images(root: &Map<String, Value>, problems: &mut Vec<Problem>) -> Images {
    let mut out = Images {
        order: Vec::new(),
        by_id: HashMap::new(),
    };
    let Some(entries) = list(root, "images", problems) else {
        return out;
    };
    let mut by_name: HashMap<String, usize> = HashMap::new();
    for (k, img) in entries.iter().enumerate() {
        let here = format!("images[{k}]");
        let Some(id) = img.get("id") else {
            problems.push(Place::json(&here).problem("has no id; give each image a unique id"));
            continue;
        };
        let Some(id) = id_text(id) else {
            problems.push(Place::json(format!("{here}.id")).problem(format!(
                "{} is not an id; use a number or a string",
                short(id)
            )));
            continue;
        };
        let name = match img.get("file_name") {
            Some(Value::String(s)) if !s.trim().is_empty() => s.trim().to_string(),
            _ => id.clone(),
        };
        if looks_like_formula(&name) {
            problems.push(Place::json(format!("{here}.file_name")).problem(format!(
                "{} starts like a spreadsheet formula; rename the image",
                quote(&name)
            )));
            continue;
        }
        if let Some(&j) = out.by_id.get(&id) {
            problems.push(Place::json(format!("{here}.id")).problem(format!(
                "image id {} is repeated: images[{j}] has it already; give each image its own id",
                quote(&id)
            )));
            continue;
        }
        if let Some(&j) = by_name.get(&name) {
            problems.push(Place::json(format!("{here}.file_name")).problem(format!(
                "image {} is repeated: images[{j}] has the same file name; give each image its own",
                quote(&name)
            )));
            continue;
        }
        by_name.insert(name.clone(), k);
        out.by_id.insert(id, out.order.len());
        out.order.push(name);
    }
    out
}

/// The categories, their keypoint names parsed (and checked) when an annotation uses them.
struct Categories<'v> {
    list: Vec<&'v Value>,
    by_id: HashMap<String, usize>,
    /// Parsed names per category: `Some(Ok)` once parsed, `Some(Err)` when it had problems.
    parsed: Vec<Option<Result<Names, ()>>>,
}

impl<'v> Categories<'v> {
    fn new(root: &'v Map<String, Value>, problems: &mut Vec<Problem>) -> Categories<'v> {
        let list: Vec<&Value> = match root.get("categories") {
            Some(Value::Array(a)) => a.iter().collect(),
            Some(_) => {
                problems.push(Place::json("categories").problem("is not a list"));
                Vec::new()
            }
            None => Vec::new(),
        };
        let by_id = list
            .iter()
            .enumerate()
            .filter_map(|(i, c)| Some((id_text(c.get("id")?)?, i)))
            .collect();
        let parsed = vec![None; list.len()];
        Categories {
            list,
            by_id,
            parsed,
        }
    }

    /// The keypoint names of an annotation's category; `None` after a problem.
    fn names_for(
        &mut self,
        ann: &Map<String, Value>,
        here: &str,
        problems: &mut Vec<Problem>,
    ) -> Option<&Names> {
        let i = match ann.get("category_id") {
            Some(id) => match id_text(id).and_then(|t| self.by_id.get(&t)) {
                Some(&i) => i,
                None if self.list.is_empty() => return Some(&NO_NAMES),
                None => {
                    problems.push(Place::json(format!("{here}.category_id")).problem(format!(
                        "{} points at no category: no entry of 'categories' has this id; correct it",
                        short(id)
                    )));
                    return None;
                }
            },
            None if self.list.len() == 1 => 0,
            None => return Some(&NO_NAMES),
        };
        if self.parsed[i].is_none() {
            self.parsed[i] = Some(parse_category(self.list[i], i, problems));
        }
        self.parsed[i].as_ref()?.as_ref().ok()
    }
}

/// The standard 21-point order with plain names.
fn standard_names() -> Vec<(Landmark, String)> {
    STANDARD_21.iter().map(|l| (*l, l.plain_name())).collect()
}

/// Parses and checks a category's keypoint names.
fn parse_category(cat: &Value, i: usize, problems: &mut Vec<Problem>) -> Result<Names, ()> {
    let here = format!("categories[{i}].keypoints");
    let raw = match cat.get("keypoints") {
        None => return Ok(None),
        Some(Value::Array(a)) if a.is_empty() => return Ok(None),
        Some(Value::Array(a)) => a,
        Some(_) => {
            problems.push(Place::json(&here).problem("is not a list of keypoint names"));
            return Err(());
        }
    };
    let before = problems.len();
    let mut names = Vec::with_capacity(raw.len());
    let mut first: HashMap<Landmark, usize> = HashMap::new();
    for (j, v) in raw.iter().enumerate() {
        let at = Place::json(format!("{here}[{j}]"));
        let Value::String(name) = v else {
            problems.push(at.problem(format!("{} is not a keypoint name", short(v))));
            continue;
        };
        let Some(l) = names::parse(name) else {
            problems.push(at.problem(format!(
                "unknown keypoint name {}; use {}",
                quote(name),
                names::ACCEPTED
            )));
            continue;
        };
        if let Some(j0) = first.get(&l) {
            problems.push(at.problem(format!(
                "{} names the {l} again ({here}[{j0}] does already); each landmark once",
                quote(name)
            )));
            continue;
        }
        first.insert(l, j);
        names.push((l, name.clone()));
    }
    if problems.len() > before {
        return Err(());
    }
    // A finger named in part: its other joints can never be read.
    for f in Finger::ALL {
        let joints = &chain(f)[1..];
        let named: Vec<bool> = joints
            .iter()
            .map(|&j| first.contains_key(&Landmark::Joint(f, j)))
            .collect();
        if named.contains(&true) && named.contains(&false) {
            let lacking: Vec<String> = joints
                .iter()
                .zip(&named)
                .filter(|(_, n)| !**n)
                .map(|(&j, _)| format!("'{}'", Landmark::Joint(f, j).plain_name()))
                .collect();
            problems.push(Place::json(&here).problem(format!(
                "names some joints of the {} finger but not {}: that landmark is missing from every hand; add it",
                f.name(),
                lacking.join(", ")
            )));
        }
    }
    if problems.len() > before {
        return Err(());
    }
    Ok(Some(names))
}

/// Fills a hand's slots from a flat keypoint list `[x, y, v, ...]` (checked to hold
/// 3 numbers per name), reporting bad values at their JSON path.
fn fill(
    hand: &mut Hand,
    kpts: &[Value],
    names: &[(Landmark, String)],
    path: &str,
    problems: &mut Vec<Problem>,
) {
    for (j, (landmark, raw)) in names.iter().enumerate() {
        let label = format!("keypoint {j} {}", quote(raw));
        let at = |o: usize| Place::json(format!("{path}[{}]", 3 * j + o));
        let mut ok = true;
        let v = &kpts[3 * j + 2];
        let visible = match v.as_f64() {
            Some(v) => v != 0.0,
            None => {
                ok = false;
                problems.push(at(2).problem(format!(
                    "image {}, {label} ({landmark}): the visibility {} is not a number; use 0 (not labelled), 1 or 2",
                    quote(&hand.image),
                    short(v)
                )));
                true
            }
        };
        let slot = if !visible {
            Slot::Unlabelled(at(0))
        } else {
            let mut xy = [0.0; 2];
            for (o, c) in xy.iter_mut().enumerate() {
                let axis = if o == 0 { "x" } else { "y" };
                let value = &kpts[3 * j + o];
                let why = match value.as_f64() {
                    Some(n) => match coordinate(n) {
                        Ok(n) => {
                            *c = n;
                            continue;
                        }
                        Err(why) => format!("{axis} {n} {why}"),
                    },
                    None => format!(
                        "{axis} is {}, not a number; give the pixel coordinate (or visibility 0 for a keypoint not labelled)",
                        short(value)
                    ),
                };
                ok = false;
                problems.push(at(o).problem(format!(
                    "image {}, {label} ({landmark}): {why}",
                    quote(&hand.image)
                )));
            }
            if ok {
                Slot::Marked(Mark {
                    x: xy[0],
                    y: xy[1],
                    place: at(0),
                    label: label.clone(),
                })
            } else {
                Slot::Invalid
            }
        };
        if let Some((finger, s)) = landmark.slot() {
            *hand.slot_mut(finger, s) = slot;
        }
    }
}
