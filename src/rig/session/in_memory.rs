//! A rig fixed as `audit --fix` would write it, in memory, and rigs deformed
//! and compared: what `deform --fix` and the report show.

use super::inputs::{refuse_unlike_tips, with_shape, wrist_ratios_beside};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::error::Error;
use crate::rig::deform::file::{self as deform_file, DeformRequest, FileDeformation};
use crate::rig::deform::verdict::JointVerdict;
use crate::rig::deform::{Pose, Skinning};
use crate::rig::fix;
use crate::rig::judge::{self, AuditOptions, AuditedRig, JudgeOptions, SoftTissue};
use crate::rig::read::map::NameMap;
use crate::rig::read::naming::{Side, hand_side};
use crate::rig::read::{GltfFile, Rig};
use std::path::Path;

/// A rig as `audit --fix` would write it, in memory: the parsed rig and its
/// fixed copy (a GLB, read back), with the moved joints (name, distance) and
/// the audit of the rig as given that the fix followed.
pub struct FixedInMemory {
    pub original: GltfFile,
    pub fixed: GltfFile,
    pub moved: Vec<(String, f64)>,
    /// The rig as given, judged with `audit`'s default options.
    pub audited: AuditedRig,
}

/// Judges `rig` against the statistics of `data` and fixes it as
/// [`audit`](super::audit) with `--fix` does, without writing anything: the fixed copy is
/// the same bytes `audit --fix OUT.glb` writes, parsed from memory;
/// `soft_tissue` as `audit` takes it, used where the rig's tips and the data's differ.
///
/// `metacarpals` is the metacarpals' dataset `audit` judges each MCP from its
/// ray's base against (its default, `data/atlas/measurements.csv`, where it
/// exists), so the fix weighs the bases as `audit --fix` does
/// ([`AuditedRig::judge_rays`]); `None` judges the fingers alone.
pub fn fix_in_memory(
    rig: &Path,
    map: Option<&Path>,
    data: &Path,
    settings: Settings,
    soft_tissue: &SoftTissue,
    metacarpals: Option<&Path>,
    carry_weights: bool,
) -> Result<FixedInMemory, Error> {
    let map = map.map(NameMap::load).transpose()?;
    let loaded = Rig::load(rig, map.as_ref())?;
    let dataset = Dataset::load(data)?;
    let analysis = analysis::analyse_without_bootstrap(&dataset, &settings);
    let atlas = match metacarpals {
        Some(path) => {
            let atlas = Dataset::load(path)?;
            Some((
                analysis::analyse_without_bootstrap(&atlas, &settings),
                wrist_ratios_beside(path)?,
            ))
        }
        None => None,
    };
    let atlas = atlas.as_ref().map(|(a, w)| (a, w.as_ref()));
    fix_loaded(rig, loaded, &analysis, soft_tissue, atlas, carry_weights)
}

/// [`fix_in_memory`] against statistics already computed (the report's),
/// the metacarpals' with their wrist ratios when given.
pub fn fix_in_memory_with(
    rig: &Path,
    map: Option<&Path>,
    analysis: &Analysis,
    soft_tissue: &SoftTissue,
    atlas: Option<(&Analysis, Option<&judge::WristRatios>)>,
) -> Result<FixedInMemory, Error> {
    let map = map.map(NameMap::load).transpose()?;
    let loaded = Rig::load(rig, map.as_ref())?;
    fix_loaded(rig, loaded, analysis, soft_tissue, atlas, true)
}

