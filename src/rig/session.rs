//! One audit of a rig file: load it, judge it against the statistics and,
//! when asked, write a fixed copy. Returns finished results; showing them is
//! the caller's business.

mod after_fix;
mod in_memory;
mod inputs;
mod rigging;

pub use after_fix::{MovedBend, MovedFinger, bends_across, moved_fingers};
pub use in_memory::{
    FixedInMemory, Verdicts, compare_deformed, compare_fixed, compare_parsed, deform_path,
    deform_request, fix_in_memory, fix_in_memory_with,
};
pub use inputs::{WRIST_LANDMARKS, soft_tissue_from, with_shape, wrist_ratios_beside};
pub use rigging::{RigRequest, Rigged, RiggedInMemory, rig, rig_in_memory};

use super::fix::{self, Fixed};
use super::judge::{self, AuditOptions, AuditedRig, JudgeOptions};
use super::read::map::NameMap;
use super::read::{GltfFile, Rig};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::error::Error;
use inputs::{container, refuse_unlike_tips};
use std::path::{Path, PathBuf};

/// What to audit, against which data, and where to write a fixed copy.
pub struct AuditRequest<'a> {
    /// The rig: a .glb, .gltf, .vrm or .fbx file.
    pub rig: &'a Path,
    /// Custom joint names (CSV with node,side,finger,joint).
    pub map: Option<&'a Path>,
    /// Where to write a fixed copy (.glb or .vrm; .gltf for an embedded buffer).
    pub fix: Option<&'a Path>,
    /// The measurement file the rig is judged against.
    pub data: &'a Path,
    /// Used as given: build them with [`Settings::new`].
    pub settings: Settings,
    /// How tips are compared and bends flagged.
    pub options: AuditOptions,
    /// `--only-outside`: the fix moves only joints outside the prediction interval.
    pub only_outside: bool,
    /// The dataset with metacarpals (an `mc` column) each MCP is also judged
    /// against from its CMC, analysed with `settings`; `None`: not judged.
    pub metacarpals: Option<&'a Path>,
    /// `--fix-mcp atlas`: the fix places each MCP outside the prediction
    /// interval from its CMC (or wrist) where `metacarpals` puts it, and holds
    /// the other MCPs ([`super::judge::ray`]); needs `metacarpals`.
    pub mcp_from_atlas: bool,
    /// `--moves`: list the nodes the fix moves ([`super::fix::moves`]), for a rig
    /// of any format (an FBX rig cannot be fixed in place).
    pub moves: bool,
    /// `--prior-hands`: the weight, in hands, of the shape each finger's joint
    /// region borrows from `metacarpals` (the atlas;
    /// [`crate::analysis::region::ShapePriors`]); 0 keeps the X-rays' own.
    pub prior_hands: f64,
}

/// A finished audit.
pub struct Audit {
    /// The statistics the rig was judged against.
    pub analysis: Analysis,
    /// The input rig, judged.
    pub rig: AuditedRig,
    /// What the fix wrote, when one was asked for.
    pub fix: Option<FixOutcome>,
    /// The nodes the fix moves, when asked for ([`AuditRequest::moves`]).
    pub moves: Option<MovesOutcome>,
    /// What the rig file was, when it was FBX.
    pub fbx: Option<super::read::source::FbxSource>,
}

/// What `--moves` lists: the nodes the fix moves, the warnings that go with
/// them, the vertices whose weights it changes, and each moved finger judged
/// again with the moves made (in memory).
pub struct MovesOutcome {
    pub moves: Vec<fix::moves::Move>,
    pub warnings: Vec<String>,
    pub weights: Vec<fix::moves::WeightChange>,
    pub fingers: Vec<MovedFinger>,
}

/// What the fix wrote.
pub struct FixOutcome {
    /// The file asked for (written only when `written`).
    pub output: PathBuf,
    /// False when the fix moves no joint: the copy would be the rig as
    /// given, so nothing is written and the output path is left untouched.
    pub written: bool,
    /// (node name, distance moved in rig units), in chain order.
    pub moved: Vec<(String, f64)>,
    /// Remarks for the user (animations that drive moved joints, external images).
    pub warnings: Vec<String>,
    /// The written copy, read back and judged again.
    pub reaudit: AuditedRig,
    /// Every moved joint's distance to where its skin bends, before the fix
    /// (the rig as given) and after it (the written copy, judged again).
    pub bends: Vec<MovedBend>,
    /// Joints (as "right index PIP") the re-audit flags as far from their
    /// bend that the rig as given did not.
    pub new_defects: Vec<String>,
    /// Every finger with a moved joint, as the re-audit judges it.
    pub fingers: Vec<MovedFinger>,
}

