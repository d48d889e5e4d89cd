//! How a finger's skin deforms in a pose, measured against its rest shape.
//!
//! **The finger's skin.** A finger's vertices are those whose largest weight
//! is on one of its joints (MCP to tip; not the metacarpal); its triangles are
//! those with at least one such vertex, so the ring where the finger meets the
//! palm is included. Positions along the finger are arc lengths s of the
//! nearest point on the rest axis, the polyline MCP - PIP - DIP - tip (its
//! first and last segments extended as rays); joint k's zone runs from halfway
//! to the joint before it to halfway to the joint after it.
//!
//! **Window.** Joint k's window is s_k +- w, with w half the shorter bone
//! next to the joint; it is cut into 21 equal bins, the middle one centred on
//! the joint.
//!
//! **Volume loss** at a joint: 1 - A_pose / A_rest for the skin's
//! cross-section, the largest over 21 sections across the window (reported
//! with its offset from the joint, `volume_loss_at`). The middle section is
//! cut by the plane through the joint that bisects its rest angle
//! (perpendicular to the finger when the finger is straight); the others by
//! planes parallel to it through the bin centres. At rest each is the closed
//! polyline(s) where the plane cuts the whole mesh, the loop winding around
//! the plane's point on the finger (the smallest when several do) with every
//! loop crossing it, clipped to the finger's strip: across the finger (along
//! the flexion axis) no farther than half the distance from its MCP to the
//! nearest other MCP, so that at the MCP, where the plane runs through the
//! palm, each finger gets its own share. In the pose the same skin points
//! (each on its mesh edge at the same fraction) are taken where the skinning
//! moved them, and their polygon's area is its vector area, (1/2) |sum p_i x
//! p_(i+1)|: the area of its projection on the plane where that is largest,
//! which for the joint's own ring is the plane bisecting the posed angle. Rest
//! area by the shoelace formula in the plane's 2-D frame. A section folded
//! through itself counts its folded part negatively (the winding-number
//! integral; a ring turned inside out has negative area). Positive = lost.
//!
//! Why the same skin points, not a fresh cut of the posed mesh: a bent LBS
//! joint's palm-side skin passes through itself, and a fresh cut of the
//! bisecting plane meets the skin of each phalanx that crossed it, out to
//! where a rigid mitre would reach (r / cos(theta/2)): on the test tube at 90
//! degrees such a cut reads a 35% gain where the skin has collapsed. And why
//! the largest over the window: a joint placed off its weights collapses
//! where the weights blend, not at the joint, and a measure taken only at the
//! joint would favour exactly that defect. Closed forms for a tube: a ring
//! weighted w to the turned bone keeps |1 - w + w e^(i theta)| of its area
//! under LBS, least at w = 1/2: loss 1 - cos(theta/2), 29% at 90 degrees,
//! wherever the blend sits relative to the joint; DQS turns every ring
//! rigidly: loss 0. What it cannot tell: where the joint is (the crease
//! offset does).
//!
//! **Self-intersection**: pairs of the finger's triangles that cross in the
//! pose and did not at rest (`intersect`); each pair is counted in
//! the zone of the mean of its two rest centroids.
//!
//! **Edge strain**: for each edge of the finger's triangles, |ln(L_pose /
//! L_rest)|; the 95th percentile (nearest rank) and the maximum, over the
//! finger and over each joint's zone (an edge by its rest midpoint).
//!
//! **Crease offset**: where the skin folds, relative to the joint, along the
//! finger. Each finger vertex's strain is the mean of its edges'; the window's
//! bins average the strain of the vertices they hold (so dense meshes do not
//! weigh more), and the offset is the strain-weighted mean bin position minus
//! s_joint (positive: distal of the joint). A centroid, not the peak bin: a
//! joint off its weights strains the skin in two ridges, where it leaves one
//! bone and where it reaches the other, and the peak jumps between them; their
//! centroid is the middle of the fold. None when nothing strains there.

use super::intersect::{crossing_pairs, triangles_cross};
use super::pose::{PosedFinger, PosedHand};
use super::section::{self, Plane};
use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use crate::rig::read::skin::SkinnedMesh;
use glam::{DVec2, DVec3};
use schemars::JsonSchema;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet, HashSet};

