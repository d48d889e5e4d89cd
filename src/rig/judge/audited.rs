//! A rig judged: every finger against the statistics ([`super::finger`])
//! with where its skin bends ([`super::bend`]) and, for a skin tip inside the
//! skin, the skin's end as its tip; the MCPs from their rays' bases
//! ([`super::ray_base`]); and the rig's scale checked.

use super::bend;
use super::finger;
pub use super::guard::Carry;
use super::guard::{carry_of, guard_on_weights};
use super::ray_base::{self, MetacarpalCheck, WRIST_DEFINITION, WristRatios};
use super::sanity;
use super::standing::{
    Basis, ChainInput, FingerAudit, Held, JudgeOptions, SoftTissue, Standing, TipKind,
};
use crate::analysis::Analysis;
use crate::analysis::placement::Joint;
use crate::analysis::region::ShapePriors;
use crate::dataset::Finger;
use crate::rig::read::FingerChain;
use crate::rig::read::weights::SkinWeights;
use glam::DVec3;
use schemars::JsonSchema;
use serde::Serialize;

/// How a rig is judged.
#[derive(Debug, Clone, PartialEq)]
pub struct AuditOptions {
    /// What the rig's tip nodes mark.
    pub rig_tip: TipKind,
    /// The soft tissue used where the rig's tips and the data's differ; the
    /// data's tips come from its `tip` column ([`JudgeOptions::new`]).
    pub soft_tissue: SoftTissue,
    /// A joint further than this from where its skin bends is flagged (rig units).
    pub bend_tolerance: f64,
    /// With skin tips: take the skin's end from the mesh when it reaches
    /// past the tip node (`--tip auto`).
    pub measure_tip: bool,
    /// Joints the artist pins (`--hold`): never moved by the explanation or the fix.
    pub hold: Vec<Joint>,
    /// The joint regions' prior shape (`None`: the X-rays' own covariance).
    pub shape: Option<ShapePriors>,
    /// The fix moves each finger's skin weights with its joints (true), or
    /// leaves them as painted (`--keep-weights`): the guards follow.
    pub carry_weights: bool,
    /// The fingertips found on the skin alone (`rig::find`, as `phalanx rig`
    /// finds them), for chains with no tip node whose weights give no end
    /// ([`bend::mesh_end`]); and, per side, why they were not found.
    pub found_tips: FoundTips,
}

/// The fingertips found on a rig's skin, for the audit of tipless chains.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FoundTips {
    /// Each found finger: its side (as its chains name it), finger and tip.
    pub tips: Vec<(Option<crate::rig::read::naming::Side>, Finger, DVec3)>,
    /// Sides whose fingers were not found, and why.
    pub why_not: Vec<(Option<crate::rig::read::naming::Side>, String)>,
}

impl Default for AuditOptions {
    fn default() -> AuditOptions {
        AuditOptions {
            rig_tip: TipKind::Skin,
            soft_tissue: SoftTissue::Unknown,
            bend_tolerance: bend::BEND_TOLERANCE_MM / 1000.0,
            measure_tip: true,
            hold: Vec::new(),
            shape: None,
            carry_weights: true,
            found_tips: FoundTips::default(),
        }
    }
}

/// A tip node this far (metres) or more inside the skin's end is not at the
/// skin: WebXR's `*-tip` joints, the centres of the fingertips' spheres, lie
/// 10-12 mm inside the generic hand's skin. 2 mm leaves room for a mesh's
/// faceting at a rounded tip.
pub const TIP_INSIDE: f64 = 0.002;

/// The skin's end of a finger, measured on its mesh and used as its tip.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SkinTip {
    /// How far the skin reaches past the tip node, along the last segment;
    /// for a tip from the mesh, past the last joint (DIP; the thumb's IP).
    pub beyond_node: f64,
    /// The point used as the tip.
    #[schemars(with = "[f64; 3]")]
    pub position: DVec3,
    /// True when the rig has no tip node and the tip is taken from the mesh
    /// ([`bend::mesh_end`]): "tip from the mesh". The finger is then judged
    /// on relative values, as a finger with a skin tip is.
    pub from_mesh: bool,
}

