//! The landmarks of one hand as a file gives them ([`Hand`]: a [`Slot`] per joint, each
//! [`Mark`] with its [`Place`] in the file), the coordinates' checks, and the row made of
//! one finger ([`LandmarkRow`]): what the three readers and the checks share.

use crate::dataset::csvinput::quote;
use crate::dataset::{Finger, MAX_LENGTH, Problem, TipKind};
use schemars::JsonSchema;
use serde::Serialize;
use std::sync::Arc;

/// Which hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    Left,
    Right,
}

impl Side {
    /// `left` or `right`, as the measurement format writes it.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// Parses `left`/`right` (or `l`/`r`), case-insensitively.
    pub fn parse(text: &str) -> Option<Side> {
        match text.trim().to_ascii_lowercase().as_str() {
            "left" | "l" => Some(Side::Left),
            "right" | "r" => Some(Side::Right),
            _ => None,
        }
    }
}

/// One measurement row made from landmarks: one finger of one image.
#[derive(Debug, Clone, PartialEq)]
pub struct LandmarkRow {
    /// The image's id (the measurement format's `xray`).
    pub image: Arc<str>,
    pub finger: Finger,
    /// J1, J2, J3 in `unit` (J3 is 0 for the thumb; use [`LandmarkRow::segments`]).
    pub lengths: [f64; 3],
    /// The metacarpal, CMC to MCP, when the CMC is marked.
    pub mc: Option<f64>,
    pub side: Option<Side>,
    pub unit: Arc<str>,
    pub source: Option<Arc<str>>,
    /// Where the fingertips are; `None` when unknown.
    pub tip: Option<TipKind>,
}

#[cfg(test)]
impl LandmarkRow {
    /// `[J1, J2]` for the thumb, `[J1, J2, J3]` otherwise.
    pub fn segments(&self) -> &[f64] {
        &self.lengths[..self.finger.segments()]
    }

    /// Total length J = sum of the segments (eq. 1).
    pub fn total(&self) -> f64 {
        self.segments().iter().sum()
    }
}

/// Where something sits in the input file: a CSV line and column with the column's name,
/// or a JSON path (in `field`, with no line).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Place {
    pub(super) line: Option<u64>,
    pub(super) column: Option<usize>,
    pub(super) field: Option<String>,
}

impl Place {
    pub(super) fn csv(line: u64, column: usize, field: impl Into<String>) -> Place {
        Place {
            line: Some(line),
            column: Some(column),
            field: Some(field.into()),
        }
    }

    pub(super) fn json(path: impl Into<String>) -> Place {
        Place {
            line: None,
            column: None,
            field: Some(path.into()),
        }
    }

    pub(super) fn problem(&self, message: impl Into<String>) -> Problem {
        Problem {
            line: self.line,
            column: self.column,
            field: self.field.clone(),
            message: message.into(),
        }
    }
}

/// One marked joint, with where the file marks it and how the file names it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Mark {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) place: Place,
    /// "landmark 22", "keypoint 6 'INDEX_FINGER_PIP'", "'index_pip'".
    pub(super) label: String,
}

/// What a file says about one joint of a hand.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Slot {
    /// Nothing.
    Empty,
    /// A position.
    Marked(Mark),
    /// Explicitly not labelled (COCO visibility 0; empty x and y in the long layout).
    Unlabelled(Place),
    /// Present but unusable; its problem is already reported.
    Invalid,
}

/// The landmarks of one hand as read from a file.
#[derive(Debug, Clone)]
pub(super) struct Hand {
    /// The id its rows get.
    pub(super) image: Arc<str>,
    /// The side the file gives (COCO-WholeBody), before the options' default.
    pub(super) side: Option<Side>,
    /// Where the file names the image (for problems of landmarks it lacks).
    pub(super) place: Place,
    /// `slots[finger.index()][k]`: joint k of [`names::chain`]`(finger)`.
    pub(super) slots: [[Slot; 5]; 5],
}

impl Hand {
    pub(super) fn new(image: Arc<str>, side: Option<Side>, place: Place) -> Hand {
        Hand {
            image,
            side,
            place,
            slots: std::array::from_fn(|_| std::array::from_fn(|_| Slot::Empty)),
        }
    }

    /// The slot of a finger joint.
    pub(super) fn slot_mut(&mut self, finger: Finger, k: usize) -> &mut Slot {
        &mut self.slots[finger.index()][k]
    }
}

/// Parses one pixel coordinate, explaining what to fix when it is not a finite,
/// non-negative number no larger than [`MAX_LENGTH`].
pub(super) fn parse_coordinate(text: &str) -> Result<f64, String> {
    let text = text.trim();
    if text.is_empty() {
        return Err("is empty: the landmark is missing; give its pixel coordinate".into());
    }
    match text.parse::<f64>() {
        Ok(v) => coordinate(v).map_err(|why| format!("{} {why}", quote(text))),
        Err(_) => Err(format!(
            "{} is not a number; give the pixel coordinate as a decimal number",
            quote(text)
        )),
    }
}

/// Checks a coordinate's value (see [`parse_coordinate`]); the error completes "VALUE ...".
pub(super) fn coordinate(v: f64) -> Result<f64, &'static str> {
    if !v.is_finite() {
        Err("is not a finite number; give the pixel coordinate")
    } else if v < 0.0 {
        Err(
            "is negative; pixel coordinates count from 0 at the image's top-left corner: check the landmark",
        )
    } else if v > MAX_LENGTH {
        Err("is implausibly large for a pixel coordinate; check the value")
    } else {
        Ok(v)
    }
}