/// What the audit says of the side of fingers whose joint names carry none,
/// by the rule `deform` curls by ([`crate::rig::read::naming::hand_side`]):
/// the side the file name says, or that no side is known and what `deform`
/// then needs. `None` when every finger's names say its side.
pub fn side_note(label: &str, chains: &[crate::rig::read::FingerChain]) -> Option<String> {
    if chains.iter().all(|c| c.side.is_some()) {
        return None;
    }
    Some(
        match crate::rig::read::naming::hand_side(None, None, label) {
            Some(side) => format!(
                "Side: the joint names do not say which hand this is; the file name says {}, and \
             deform curls it as that",
                side.name()
            ),
            None => "Side: neither the joint names nor the file name say which hand this is. The \
                 fingers are judged all the same (their proportions do not depend on the side), \
                 but deform needs --side left or --side right to curl them"
                .to_string(),
        },
    )
}

/// Audits a rig against the statistics, and with `fix` writes a corrected copy;
/// with `moves`, lists the nodes that copy moves (the same copy: one fix
/// serves both, so the list follows the fix).
///
/// The fix is refused before any work when it would overwrite the input or its
/// extension names no glTF container. The fixed copy is read back from memory
/// before it is written, so a copy that would not load is never left on disk;
/// it is written atomically and the input is never modified.
pub fn audit(req: &AuditRequest<'_>) -> Result<Audit, Error> {
    let map = req.map.map(NameMap::load).transpose()?;
    let fix_glb = req.fix.map(|out| fix_container(req.rig, out)).transpose()?;
    let rig = Rig::load(req.rig, map.as_ref())?;
    refuse_fbx_fix(req, &rig)?;
    let dataset = Dataset::load(req.data)?;
    // The judgement reads no bootstrap interval: the analysis is computed without one
    // (so no bootstrap budget applies either).
    let analysis = analysis::analyse_without_bootstrap(&dataset, &req.settings);
    refuse_unlike_tips(
        &JudgeOptions::new(
            req.options.rig_tip,
            req.options.soft_tissue.clone(),
            &analysis,
        ),
        &analysis,
    )?;
    if req.mcp_from_atlas && req.metacarpals.is_none() {
        return Err(Error::Usage(
            "--fix-mcp atlas needs the metacarpals' dataset: give --metacarpals DATASET (the \
             default data/atlas/measurements.csv was not found)"
                .into(),
        ));
    }
    let atlas = match req.metacarpals {
        Some(path) => {
            let atlas = Dataset::load(path)?;
            Some(analysis::analyse_without_bootstrap(&atlas, &req.settings))
        }
        None => None,
    };
    let mut options = with_shape(&req.options, atlas.as_ref(), req.prior_hands);
    options.found_tips = found_tips(&rig);
    let options = &options;
    // The atlas's landmarks beside its measurements give the wrist-to-MCP
    // ratios of the wrist judgement; without them it is skipped with a note.
    let wrist = match req.metacarpals {
        Some(path) if atlas.is_some() => wrist_ratios_beside(path)?,
        _ => None,
    };
    let rays = atlas.as_ref().map(|a| (a, wrist.as_ref()));
    let mut audited = AuditedRig::with(
        &rig.file.label,
        &rig.chains,
        &rig.notes,
        &analysis,
        options,
        rig.weights.as_ref(),
    );
    if let Some((atlas, wrist)) = rays {
        audited.judge_rays(atlas, wrist, &analysis, options, rig.weights.as_ref());
    }
    if let Some(note) = side_note(&rig.file.label, &rig.chains) {
        audited.notes.push(note);
    }
    // One fix serves both --fix and --moves: the moves are read off the very
    // bytes --fix writes, so they follow whatever the fix decides.
    let fixed = if req.fix.is_some() || req.moves {
        Some(fix_audited(
            req,
            &rig,
            &mut audited,
            (&analysis, atlas.is_some()),
            options,
            fix_glb.unwrap_or(true),
        )?)
    } else {
        None
    };
    let judged = Judged {
        rig: &rig,
        map: map.as_ref(),
        analysis: &analysis,
        options,
        rays,
    };
    let moves = match &fixed {
        Some(fixed) if req.moves => Some(moves_outcome(&judged, fixed)?),
        _ => None,
    };
    let fix = match (req.fix, fixed) {
        (Some(out), Some(fixed)) => Some(fix_outcome(&judged, &audited, fixed, out)?),
        _ => None,
    };
    audited.settle_fix(req.only_outside && (req.fix.is_some() || req.moves));
    Ok(Audit {
        analysis,
        rig: audited,
        fix,
        moves,
        fbx: rig.file.fbx.clone(),
    })
}

