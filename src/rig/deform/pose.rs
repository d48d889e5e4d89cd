//! Curling the fingers of a rig: the palm, each finger's flexion axis, and the
//! posed world matrix of every node.
//!
//! **Palm.** The palm plane is the least-squares plane through the wrist (or,
//! without one, the metacarpals' origins, the CMC joints) and the MCPs of the
//! index to little fingers: its normal is the eigenvector of the smallest
//! eigenvalue of the points' 3x3 covariance. The thumb is left out of the fit
//! (it stands off the palm). The distal direction runs from the wrist (or the
//! CMCs' centroid) to the MCPs' centroid, in the plane. The normal is oriented
//! to the palm side (where fingers curl to) by the hand's side and the thumb:
//! with t from the fingers' MCP centroid to the thumb's MCP (or its CMC) and d
//! distal, a right hand's palm side is n with n . (t x d) > 0, a left hand's
//! n . (t x d) < 0 (hold a right hand palm to the face, fingers up: the thumb
//! is on the right, t x d points to the face). A mirrored hand therefore gets
//! the mirrored normal, and its flexion axes the mirrored axial vectors
//! (a_L = -M a_R for a reflection M), so its pose is the mirror image.
//! A file without a thumb, or with fewer than three non-collinear palm points,
//! is refused with the reason.
//!
//! **Flexion axes.** Each finger turns about one axis through each of its
//! joints: a = f x n normalised, with f the finger's direction (MCP to tip,
//! or to the last joint) and n the palm side; so a lies in the palm plane, is
//! perpendicular to the finger, and a positive angle swings the finger to the
//! palm side. The thumb is opposed: its nail faces about sideways, so it bends
//! across the palm, not straight out of it. Its flexion direction is taken
//! halfway between the palm side and the ulnar side (towards the little
//! finger), g = (n - r)/|n - r| with r the radial in-plane direction, and its
//! axis a = f x g (normalised after removing g's part along f).
//!
//! **Posing.** Joint k of a finger turns by theta_k about the axis through its
//! rest position p_k: G_k = T(p_k) R(a, theta_k) T(-p_k). The node of joint k
//! (the bone from it to the next joint) moves by D_k = G_0 G_1 ... G_k, all in
//! rest coordinates (forward kinematics). The tip node follows the last joint;
//! the metacarpal and the wrist stay. Every other node moves with its nearest
//! ancestor that moved, so children follow through the hierarchy when there is
//! one; in a rig whose joints are siblings (WebXR) the chain alone carries each
//! distal joint with the joints proximal to it. Posed world matrix: D W.

use super::{FingerNodes, HandChains, Skeleton};
use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use crate::rig::read::naming::Side;
use glam::{DMat3, DMat4, DQuat, DVec3};
use schemars::JsonSchema;
use serde::Serialize;

/// Flexion angles of one finger in degrees (positive towards the palm).
/// For the thumb, `mcp` is its MCP and `pip` its IP; `dip` is unused.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct Angles {
    pub mcp: f64,
    pub pip: f64,
    pub dip: f64,
}

/// Normal active range of motion of each joint, in degrees (negative:
/// hyperextension), from the American Academy of Orthopaedic Surgeons'
/// average values (AAOS, *Joint Motion: Method of Measuring and Recording*,
/// 1965; the same table in Greene & Heckman, *The Clinical Measurement of
/// Joint Motion*, AAOS 1994): finger MCP flexion 90 and hyperextension 45,
/// PIP flexion 100 and extension 0, DIP flexion 90 and hyperextension 10;
/// thumb MCP flexion 50 and extension 0, IP flexion 80 and hyperextension 20.
/// Rows: thumb, then the other fingers; columns MCP, PIP (the thumb's IP), DIP.
pub const NORMAL_RANGE: [[(f64, f64); 3]; 2] = [
    [(0.0, 50.0), (-20.0, 80.0), (0.0, 0.0)],
    [(-45.0, 90.0), (0.0, 100.0), (-10.0, 90.0)],
];

/// A named set of flexion angles for the five fingers.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Pose {
    pub name: String,
    /// Thumb, index, middle, ring, little ([`Finger::ALL`] order).
    pub fingers: [Angles; 5],
    /// The finger the thumb folds across (see [`fold_thumb`]): its tip is
    /// brought to that finger's posed middle phalanx by turning the whole
    /// thumb about its CMC. `None`: the thumb only bends. Left out of the
    /// JSON document, whose schema (version 1) holds the angles only; the
    /// text's pose line says it.
    #[serde(skip)]
    #[schemars(skip)]
    pub thumb_across: Option<Finger>,
}