/// A rig finger with its judgement.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AuditedFinger {
    #[serde(flatten)]
    pub chain: FingerChain,
    pub audit: FingerAudit,
    /// Where the skin bends at each joint (empty without skin weights).
    pub bends: Vec<bend::Bend>,
    /// The skin's end used as the tip, when the tip node lies inside the skin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skin_tip: Option<SkinTip>,
    /// The MCP judged from the CMC against the metacarpals' dataset, when the
    /// rig has a metacarpal node and the audit was given one
    /// ([`AuditedRig::judge_rays`]). Not `metacarpal`: that key is
    /// the chain's metacarpal node.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metacarpal_check: Option<MetacarpalCheck>,
    /// With the weights carried by the fix: for each joint, why its skin
    /// cannot follow it (`None`: it can, or there is no skin to carry);
    /// `None` when the weights stay as painted (`--keep-weights`).
    #[serde(skip)]
    #[schemars(skip)]
    pub carry: Option<Carry>,
}

impl AuditedFinger {
    /// The chain's geometry as it was judged: with the skin's end as its tip
    /// where one was measured ([`SkinTip`]), appended for a tip from the mesh.
    pub fn judged_input(&self) -> ChainInput {
        let mut input = self.chain.input();
        if let Some(t) = &self.skin_tip {
            if t.from_mesh {
                input.points.push(t.position);
                input.has_tip = true;
            } else if let Some(last) = input.points.last_mut() {
                *last = t.position;
            }
        }
        input
    }
}

/// Every finger of a rig judged against the statistics.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AuditedRig {
    /// The file (or reference rig) the chains come from.
    pub label: String,
    /// How the tips were compared.
    pub tips: JudgeOptions,
    /// The bend tolerance used, in rig units.
    pub bend_tolerance: f64,
    pub fingers: Vec<AuditedFinger>,
    /// Fingers left out and other remarks.
    pub notes: Vec<String>,
    /// Things that make the judgement doubtful (the rig's scale).
    pub warnings: Vec<String>,
}

/// Plausible lengths of an adult finger from MCP to tip, in metres: a
/// fingertip-to-knuckle length is 50-110 mm; half and twice that allow for
/// children and stylised characters.
const PLAUSIBLE_FINGER: (f64, f64) = (0.025, 0.22);

/// A warning when the fingers' median length (MCP to the last point, in file
/// units read as metres) is implausible, naming the unit that would make it
/// plausible (the one nearest a 75 mm finger).
fn scale_warning(lengths: &[f64]) -> Option<String> {
    let mut l: Vec<f64> = lengths
        .iter()
        .copied()
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    if l.is_empty() {
        return None;
    }
    l.sort_by(f64::total_cmp);
    let median = l[l.len() / 2];
    let plausible = |x: f64| (PLAUSIBLE_FINGER.0..=PLAUSIBLE_FINGER.1).contains(&x);
    if plausible(median) {
        return None;
    }
    let units = [
        ("centimetres", 0.01),
        ("millimetres", 0.001),
        ("inches", 0.0254),
        ("decimetres", 0.1),
    ];
    let likely = units
        .iter()
        .filter(|(_, m)| plausible(median * m))
        .min_by(|a, b| {
            let off = |m: f64| (median * m / 0.075).ln().abs();
            off(a.1).total_cmp(&off(b.1))
        });
    let shown = format!(
        "its fingers are {} m long (median, MCP to tip), implausible for a hand in metres",
        crate::format::num(median, 4)
    );
    Some(match likely {
        Some((unit, m)) => format!(
            "{shown}; the file is likely in {unit} ({} mm fingers). Re-export it in metres (glTF \
             is in metres; an FBX file must declare its true unit, with no scale on the armature \
             hiding it). The mm figures, the soft tissue and the bend tolerance are off; relative \
             values and ratios are not",
            crate::format::num(median * m * 1000.0, 1)
        ),
        None => format!(
            "{shown} or in any common unit; the mm figures, the soft tissue and the bend \
             tolerance are off; relative values and ratios are not"
        ),
    })
}

