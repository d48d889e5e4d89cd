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

/// Lines of rows as people read them, "2-6, 9, 12-13": runs of consecutive lines, the
/// first few kept and the others counted, so that a message about a million rows stays
/// one line.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineRuns {
    /// The first runs, each its first and last line.
    runs: Vec<(u64, u64)>,
    /// How many runs after those.
    more: usize,
}

impl LineRuns {
    /// The runs of `lines` (in file order), at most `max` of them kept. O(lines).
    pub fn of(lines: impl IntoIterator<Item = u64>, max: usize) -> LineRuns {
        let mut out = LineRuns::default();
        let mut last: Option<u64> = None;
        for l in lines {
            let continues = last.is_some_and(|p| p + 1 == l);
            last = Some(l);
            if continues {
                if out.more == 0
                    && let Some((_, hi)) = out.runs.last_mut()
                {
                    *hi = l;
                }
            } else if out.runs.len() < max && out.more == 0 {
                out.runs.push((l, l));
            } else {
                out.more += 1;
            }
        }
        out
    }

    /// True when no line is named.
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// True when the lines are one line alone.
    pub fn is_one_line(&self) -> bool {
        self.more == 0 && matches!(self.runs.as_slice(), [(a, b)] if a == b)
    }

    /// "2-6, 9, 12-13", then "and 4 more" for runs not kept.
    pub fn describe(&self) -> String {
        let shown: Vec<String> = self
            .runs
            .iter()
            .map(|&(a, b)| {
                if a == b {
                    a.to_string()
                } else {
                    format!("{a}-{b}")
                }
            })
            .collect();
        if self.more > 0 {
            format!("{} and {} more", shown.join(", "), self.more)
        } else {
            shown.join(", ")
        }
    }

    /// "line 9", "lines 2-6, 9".
    pub fn with_word(&self) -> String {
        format!(
            "line{} {}",
            if self.is_one_line() { "" } else { "s" },
            self.describe()
        )
    }
}

/// [`pooling_problem`] and [`record_new`], with the rows they read, live in
/// [`super::tip_rows`]; named here too, where the fingertips are.
pub use super::tip_rows::pooling_problem;
pub(crate) use super::tip_rows::record_new;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_runs_keep_the_first_runs_and_count_the_rest() {
        let r = LineRuns::of([4], 6);
        assert!(r.is_one_line());
        assert_eq!(r.with_word(), "line 4");
        let r = LineRuns::of([2, 3, 4, 9, 12, 13, 20, 22, 23], 3);
        assert_eq!(r.with_word(), "lines 2-4, 9, 12-13 and 2 more");
        assert!(LineRuns::of([], 6).is_empty());
    }
}
