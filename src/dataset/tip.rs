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

/// Lines as people read them: "2-6, 9, 12-13", at most `max` runs, then "and N more".
fn line_runs(lines: &[u64], max: usize) -> String {
    let mut runs: Vec<(u64, u64)> = Vec::new();
    for &l in lines {
        match runs.last_mut() {
            Some((_, hi)) if *hi + 1 == l => *hi = l,
            _ => runs.push((l, l)),
        }
    }
    let shown: Vec<String> = runs
        .iter()
        .take(max)
        .map(|&(a, b)| {
            if a == b {
                a.to_string()
            } else {
                format!("{a}-{b}")
            }
        })
        .collect();
    let more = runs.len().saturating_sub(max);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// The refusal to pool rows whose fingertips differ: `None` unless some rows of `files`
/// (each a file's name and its rows) record their tips at the bone and others at the skin.
/// Rows with no recorded tip pool with either. The message names the rows of each kind,
/// why pooling them is wrong, and the way out (`option`, e.g. `--mixed-tips`).
///
/// A last segment to the bone is shorter than one to the skin by the fingertip's soft
/// tissue (3.7 to 5.7 mm on average, Buryanov and Kotiuk 2010, about 4-8% of the finger),
/// so a pooled J~3 mixes two quantities and every relative value shifts with it.
pub fn pooling_problem(files: &[(&str, &[super::Row])], option: &str) -> Option<String> {
    let kind = |k: TipKind| -> Vec<String> {
        files
            .iter()
            .filter_map(|(name, rows)| {
                let lines: Vec<u64> = rows
                    .iter()
                    .filter(|r| r.meta.tip == Some(k))
                    .map(|r| r.line)
                    .collect();
                (!lines.is_empty()).then(|| {
                    let n = lines.len();
                    format!(
                        "{n} row{} of {name} (line{} {})",
                        if n == 1 { "" } else { "s" },
                        if n == 1 { "" } else { "s" },
                        line_runs(&lines, 6)
                    )
                })
            })
            .collect()
    };
    let (bone, skin) = (kind(TipKind::Bone), kind(TipKind::Skin));
    if bone.is_empty() || skin.is_empty() {
        return None;
    }
    Some(format!(
        "the rows measure the last segment to different fingertips: {} at the end of the bone, {} at the skin's outline. A last segment to the skin is longer by the fingertip's soft tissue (3.7 to 5.7 mm on average, Buryanov & Kotiuk 2010), so pooled statistics would mix two quantities. Keep them in separate files and compare them with 'phalanx compare', re-measure one group to the other's tip, or give {option} to pool them anyway",
        bone.join(" and "),
        skin.join(" and ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::Dataset;

    #[test]
    fn bone_with_skin_is_refused_naming_the_rows() {
        let skin = Dataset::from_bytes(
            "data.csv",
            b"xray,finger,j1,j2,j3,tip\na,index,4,2,2,skin\nb,index,4,2,2,skin\nc,index,4,2,2,\n",
        )
        .unwrap();
        let bone = Dataset::from_bytes(
            "new.csv",
            b"xray,finger,j1,j2,j3,tip\nd,index,4,2,2,bone\ne,index,4,2,2,bone\nf,index,4,2,2,bone\ng,index,4,2,2,skin\n",
        )
        .unwrap();
        let m = pooling_problem(
            &[("data.csv", &skin.rows), ("new.csv", &bone.rows)],
            "--mixed-tips",
        )
        .unwrap();
        assert!(
            m.contains("3 rows of new.csv (lines 2-4) at the end of the bone"),
            "{m}"
        );
        assert!(
            m.contains("2 rows of data.csv (lines 2-3) and 1 row of new.csv (line 5) at the skin"),
            "{m}"
        );
        assert!(m.contains("give --mixed-tips"), "{m}");
        // Unrecorded tips pool with either; one kind alone is fine.
        assert_eq!(
            pooling_problem(&[("data.csv", &skin.rows)], "--mixed-tips"),
            None
        );
        assert_eq!(line_runs(&[1, 2, 3, 5, 7, 8], 2), "1-3, 5 and 1 more");
    }
}