/// The measures of one joint of a finger.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct JointMeasures {
    pub joint: Joint,
    /// Flexion in the pose, degrees.
    pub angle: f64,
    /// Cross-section area at rest and in the pose (file units squared), of the
    /// section that loses most.
    pub rest_area: Option<f64>,
    pub posed_area: Option<f64>,
    /// 1 - posed / rest area (positive: area lost), of the section that loses most.
    pub volume_loss: Option<f64>,
    /// Where that section is: its distance from the joint (file units; + distal).
    pub volume_loss_at: Option<f64>,
    /// New crossing triangle pairs in this joint's zone.
    pub self_intersections: usize,
    /// 95th percentile and maximum of |ln(posed / rest edge length)| in the zone.
    pub strain_p95: Option<f64>,
    pub strain_max: Option<f64>,
    /// Where the strain peaks, minus the joint, along the finger (file units; + distal).
    pub crease_offset: Option<f64>,
}

/// The measures of one finger.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct FingerMeasures {
    pub finger: Finger,
    pub vertices: usize,
    pub triangles: usize,
    /// New crossing triangle pairs of the whole finger.
    pub self_intersections: usize,
    /// Over all the finger's edges.
    pub strain_p95: Option<f64>,
    pub strain_max: Option<f64>,
    pub joints: Vec<JointMeasures>,
    /// Measures that could not be taken, and why.
    pub notes: Vec<String>,
}

/// Every finger of a hand, measured.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct HandMeasures {
    pub fingers: Vec<FingerMeasures>,
}

/// The 95th percentile (nearest rank) and the maximum of `values`.
fn p95_max(values: &mut [f64]) -> (Option<f64>, Option<f64>) {
    if values.is_empty() {
        return (None, None);
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n);
    (Some(values[rank - 1]), Some(values[n - 1]))
}

/// Arc-length positions along a polyline whose end segments extend as rays.
struct Axis {
    points: Vec<DVec3>,
    /// Arc length at each point.
    at: Vec<f64>,
}

impl Axis {
    fn new(points: Vec<DVec3>) -> Axis {
        let mut at = vec![0.0];
        for w in points.windows(2) {
            at.push(at[at.len() - 1] + w[0].distance(w[1]));
        }
        Axis { points, at }
    }

    /// Arc length of the point of the axis nearest to `p`.
    fn project(&self, p: DVec3) -> f64 {
        let n = self.points.len();
        if n < 2 {
            return 0.0;
        }
        let mut best = (f64::INFINITY, 0.0);
        for i in 0..n - 1 {
            let (a, b) = (self.points[i], self.points[i + 1]);
            let ab = b - a;
            let len2 = ab.length_squared();
            if len2 == 0.0 {
                continue;
            }
            let mut t = (p - a).dot(ab) / len2;
            if i > 0 {
                t = t.max(0.0);
            }
            if i + 2 < n {
                t = t.min(1.0);
            }
            let d = (a + ab * t).distance_squared(p);
            if d < best.0 {
                best = (d, self.at[i] + t * len2.sqrt());
            }
        }
        best.1
    }
}

/// The joint zone of arc length `s`, given the joints' arc lengths.
fn zone(joints: &[f64], s: f64) -> usize {
    joints
        .windows(2)
        .filter(|w| s >= (w[0] + w[1]) / 2.0)
        .count()
}

/// Per-edge |ln(posed / rest length)| over the unique (welded) edges of `tris`.
fn edge_strains(
    mesh: &SkinnedMesh,
    rest: &[DVec3],
    posed: &[DVec3],
    tris: impl Iterator<Item = [u32; 3]>,
) -> Vec<((u32, u32), f64)> {
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    for t in tris {
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (mesh.welded[t[i] as usize], mesh.welded[t[j] as usize]);
            let k = if a < b { (a, b) } else { (b, a) };
            if !seen.insert(k) {
                continue;
            }
            let (a, b) = (k.0 as usize, k.1 as usize);
            let lr = rest[a].distance(rest[b]);
            let lp = posed[a].distance(posed[b]);
            if lr > 0.0 && lp > 0.0 && (lp / lr).is_finite() {
                out.push((k, (lp / lr).ln().abs()));
            }
        }
    }
    out
}

/// Per vertex: the mean edge strain of its edges over the whole mesh (0 for a
/// vertex on no triangle); seam duplicates share their welded vertex's value.
pub fn vertex_strain(mesh: &SkinnedMesh, rest: &[DVec3], posed: &[DVec3]) -> Vec<f64> {
    let n = mesh.positions.len();
    let mut sum = vec![0.0; n];
    let mut count = vec![0u32; n];
    for ((a, b), r) in edge_strains(mesh, rest, posed, mesh.triangles.iter().copied()) {
        for v in [a, b] {
            sum[v as usize] += r;
            count[v as usize] += 1;
        }
    }
    (0..n)
        .map(|v| {
            let w = mesh.welded[v] as usize;
            if count[w] > 0 {
                sum[w] / f64::from(count[w])
            } else {
                0.0
            }
        })
        .collect()
}