/// The rig's scale warning, unless the nodes' rest pose disagrees with the
/// skin's bind pose and the bind pose's fingers are of a plausible length
/// (then the disagreement, named instead, is the cause); then the joints far
/// outside their mesh ([`sanity`]).
fn geometry_warnings(
    chains: &[FingerChain],
    weights: Option<&SkinWeights>,
    lengths: &[f64],
) -> Vec<String> {
    let rest = weights.and_then(|w| sanity::rest_not_bind(chains, w));
    let mut out = Vec::new();
    if rest
        .as_ref()
        .is_none_or(|r| scale_warning(&r.bind_lengths).is_some())
    {
        out.extend(scale_warning(lengths));
    }
    out.extend(rest.map(|r| r.warning));
    out.extend(weights.and_then(|w| sanity::joints_outside_mesh(chains, w)));
    out
}

/// The note saying how the MCPs were judged from their rays' bases.
fn metacarpal_note(
    atlas: &Analysis,
    wrist: Option<&WristRatios>,
    from_cmc: usize,
    from_wrist: usize,
) -> String {
    let n = atlas
        .fingers
        .iter()
        .filter_map(|fa| fa.quantity(crate::dataset::Quantity::RatioMcJ))
        .map(|s| s.n)
        .max()
        .unwrap_or(0);
    let mcps = |k: usize| match k {
        1 => "1 MCP is".to_string(),
        k => format!("{k} MCPs are"),
    };
    let judged = match (from_cmc, from_wrist) {
        (c, 0) => format!("{} also judged from their CMC", mcps(c)),
        (0, w) => format!("{} also judged from the wrist", mcps(w)),
        (c, w) => format!(
            "{} also judged from their CMC and {w} from the wrist",
            mcps(c)
        ),
    };
    let mut out = format!(
        "Metacarpals: {judged} against {} ({} with the metacarpal measured), with the same \
         settings. The Digital Hand Atlas (the default) is children's left hands with {}: read \
         this as a guide.",
        atlas.dataset.path,
        crate::format::xrays(n),
        crate::dataset::landmarks::ATLAS_LANDMARKS
    );
    if from_wrist > 0 {
        out.push_str(&format!(
            " The wrist is {}; the rig's wrist-to-MCP distance over the finger's length (w/J) \
             is judged against the same ratio measured on each X-ray of the atlas's landmarks \
             (from {}). The thumb is not judged from the wrist: its distance depends on the \
             thumb's pose.",
            WRIST_DEFINITION,
            wrist.map_or("the atlas's landmarks", |w| w.source.as_str())
        ));
    }
    out
}

impl AuditedRig {
    /// Judges `chains` against the analysis with the default options (skin
    /// tips, no soft tissue figure) and no skin; fingers the data lacks become notes.
    pub fn of(label: &str, chains: &[FingerChain], notes: &[String], a: &Analysis) -> AuditedRig {
        AuditedRig::with(label, chains, notes, a, &AuditOptions::default(), None)
    }

