//! One audit of a rig file: load it, judge it against the statistics and,
//! when asked, write a fixed copy. Returns finished results; showing them is
//! the caller's business.

use super::deform::file::{self as deform_file, DeformRequest, FileDeformation};
use super::deform::verdict::JointVerdict;
use super::deform::{Pose, Skinning};
use super::fix::{self, Fixed};
use super::judge::{self, AuditOptions, AuditedRig, JudgeOptions, SoftTissue};
use super::read::map::NameMap;
use super::read::naming::{Side, hand_side};
use super::read::{GltfFile, Rig};
use crate::analysis::{self, Analysis, Settings};
use crate::dataset::Dataset;
use crate::error::Error;
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
    /// The file written.
    pub output: PathBuf,
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

/// A finger the fix moved, judged again from the written copy.
#[derive(Debug, Clone, PartialEq)]
pub struct MovedFinger {
    /// The finger, as "right index".
    pub label: String,
    /// Its T^2 and the region's bound in the re-audit (`None`: judged
    /// without a region, on J2/J1).
    pub t2: Option<(f64, f64)>,
    /// Inside the region (or J2/J1's interval) after the fix.
    pub inside: bool,
}

/// The fingers of `after` (the written copy, judged) that hold a node of
/// `moved`, in the copy's order.
pub fn moved_fingers(after: &AuditedRig, moved: &[(String, f64)]) -> Vec<MovedFinger> {
    after
        .fingers
        .iter()
        .filter(|f| {
            f.chain
                .joints
                .iter()
                .any(|j| moved.iter().any(|(node, d)| *d > 0.0 && *node == j.name))
        })
        .map(|f| MovedFinger {
            label: f.chain.label(),
            t2: f.audit.region.as_ref().map(|r| (r.t2, r.bound)),
            inside: f.audit.is_consistent(),
        })
        .collect()
}

/// A moved joint and its distance to where its skin bends, in rig units.
#[derive(Debug, Clone, PartialEq)]
pub struct MovedBend {
    /// The node.
    pub node: String,
    /// The joint, as "right index PIP".
    pub joint: String,
    /// Before the fix: from the rig's joint to its bend (`None`: no bend found).
    pub before: Option<f64>,
    /// After it: from the moved joint to its bend in the fixed copy.
    pub after: Option<f64>,
    /// Vertices whose weights the fix changed, counted for the moved joint
    /// nearest each (0 with the weights as painted).
    pub reweighted: usize,
}

/// The distance from joint `node` of `rig` to where its skin bends, with the
/// joint's label ("right index PIP"); `None` when the node is not a judged
/// finger's joint.
fn bend_of(rig: &AuditedRig, node: &str) -> Option<(String, Option<f64>)> {
    rig.fingers.iter().find_map(|f| {
        let j = f.chain.joints.iter().find(|j| j.name == node)?;
        let d = f
            .bends
            .iter()
            .find(|b| b.joint == j.joint)
            .and_then(|b| b.at)
            .map(|at| at.distance(j.position));
        Some((format!("{} {}", f.chain.label(), j.joint.name()), d))
    })
}

/// The moved joints' bends before and after a fix, and the bend defects
/// `after` (the fixed copy, judged) flags that `before` (the rig) did not.
pub fn bends_across(
    before: &AuditedRig,
    after: &AuditedRig,
    moved: &[(String, f64)],
) -> (Vec<MovedBend>, Vec<String>) {
    let bends = moved
        .iter()
        .filter_map(|(node, _)| {
            let (joint, d0) = bend_of(before, node)?;
            let d1 = bend_of(after, node).and_then(|b| b.1);
            Some(MovedBend {
                node: node.clone(),
                joint,
                before: d0,
                after: d1,
                reweighted: 0,
            })
        })
        .collect();
    let flagged = |rig: &AuditedRig| -> Vec<String> {
        rig.fingers
            .iter()
            .flat_map(|f| {
                f.bends
                    .iter()
                    .filter(|b| b.flagged)
                    .map(move |b| format!("{} {}", f.chain.label(), b.joint.name()))
            })
            .collect()
    };
    let old = flagged(before);
    let new = flagged(after)
        .into_iter()
        .filter(|j| !old.contains(j))
        .collect();
    (bends, new)
}