/// Measures every finger of `hand` (see the module doc). Cost: O(triangles)
/// per joint for the sections, and the grid search for crossings.
pub fn measure(
    mesh: &SkinnedMesh,
    rest: &[DVec3],
    posed: &[DVec3],
    hand: &PosedHand,
) -> HandMeasures {
    let mcps: Vec<(Finger, DVec3)> = hand
        .fingers
        .iter()
        .filter_map(|f| f.joints.first().map(|j| (f.finger, j.rest)))
        .collect();
    let fingers = hand
        .fingers
        .iter()
        .map(|f| {
            let half = mcps
                .iter()
                .filter(|(g, _)| *g != f.finger)
                .map(|(_, p)| p.distance(f.joints[0].rest) / 2.0)
                .fold(f64::INFINITY, f64::min);
            measure_finger(mesh, rest, posed, f, half)
        })
        .collect();
    HandMeasures { fingers }
}

/// The skinned mesh and the two poses being measured.
struct Meshes<'a> {
    mesh: &'a SkinnedMesh,
    rest: &'a [DVec3],
    posed: &'a [DVec3],
}

/// Measures one finger, in steps: its skin, its axis, strain per zone, new
/// crossings per zone, then each joint.
fn measure_finger(
    mesh: &SkinnedMesh,
    rest: &[DVec3],
    posed: &[DVec3],
    f: &PosedFinger,
    half: f64,
) -> FingerMeasures {
    let m = Meshes { mesh, rest, posed };
    let mut notes = Vec::new();
    let (vertices, tris) = finger_skin(mesh, f);
    if vertices == 0 {
        notes.push(format!(
            "no vertex has its largest weight on the {} joints, so its skin is not measured",
            f.finger
        ));
    }
    let axis = finger_axis(f);
    let joint_s: Vec<f64> = f.joints.iter().map(|j| axis.project(j.rest)).collect();
    let strains = edge_strains(mesh, rest, posed, tris.iter().map(|&t| mesh.triangles[t]));
    let mut all: Vec<f64> = strains.iter().map(|e| e.1).collect();
    let (p95, max) = p95_max(&mut all);
    let (mut by_zone, vertex_s) = strain_along(&m, &strains, &axis, &joint_s);
    let (crossings, crossings_by_zone) = new_crossings(&m, &tris, &axis, &joint_s);
    let joints = (0..f.joints.len())
        .map(|k| {
            let zone_strains = by_zone.get_mut(&k).map(std::mem::take).unwrap_or_default();
            let zone_crossings = crossings_by_zone.get(&k).copied().unwrap_or(0);
            joint_measures(
                &m,
                f,
                k,
                &joint_s,
                half,
                &vertex_s,
                zone_strains,
                zone_crossings,
                &mut notes,
            )
        })
        .collect();
    FingerMeasures {
        finger: f.finger,
        vertices,
        triangles: tris.len(),
        self_intersections: crossings,
        strain_p95: p95,
        strain_max: max,
        joints,
        notes,
    }
}

/// The finger's skin: how many vertices have their largest weight on its
/// joints, and the triangles with at least one such vertex.
fn finger_skin(mesh: &SkinnedMesh, f: &PosedFinger) -> (usize, Vec<usize>) {
    let slots: BTreeSet<u16> = f.nodes.iter().filter_map(|&n| mesh.slot_of(n)).collect();
    let mine: Vec<bool> = (0..mesh.positions.len())
        .map(|v| mesh.dominant(v).is_some_and(|j| slots.contains(&j)))
        .collect();
    let tris: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&t| mesh.triangles[t].iter().any(|&v| mine[v as usize]))
        .collect();
    (mine.iter().filter(|&&m| m).count(), tris)
}

/// The finger's rest axis (with the root before a lone joint).
fn finger_axis(f: &PosedFinger) -> Axis {
    let mut axis_points = f.rest_axis();
    if axis_points.len() < 2
        && let Some(r) = f.root
    {
        axis_points.insert(0, r);
    }
    Axis::new(axis_points)
}

/// Edge strains per joint zone.
type ZoneStrains = BTreeMap<usize, Vec<f64>>;