    /// Judges `chains` against the analysis with `opts`, and finds where the
    /// skin bends when `weights` are given.
    pub fn with(
        label: &str,
        chains: &[FingerChain],
        notes: &[String],
        a: &Analysis,
        opts: &AuditOptions,
        weights: Option<&SkinWeights>,
    ) -> AuditedRig {
        let judge = JudgeOptions::new(opts.rig_tip, opts.soft_tissue.clone(), a)
            .with_shape(opts.shape.clone());
        let mut notes = notes.to_vec();
        let mut fingers = Vec::new();
        let mut lengths = Vec::new();
        for chain in chains {
            let mut input = chain.input();
            let skin_tip = measure_tip(chain, opts, weights, &mut input, &mut notes);
            lengths.push(
                input
                    .points
                    .windows(2)
                    .map(|w| w[0].distance(w[1]))
                    .sum::<f64>(),
            );
            match finger::audit_with(a, &input, &judge) {
                Some(audit) => {
                    let bends = weights
                        .map(|w| bend::bends(chain, w, opts.bend_tolerance))
                        .unwrap_or_default();
                    let carry = opts.carry_weights.then(|| carry_of(chain, chains, weights));
                    let audit = guard_on_weights(
                        a,
                        &input,
                        &judge,
                        audit,
                        (&bends, carry.as_ref()),
                        chain,
                        weights.map(|w| (w, opts.bend_tolerance)),
                        &opts.hold,
                    );
                    fingers.push(AuditedFinger {
                        chain: chain.clone(),
                        audit,
                        bends,
                        carry,
                        skin_tip,
                        metacarpal_check: None,
                    });
                }
                None if input.has_tip
                    && a.finger(chain.finger).is_some()
                    && judge.tip_correction(chain.finger, 1.0).is_none() =>
                {
                    notes.push(format!(
                        "{}: its tip is read as a {} tip and {}'s as {} tips, and no figure for \
                         this finger's soft tissue between the two is known, so it is not judged",
                        chain.label(),
                        judge.rig_tip.name(),
                        a.dataset.path,
                        judge.data_tip.name()
                    ))
                }
                None => notes.push(format!(
                    "{}: {} has no statistics for this finger (or the chain has zero length, or \
                     a last segment no longer than the tip's soft tissue), so it is not judged",
                    chain.label(),
                    a.dataset.path
                )),
            }
        }
        let mut warnings = geometry_warnings(chains, weights, &lengths);
        if fingers.iter().any(|f| f.audit.basis == Basis::Relative) {
            warnings.extend(judge.assumption(&a.dataset.path));
        }
        AuditedRig {
            label: label.to_string(),
            tips: judge,
            bend_tolerance: opts.bend_tolerance,
            fingers,
            notes,
            warnings,
        }
    }

    /// Fingers with a joint or value outside the prediction interval.
    pub fn outside(&self) -> usize {
        self.fingers
            .iter()
            .filter(|f| !f.audit.is_consistent())
            .count()
    }

    /// Judges every finger's MCP from its ray's base against `atlas`
    /// ([`AuditedRig::judge_metacarpals`]), then weighs that with the finger's
    /// own judgement ([`AuditedRig::weigh_bases`], with the statistics `a`, the
    /// options `opts` and the skin `weights` the rig was judged with): the one
    /// call every audit with a metacarpals' dataset makes.
    pub fn judge_rays(
        &mut self,
        atlas: &Analysis,
        wrist: Option<&WristRatios>,
        a: &Analysis,
        opts: &AuditOptions,
        weights: Option<&SkinWeights>,
    ) {
        self.judge_metacarpals(atlas, wrist);
        self.weigh_bases(a, opts, weights);
    }