fn fix_loaded(
    rig: &Path,
    loaded: Rig,
    analysis: &Analysis,
    soft_tissue: &SoftTissue,
    atlas: Option<(&Analysis, Option<&judge::WristRatios>)>,
    carry_weights: bool,
) -> Result<FixedInMemory, Error> {
    // `audit --fix OUT.glb` with its default options: the same judgement
    // (skin tips, bends from the skin weights) and the same fix.
    let options = with_shape(
        &AuditOptions {
            soft_tissue: soft_tissue.clone(),
            carry_weights,
            ..AuditOptions::default()
        },
        atlas.map(|(a, _)| a),
        crate::analysis::region::PRIOR_HANDS,
    );
    refuse_unlike_tips(
        &JudgeOptions::new(options.rig_tip, options.soft_tissue.clone(), analysis),
        analysis,
    )?;
    let mut audited = AuditedRig::with(
        &loaded.file.label,
        &loaded.chains,
        &loaded.notes,
        analysis,
        &options,
        loaded.weights.as_ref(),
    );
    if let Some((atlas, wrist)) = atlas {
        audited.judge_rays(atlas, wrist, analysis, &options, loaded.weights.as_ref());
    }
    let dir = rig.parent().unwrap_or(Path::new("."));
    let out = fix::fix_with(
        &loaded.file,
        &audited.fingers,
        // As `audit --fix` does: the weights move with the joints.
        loaded.weights.as_ref().filter(|_| options.carry_weights),
        dir,
        true,
        &fix::FixOptions::default(),
    )?;
    let label = format!("{} (as audit --fix would write it)", loaded.file.label);
    let fixed = GltfFile::from_bytes(&label, &out.bytes).map_err(|e| {
        Error::render(
            format!("the fixed copy of {} did not read back", loaded.file.label),
            e,
        )
    })?;
    Ok(FixedInMemory {
        original: loaded.file,
        fixed,
        moved: out.moved,
        audited,
    })
}

/// The verdicts of one hand per side both rigs have.
pub type Verdicts = Vec<(Side, Vec<JointVerdict>)>;

/// The default deformation request of a rig file: no map, the side its name says.
pub fn deform_request<'a>(rig: &Path, pose: &'a Pose, method: Skinning) -> DeformRequest<'a> {
    DeformRequest {
        map: None,
        side: hand_side(None, None, &rig.display().to_string()),
        pose,
        method,
    }
}

/// Reads `path` and deforms it.
pub fn deform_path(path: &Path, req: &DeformRequest<'_>) -> Result<FileDeformation, Error> {
    let file = crate::rig::read::open(path)?;
    deform_parsed(&file, path, req)
}

/// Deforms a parsed rig read from `path` (its buffers beside it).
fn deform_parsed(
    file: &GltfFile,
    path: &Path,
    req: &DeformRequest<'_>,
) -> Result<FileDeformation, Error> {
    let dir = path.parent().unwrap_or(Path::new("."));
    Ok(deform_file::deform_file(file, dir, req)?)
}

/// Deforms the rig as given (A) and as `audit --fix` would write it (B) alike
/// and compares them per joint: what `phalanx deform RIG --fix` shows.
pub fn compare_fixed(
    fixed: &FixedInMemory,
    rig: &Path,
    req: &DeformRequest<'_>,
) -> Result<(FileDeformation, FileDeformation, Verdicts), Error> {
    compare_parsed(&fixed.original, &fixed.fixed, rig, req)
}

/// Deforms two parsed versions of the rig at `rig` (A, B) alike and compares
/// them per joint.
pub fn compare_parsed(
    a: &GltfFile,
    b: &GltfFile,
    rig: &Path,
    req: &DeformRequest<'_>,
) -> Result<(FileDeformation, FileDeformation, Verdicts), Error> {
    let a = deform_parsed(a, rig, req)?;
    let b = deform_parsed(b, rig, req)?;
    let verdicts = compare_deformed(&a, &b)?;
    Ok((a, b, verdicts))
}

/// The verdicts of A against B; refused when they share no hand.
pub fn compare_deformed(a: &FileDeformation, b: &FileDeformation) -> Result<Verdicts, Error> {
    let verdicts = deform_file::compare_files(a, b);
    if verdicts.is_empty() {
        return Err(Error::Usage(format!(
            "{} and {} have no hand in common (by side), so there is nothing to compare",
            a.label, b.label
        )));
    }
    Ok(verdicts)
}