/// Edge strains by joint zone (an edge by its rest midpoint), and each
/// vertex's (arc length, mean strain of its edges), for the creases.
fn strain_along(
    m: &Meshes<'_>,
    strains: &[((u32, u32), f64)],
    axis: &Axis,
    joint_s: &[f64],
) -> (ZoneStrains, Vec<(f64, f64)>) {
    let mut by_zone: BTreeMap<usize, Vec<f64>> = BTreeMap::new();
    let mut vsum: BTreeMap<u32, (f64, u32)> = BTreeMap::new();
    for &((a, b), r) in strains {
        let mid = (m.rest[a as usize] + m.rest[b as usize]) / 2.0;
        by_zone
            .entry(zone(joint_s, axis.project(mid)))
            .or_default()
            .push(r);
        for v in [a, b] {
            let e = vsum.entry(v).or_insert((0.0, 0));
            e.0 += r;
            e.1 += 1;
        }
    }
    let vertex_s = vsum
        .iter()
        .map(|(&v, &(sum, n))| (axis.project(m.rest[v as usize]), sum / f64::from(n)))
        .collect();
    (by_zone, vertex_s)
}

/// New crossings: triangle pairs of the finger crossing in the pose that did
/// not at rest; their count, and the count per joint zone (a pair by the mean
/// of its rest centroids).
fn new_crossings(
    m: &Meshes<'_>,
    tris: &[usize],
    axis: &Axis,
    joint_s: &[f64],
) -> (usize, BTreeMap<usize, usize>) {
    let mesh = m.mesh;
    let corners = |p: &[DVec3], t: usize| mesh.triangles[t].map(|v| p[v as usize]);
    let new: Vec<(usize, usize)> = crossing_pairs(m.posed, &mesh.welded, &mesh.triangles, tris)
        .into_iter()
        .filter(|&(i, j)| !triangles_cross(&corners(m.rest, i), &corners(m.rest, j)))
        .collect();
    let mut by_zone: BTreeMap<usize, usize> = BTreeMap::new();
    let centroid = |t: usize| {
        mesh.triangles[t]
            .iter()
            .map(|&v| m.rest[v as usize])
            .sum::<DVec3>()
            / 3.0
    };
    for &(i, j) in &new {
        let s = axis.project((centroid(i) + centroid(j)) / 2.0);
        *by_zone.entry(zone(joint_s, s)).or_default() += 1;
    }
    (new.len(), by_zone)
}

/// The measures of joint `k`: its window (half the shorter bone next to it),
/// the worst section there, its zone's strain and crossings, and the crease.
#[allow(clippy::too_many_arguments)]
fn joint_measures(
    m: &Meshes<'_>,
    f: &PosedFinger,
    k: usize,
    joint_s: &[f64],
    half: f64,
    vertex_s: &[(f64, f64)],
    mut zone_strains: Vec<f64>,
    zone_crossings: usize,
    notes: &mut Vec<String>,
) -> JointMeasures {
    let j = &f.joints[k];
    let (zp95, zmax) = p95_max(&mut zone_strains);
    let before_len = if k > 0 {
        Some(joint_s[k] - joint_s[k - 1])
    } else {
        f.root.map(|r| r.distance(j.rest))
    };
    let after_len = if k + 1 < joint_s.len() {
        Some(joint_s[k + 1] - joint_s[k])
    } else {
        f.tip.map(|t| t.distance(j.rest))
    };
    let w = before_len
        .into_iter()
        .chain(after_len)
        .filter(|x| *x > 0.0)
        .fold(f64::INFINITY, f64::min)
        / 2.0;
    let worst = worst_section(m.mesh, m.rest, m.posed, f, k, w, half, notes);
    JointMeasures {
        joint: j.joint,
        angle: j.angle.to_degrees(),
        rest_area: worst.map(|x| x.rest),
        posed_area: worst.map(|x| x.posed),
        volume_loss: worst.map(|x| 1.0 - x.posed / x.rest),
        volume_loss_at: worst.map(|x| x.offset),
        self_intersections: zone_crossings,
        strain_p95: zp95,
        strain_max: zmax,
        crease_offset: crease(vertex_s, joint_s[k], w),
    }
}

/// Bins (and sections) across a joint's window: odd, so one is centred on the joint.
const BINS: usize = 21;

/// One section of a joint's window.
#[derive(Debug, Clone, Copy)]
struct Section {
    /// Distance of its plane from the joint, along the rest bisector's normal.
    offset: f64,
    rest: f64,
    posed: f64,
}

