//! The long layout: a CSV `image,landmark,x,y` with a header, one landmark per line.
//!
//! Landmark names as in [`super::names`]. The lines of an image may come in any order and
//! need not be adjacent. A line with `x` and `y` both empty marks a landmark as not
//! labelled (its finger is left out with a note, as COCO's visibility 0).

use super::names::{self, Landmark};
use super::{Hand, Mark, Place, Slot, parse_coordinate, quote};
use crate::dataset::csvinput::{self, CsvScan, Header};
use crate::dataset::{DataError, Problem, looks_like_formula};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::Arc;

/// The columns, all required, in canonical order.
pub const COLUMNS: [&str; 4] = ["image", "landmark", "x", "y"];

/// Reads every line; groups landmarks into hands by image, in order of first appearance.
pub(super) fn read(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
) -> Result<Vec<Hand>, DataError> {
    let mut scan = CsvScan::new(label, input)?;
    let Some(rec) = scan.next_record(problems) else {
        if problems.is_empty() {
            problems.push(Problem::file(
                "is empty; the long layout needs the header image,landmark,x,y and one line per landmark",
            ));
        }
        return Ok(Vec::new());
    };
    let header = Header::parse(&rec, &COLUMNS, &[], problems);
    if !problems.is_empty() {
        return Ok(Vec::new()); // column meanings are unknown; the header problems say why
    }
    let width = header.names.len();
    let col = |k: usize| header.positions[k].unwrap_or(k);
    let mut hands: Vec<Hand> = Vec::new();
    let mut index: HashMap<Arc<str>, usize> = HashMap::new();
    let mut seen: HashMap<(usize, Landmark), u64> = HashMap::new();
    let mut records = 0usize;
    while let Some(rec) = scan.next_record(problems) {
        records += 1;
        let line = rec.line;
        if rec.len() != width {
            problems.push(csvinput::field_count_problem(&rec, width));
            continue;
        }
        let field = |k: usize| rec.get(col(k));
        let place = |k: usize| Place::csv(line, col(k) + 1, COLUMNS[k]);
        let (Some(id), Some(name), Some(x_text), Some(y_text)) =
            (field(0), field(1), field(2), field(3))
        else {
            continue; // not UTF-8: reported by the scanner
        };
        if id.is_empty() {
            problems.push(place(0).problem("is empty; give every line the id of its image"));
            continue;
        }
        if looks_like_formula(id) {
            problems.push(place(0).problem(format!(
                "{} starts like a spreadsheet formula; remove the leading '{}'",
                quote(id),
                id.chars().next().unwrap_or('=')
            )));
            continue;
        }
        let Some(landmark) = names::parse(name) else {
            problems.push(place(1).problem(format!(
                "image {}: unknown landmark {}; use {}",
                quote(id),
                quote(name),
                names::ACCEPTED
            )));
            continue;
        };
        let h = match index.entry(Arc::from(id)) {
            Entry::Occupied(e) => *e.get(),
            Entry::Vacant(e) => {
                let image = e.key().clone();
                hands.push(Hand::new(image, None, place(0)));
                *e.insert(hands.len() - 1)
            }
        };
        match seen.entry((h, landmark)) {
            Entry::Occupied(first) => {
                problems.push(place(1).problem(format!(
                    "image {}: the {landmark} is given twice, here and on line {}; keep one",
                    quote(id),
                    first.get()
                )));
                continue;
            }
            Entry::Vacant(v) => {
                v.insert(line);
            }
        }
        let slot = if x_text.is_empty() && y_text.is_empty() {
            Slot::Unlabelled(place(1))
        } else {
            let mut xy = [0.0; 2];
            let mut ok = true;
            for (k, (text, v)) in [x_text, y_text].into_iter().zip(&mut xy).enumerate() {
                match parse_coordinate(text) {
                    Ok(c) => *v = c,
                    Err(why) => {
                        ok = false;
                        problems.push(
                            place(2 + k).problem(format!("image {}, {landmark}: {why}", quote(id))),
                        );
                    }
                }
            }
            if ok {
                Slot::Marked(Mark {
                    x: xy[0],
                    y: xy[1],
                    place: place(1),
                    label: quote(name),
                })
            } else {
                Slot::Invalid
            }
        };
        if let Some((finger, s)) = landmark.slot() {
            *hands[h].slot_mut(finger, s) = slot;
        }
    }
    if let Err(e) = scan.finish() {
        problems.push(Problem::file(format!("could not be read to the end ({e})")));
    }
    if records == 0 && problems.is_empty() {
        problems.push(Problem::file(
            "has a header but no landmarks; add one line per landmark: image,landmark,x,y",
        ));
    }
    Ok(hands)
}
