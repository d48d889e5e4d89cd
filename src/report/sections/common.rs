//! Pieces several sections share: how many X-rays a table lists, whether the data are
//! the paper's X-rays, and the interval cells of a table row.

use crate::format::interval_cells;
use crate::stats::Intervals;
use serde::Serialize;

/// Most X-rays listed row by row in the data tables; the rest are summarised.
pub const MAX_LISTED_XRAYS: usize = 100;

pub(crate) fn truncation(total: usize) -> Option<String> {
    (total > MAX_LISTED_XRAYS).then(|| {
        format!(
            "The first {MAX_LISTED_XRAYS} of {total} X-rays are listed; the statistics use all of them."
        )
    })
}

/// True when the dataset holds exactly the X-rays the paper's claims name.
pub(crate) fn is_paper((named, xrays): (usize, usize)) -> bool {
    named > 0 && named == xrays
}

/// The four intervals of a table row as text (keys `ci_t`, `ci_percentile`, `ci_bca`, `pi`).
#[derive(Debug, Clone, Serialize)]
pub struct IntervalCells {
    pub ci_t: String,
    pub ci_percentile: String,
    pub ci_bca: String,
    pub pi: String,
}

impl IntervalCells {
    /// The cells of `iv` with `d` decimals (from `format::interval_cells`).
    pub fn new(iv: &Intervals, d: usize) -> IntervalCells {
        let [ci_t, ci_percentile, ci_bca, pi] = interval_cells(iv, d);
        IntervalCells {
            ci_t,
            ci_percentile,
            ci_bca,
            pi,
        }
    }
}

/// How the report names its data: the paper's X-rays, or whatever X-rays a lab holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct DataName {
    /// True for exactly the paper's X-rays.
    pub paper: bool,
    /// "the paper" or "the X-rays".
    pub the: &'static str,
    /// "The paper" or "The X-rays".
    pub title: &'static str,
    /// "the paper's" or "the X-rays'".
    pub of: &'static str,
}

impl DataName {
    /// The paper's name when the data are exactly its X-rays, "the X-rays" otherwise.
    pub(crate) fn of(paper_xrays: (usize, usize)) -> DataName {
        if is_paper(paper_xrays) {
            DataName {
                paper: true,
                the: "the paper",
                title: "The paper",
                of: "the paper's",
            }
        } else {
            DataName {
                paper: false,
                the: "the X-rays",
                title: "The X-rays",
                of: "the X-rays'",
            }
        }
    }
}

impl DataName {
    /// `text` with "the X-rays's", as the sentences shared with `compare` write a name's
    /// possessive, made "the X-rays'".
    pub(crate) fn possessive_in(&self, text: String) -> String {
        let wrong = format!("{}'s", self.the);
        if self.of == wrong {
            text
        } else {
            text.replace(&wrong, self.of)
        }
    }
}

/// The anchor GitHub gives a Markdown heading: lower case, spaces to hyphens, other
/// punctuation dropped.
pub(crate) fn md_anchor(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| match c {
            ' ' | '-' => Some('-'),
            '_' => Some('_'),
            c if c.is_alphanumeric() => Some(c.to_ascii_lowercase()),
            _ => None,
        })
        .collect()
}