/// The atlas's landmark file, looked for beside the metacarpals' dataset.
pub const WRIST_LANDMARKS: &str = "landmarks.csv";

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
    let mut audited = AuditedRig::with(
        &rig.file.label,
        &rig.chains,
        &rig.notes,
        &analysis,
        options,
        rig.weights.as_ref(),
    );
    if let Some(atlas) = &atlas {
        audited.judge_rays(
            atlas,
            wrist.as_ref(),
            &analysis,
            options,
            rig.weights.as_ref(),
        );
    }
    if let Some(note) = side_note(&rig.file.label, &rig.chains) {
        audited.notes.push(note);
    }
    // One fix serves both --fix and --moves: the moves are read off the very
    // bytes --fix writes, so they follow whatever the fix decides.
    let fixed = if req.fix.is_some() || req.moves {
        let dir = req.rig.parent().unwrap_or(Path::new("."));
        let opts = fix::FixOptions {
            only_outside: req.only_outside,
        };
        let placed = match &atlas {
            Some(_) if req.mcp_from_atlas => {
                let placed =
                    judge::ray::mcp_from_base(&audited, &analysis, &audited.tips, &options.hold);
                show_placed(&mut audited, &placed);
                placed
            }
            _ => audited.fingers.clone(),
        };
        let glb = fix_glb.unwrap_or(true);
        // The skin weights move with the joints, unless `--keep-weights`.
        let weights = rig.weights.as_ref().filter(|_| options.carry_weights);
        Some(fix::fix_with(&rig.file, &placed, weights, dir, glb, &opts)?)
    } else {
        None
    };
    let rays = atlas.as_ref().map(|a| (a, wrist.as_ref()));
    let moves = match &fixed {
        Some(fixed) if req.moves => {
            let (moves, warnings, weights) = moves_of(&rig.file, fixed)?;
            // The copy the moves make, judged again in memory (an FBX rig
            // cannot be written): each moved finger's standing after them.
            let label = format!("{} (with the moves)", rig.file.label);
            let after = reaudit(
                &rig,
                fixed,
                &label,
                None,
                map.as_ref(),
                &analysis,
                options,
                rays,
            )?;
            Some(MovesOutcome {
                moves,
                warnings,
                weights,
                fingers: moved_fingers(&after, &fixed.moved),
            })
        }
        _ => None,
    };
    let fix = match (req.fix, fixed) {
        (Some(out), Some(fixed)) => {
            let label = out.display().to_string();
            let reaudit = reaudit(
                &rig,
                &fixed,
                &label,
                Some(out),
                map.as_ref(),
                &analysis,
                options,
                rays,
            )?;
            let (mut bends, new_defects) = bends_across(&audited, &reaudit, &fixed.moved);
            for b in &mut bends {
                b.reweighted = fixed
                    .reweighted
                    .iter()
                    .find(|(node, _)| *node == b.node)
                    .map_or(0, |(_, n)| *n);
            }
            let fingers = moved_fingers(&reaudit, &fixed.moved);
            Some(FixOutcome {
                output: out.to_path_buf(),
                moved: fixed.moved,
                warnings: fixed.warnings,
                reaudit,
                bends,
                new_defects,
                fingers,
            })
        }
        _ => None,
    };
    Ok(Audit {
        analysis,
        rig: audited,
        fix,
        moves,
        fbx: rig.file.fbx.clone(),
    })
}

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
/// [`audit`] with `--fix` does, without writing anything: the fixed copy is
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
    let file = super::read::open(path)?;
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

/// Refuses to judge a rig whose tips differ from the data's (one at the bone,
/// the other at the skin) when no soft tissue figure is known to bridge them.
fn refuse_unlike_tips(judge: &JudgeOptions, a: &Analysis) -> Result<(), Error> {
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

/// The container of a fixed copy written to `out`: `true` for GLB (.glb,
/// .vrm), `false` for .gltf; refuses an output that is the input rig.
fn fix_container(rig: &Path, out: &Path) -> Result<bool, Error> {
    container("--fix", rig, out)
}

/// Whether the copy `option` names is a GLB (.glb, .vrm) or a .gltf with
/// an embedded buffer; anything else, or the input itself, is refused.
fn container(option: &str, rig: &Path, out: &Path) -> Result<bool, Error> {
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
    pub make: super::make::MakeOptions,
    /// The prior's weight in hands for the re-audit's joint regions.
    pub prior_hands: f64,
}

/// A rigged hand: what was made and written, and the written copy read back
/// and judged as `audit` would judge it.
pub struct Rigged {
    pub analysis: Analysis,
    pub made: super::make::Made,
    pub audit: AuditedRig,
    pub output: PathBuf,
}

/// Rigs a hand ([`super::make::make`]) and writes the copy; it is read back
/// and audited before it is written, so nothing is written when it would not
/// read. A file that is not a hand, a hand already rigged (without
/// `--replace-fingers`), two hands without `--side`: exit status 2 with the
/// reason.
pub fn rig(req: &RigRequest<'_>) -> Result<Rigged, Error> {
    let glb = container("--out", req.input, req.output)?;
    let rig = Rig::with_any_chains(super::open(req.input)?, None)?;
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
    pub made: super::make::Made,
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
    make: &super::make::MakeOptions,
    prior_hands: f64,
) -> Result<RiggedInMemory, Error> {
    let proportions = super::make::place::Proportions::new(
        analysis,
        atlas.map(|(a, _)| a),
        atlas.and_then(|(_, w)| w),
        soft_tissue.clone(),
    );
    let dir = rig.file.dir.as_deref().unwrap_or(Path::new("."));
    let made = super::make::make(rig, &proportions, make, dir).map_err(|e| match e {
        super::make::MakeError::File(e) => Error::Data(e),
        super::make::MakeError::Find(e) => Error::Data(e.in_file(&rig.file.label)),
        super::make::MakeError::Refused(why) => {
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
