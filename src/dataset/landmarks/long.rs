//! The long layout: a CSV `image,landmark,x,y` with a header, one landmark per line.
//!
//! Landmark names as in [`super::names`]. The lines of an image may come in any order and
//! need not be adjacent. A line with `x` and `y` both empty marks a landmark as not
//! labelled (its finger is left out with a note, as COCO's visibility 0).

use super::hand::{Hand, Mark, Place, Slot, parse_coordinate};
use super::names::{self, Landmark};
use crate::dataset::csvinput::quote;
use crate::dataset::csvinput::{self, Cells, Columns};
use crate::dataset::{DataError, Problem, looks_like_formula};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::Arc;

/// The columns of the long layout, all required: `image,landmark,x,y`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    Image,
    Landmark,
    X,
    Y,
}

impl Columns for Column {
    const ALL: &'static [Column] = &[Column::Image, Column::Landmark, Column::X, Column::Y];
    const EMPTY: &'static str =
        "is empty; the long layout needs the header image,landmark,x,y and one line per landmark";
    const NO_ROWS: Option<&'static str> =
        Some("has a header but no landmarks; add one line per landmark: image,landmark,x,y");

    fn name(self) -> &'static str {
        match self {
            Column::Image => "image",
            Column::Landmark => "landmark",
            Column::X => "x",
            Column::Y => "y",
        }
    }

    fn required(self) -> bool {
        true
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Reads every line; groups landmarks into hands by image, in order of first appearance.
/// Problems of the file (its header, bytes and cells) are pushed to `problems`.
pub(super) fn read(
    label: &str,
    input: &[u8],
    problems: &mut Vec<Problem>,
) -> Result<Vec<Hand>, DataError> {
    let mut hands: Vec<Hand> = Vec::new();
    let mut index: HashMap<Arc<str>, usize> = HashMap::new();
    let mut seen: HashMap<(usize, Landmark), u64> = HashMap::new();
    let read = csvinput::read_table(label, input, |cells: &mut Cells<'_, '_, Column>| {
        let (Some(id), Some(name), Some(x_text), Some(y_text)) = (
            cells.text(Column::Image),
            cells.text(Column::Landmark),
            cells.text(Column::X),
            cells.text(Column::Y),
        ) else {
            return; // not UTF-8: reported by the reader
        };
        let Some(landmark) = checked_landmark(cells, id, name) else {
            return;
        };
        let h = match index.entry(Arc::from(id)) {
            Entry::Occupied(e) => *e.get(),
            Entry::Vacant(e) => {
                let image = e.key().clone();
                hands.push(Hand::new(image, None, place(cells, Column::Image)));
                *e.insert(hands.len() - 1)
            }
        };
        match seen.entry((h, landmark)) {
            Entry::Occupied(first) => {
                cells.bad(
                    Column::Landmark,
                    format!(
                        "image {}: the {landmark} is given twice, here and on line {}; keep one",
                        quote(id),
                        first.get()
                    ),
                );
                return;
            }
            Entry::Vacant(v) => {
                v.insert(cells.line());
            }
        }
        let slot = slot(cells, id, name, landmark, x_text, y_text);
        if let Some((finger, s)) = landmark.slot() {
            *hands[h].slot_mut(finger, s) = slot;
        }
    });
    // The reader's problems (header, bytes, cells) join the geometry's; a file it refuses
    // as a whole (UTF-16, unreadable) has no hands.
    if let Err(e) = read {
        problems.extend(e.problems);
    }
    Ok(hands)
}

/// Where column `c` of the current line is.
fn place(cells: &Cells<'_, '_, Column>, c: Column) -> Place {
    Place::csv(cells.line(), cells.column(c), c.name())
}

/// The line's landmark, after checking its image id (not empty, not a formula) and its
/// landmark name; `None` after a problem.
fn checked_landmark(cells: &mut Cells<'_, '_, Column>, id: &str, name: &str) -> Option<Landmark> {
    if id.is_empty() {
        cells.bad(
            Column::Image,
            "is empty; give every line the id of its image",
        );
        return None;
    }
    if looks_like_formula(id) {
        cells.bad(
            Column::Image,
            format!(
                "{} starts like a spreadsheet formula; remove the leading '{}'",
                quote(id),
                id.chars().next().unwrap_or('=')
            ),
        );
        return None;
    }
    let landmark = names::parse(name);
    if landmark.is_none() {
        cells.bad(
            Column::Landmark,
            format!(
                "image {}: unknown landmark {}; use {}",
                quote(id),
                quote(name),
                names::ACCEPTED
            ),
        );
    }
    landmark
}

/// The landmark's slot: unlabelled when x and y are both empty, marked when both are
/// coordinates, else invalid (a problem pushed for each bad one).
fn slot(
    cells: &mut Cells<'_, '_, Column>,
    id: &str,
    name: &str,
    landmark: Landmark,
    x_text: &str,
    y_text: &str,
) -> Slot {
    if x_text.is_empty() && y_text.is_empty() {
        return Slot::Unlabelled(place(cells, Column::Landmark));
    }
    let mut xy = [0.0; 2];
    let mut ok = true;
    for ((c, text), v) in [(Column::X, x_text), (Column::Y, y_text)]
        .into_iter()
        .zip(&mut xy)
    {
        match parse_coordinate(text) {
            Ok(value) => *v = value,
            Err(why) => {
                ok = false;
                cells.bad(c, format!("image {}, {landmark}: {why}", quote(id)));
            }
        }
    }
    if ok {
        Slot::Marked(Mark {
            x: xy[0],
            y: xy[1],
            place: place(cells, Column::Landmark),
            label: quote(name),
        })
    } else {
        Slot::Invalid
    }
}