/// The thumb's angles are the fingers' MCP and PIP angles times this. The
/// thumb's MCP flexes about half as far as the fingers' (AAOS average ranges:
/// thumb MCP 0-50 degrees against 0-90 for the fingers), and a thumb bent as
/// far as the fingers would pass through the index finger, which the pose does
/// not model.
pub const THUMB_FACTOR: f64 = 0.5;

impl Pose {
    /// The pose names [`Pose::named`] knows.
    pub const NAMES: [&'static str; 4] = ["fist", "grip", "point", "rest"];

    /// Fingers at `mcp`, `pip`, `dip` degrees; the thumb at [`THUMB_FACTOR`]
    /// times the MCP and PIP angles. Angles must be finite, -30 to 180.
    pub fn from_angles(name: &str, mcp: f64, pip: f64, dip: f64) -> Result<Pose, String> {
        for (j, a) in [("MCP", mcp), ("PIP", pip), ("DIP", dip)] {
            if !(a.is_finite() && (-30.0..=180.0).contains(&a)) {
                return Err(format!(
                    "{j} angle {a} is out of range; give degrees from -30 to 180"
                ));
            }
        }
        let f = Angles { mcp, pip, dip };
        let thumb = Angles {
            mcp: mcp * THUMB_FACTOR,
            pip: pip * THUMB_FACTOR,
            dip: 0.0,
        };
        Ok(Pose {
            name: name.to_string(),
            fingers: [thumb, f, f, f, f],
            thumb_across: None,
        })
    }

    /// One note per joint angle beyond its normal active range
    /// ([`NORMAL_RANGE`]): such a pose can test a rig (a fold onto itself)
    /// but is not one a hand makes. Fingers bent alike share a note.
    pub fn anatomy_notes(&self) -> Vec<String> {
        // (joint name, angle, range) -> the fingers so bent, in order.
        type Key = (&'static str, f64, (f64, f64));
        let mut beyond: Vec<(Key, Vec<Finger>)> = Vec::new();
        for (i, a) in self.fingers.iter().enumerate() {
            let finger = Finger::ALL[i];
            let thumb = finger == Finger::Thumb;
            let range = &NORMAL_RANGE[usize::from(!thumb)];
            let names = if thumb {
                ["MCP", "IP", ""]
            } else {
                ["MCP", "PIP", "DIP"]
            };
            for (k, angle) in [a.mcp, a.pip, a.dip].into_iter().enumerate() {
                if names[k].is_empty() || (range[k].0..=range[k].1).contains(&angle) {
                    continue;
                }
                let key = (names[k], angle, range[k]);
                match beyond.iter_mut().find(|(b, _)| *b == key) {
                    Some((_, fingers)) => fingers.push(finger),
                    None => beyond.push((key, vec![finger])),
                }
            }
        }
        let t = |x: f64| crate::format::trimmed(x, 1);
        beyond
            .into_iter()
            .map(|((joint, angle, (low, high)), fingers)| {
                let names: Vec<&str> = fingers.iter().map(|f| f.name()).collect();
                let who = match names[..] {
                    ["thumb"] => "the thumb's".to_string(),
                    [one] => format!("the {one} finger's"),
                    _ if names.len() == 4 => "the fingers'".to_string(),
                    _ => format!("the {} fingers'", names.join(" and ")),
                };
                format!(
                    "{who} {joint} at {} degrees is beyond its normal active range \
                     ({} to {} degrees, AAOS; negative: hyperextension): \
                     the pose is not one a hand makes",
                    t(angle),
                    t(low),
                    t(high)
                )
            })
            .collect()
    }

    /// The relaxed fist: MCP 60, PIP 90, DIP 60 degrees (about two thirds of
    /// each joint's active range, AAOS: MCP 90, PIP 100, DIP 80, so the
    /// fingertips come to the palm without pressing into it); thumb MCP 30, IP 45.
    /// The thumb folded across the index's middle phalanx (a fist's thumb
    /// lies over the index and middle fingers, not out of the palm).
    pub fn fist() -> Pose {
        Pose {
            thumb_across: Some(Finger::Index),
            ..Self::fixed("fist", 60.0, 90.0, 60.0)
        }
    }

    /// Holding a bar of about 4 cm: MCP 45, PIP 60, DIP 30; thumb MCP 22.5, IP 30.
    pub fn grip() -> Pose {
        Self::fixed("grip", 45.0, 60.0, 30.0)
    }

    /// Pointing: the index finger straight, the others in the fist, the
    /// thumb folded across the middle finger.
    pub fn point() -> Pose {
        let mut p = Self::fixed("point", 60.0, 90.0, 60.0);
        p.thumb_across = Some(Finger::Middle);
        p.fingers[1] = Angles {
            mcp: 0.0,
            pip: 0.0,
            dip: 0.0,
        };
        p
    }

    /// No joint bent: the rest pose itself.
    pub fn rest() -> Pose {
        Self::fixed("rest", 0.0, 0.0, 0.0)
    }

    /// The pose called `name` (see [`Pose::NAMES`]).
    pub fn named(name: &str) -> Option<Pose> {
        match name {
            "fist" => Some(Self::fist()),
            "grip" => Some(Self::grip()),
            "point" => Some(Self::point()),
            "rest" => Some(Self::rest()),
            _ => None,
        }
    }

    fn fixed(name: &str, mcp: f64, pip: f64, dip: f64) -> Pose {
        Self::from_angles(name, mcp, pip, dip).unwrap_or_else(|_| Pose {
            name: name.to_string(),
            fingers: [Angles {
                mcp: 0.0,
                pip: 0.0,
                dip: 0.0,
            }; 5],
            thumb_across: None,
        })
    }

    /// The angles of `finger`'s bending joints, MCP first, in radians.
    pub fn radians(&self, finger: Finger) -> Vec<f64> {
        let i = Finger::ALL.iter().position(|&f| f == finger).unwrap_or(0);
        let a = self.fingers[i];
        let all = if finger == Finger::Thumb {
            vec![a.mcp, a.pip]
        } else {
            vec![a.mcp, a.pip, a.dip]
        };
        all.into_iter().map(f64::to_radians).collect()
    }
}

/// The palm of a hand in its rest pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PalmFrame {
    pub side: Side,
    /// The wrist, or the centroid of the palm points.
    pub origin: DVec3,
    /// Unit normal of the palm plane, pointing to the palm side.
    pub normal: DVec3,
    /// Unit in-plane direction from the wrist to the knuckles.
    pub distal: DVec3,
    /// Unit in-plane direction towards the thumb (distal x normal for a right
    /// hand, the opposite for a left hand).
    pub radial: DVec3,
}

impl PalmFrame {
    /// A frame from a palm-side normal and a distal direction (made
    /// orthonormal); `None` when they are parallel or not finite.
    pub fn new(side: Side, origin: DVec3, normal: DVec3, distal: DVec3) -> Option<PalmFrame> {
        let n = normal.try_normalize()?;
        let d = (distal - n * distal.dot(n)).try_normalize()?;
        // Right hand: the thumb is on the side of d x n (palm to the face, n towards
        // it, fingers up: the thumb is on the right, and up x towards = right).
        let r = match side {
            Side::Right => d.cross(n),
            Side::Left => n.cross(d),
        };
        origin.is_finite().then_some(PalmFrame {
            side,
            origin,
            normal: n,
            distal: d,
            radial: r,
        })
    }