/// Refuses `--fix` of an FBX rig: phalanx cannot write FBX.
fn refuse_fbx_fix(req: &AuditRequest<'_>, rig: &Rig) -> Result<(), Error> {
    if let (Some(src), Some(out)) = (&rig.file.fbx, req.fix) {
        return Err(Error::Usage(format!(
            "--fix {}: {} is an FBX file (FBX {}), and phalanx cannot write FBX (its reader, \
             ufbx, only reads). Give --moves FILE.csv instead: it lists each joint the fix \
             would move with its new world position and its new Lcl Translation, to set in \
             Maya, Blender or another DCC (see the README's recipe)",
            out.display(),
            req.rig.display(),
            src.version
        )));
    }
    Ok(())
}

/// The fix of the judged `audited` (`analysis`; `with_atlas` when the
/// metacarpals' dataset was judged): with `--fix-mcp atlas`, the MCPs placed
/// from their rays' bases and shown in `audited` ([`show_placed`]); the
/// weights carried unless `--keep-weights`; a GLB when `glb`.
fn fix_audited(
    req: &AuditRequest<'_>,
    rig: &Rig,
    audited: &mut AuditedRig,
    (analysis, with_atlas): (&Analysis, bool),
    options: &AuditOptions,
    glb: bool,
) -> Result<Fixed, Error> {
    let dir = req.rig.parent().unwrap_or(Path::new("."));
    let opts = fix::FixOptions {
        only_outside: req.only_outside,
    };
    let placed = if with_atlas && req.mcp_from_atlas {
        let placed = judge::ray::mcp_from_base(audited, analysis, &audited.tips, &options.hold);
        show_placed(audited, &placed);
        placed
    } else {
        audited.fingers.clone()
    };
    // The skin weights move with the joints, unless `--keep-weights`.
    let weights = rig.weights.as_ref().filter(|_| options.carry_weights);
    Ok(fix::fix_with(&rig.file, &placed, weights, dir, glb, &opts)?)
}

/// What a fixed copy is judged again with: the rig as loaded (with its
/// name map), the statistics, the audit's options and the rays' atlas.
struct Judged<'a> {
    rig: &'a Rig,
    map: Option<&'a NameMap>,
    analysis: &'a Analysis,
    options: &'a AuditOptions,
    rays: Option<(&'a Analysis, Option<&'a judge::WristRatios>)>,
}

/// `--moves`: the nodes `fixed` moves, read off its bytes, and each moved
/// finger judged again with the moves made, in memory (an FBX rig cannot be
/// written).
fn moves_outcome(j: &Judged<'_>, fixed: &Fixed) -> Result<MovesOutcome, Error> {
    let (moves, warnings, weights) = moves_of(&j.rig.file, fixed)?;
    let label = format!("{} (with the moves)", j.rig.file.label);
    let after = reaudit(
        j.rig, fixed, &label, None, j.map, j.analysis, j.options, j.rays,
    )?;
    Ok(MovesOutcome {
        moves,
        warnings,
        weights,
        fingers: moved_fingers(&after, &fixed.moved),
    })
}

/// `--fix OUT`: `fixed` written to `out`, judged again, and its moved
/// joints' bends and fingers set beside those of `audited` (the rig as given).
fn fix_outcome(
    j: &Judged<'_>,
    audited: &AuditedRig,
    fixed: Fixed,
    out: &Path,
) -> Result<FixOutcome, Error> {
    let label = out.display().to_string();
    let written = fixed.moved.iter().any(|(_, d)| *d > 0.0);
    let reaudit = reaudit(
        j.rig,
        &fixed,
        &label,
        written.then_some(out),
        j.map,
        j.analysis,
        j.options,
        j.rays,
    )?;
    let (mut bends, new_defects) = bends_across(audited, &reaudit, &fixed.moved);
    for b in &mut bends {
        b.reweighted = fixed
            .reweighted
            .iter()
            .find(|(node, _)| *node == b.node)
            .map_or(0, |(_, n)| *n);
    }
    let fingers = moved_fingers(&reaudit, &fixed.moved);
    Ok(FixOutcome {
        output: out.to_path_buf(),
        written,
        moved: fixed.moved,
        warnings: fixed.warnings,
        reaudit,
        bends,
        new_defects,
        fingers,
    })
}

/// With `--fix-mcp atlas`, what the audit says each finger's fix does is
/// what the fix writes: each finger's explanation and every joint's move
/// (`moves`, `suggested`, `shift`, `held`) are taken from `placed`, the
/// fingers the fix applies ([`judge::ray::mcp_from_base`]); the standings,
/// which are of the rig as it is, stay.
fn show_placed(audited: &mut AuditedRig, placed: &[judge::AuditedFinger]) {
    for (f, p) in audited.fingers.iter_mut().zip(placed) {
        f.audit.explanation = p.audit.explanation.clone();
        for j in &mut f.audit.joints {
            if let Some(q) = p.audit.joint(j.joint) {
                j.moves = q.moves;
                j.suggested = q.suggested;
                j.shift = q.shift;
                j.shift_along = q.shift_along;
                j.held = q.held.clone();
            }
        }
    }
}

