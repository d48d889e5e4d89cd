//! Implausible data that passes every check of the loader: warnings, not errors.
//!
//! In every finger the proximal phalanx is the longest and the distal one the
//! shortest (the paper's Table 1: J1 about 0.46-0.48 of the finger, J3 about
//! 0.22-0.25). A finger whose J3 exceeds J1 in every X-ray most likely has its
//! j1 and j3 columns swapped (measured from the tip instead of the root).

use super::{Analysis, FingerAnalysis};

/// The warning for a finger whose J3 exceeds J1 in every X-ray, if it does.
/// The thumb (two segments) is never warned about. O(n).
pub(crate) fn swapped_segments(f: &FingerAnalysis) -> Option<String> {
    if f.finger.segments() != 3 || f.xrays.is_empty() {
        return None;
    }
    f.xrays
        .iter()
        .all(|x| x.lengths[2] > x.lengths[0])
        .then(|| {
            let every = if f.n == 1 {
                "its only X-ray".to_string()
            } else {
                format!("every one of its {} X-rays", f.n)
            };
            format!(
                "{}: J3 (distal) is longer than J1 (proximal) in {every}, but the proximal phalanx is \
                 the longest of a finger: j1 and j3 look swapped (measured from the tip?); check the column order",
                f.finger
            )
        })
}

/// Every such warning of an analysis, thumb first.
pub(crate) fn warnings(a: &Analysis) -> Vec<String> {
    a.fingers.iter().filter_map(swapped_segments).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Settings, analyse};
    use crate::dataset::Dataset;

    #[test]
    fn swapped_columns_are_named_and_the_papers_data_is_not() {
        let paper = Dataset::load(std::path::Path::new("data/measurements.csv")).unwrap();
        assert!(warnings(&analyse(&paper, &Settings::default())).is_empty());
        let text = "xray,finger,j1,j2,j3\na,index,170,189,340\nb,index,187,195,342\nc,ring,358,226,191\nd,ring,190,226,372\n";
        let d = Dataset::from_bytes("s.csv", text.as_bytes()).unwrap();
        let w = warnings(&analyse(&d, &Settings::default()));
        // Index: every X-ray; ring: one of two, so no warning.
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with(
                "index: J3 (distal) is longer than J1 (proximal) in every one of its 2 X-rays"
            ),
            "{}",
            w[0]
        );
        assert!(w[0].contains("j1 and j3 look swapped"), "{}", w[0]);
    }
}