/// The section of the window of joint `k` (half-width `w`) that loses the most
/// area (see the module doc); a note when the one at the joint cannot be cut.
#[allow(clippy::too_many_arguments)]
fn worst_section(
    mesh: &SkinnedMesh,
    rest: &[DVec3],
    posed: &[DVec3],
    f: &PosedFinger,
    k: usize,
    w: f64,
    half: f64,
    notes: &mut Vec<String>,
) -> Option<Section> {
    let j = &f.joints[k];
    let label = format!("{} {}", f.finger, j.joint.name());
    let step = if w.is_finite() {
        2.0 * w / BINS as f64
    } else {
        0.0
    };
    let offsets = (0..BINS).map(|b| (b as f64 - (BINS / 2) as f64) * step);
    // Only triangles reaching into the slab of the window's planes can be cut.
    let reach = if step > 0.0 { w + step } else { 0.0 };
    let d: Vec<f64> = rest
        .iter()
        .map(|p| (*p - j.rest).dot(j.rest_normal))
        .collect();
    let slab: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .filter(|t| {
            let dd = t.map(|v| d[v as usize]);
            dd.iter().any(|&x| x >= -reach) && dd.iter().any(|&x| x <= reach)
        })
        .copied()
        .collect();
    let mut worst: Option<Section> = None;
    for offset in offsets {
        let Some(s) = section_at(mesh, &slab, rest, posed, f, k, offset, half) else {
            if offset == 0.0 {
                notes.push(format!(
                    "{label}: at rest no closed section of the skin surrounds the joint \
                     (is the joint outside the mesh, or the mesh open there?)"
                ));
                return None;
            }
            continue;
        };
        let loss = |x: &Section| 1.0 - x.posed / x.rest;
        if worst.is_none_or(|m| loss(&s) > loss(&m)) {
            worst = Some(s);
        }
        if step == 0.0 {
            break;
        }
    }
    worst
}

/// The rest and posed area of the section of joint `k`'s skin `offset` from
/// the joint, cut from `triangles` (see the module doc); `None` when no loop
/// winds around the plane's point on the finger at rest.
#[allow(clippy::too_many_arguments)]
fn section_at(
    mesh: &SkinnedMesh,
    triangles: &[[u32; 3]],
    rest: &[DVec3],
    posed: &[DVec3],
    f: &PosedFinger,
    k: usize,
    offset: f64,
    half: f64,
) -> Option<Section> {
    let j = &f.joints[k];
    let rest_plane = Plane::new(j.rest + j.rest_normal * offset, j.rest_normal, f.axis)?;
    let facing = j.posed_normal(f.axis);
    let cuts = section::loops(rest, &mesh.welded, triangles, &rest_plane);
    let flat: Vec<Vec<DVec2>> = cuts
        .iter()
        .map(|l| l.iter().map(|c| c.at).collect())
        .collect();
    let group = section::around_origin(&flat)?;
    let mut a_rest = 0.0;
    let mut vector = DVec3::ZERO;
    for g in group {
        let carried: Vec<(DVec2, DVec3)> =
            cuts[g].iter().map(|c| (c.at, c.carried(posed))).collect();
        let clipped = section::clip_strip(&carried, half);
        let r: Vec<DVec2> = clipped.iter().map(|c| c.0).collect();
        a_rest += section::shoelace(&r);
        vector += section::vector_area(&clipped.iter().map(|c| c.1).collect::<Vec<_>>());
    }
    if a_rest == 0.0 || !a_rest.is_finite() {
        return None;
    }
    // Turned inside out (facing against the bisecting plane's normal, relative to rest): negative.
    let a_pose = if vector.dot(facing) * a_rest.signum() < 0.0 {
        -vector.length()
    } else {
        vector.length()
    };
    Some(Section {
        offset,
        rest: a_rest.abs(),
        posed: a_pose,
    })
}

/// The crease offset: the strain-weighted mean position of the bins across
/// `s0` +- `w` (bin mean strains as weights), minus `s0`. `None` when no vertex
/// strains there.
fn crease(vertex_s: &[(f64, f64)], s0: f64, w: f64) -> Option<f64> {
    if !(w.is_finite() && w > 0.0) {
        return None;
    }
    let width = 2.0 * w / BINS as f64;
    let mut sum = [0.0; BINS];
    let mut n = [0u32; BINS];
    for &(s, r) in vertex_s {
        let x = (s - (s0 - w)) / width;
        if x >= 0.0 && x < BINS as f64 {
            sum[x as usize] += r;
            n[x as usize] += 1;
        }
    }
    let (mut total, mut moment) = (0.0, 0.0);
    for b in 0..BINS {
        if n[b] > 0 {
            let mean = sum[b] / f64::from(n[b]);
            total += mean;
            moment += mean * ((b as f64 + 0.5) * width - w);
        }
    }
    (total > 0.0).then(|| moment / total)
}

#[cfg(test)]
mod tests;
