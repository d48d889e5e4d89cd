//! The quantities measured once per X-ray of a finger: the relative segment
//! lengths (eq. 2), the ratios of adjacent segments and the total length (eq. 1),
//! and, where the metacarpal is measured, its ratios to the finger.

use super::Finger;
use super::named::serde_by_name;

/// A quantity measured once per X-ray of a finger.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Quantity {
    /// J~1 = J1 / J.
    RelJ1,
    /// J~2 = J2 / J.
    RelJ2,
    /// J~3 = J3 / J (not for the thumb).
    RelJ3,
    /// J2 / J1, the ratio of adjacent segments (needs no fingertip).
    RatioJ2J1,
    /// J3 / J2 (not for the thumb).
    RatioJ3J2,
    /// J, the total length in data units.
    Total,
    /// mc / J: the metacarpal (CMC to MCP) over the finger's total length. Places the
    /// MCP from the CMC, the part of the hand the paper leaves open.
    RatioMcJ,
    /// J1 / mc: the first phalanx over the metacarpal.
    RatioJ1Mc,
}

impl Quantity {
    /// Every quantity, in output order.
    pub const ALL: [Quantity; 8] = [
        Quantity::RelJ1,
        Quantity::RelJ2,
        Quantity::RelJ3,
        Quantity::RatioJ2J1,
        Quantity::RatioJ3J2,
        Quantity::Total,
        Quantity::RatioMcJ,
        Quantity::RatioJ1Mc,
    ];

    /// The quantities of the metacarpal, for X-rays whose metacarpal is measured.
    pub const METACARPAL: [Quantity; 2] = [Quantity::RatioMcJ, Quantity::RatioJ1Mc];

    /// The quantities of a finger measured on every X-ray (the metacarpal's are
    /// [`Quantity::METACARPAL`], where it is measured).
    pub fn of(finger: Finger) -> &'static [Quantity] {
        match finger {
            Finger::Thumb => &[
                Quantity::RelJ1,
                Quantity::RelJ2,
                Quantity::RatioJ2J1,
                Quantity::Total,
            ],
            _ => &Quantity::ALL[..6],
        }
    }

    /// True for the quantities that need the metacarpal.
    pub fn needs_mc(self) -> bool {
        matches!(self, Quantity::RatioMcJ | Quantity::RatioJ1Mc)
    }

    /// Machine name (`rel_j1`, ..., `total`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::RelJ1 => "rel_j1",
            Quantity::RelJ2 => "rel_j2",
            Quantity::RelJ3 => "rel_j3",
            Quantity::RatioJ2J1 => "ratio_j2_j1",
            Quantity::RatioJ3J2 => "ratio_j3_j2",
            Quantity::Total => "total",
            Quantity::RatioMcJ => "ratio_mc_j",
            Quantity::RatioJ1Mc => "ratio_j1_mc",
        }
    }

    /// Parses a machine name.
    pub fn parse(text: &str) -> Option<Quantity> {
        Quantity::ALL
            .into_iter()
            .find(|q| q.name() == text.trim().to_ascii_lowercase())
    }

    /// Name for people, in the paper's notation.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::RelJ1 => "J~1 = J1/J",
            Quantity::RelJ2 => "J~2 = J2/J",
            Quantity::RelJ3 => "J~3 = J3/J",
            Quantity::RatioJ2J1 => "J2/J1",
            Quantity::RatioJ3J2 => "J3/J2",
            Quantity::Total => "J (total length)",
            Quantity::RatioMcJ => "mc/J",
            Quantity::RatioJ1Mc => "J1/mc",
        }
    }

    /// The symbol alone: "J~1", "J2/J1", "J (total length)".
    pub fn symbol(self) -> &'static str {
        self.label().split(" = ").next().unwrap_or(self.name())
    }

    /// True for the relative values J~k (fractions of the total length).
    pub fn is_relative(self) -> bool {
        matches!(self, Quantity::RelJ1 | Quantity::RelJ2 | Quantity::RelJ3)
    }

    /// True for every quantity without a unit (relative values and ratios).
    pub fn is_unitless(self) -> bool {
        self != Quantity::Total
    }
}

serde_by_name!(
    Quantity,
    "quantity",
    "A quantity, by its machine name: rel_j1..rel_j3 = J~k (eq. 2), ratio_j2_j1, ratio_j3_j2, total = J (eq. 1).",
    Quantity::ALL.map(Quantity::name).join(", ")
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for q in Quantity::ALL {
            assert_eq!(Quantity::parse(q.name()), Some(q));
            let json = serde_json::to_string(&q).unwrap();
            assert_eq!(json, format!("\"{}\"", q.name()));
            assert_eq!(serde_json::from_str::<Quantity>(&json).unwrap(), q);
        }
        let e = serde_json::from_str::<Quantity>("\"rel_j4\"").unwrap_err();
        assert!(
            e.to_string()
                .contains("unknown quantity 'rel_j4', expected one of rel_j1, "),
            "{e}"
        );
        assert_eq!(Quantity::of(Finger::Thumb).len(), 4);
        assert_eq!(Quantity::of(Finger::Index).len(), 6);
        assert!(!Quantity::of(Finger::Index).iter().any(|q| q.needs_mc()));
        assert!(
            Quantity::METACARPAL
                .iter()
                .all(|q| q.needs_mc() && q.is_unitless())
        );
        assert_eq!(Quantity::RatioMcJ.symbol(), "mc/J");
        assert_eq!(Quantity::RelJ1.symbol(), "J~1");
        assert_eq!(Quantity::Total.symbol(), "J (total length)");
    }
}