    /// The flexion axis of a finger pointing along `dir` (see the module doc).
    pub fn flexion_axis(&self, finger: Finger, dir: DVec3) -> Option<DVec3> {
        let f = dir.try_normalize()?;
        let g = if finger == Finger::Thumb {
            (self.normal - self.radial).normalize()
        } else {
            self.normal
        };
        f.cross(g - f * g.dot(f)).try_normalize()
    }
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations
/// (Numerical Recipes, section 11.1): eigenvalues and the eigenvectors as the
/// matching columns. Hand-written: glam has none, and a linear-algebra crate
/// for one 3x3 solve is not worth its weight. Converges quadratically; 50
/// sweeps is far more than a 3x3 ever needs.
fn symmetric_eigen(m: DMat3) -> ([f64; 3], [DVec3; 3]) {
    // Symmetric, so rows and columns are the same: a[i][j].
    let mut a = m.to_cols_array_2d();
    // v[row][col]; column j converges to eigenvector j. V <- V P each rotation.
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-32 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation P (P_pp = P_qq = c, P_pq = s, P_qp = -s) that zeroes a[p][q] in P^T A P.
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in &mut v {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
        }
    }
    let col = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]);
    ([a[0][0], a[1][1], a[2][2]], [col(0), col(1), col(2)])
}