    /// Judges the MCP of every finger from the base of its ray against
    /// `atlas`'s metacarpal statistics: from its CMC where the finger has a
    /// metacarpal node ([`ray_base::metacarpal`]), else from the wrist where the
    /// hand has a wrist bone ([`ray_base::wrist`]; not the thumb). The fingers'
    /// own standings are unchanged. A finger with a metacarpal that cannot be
    /// judged (no tip, no mc/J in `atlas`) gets a note; without `wrist` (the
    /// atlas's wrist-to-MCP over finger length, read from its landmark file) no MCP is
    /// judged from the wrist, and a rig that has one gets a note.
    fn judge_metacarpals(&mut self, atlas: &Analysis, wrist: Option<&WristRatios>) {
        let (mut from_cmc, mut from_wrist, mut wrist_skipped, mut wrist_unbridged) = (0, 0, 0, 0);
        for f in &mut self.fingers {
            let Some(mcp) = f.chain.joints.first() else {
                continue;
            };
            // The finger's length to the metacarpals' dataset's own tips
            // (the atlas's are at the bone), not to the finger data's.
            let length = f
                .audit
                .length
                .and_then(|_| {
                    self.tips
                        .length_against(&atlas.tips, f.audit.finger, &f.audit.segments)
                })
                .unwrap_or(f64::NAN);
            if let Some(node) = &f.chain.metacarpal {
                f.metacarpal_check = ray_base::metacarpal(
                    atlas,
                    &f.audit,
                    length,
                    &node.name,
                    node.position,
                    mcp.position,
                );
                match f.metacarpal_check {
                    Some(_) => from_cmc += 1,
                    None => self.notes.push(format!(
                        "{}: its MCP is not judged from the metacarpal {} ({})",
                        f.chain.label(),
                        node.name,
                        if f.audit.length.is_none() {
                            "the rig has no tip, so the finger's length is unknown".to_string()
                        } else if length.is_nan() {
                            format!(
                                "its tip is read as a {} tip and {}'s as {} tips, and no figure \
                                 for the soft tissue between the two is known",
                                self.tips.rig_tip.name(),
                                atlas.dataset.path,
                                super::standing::data_tip_of(&atlas.tips).name()
                            )
                        } else {
                            format!("{} has no mc/J for this finger", atlas.dataset.path)
                        }
                    )),
                }
            } else if let Some(node) = &f.chain.wrist {
                match wrist {
                    Some(rho) => {
                        f.metacarpal_check = ray_base::wrist(
                            atlas,
                            rho,
                            &f.audit,
                            length,
                            &node.name,
                            node.position,
                            mcp.position,
                        );
                        from_wrist += usize::from(f.metacarpal_check.is_some());
                        wrist_unbridged += usize::from(
                            f.metacarpal_check.is_none()
                                && f.audit.length.is_some()
                                && length.is_nan()
                                && f.audit.finger != Finger::Thumb,
                        );
                    }
                    None => wrist_skipped += usize::from(f.audit.finger != Finger::Thumb),
                }
            }
        }
        if from_cmc + from_wrist > 0 {
            self.notes
                .push(metacarpal_note(atlas, wrist, from_cmc, from_wrist));
        }
        if wrist_skipped > 0 {
            self.notes.push(format!(
                "Metacarpals: {wrist_skipped} MCPs are not judged from the wrist: the rig has no \
                 metacarpals, and the atlas's landmark file (landmarks.csv beside {}, which gives \
                 the wrist-to-MCP distance over the finger's length) was not found",
                atlas.dataset.path
            ));
        }
        if wrist_unbridged > 0 {
            self.notes.push(format!(
                "Metacarpals: {wrist_unbridged} MCPs are not judged from the wrist: the rig's tips \
                 are read as {} tips and {}'s as {} tips, and no figure for the soft tissue \
                 between the two is known",
                self.tips.rig_tip.name(),
                atlas.dataset.path,
                super::standing::data_tip_of(&atlas.tips).name()
            ));
        }
    }

