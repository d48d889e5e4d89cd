//! Section 3, the derived values: eqs. (1)-(4) per X-ray for each finger.

use super::common::{MAX_LISTED_XRAYS, truncation};
use crate::format::num;
use serde::Serialize;

/// Eqs. (1)-(4) per X-ray for one finger.
#[derive(Debug, Clone, Serialize)]
pub struct DerivedFinger {
    pub finger: String,
    pub id: String,
    /// Headers of the relative columns: "J~1", "J~2"[, "J~3"].
    pub relative_headers: Vec<String>,
    pub rows: Vec<DerivedRow>,
    pub truncated: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct DerivedRow {
    pub xray: String,
    pub total: String,
    pub relative: Vec<String>,
}

pub(crate) fn derived(f: &crate::analysis::FingerAnalysis) -> DerivedFinger {
    DerivedFinger {
        finger: f.finger.name().to_string(),
        id: f.finger.name().to_string(),
        relative_headers: (1..=f.finger.segments())
            .map(|k| format!("J~{k}"))
            .collect(),
        rows: f
            .xrays
            .iter()
            .take(MAX_LISTED_XRAYS)
            .map(|x| DerivedRow {
                xray: x.xray.to_string(),
                total: num(x.total, 2),
                relative: x.relative.iter().map(|r| num(*r, 4)).collect(),
            })
            .collect(),
        truncated: truncation(f.xrays.len()),
    }
}
