//! Where a dataset's fingertips are: at the end of the bone or at the skin's outline.

use serde::Serialize;

/// Where a finger's last segment (J3, the thumb's J2) ends.
///
/// Written in the measurement file's `tip` column as `bone` or `skin`, or left empty when
/// unknown. A tip at the skin includes the soft tissue beyond the distal phalanx and makes
/// the last segment longer than a tip at the bone.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum TipKind {
    /// At the end of the distal phalanx (landmarks on the bone).
    Bone,
    /// At the skin's outline (soft tissue included).
    Skin,
}

impl TipKind {
    /// `bone` or `skin`.
    pub fn name(self) -> &'static str {
        match self {
            TipKind::Bone => "bone",
            TipKind::Skin => "skin",
        }
    }

    /// Parses `bone` or `skin`, case-insensitively.
    pub fn parse(text: &str) -> Option<TipKind> {
        match text.trim().to_ascii_lowercase().as_str() {
            "bone" => Some(TipKind::Bone),
            "skin" => Some(TipKind::Skin),
            _ => None,
        }
    }

    /// "at the end of the bone (the distal phalanx)", "at the skin's outline (soft tissue included)".
    pub fn phrase(self) -> &'static str {
        match self {
            TipKind::Bone => "at the end of the bone (the distal phalanx)",
            TipKind::Skin => "at the skin's outline (soft tissue included)",
        }
    }
}

/// How many rows of a dataset put their fingertips where.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, schemars::JsonSchema)]
pub struct TipCounts {
    pub bone: usize,
    pub skin: usize,
    /// Rows whose `tip` is empty or whose file has no `tip` column.
    pub unknown: usize,
}

impl TipCounts {
    /// Counts the tips of rows.
    pub fn of(tips: impl IntoIterator<Item = Option<TipKind>>) -> TipCounts {
        let mut c = TipCounts::default();
        for t in tips {
            match t {
                Some(TipKind::Bone) => c.bone += 1,
                Some(TipKind::Skin) => c.skin += 1,
                None => c.unknown += 1,
            }
        }
        c
    }

    /// The one kind every row has, if they all have the same known kind.
    pub fn single(&self) -> Option<TipKind> {
        match (self.bone, self.skin, self.unknown) {
            (b, 0, 0) if b > 0 => Some(TipKind::Bone),
            (0, s, 0) if s > 0 => Some(TipKind::Skin),
            _ => None,
        }
    }

    /// For people: "at the end of the bone (the distal phalanx)", "not recorded",
    /// "mixed: 40 rows at the bone, 5 at the skin, 3 not recorded".
    pub fn describe(&self) -> String {
        if let Some(t) = self.single() {
            return t.phrase().to_string();
        }
        if self.bone == 0 && self.skin == 0 {
            return "not recorded".to_string();
        }
        let mut parts = Vec::new();
        for (n, what) in [
            (self.bone, "at the bone"),
            (self.skin, "at the skin"),
            (self.unknown, "not recorded"),
        ] {
            if n > 0 {
                parts.push(format!("{n} row{} {what}", if n == 1 { "" } else { "s" }));
            }
        }
        format!("mixed: {}", parts.join(", "))
    }
}