/// The nodes `fixed` (the fix of `original`, as `--fix` writes it) moves,
/// read back from its bytes ([`fix::moves`]), with their warnings.
type MovesRead = (
    Vec<fix::moves::Move>,
    Vec<String>,
    Vec<fix::moves::WeightChange>,
);

fn moves_of(original: &GltfFile, fixed: &Fixed) -> Result<MovesRead, Error> {
    let copy = GltfFile::from_bytes(&original.label, &fixed.bytes).map_err(|e| {
        Error::render(
            format!("the fixed copy of {} did not read back", original.label),
            e,
        )
    })?;
    let (moves, warnings) = fix::moves::moves(original, &copy);
    Ok((moves, warnings, fix::moves::weight_changes(original, &copy)))
}

/// The container of a fixed copy written to `out`: `true` for GLB (.glb,
/// .vrm), `false` for .gltf; refuses an output that is the input rig.
fn fix_container(rig: &Path, out: &Path) -> Result<bool, Error> {
    container("--fix", rig, out)
}

/// Reads the fixed copy back (as `label`), writes it to `out` atomically when
/// given, and judges it again as the rig was (`options`; the rays against
/// `atlas` with its wrist ratios, when given). A copy that would not read back
/// is refused before anything is written.
#[allow(clippy::too_many_arguments)]
fn reaudit(
    rig: &Rig,
    fixed: &Fixed,
    label: &str,
    out: Option<&Path>,
    map: Option<&NameMap>,
    analysis: &Analysis,
    options: &AuditOptions,
    atlas: Option<(&Analysis, Option<&judge::WristRatios>)>,
) -> Result<AuditedRig, Error> {
    let re = GltfFile::from_bytes(label, &fixed.bytes)
        .and_then(|f| Rig::from_file(f, map))
        .map_err(|e| {
            Error::render(
                format!(
                    "the fixed copy of {} did not read back; nothing was written",
                    rig.file.label
                ),
                e,
            )
        })?;
    if let Some(out) = out {
        crate::atomic::replace(out, &fixed.bytes).map_err(Error::write(out))?;
    }
    let mut audited = AuditedRig::with(
        &re.file.label,
        &re.chains,
        &re.notes,
        analysis,
        options,
        re.weights.as_ref(),
    );
    if let Some((atlas, wrist)) = atlas {
        audited.judge_rays(atlas, wrist, analysis, options, re.weights.as_ref());
    }
    Ok(audited)
}

/// The fingertips found on the skin alone (`rig::find`, as `phalanx rig`
/// finds them) for each hand with a chain that has no tip node, so the audit
/// can judge a tipless finger whose weights give no end; nothing when every
/// chain has its tip. Per hand: the vertices under its hand bone in a file
/// of two hands, else the whole mesh; the hand bone's origin as the wrist.
fn found_tips(rig: &Rig) -> judge::audited::FoundTips {
    use super::find::{FindOptions, MeshSelect, find_hand, hand_mesh};
    let mut out = judge::audited::FoundTips::default();
    let mut sides: Vec<_> = rig.chains.iter().map(|c| c.side).collect();
    sides.sort();
    sides.dedup();
    for &side in &sides {
        let chains: Vec<_> = rig.chains.iter().filter(|c| c.side == side).collect();
        if chains.iter().all(|c| c.has_tip) {
            continue;
        }
        let wrist = chains.iter().find_map(|c| c.wrist.as_ref());
        let select = MeshSelect::for_hand(
            wrist.map(|w| w.node),
            sides.len() > 1,
            rig.weights.is_some(),
        );
        let found = hand_mesh(&rig.file, &select)
            .map_err(|e| {
                e.problems
                    .iter()
                    .map(|p| p.message.as_str())
                    .collect::<Vec<_>>()
                    .join("; ")
            })
            .and_then(|mesh| {
                let opts = FindOptions {
                    fingers: chains.len(),
                    wrist: wrist.map(|w| w.position),
                    side,
                    ..FindOptions::default()
                };
                find_hand(&mesh, &opts).map_err(|e| e.to_string())
            });
        match found {
            Ok(hand) => out
                .tips
                .extend(hand.fingers.iter().map(|f| (side, f.finger, f.tip))),
            Err(why) => out.why_not.push((side, why)),
        }
    }
    out
}