/// The least-squares plane normal of `points` and the ratio of the smallest to
/// the middle eigenvalue (near 1: no plane stands out; near 0: a clear plane).
fn plane_normal(points: &[DVec3]) -> Option<(DVec3, f64)> {
    if points.len() < 3 {
        return None;
    }
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let mut cov = DMat3::ZERO;
    for p in points {
        let d = *p - c;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let (vals, vecs) = symmetric_eigen(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| vals[i].total_cmp(&vals[j]));
    if vals[order[1]] <= 1e-24 * vals[order[2]].max(1e-300) {
        return None; // collinear
    }
    let n = vecs[order[0]].try_normalize()?;
    Some((n, vals[order[0]] / vals[order[1]]))
}

/// Finds the palm of a hand (see the module doc).
pub fn palm_frame(skeleton: &Skeleton, chains: &HandChains) -> Result<PalmFrame, String> {
    let pos = |n: usize| skeleton.position(n);
    let of = |f: Finger| chains.fingers.iter().find(|c| c.finger == f);
    let mcps: Vec<DVec3> = chains
        .fingers
        .iter()
        .filter(|c| c.finger != Finger::Thumb)
        .filter_map(|c| c.joints.first().map(|&n| pos(n)))
        .collect();
    if mcps.is_empty() {
        return Err(
            "no finger other than the thumb is given, so there is no palm to curl towards".into(),
        );
    }
    let base: Vec<DVec3> = match chains.wrist {
        Some(w) => vec![pos(w)],
        None => chains
            .fingers
            .iter()
            .filter(|c| c.finger != Finger::Thumb)
            .filter_map(|c| c.metacarpal.map(pos))
            .collect(),
    };
    if base.is_empty() {
        return Err(
            "neither a wrist nor metacarpal bones are given, so the palm plane cannot be found"
                .into(),
        );
    }
    let points: Vec<DVec3> = base.iter().chain(&mcps).copied().collect();
    let (n, _) = plane_normal(&points)
        .ok_or("the wrist and the knuckles lie on one line, so they give no palm plane")?;
    let base_c = base.iter().copied().sum::<DVec3>() / base.len() as f64;
    let mcp_c = mcps.iter().copied().sum::<DVec3>() / mcps.len() as f64;
    let distal = mcp_c - base_c;
    let thumb = of(Finger::Thumb)
        .and_then(|t| t.joints.first().copied().or(t.metacarpal))
        .ok_or("no thumb is given; the thumb tells the palm side from the back of the hand")?;
    let t = pos(thumb) - mcp_c;
    let s = n.dot(t.cross(distal));
    if !s.is_finite() || s.abs() <= 1e-12 * (t.length() * distal.length()).max(1e-300) {
        return Err(
            "the thumb lies in line with the wrist and the knuckles, so the palm side is unclear"
                .into(),
        );
    }
    let n = match chains.side {
        Side::Right if s < 0.0 => -n,
        Side::Left if s > 0.0 => -n,
        _ => n,
    };
    let origin = chains.wrist.map_or(base_c, pos);
    PalmFrame::new(chains.side, origin, n, distal)
        .ok_or_else(|| "the hand's long axis is perpendicular to its palm plane".to_string())
}

/// One bent joint of a posed finger.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PosedJoint {
    pub joint: Joint,
    pub node: usize,
    /// Rest position.
    pub rest: DVec3,
    /// Flexion angle, radians.
    pub angle: f64,
    /// The motion of the joints proximal to this one (D_{k-1}).
    pub before: DMat4,
    /// The motion of this joint's bone (D_k).
    pub after: DMat4,
    /// Unit normal of the plane that bisects the joint's rest angle: the sum
    /// of the unit directions of the bone before and the bone after it.
    pub rest_normal: DVec3,
}

impl PosedJoint {
    /// The joint's posed position.
    pub fn posed(&self) -> DVec3 {
        self.before.transform_point3(self.rest)
    }

    /// Unit normal of the plane that bisects the posed joint's angle: the rest
    /// bisector turned by the proximal joints and half this joint's angle.
    pub fn posed_normal(&self, axis: DVec3) -> DVec3 {
        let half = DQuat::from_axis_angle(axis, self.angle / 2.0);
        self.before
            .transform_vector3(half * self.rest_normal)
            .normalize_or_zero()
    }
}