    /// Weighs each finger's own judgement with its MCP's from its ray's base
    /// ([`AuditedRig::judge_metacarpals`] runs first), so the two
    /// never contradict each other: where the base puts the MCP inside the
    /// atlas's prediction interval and the finger's explanation would move it
    /// (the finger alone reads an MCP at the finger's web as a misplaced
    /// knuckle), the MCP is held ([`HoldReason::Base`](super::standing::HoldReason::Base)) and the explanation
    /// sought again among the inner joints, with the same guards as the
    /// finger's own (the bend guard on `weights`, the tolerance, `opts.hold`).
    /// So is an MCP the finger would move one way while the base puts it
    /// outside the other way ([`HoldReason::BaseOpposes`](super::standing::HoldReason::BaseOpposes)): no move of it
    /// satisfies both. An MCP the base puts outside the way the finger would
    /// move it is left to the finger's explanation and to `--fix-mcp atlas`;
    /// one the finger does not move, the audit's opening line names. O(fingers) re-judgements.
    fn weigh_bases(&mut self, a: &Analysis, opts: &AuditOptions, weights: Option<&SkinWeights>) {
        if opts.hold.contains(&Joint::Mcp) {
            return;
        }
        let judge = self.tips.clone();
        for f in &mut self.fingers {
            let Some(m) = &f.metacarpal_check else {
                continue;
            };
            let Some((given_up, along)) = f
                .audit
                .joint(Joint::Mcp)
                .filter(|j| j.moves && j.shift > 0.0)
                .map(|j| (j.shift, j.shift_along))
            else {
                continue;
            };
            // The base's own direction: too distal asks for a move towards
            // the root (negative along the finger), too proximal towards the tip.
            // An MCP outside the way the finger moves it is left to the finger.
            let agrees = match m.standing {
                Standing::InRange | Standing::InPrediction => false,
                Standing::Above { .. } => along <= 0.0,
                Standing::Below { .. } => along >= 0.0,
            };
            if agrees {
                continue;
            }
            let base = match m.base {
                ray_base::RayBase::Cmc => format!("its CMC ({})", m.node),
                ray_base::RayBase::Wrist => format!("the wrist ({})", m.node),
            };
            let input = f.judged_input();
            let Some(first) = finger::audit_with(a, &input, &judge) else {
                continue;
            };
            let hold: Vec<Joint> = opts
                .hold
                .iter()
                .copied()
                .chain(std::iter::once(Joint::Mcp))
                .collect();
            let mut audit = guard_on_weights(
                a,
                &input,
                &judge,
                first,
                (&f.bends, f.carry.as_ref()),
                &f.chain,
                weights.map(|w| (w, opts.bend_tolerance)),
                &hold,
            );
            // The MCP's move the finger alone asks for is what the base's
            // evidence gives up, whether or not the unguarded explanation named it.
            for j in &mut audit.joints {
                if j.joint == Joint::Mcp {
                    j.held = Some(Held::from_base(given_up, &base, m.standing));
                }
            }
            f.audit = audit;
        }
    }

    /// Sets each joint's `fix` from its move and its hold, once the audit is
    /// finished; with `only_outside` (`--only-outside` with a fix), a joint
    /// inside its own prediction interval is not moved, as the fix decides.
    pub fn settle_fix(&mut self, only_outside: bool) {
        for j in self
            .fingers
            .iter_mut()
            .flat_map(|f| f.audit.joints.iter_mut())
        {
            j.fix = j.fix_moves() && !(only_outside && j.standing.is_consistent());
        }
    }

    /// Fingers whose MCP lies outside the prediction interval from its ray's
    /// base (the CMC or the wrist).
    pub fn metacarpals_outside(&self) -> usize {
        self.fingers
            .iter()
            .filter_map(|f| f.metacarpal_check.as_ref())
            .filter(|m| !m.standing.is_consistent())
            .count()
    }

    /// Joints further from their bend than the tolerance.
    pub fn bends_flagged(&self) -> usize {
        self.fingers
            .iter()
            .flat_map(|f| &f.bends)
            .filter(|b| b.flagged)
            .count()
    }
}

