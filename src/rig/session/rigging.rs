//! One rigging of a hand's file: its fingers made, written, read back and
//! judged as `audit` would judge them.

use super::inputs::{container, with_shape, wrist_ratios_beside};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::error::Error;
use crate::rig::judge::{self, AuditOptions, AuditedRig, SoftTissue};
use crate::rig::read::{GltfFile, Rig};
use std::path::{Path, PathBuf};

/// What to rig: a hand's file, where to write the rigged copy, and the
/// statistics its joints are placed from.
pub struct RigRequest<'a> {
    /// The hand: a .glb, .gltf, .vrm or .fbx file.
    pub input: &'a Path,
    /// Where the rigged copy goes (.glb, or .gltf with its buffer embedded).
    pub output: &'a Path,
    /// The measurements the joints are placed from (the data, or `--reference`).
    pub data: &'a Path,
    pub settings: Settings,
    /// The atlas: its mc/J places the thumb's MCP, its landmarks beside it
    /// the fingers' MCPs and the thumb's CMC.
    pub metacarpals: Option<&'a Path>,
    /// The fingertip's soft tissue, to carry bone tips to the skin.
    pub soft_tissue: SoftTissue,
    /// How the hand is found and written.
    pub make: crate::rig::make::MakeOptions,
    /// The prior's weight in hands for the re-audit's joint regions.
    pub prior_hands: f64,
}

/// A rigged hand: what was made and written, and the written copy read back
/// and judged as `audit` would judge it.
pub struct Rigged {
    pub analysis: Analysis,
    pub made: crate::rig::make::Made,
    pub audit: AuditedRig,
    pub output: PathBuf,
}

/// Rigs a hand ([`crate::rig::make::make`]) and writes the copy; it is read back
/// and audited before it is written, so nothing is written when it would not
/// read. A file that is not a hand, a hand already rigged (without
/// `--replace-fingers`), two hands without `--side`: exit status 2 with the
/// reason.
pub fn rig(req: &RigRequest<'_>) -> Result<Rigged, Error> {
    let glb = container("--out", req.input, req.output)?;
    let rig = Rig::with_any_chains(crate::rig::read::open(req.input)?, None)?;
    let dataset = Dataset::load(req.data)?;
    let analysis = analysis::analyse_without_bootstrap(&dataset, &req.settings);
    let atlas = match req.metacarpals {
        Some(path) => Some(analysis::analyse_without_bootstrap(
            &Dataset::load(path)?,
            &req.settings,
        )),
        None => None,
    };
    let wrist = match req.metacarpals {
        Some(path) => wrist_ratios_beside(path)?,
        None => None,
    };
    let mut make = req.make;
    make.write.glb = glb;
    let rigged = rig_in_memory(
        &rig,
        &req.output.display().to_string(),
        &analysis,
        atlas.as_ref().map(|a| (a, wrist.as_ref())),
        &req.soft_tissue,
        &make,
        req.prior_hands,
    )?;
    let bytes = &rigged.made.written.bytes;
    crate::atomic::replace(req.output, bytes).map_err(Error::write(req.output))?;
    Ok(Rigged {
        analysis,
        made: rigged.made,
        audit: rigged.audit,
        output: req.output.to_path_buf(),
    })
}

/// A hand rigged in memory: what [`rig`] writes (the bytes are
/// `made.written.bytes`), not written.
pub struct RiggedInMemory {
    pub made: crate::rig::make::Made,
    /// The copy read back and judged as `audit` would judge it.
    pub audit: AuditedRig,
}

/// Rigs the hand `rig` as [`rig`] does, against statistics already computed
/// (`analysis`; the atlas's with its wrist ratios, when given), and writes
/// nothing: the copy (a GLB or .gltf as `make.write.glb` says) is read back
/// as `label` and judged, its joint regions shaped by the atlas weighted as
/// `prior_hands` hands.
pub fn rig_in_memory(
    rig: &Rig,
    label: &str,
    analysis: &Analysis,
    atlas: Option<(&Analysis, Option<&judge::WristRatios>)>,
    soft_tissue: &SoftTissue,
    make: &crate::rig::make::MakeOptions,
    prior_hands: f64,
) -> Result<RiggedInMemory, Error> {
    let proportions = crate::rig::make::place::Proportions::new(
        analysis,
        atlas.map(|(a, _)| a),
        atlas.and_then(|(_, w)| w),
        soft_tissue.clone(),
    );
    let dir = rig.file.dir.as_deref().unwrap_or(Path::new("."));
    let made = crate::rig::make::make(rig, &proportions, make, dir).map_err(|e| match e {
        crate::rig::make::MakeError::File(e) => Error::Data(e),
        crate::rig::make::MakeError::Find(e) => Error::Data(e.in_file(&rig.file.label)),
        crate::rig::make::MakeError::Refused(why) => {
            Error::Data(crate::dataset::DataError::whole_file(&rig.file.label, why))
        }
    })?;
    let re = GltfFile::from_bytes(label, &made.written.bytes)
        .and_then(|f| Rig::from_file(f, None))
        .map_err(|e| {
            Error::render(
                format!(
                    "the rigged copy of {} did not read back; nothing was written",
                    rig.file.label
                ),
                e,
            )
        })?;
    let options = AuditOptions {
        soft_tissue: soft_tissue.clone(),
        ..AuditOptions::default()
    };
    let options = with_shape(&options, atlas.map(|(a, _)| a), prior_hands);
    // The made hand's chains only: a body's other hand is not this rig's.
    let side = made.hand.side;
    let chains: Vec<_> = re
        .chains
        .iter()
        .filter(|c| c.side.is_none_or(|s| s == side))
        .cloned()
        .collect();
    let mut audited = AuditedRig::with(
        &re.file.label,
        &chains,
        &re.notes,
        analysis,
        &options,
        re.weights.as_ref(),
    );
    if let Some((atlas, wrist)) = atlas {
        audited.judge_rays(atlas, wrist, analysis, &options, re.weights.as_ref());
    }
    Ok(RiggedInMemory {
        made,
        audit: audited,
    })
}
