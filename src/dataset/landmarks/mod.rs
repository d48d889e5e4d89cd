//! Landmark annotations in, measurement rows out.
//!
//! Labs and atlases hold landmarks, the pixel position of each joint clicked on a radiograph,
//! not segment lengths. [`import`] reads them in one of three [`Layout`]s and turns every
//! image's hand into measurement rows, one per finger ([`LandmarkRow`]):
//!
//! - J1, J2, J3 (J1, J2 for the thumb): Euclidean distances between consecutive joints,
//!   MCP -> PIP -> DIP -> tip (thumb: MCP -> IP -> tip), the segments of the paper's eq. (1);
//! - `mc`: the metacarpal, CMC -> MCP, where the file marks the CMC (the atlas: every finger;
//!   the 21-point hand: the thumb only).
//!
//! Lengths are in pixels (unit [`PIXEL_UNIT`], or the unit named by the options) unless a
//! pixel spacing is given, which scales them to millimetres ([`MM_UNIT`]).
//!
//! Every problem of a file is reported together in one [`DataError`], each naming the image,
//! the landmark and its place (line and column of a CSV; JSON path such as
//! `annotations[3].keypoints[18]` in a COCO file) and what to fix: missing or duplicated
//! landmarks, coordinates that are not finite non-negative numbers, repeated image ids,
//! unknown keypoint names, annotations that point at no image, and hands whose geometry
//! cannot be a finger ([`checks`]). A finger the file does not annotate at all (or marks as
//! not labelled) is left out with a note; the notes are returned, not printed.

/// Where the Digital Hand Atlas's landmarks sit, said once for every text that names them
/// (audit, report): at the joints where one bone meets the next, and at the bone tips.
pub(crate) const ATLAS_LANDMARKS: &str = "landmarks where one bone meets the next (the middle of each joint as the X-ray shows it, not the rotation centre a rig's joint is) and at the tips of the distal phalanges (bone tips, no soft tissue)";

mod atlas37;
mod checks;
mod coco;
mod hand;
mod long;
pub mod names;
mod output;

pub use hand::{LandmarkRow, Side};
pub use names::Landmark;
pub use output::write_csv;

pub use super::TipKind;
use super::csvinput::{self, quote};
use super::{DataError, Finger, Problem};
use serde::Serialize;
use std::path::Path;
use std::sync::Arc;

/// The unit of lengths measured in pixels.
pub const PIXEL_UNIT: &str = "px";
/// The unit of lengths scaled by a pixel spacing (millimetres per pixel).
pub const MM_UNIT: &str = "mm";

/// How landmarks are laid out in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// The Digital Hand Atlas's headerless CSV: `image_id, x0, y0, ..., x36, y36`
    /// (75 fields; landmarks as in `data/atlas/README.md`).
    Atlas37,
    /// COCO keypoints JSON (`images`, `annotations`, `categories`), as CVAT, Label Studio
    /// and COCO-WholeBody export it.
    Coco,
    /// CSV `image,landmark,x,y` with a header, one landmark per line.
    Long,
}

impl Layout {
    /// Every layout.
    #[cfg(test)]
    pub const ALL: [Layout; 3] = [Layout::Atlas37, Layout::Coco, Layout::Long];

    /// Where the layout's fingertips are unless the options say: `bone` for the atlas
    /// (landmarks at the tips of the distal phalanges), unknown otherwise.
    pub fn default_tip(self) -> Option<TipKind> {
        match self {
            Layout::Atlas37 => Some(TipKind::Bone),
            Layout::Coco | Layout::Long => None,
        }
    }

    /// The side of the layout's hands unless the options say: `left` for the atlas (every
    /// hand of the Digital Hand Atlas is a left hand), unknown otherwise.
    pub fn default_side(self) -> Option<Side> {
        match self {
            Layout::Atlas37 => Some(Side::Left),
            Layout::Coco | Layout::Long => None,
        }
    }
}

/// Options of an import; every one may be left unset.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ImportOptions {
    /// The side of every hand. COCO-WholeBody's `lefthand_kpts`/`righthand_kpts` carry
    /// their own side; with this set, only hands of this side are read from them.
    /// Default: [`Layout::default_side`].
    pub side: Option<Side>,
    /// Millimetres per pixel: lengths are multiplied by it and their unit is [`MM_UNIT`].
    pub pixel_spacing: Option<f64>,
    /// The unit of unscaled lengths (default [`PIXEL_UNIT`]); not with `pixel_spacing`.
    pub unit: Option<String>,
    /// Text for every row's `source` column.
    pub source: Option<String>,
    /// Where the fingertips are. Default: [`Layout::default_tip`].
    pub tip: Option<TipKind>,
}

