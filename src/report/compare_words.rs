//! The words both comparisons share, [`super::compare`] and [`super::compare_table`]:
//! how the two cohorts are called in sentences and a quantity's short symbol.

use crate::analysis::Quantity;

/// How the two cohorts are called in sentences: "A" and "B" on the terminal, "the paper"
/// and "the atlas" in the report.
#[derive(Debug, Clone, Copy)]
pub struct Names<'a> {
    pub a: &'a str,
    pub b: &'a str,
}

impl Names<'_> {
    /// The terminal's names.
    pub const AB: Names<'static> = Names { a: "A", b: "B" };
}

/// The symbol of a quantity in a narrow table: "J~1", "J2/J1", "mc/J", "J".
pub fn short(q: Quantity) -> &'static str {
    match q {
        Quantity::Total => "J",
        other => other.symbol(),
    }
}