/// A posed finger.
#[derive(Debug, Clone, PartialEq)]
pub struct PosedFinger {
    pub finger: Finger,
    /// Unit flexion axis (the same for every joint of the finger).
    pub axis: DVec3,
    /// The point before the MCP: the CMC (metacarpal origin) or the wrist.
    pub root: Option<DVec3>,
    pub joints: Vec<PosedJoint>,
    /// The tip's rest position.
    pub tip: Option<DVec3>,
    /// The nodes of the finger proper (joints and tip, not the metacarpal).
    pub nodes: Vec<usize>,
    /// Whether `root` is the finger's own metacarpal (else the wrist).
    pub has_metacarpal: bool,
}

impl PosedFinger {
    /// Rest points along the finger: MCP, the inner joints, then the tip.
    pub fn rest_axis(&self) -> Vec<DVec3> {
        self.joints.iter().map(|j| j.rest).chain(self.tip).collect()
    }
}

/// A hand in a pose.
#[derive(Debug, Clone)]
pub struct PosedHand {
    pub pose: Pose,
    pub frame: PalmFrame,
    pub fingers: Vec<PosedFinger>,
    /// Per node: its motion D (identity for nodes that stay).
    pub motion: Vec<DMat4>,
    /// Per node: the posed world matrix D W.
    pub world: Vec<DMat4>,
}

/// Poses a hand: finds its palm ([`palm_frame`]) and curls it ([`pose_in_frame`]).
pub fn pose_hand(
    skeleton: &Skeleton,
    chains: &HandChains,
    pose: &Pose,
) -> Result<PosedHand, String> {
    let frame = palm_frame(skeleton, chains)?;
    pose_in_frame(skeleton, chains, frame, pose)
}

/// Rotation by `angle` about the line through `p` along the unit `axis`.
fn turn_about(p: DVec3, axis: DVec3, angle: f64) -> DMat4 {
    DMat4::from_translation(p)
        * DMat4::from_quat(DQuat::from_axis_angle(axis, angle))
        * DMat4::from_translation(-p)
}

/// Curls the fingers of `chains` in the palm `frame` (see the module doc).
pub fn pose_in_frame(
    skeleton: &Skeleton,
    chains: &HandChains,
    frame: PalmFrame,
    pose: &Pose,
) -> Result<PosedHand, String> {
    let n = skeleton.world.len();
    chains.check(n).map_err(|p| p.join("; "))?;
    let mut own: Vec<Option<DMat4>> = vec![None; n];
    let mut fingers = chains
        .fingers
        .iter()
        .map(|chain| pose_finger(skeleton, chains, &frame, chain, pose))
        .collect::<Result<Vec<_>, _>>()?;
    // The turn of the thumb about its CMC, when the pose folds it.
    let fold = pose
        .thumb_across
        .and_then(|to| fold_thumb(&mut fingers, &frame, to));
    for (chain, f) in chains.fingers.iter().zip(&fingers) {
        for j in &f.joints {
            own[j.node] = Some(j.after);
        }
        if let (Some(tip), Some(last)) = (chain.tip, f.joints.last()) {
            own[tip] = Some(last.after);
        }
        if let Some(m) = chain.metacarpal {
            let turn = if chain.finger == Finger::Thumb {
                fold
            } else {
                None
            };
            own[m] = Some(turn.unwrap_or(DMat4::IDENTITY));
        }
    }
    // Every other node moves with its nearest ancestor that has a motion.
    let mut motion = vec![DMat4::IDENTITY; n];
    for (i, m) in motion.iter_mut().enumerate() {
        let mut at = Some(i);
        let mut steps = 0;
        while let Some(k) = at {
            if let Some(d) = own[k] {
                *m = d;
                break;
            }
            steps += 1;
            if steps > n {
                break;
            }
            at = skeleton.parent.get(k).copied().flatten();
        }
    }
    let world = motion
        .iter()
        .zip(&skeleton.world)
        .map(|(d, w)| *d * *w)
        .collect();
    Ok(PosedHand {
        pose: pose.clone(),
        frame,
        fingers,
        motion,
        world,
    })
}

/// How far from the axis of the finger it folds across the thumb's tip is
/// put, in lengths of that finger's middle phalanx: the two fingers' radii,
/// about 9 and 10 mm against a middle phalanx of about 25 mm in an adult
/// hand, so the thumb lies on the finger's skin rather than in it.
pub const THUMB_CLEARANCE: f64 = 0.75;

