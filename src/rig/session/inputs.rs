//! A session's inputs checked and read: the written copy's container, a rig
//! refused whose tips differ from the data's with nothing to bridge them, the
//! soft tissue, the atlas's wrist ratios and the options' shape priors.

use crate::analysis::Analysis;
use crate::error::Error;
use crate::rig::judge::{self, AuditOptions, JudgeOptions};
use std::path::Path;

/// The atlas's landmark file, looked for beside the metacarpals' dataset.
pub const WRIST_LANDMARKS: &str = "landmarks.csv";

/// `options` with each finger's joint region shaped by `atlas`'s correlations
/// weighted as `hands` hands ([`Analysis::shape_priors`]); as given without an
/// atlas, with a weight of 0, or when `options` already has a shape.
pub fn with_shape(options: &AuditOptions, atlas: Option<&Analysis>, hands: f64) -> AuditOptions {
    let mut options = options.clone();
    if options.shape.is_none() && hands > 0.0 {
        options.shape = atlas.map(|a| a.shape_priors(hands));
    }
    options
}

/// Refuses to judge a rig whose tips differ from the data's (one at the bone,
/// the other at the skin) when no soft tissue figure is known to bridge them.
pub(super) fn refuse_unlike_tips(judge: &JudgeOptions, a: &Analysis) -> Result<(), Error> {
    if !judge.lacks_soft_tissue() {
        return Ok(());
    }
    let data = match judge.data_tips.single() {
        Some(t) => format!("{}'s rows end {}", a.dataset.path, t.phrase()),
        None => format!(
            "{}'s tips are {}, taken as bone tips",
            a.dataset.path,
            judge.data_tips.describe()
        ),
    };
    Err(Error::Usage(format!(
        "the rig's tips are read as {rig} tips and {data}, so each last segment must be \
         corrected by the fingertip's soft tissue, and no figure for it is known: {table} (its \
         measured mean per finger) was not found here. Run from the folder that holds data/, \
         give --tip-soft-tissue MM, or give --tip {kind} if the rig's tips mark the {kind} too",
        rig = judge.rig_tip.name(),
        kind = judge.data_tip.name(),
        table = judge::SOFT_TISSUE_TABLE,
    )))
}

/// Whether the copy `option` names is a GLB (.glb, .vrm) or a .gltf with
/// an embedded buffer; anything else, or the input itself, is refused.
pub(super) fn container(option: &str, rig: &Path, out: &Path) -> Result<bool, Error> {
    if crate::atomic::same_file(rig, out) {
        return Err(Error::Usage(format!(
            "{option} {} would overwrite the input rig; name a new file (the input is never modified)",
            out.display()
        )));
    }
    match out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("glb" | "vrm") => Ok(true),
        Some("gltf") => Ok(false),
        _ => Err(Error::Usage(format!(
            "{option} {}: name the output .glb or .vrm (or .gltf for an embedded buffer)",
            out.display()
        ))),
    }
}

/// The soft tissue of the summary table at `path`, unknown when there is no such file.
pub fn soft_tissue_from(path: &Path) -> Result<judge::SoftTissue, Error> {
    if !path.is_file() {
        return Ok(judge::SoftTissue::Unknown);
    }
    let table = crate::dataset::SummaryTable::load(path)?;
    let name = crate::dataset::CohortNotes::beside(path)?.and_then(|n| n.name);
    Ok(judge::SoftTissue::from_table(&table, name))
}

/// The wrist-to-MCP ratios from the atlas's landmarks ([`WRIST_LANDMARKS`])
/// beside the metacarpals' dataset `measurements`; `None` when that file is absent.
pub fn wrist_ratios_beside(measurements: &Path) -> Result<Option<judge::WristRatios>, Error> {
    let landmarks = measurements.with_file_name(WRIST_LANDMARKS);
    if landmarks.is_file() {
        Ok(Some(judge::WristRatios::load(&landmarks)?))
    } else {
        Ok(None)
    }
}
