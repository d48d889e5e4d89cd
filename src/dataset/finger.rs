//! The five fingers and the names they go by.

use super::named::serde_by_name;
use std::fmt;

/// One finger of a hand, in the order the report lists them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Finger {
    Thumb,
    Index,
    Middle,
    Ring,
    Little,
}

impl Finger {
    /// Every finger, thumb first (the order of the hand, radial to ulnar).
    pub const ALL: [Finger; 5] = [
        Finger::Thumb,
        Finger::Index,
        Finger::Middle,
        Finger::Ring,
        Finger::Little,
    ];

    /// The canonical lower-case name used in data files and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Finger::Thumb => "thumb",
            Finger::Index => "index",
            Finger::Middle => "middle",
            Finger::Ring => "ring",
            Finger::Little => "little",
        }
    }

    /// The name for people, naming the paper's term where it differs.
    pub fn display_name(self) -> &'static str {
        match self {
            Finger::Index => "index (the paper's 'grooming' finger)",
            other => other.name(),
        }
    }

    /// The name with its indefinite article: "an index", "a ring".
    pub(crate) fn with_article(self) -> String {
        match self {
            Finger::Index => "an index".to_string(),
            other => format!("a {}", other.name()),
        }
    }

    /// Number of measured segments: 2 for the thumb (J1, J2), 3 for the others (J1..J3).
    pub fn segments(self) -> usize {
        match self {
            Finger::Thumb => 2,
            _ => 3,
        }
    }

    /// Position in [`Finger::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Parses a finger name case-insensitively, accepting the aliases
    /// `grooming`, `pointer`, `forefinger` (index) and `pinky`, `small` (little).
    pub fn parse(text: &str) -> Option<Finger> {
        let t = text.trim().to_ascii_lowercase();
        Some(match t.as_str() {
            "thumb" => Finger::Thumb,
            "index" | "grooming" | "pointer" | "forefinger" => Finger::Index,
            "middle" => Finger::Middle,
            "ring" => Finger::Ring,
            "little" | "pinky" | "small" => Finger::Little,
            _ => return None,
        })
    }

    /// The accepted spellings, for error messages and `--help`.
    pub const ACCEPTED: &'static str =
        "thumb, index (or grooming, pointer, forefinger), middle, ring, little (or pinky, small)";
}

impl fmt::Display for Finger {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

serde_by_name!(
    Finger,
    "finger",
    "A finger, by its canonical name.",
    Finger::ACCEPTED
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_and_case() {
        assert_eq!(Finger::parse("Grooming"), Some(Finger::Index));
        assert_eq!(Finger::parse(" POINTER "), Some(Finger::Index));
        assert_eq!(Finger::parse("forefinger"), Some(Finger::Index));
        assert_eq!(Finger::parse("Pinky"), Some(Finger::Little));
        assert_eq!(Finger::parse("small"), Some(Finger::Little));
        assert_eq!(Finger::parse("THUMB"), Some(Finger::Thumb));
        assert_eq!(Finger::parse("toe"), None);
        assert_eq!(Finger::parse(""), None);
    }

    #[test]
    fn json_names_round_trip_and_unknown_names_are_refused() {
        for f in Finger::ALL {
            let json = serde_json::to_string(&f).unwrap();
            assert_eq!(json, format!("\"{}\"", f.name()));
            assert_eq!(serde_json::from_str::<Finger>(&json).unwrap(), f);
        }
        let e = serde_json::from_str::<Finger>("\"toe\"").unwrap_err();
        assert!(
            e.to_string()
                .contains("unknown finger 'toe', expected one of thumb, "),
            "{e}"
        );
    }

    #[test]
    fn segments_per_finger() {
        assert_eq!(Finger::Thumb.segments(), 2);
        for f in &Finger::ALL[1..] {
            assert_eq!(f.segments(), 3);
        }
        assert_eq!(
            Finger::Index.display_name(),
            "index (the paper's 'grooming' finger)"
        );
    }
}