/// Folds the posed thumb across finger `to`: turns the whole thumb (its
/// metacarpal, joints and tip) about its CMC (the metacarpal's origin, or
/// its MCP without one) by the smallest rotation that points the CMC-to-tip
/// line at the target, the midpoint of `to`'s posed middle phalanx (PIP to
/// DIP) moved [`THUMB_CLEARANCE`] of that phalanx's length off it on its
/// back, which faces the thumb in a fist. The thumb's own MCP and IP angles
/// are kept. Returns the turn, `None` (nothing changed) when the hand has
/// no such finger or thumb, or the turn is not defined.
fn fold_thumb(fingers: &mut [PosedFinger], frame: &PalmFrame, to: Finger) -> Option<DMat4> {
    let target = {
        let f = fingers.iter().find(|f| f.finger == to)?;
        let (pip, dip) = (f.joints.get(1)?, f.joints.get(2)?);
        let (a, b) = (pip.posed(), dip.posed());
        let len = a.distance(b);
        // The phalanx's back: the rest back of the hand (-normal) turned with it.
        let back = pip.after.transform_vector3(-frame.normal).try_normalize()?;
        (a + b) / 2.0 + back * (THUMB_CLEARANCE * len)
    };
    let thumb = fingers.iter_mut().find(|f| f.finger == Finger::Thumb)?;
    let pivot = thumb
        .root
        .filter(|_| thumb.has_metacarpal)
        .unwrap_or(thumb.joints.first()?.rest);
    let last = thumb.joints.last()?;
    let tip = last.after.transform_point3(thumb.tip.unwrap_or(last.rest));
    let from = (tip - pivot).try_normalize()?;
    let towards = (target - pivot).try_normalize()?;
    let q = DQuat::from_rotation_arc(from, towards);
    if !q.is_finite() {
        return None;
    }
    let turn =
        DMat4::from_translation(pivot) * DMat4::from_quat(q) * DMat4::from_translation(-pivot);
    for j in &mut thumb.joints {
        j.before = turn * j.before;
        j.after = turn * j.after;
    }
    Some(turn)
}

fn pose_finger(
    skeleton: &Skeleton,
    chains: &HandChains,
    frame: &PalmFrame,
    chain: &FingerNodes,
    pose: &Pose,
) -> Result<PosedFinger, String> {
    let pos = |k: usize| skeleton.position(k);
    let points: Vec<DVec3> = chain.joints.iter().map(|&k| pos(k)).collect();
    let tip = chain.tip.map(pos);
    let root = chain.metacarpal.or(chains.wrist).map(pos);
    let first = points[0];
    let end = tip.or(points.last().copied()).unwrap_or(first);
    let dir = if end.distance(first) > 0.0 {
        end - first
    } else {
        first - root.unwrap_or(first)
    };
    let axis = frame.flexion_axis(chain.finger, dir).ok_or_else(|| {
        format!(
            "{}: the finger has no length or points straight out of the palm, so it has no flexion axis",
            chain.finger
        )
    })?;
    let angles = pose.radians(chain.finger);
    let kinds = chain.joint_kinds();
    let mut d = DMat4::IDENTITY;
    let mut joints = Vec::new();
    for (k, &node) in chain.joints.iter().enumerate() {
        let p = points[k];
        let prev = if k == 0 { root } else { Some(points[k - 1]) };
        let next = points.get(k + 1).copied().or(tip);
        let before_dir = prev.and_then(|q| (p - q).try_normalize());
        let after_dir = next.and_then(|q| (q - p).try_normalize());
        let rest_normal = match (before_dir, after_dir) {
            (Some(a), Some(b)) => (a + b).try_normalize().unwrap_or(b),
            (Some(a), None) => a,
            (None, Some(b)) => b,
            (None, None) => dir.normalize(),
        };
        let angle = angles.get(k).copied().unwrap_or(0.0);
        let before = d;
        d *= turn_about(p, axis, angle);
        joints.push(PosedJoint {
            joint: kinds[k],
            node,
            rest: p,
            angle,
            before,
            after: d,
            rest_normal,
        });
    }
    Ok(PosedFinger {
        finger: chain.finger,
        axis,
        root,
        joints,
        tip,
        nodes: chain.finger_nodes(),
        has_metacarpal: chain.metacarpal.is_some(),
    })
}

#[cfg(test)]
pub(crate) mod tests;