impl ImportOptions {
    /// Checks the options, explaining what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(s) = self.pixel_spacing {
            if !(s.is_finite() && s > 0.0) {
                return Err(format!(
                    "the pixel spacing must be a positive number of millimetres per pixel (e.g. 0.108), got {s}"
                ));
            }
            if self.unit.is_some() {
                return Err(
                    "give either a pixel spacing (lengths in mm) or a unit name (lengths in pixels), not both"
                        .into(),
                );
            }
        }
        for (what, text) in [("unit", &self.unit), ("source", &self.source)] {
            if let Some(t) = text {
                if t.trim().is_empty() {
                    return Err(format!(
                        "the {what} is empty; give some text or leave it out"
                    ));
                }
                if super::looks_like_formula(t) {
                    return Err(format!(
                        "the {what} {} starts like a spreadsheet formula; remove the leading '{}'",
                        quote(t),
                        t.chars().next().unwrap_or('=')
                    ));
                }
            }
        }
        Ok(())
    }

    /// The unit every row gets: "mm" with a pixel spacing, else the unit given, else "px".
    pub fn unit(&self) -> &str {
        match (&self.pixel_spacing, &self.unit) {
            (Some(_), _) => MM_UNIT,
            (None, Some(u)) => u.trim(),
            (None, None) => PIXEL_UNIT,
        }
    }
}

/// The outcome of an import.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    pub layout: Layout,
    /// Hands read (images, or image sides for COCO-WholeBody).
    pub hands: usize,
    /// One row per hand and finger measured: hands in file order, fingers thumb first.
    pub rows: Vec<LandmarkRow>,
    /// What was left out and why (fingers not annotated or not labelled).
    pub notes: Vec<String>,
}

/// Reads and measures a landmark file; `label` names it in errors. Cost: O(bytes).
///
/// Errors with every problem of the file when any landmark is bad, and when the file holds
/// no hand with a complete finger. Invalid `options` are reported as a problem of the file.
pub fn import(
    layout: Layout,
    label: &str,
    input: &[u8],
    options: &ImportOptions,
) -> Result<Import, DataError> {
    if let Err(message) = options.validate() {
        return Err(DataError::whole_file(label, message));
    }
    let mut problems = Vec::new();
    let mut notes = checks::Notes::default();
    let hands = match layout {
        Layout::Atlas37 => atlas37::read(label, input, &mut problems)?,
        Layout::Long => long::read(label, input, &mut problems)?,
        Layout::Coco => coco::read(label, input, options.side, &mut problems, &mut notes)?,
    };
    let meta = checks::RowMeta {
        scale: options.pixel_spacing.unwrap_or(1.0),
        unit: Arc::from(options.unit()),
        source: options.source.as_deref().map(|s| Arc::from(s.trim())),
        tip: options.tip.or(layout.default_tip()),
        side: options.side.or(layout.default_side()),
    };
    let mut rows = Vec::new();
    for hand in &hands {
        checks::measure(hand, &meta, &mut rows, &mut problems, &mut notes);
    }
    if problems.is_empty() && rows.is_empty() {
        problems.push(Problem::file(format!(
            "has no hand with a complete finger ({} hand{} read); every finger needs its MCP, PIP (thumb: IP), DIP and tip",
            hands.len(),
            if hands.len() == 1 { "" } else { "s" }
        )));
    }
    if !problems.is_empty() {
        // CSV problems in line order; JSON problems (no line) keep the order found.
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        return Err(DataError {
            file: label.to_string(),
            problems,
        });
    }
    Ok(Import {
        layout,
        hands: hands.len(),
        rows,
        notes: notes.finish(),
    })
}

/// [`import`] of a file on disk, naming it as given.
pub fn import_file(
    layout: Layout,
    path: &Path,
    options: &ImportOptions,
) -> Result<Import, DataError> {
    let bytes = csvinput::read_input(path)?;
    import(layout, &path.display().to_string(), &bytes, options)
}

/// Per image of an atlas37 landmark file on disk, each finger's wrist-to-MCP distance over
/// its length J1 + J2 + J3 (index, middle, ring, little; see `atlas37::wrist_over_length`).
/// Errors with every problem of the file. Cost: O(bytes).
pub fn wrist_over_length_file(path: &Path) -> Result<Vec<(Finger, Vec<f64>)>, DataError> {
    let bytes = csvinput::read_input(path)?;
    let label = path.display().to_string();
    let mut problems = Vec::new();
    let ratios = atlas37::wrist_over_length(&label, &bytes, &mut problems)?;
    if problems.is_empty() {
        Ok(ratios)
    } else {
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        Err(DataError {
            file: label,
            problems,
        })
    }
}

/// Per image of an atlas37 landmark file on disk, the thumb's CMC in the hand's frame of
/// wrist and middle MCP (see `atlas37::thumb_cmc_in_hand`). Errors with every problem of
/// the file. Cost: O(bytes).
pub fn thumb_cmc_in_hand_file(path: &Path) -> Result<Vec<[f64; 2]>, DataError> {
    let bytes = csvinput::read_input(path)?;
    let label = path.display().to_string();
    let mut problems = Vec::new();
    let at = atlas37::thumb_cmc_in_hand(&label, &bytes, &mut problems)?;
    if problems.is_empty() {
        Ok(at)
    } else {
        problems.sort_by_key(|p| (p.line.unwrap_or(0), p.column.unwrap_or(0)));
        Err(DataError {
            file: label,
            problems,
        })
    }
}

#[cfg(test)]
mod tests;