/// The skin's end as `chain`'s tip, when `opts` measure it on skin tips:
/// a tip node inside the skin moved out to the weights' end, or a tipless
/// finger given one (the weights' end, else the fingertip found on the skin,
/// [`found_reach`]); `input` changed to match, and the notes that say why not.
fn measure_tip(
    chain: &FingerChain,
    opts: &AuditOptions,
    weights: Option<&SkinWeights>,
    input: &mut ChainInput,
    notes: &mut Vec<String>,
) -> Option<SkinTip> {
    let n = input.points.len();
    if opts.measure_tip
        && opts.rig_tip == TipKind::Skin
        && let Some(w) = weights
        && let Some(reach) = bend::skin_end(chain, w)
        && n >= 2
    {
        let (last, tip) = (input.points[n - 2], input.points[n - 1]);
        let node = last.distance(tip);
        if reach > node + TIP_INSIDE {
            let position = last + (tip - last).normalize_or_zero() * reach;
            input.points[n - 1] = position;
            return Some(SkinTip {
                beyond_node: reach - node,
                position,
                from_mesh: false,
            });
        }
    } else if opts.measure_tip && opts.rig_tip == TipKind::Skin && !chain.has_tip && n >= 2 {
        let (prev, last) = (input.points[n - 2], input.points[n - 1]);
        let dir = (last - prev).normalize_or_zero();
        let end = match weights {
            Some(w) => bend::mesh_end(chain, w),
            None => Err("the file has no skin weights".to_string()),
        };
        // The reach past the last joint: the weights' end, else the
        // skin's end as `rig` finds it (the found tip's reach along
        // the last bone, within the range a distal phalanx with its
        // pulp spans); `None` with the note that says why not.
        let reach = match end {
            Ok(reach) => Some(reach),
            Err(why) => found_reach(chain, opts, weights.is_none(), (prev, last), &why)
                .map_err(|note| notes.extend(note))
                .ok()
                .map(|(reach, note)| {
                    notes.push(note);
                    reach
                }),
        };
        if let Some(reach) = reach {
            let position = last + dir * reach;
            input.points.push(position);
            input.has_tip = true;
            return Some(SkinTip {
                beyond_node: reach,
                position,
                from_mesh: true,
            });
        }
    }
    None
}

/// A tipless finger's reach past its last joint (`last`, along the bone from
/// `prev`) from the
/// fingertip found on the skin (`opts.found_tips`), when the weights gave
/// none (`why`), with the note that says so; else the note that says why
/// not (none for a rig with no weights and nothing found on a skin: a rig of
/// nodes alone, a reference profile).
fn found_reach(
    chain: &FingerChain,
    opts: &AuditOptions,
    unweighted: bool,
    (prev, last): (DVec3, DVec3),
    why: &str,
) -> Result<(f64, String), Option<String>> {
    use crate::format::num;
    let dir = (last - prev).normalize_or_zero();
    let segment = prev.distance(last);
    let (lo, hi) = bend::MESH_END_RANGE;
    let found = opts
        .found_tips
        .tips
        .iter()
        .find(|t| t.0 == chain.side && t.1 == chain.finger)
        .map(|t| (t.2 - last).dot(dir));
    match found {
        Some(reach) if reach >= lo * segment && reach <= hi * segment => Ok((
            reach,
            format!(
                "{}: its weights give no tip ({why}); the tip is the skin's end found on the \
                 mesh ({} mm past its last joint)",
                chain.label(),
                num(reach * 1000.0, 1)
            ),
        )),
        Some(reach) => Err(Some(format!(
            "{}: no tip from the mesh ({why}; the fingertip found on the skin lies {} mm past \
             its last joint, outside {lo}-{hi} times its last segment), so it is judged on \
             J2/J1 alone",
            chain.label(),
            num(reach * 1000.0, 1)
        ))),
        None if unweighted && opts.found_tips.why_not.is_empty() => Err(None),
        None => {
            let also = opts
                .found_tips
                .why_not
                .iter()
                .find(|w| w.0 == chain.side)
                .map(|w| format!("; the fingers were not found on the skin: {}", w.1))
                .unwrap_or_default();
            Err(Some(format!(
                "{}: no tip from the mesh ({why}{also}), so it is judged on J2/J1 alone",
                chain.label()
            )))
        }
    }
}

#[cfg(test)]
mod tests;
