//! Linear blend and dual-quaternion skinning.
//!
//! Linear blend skinning (LBS): v' = (sum_j w_j S_j) v with S_j = W_j B_j the
//! skin matrix of joint j (posed world matrix times inverse bind matrix).
//! Blending matrices collapses the skin at a bent joint: a point weighted 1/2
//! to two bones turned theta apart lands at the chord midpoint, at cos(theta/2)
//! of its distance from the joint ("candy wrapper", "collapsing elbow").
//!
//! Dual-quaternion skinning (DQS; Kavan, Collins, Zara and O'Sullivan 2007,
//! following Kavan and Zara 2005 in the paper's references): each S_j's rigid
//! part is the unit dual quaternion q_j = r_j + eps (1/2) t_j r_j; the blend
//! b = sum_j w_j s_j q_j, with s_j = +1 or -1 putting each r_j in the
//! hemisphere of the vertex's dominant (largest-weight) joint's r (q and -q
//! are the same motion; without the flip the blend could pass through the long
//! way round), is normalised by |b_real| and applied as a rigid motion. So a
//! point between two bones turns by the blended angle about the joint and
//! keeps its distance. DQS blends rigid motions only: scale and shear in a
//! skin matrix are dropped (its rotation is the polar part, its translation
//! kept), with a note naming the joints.
//!
//! A vertex with no weight stays where it is stored. Cost: O(vertices x
//! influences). Dual quaternions are written out here: glam has none, and the
//! crates that do are not widely kept; the algebra is a few lines.

use crate::rig::read::skin::SkinnedMesh;
use glam::{DMat3, DMat4, DQuat, DVec3};
use schemars::JsonSchema;
use serde::Serialize;

/// How a mesh follows its joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Skinning {
    /// Linear blend skinning.
    Lbs,
    /// Dual-quaternion skinning.
    Dqs,
}

impl Skinning {
    /// "lbs" or "dqs".
    pub fn name(self) -> &'static str {
        match self {
            Skinning::Lbs => "lbs",
            Skinning::Dqs => "dqs",
        }
    }

    /// Parses "lbs" or "dqs" (any case).
    pub fn parse(text: &str) -> Option<Skinning> {
        match text.trim().to_ascii_lowercase().as_str() {
            "lbs" => Some(Skinning::Lbs),
            "dqs" => Some(Skinning::Dqs),
            _ => None,
        }
    }
}

/// Skins `mesh` with skin matrices `skin` (one per joint slot) by `method`;
/// returns the positions and notes.
pub fn skin(method: Skinning, mesh: &SkinnedMesh, skin: &[DMat4]) -> (Vec<DVec3>, Vec<String>) {
    match method {
        Skinning::Lbs => (lbs(mesh, skin), Vec::new()),
        Skinning::Dqs => dqs(mesh, skin),
    }
}

/// Linear blend skinning (see the module doc).
pub fn lbs(mesh: &SkinnedMesh, skin: &[DMat4]) -> Vec<DVec3> {
    (0..mesh.positions.len())
        .map(|v| {
            let p = mesh.positions[v];
            let infl = mesh.influences_of(v);
            if infl.is_empty() {
                return p;
            }
            infl.iter()
                .map(|&(j, w)| {
                    let m = skin.get(usize::from(j)).copied().unwrap_or(DMat4::IDENTITY);
                    m.transform_point3(p) * w
                })
                .sum()
        })
        .collect()
}

/// A unit dual quaternion: rotation `real`, translation t in `dual` = t r / 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DualQuat {
    pub real: DQuat,
    pub dual: DQuat,
}

impl DualQuat {
    /// The rigid motion x -> r x + t.
    pub fn from_rotation_translation(r: DQuat, t: DVec3) -> DualQuat {
        DualQuat {
            real: r,
            dual: DQuat::from_xyzw(t.x, t.y, t.z, 0.0) * r * 0.5,
        }
    }

    /// The rotation and translation of a normalised (|real| = 1) dual quaternion.
    pub fn to_rotation_translation(self) -> (DQuat, DVec3) {
        let t = self.dual * self.real.conjugate() * 2.0;
        (self.real, DVec3::new(t.x, t.y, t.z))
    }

    /// Applies the motion to a point; the dual quaternion must be unit.
    pub fn transform_point(self, p: DVec3) -> DVec3 {
        let (r, t) = self.to_rotation_translation();
        r * p + t
    }
}

/// The rigid part of an affine matrix: rotation (nearest, by polar
/// decomposition) and translation; `exact` is false when it had scale or shear
/// beyond 1e-6 (relative) or a reflection.
fn rigid_part(m: &DMat4) -> (DQuat, DVec3, bool) {
    let a = DMat3::from_mat4(*m);
    let t = m.w_axis.truncate();
    let r = polar_rotation(a);
    let exact = a.abs_diff_eq(r, 1e-6) && a.determinant() > 0.0;
    (DQuat::from_mat3(&r).normalize(), t, exact)
}

/// The rotation nearest to `a` (polar decomposition, by the Newton iteration
/// R <- (R + R^-T)/2, which converges quadratically from a itself for a
/// non-singular a); identity when `a` is singular or a reflection.
fn polar_rotation(a: DMat3) -> DMat3 {
    if !a.is_finite() || a.determinant() <= 1e-300 {
        return DMat3::IDENTITY;
    }
    let mut r = a;
    for _ in 0..30 {
        let next = (r + r.inverse().transpose()) * 0.5;
        let done = next.abs_diff_eq(r, 1e-15);
        r = next;
        if done {
            break;
        }
    }
    r
}

/// Dual-quaternion skinning (see the module doc).
pub fn dqs(mesh: &SkinnedMesh, skin: &[DMat4]) -> (Vec<DVec3>, Vec<String>) {
    let mut inexact = Vec::new();
    let dq: Vec<DualQuat> = skin
        .iter()
        .enumerate()
        .map(|(j, m)| {
            let (r, t, exact) = rigid_part(m);
            if !exact {
                inexact.push(j);
            }
            DualQuat::from_rotation_translation(r, t)
        })
        .collect();
    // Slots whose matrix is off but which no vertex uses do not matter.
    let used: std::collections::BTreeSet<u16> = mesh.influences.iter().map(|&(j, _)| j).collect();
    inexact.retain(|&j| used.contains(&(j as u16)));
    let mut notes = Vec::new();
    if !inexact.is_empty() {
        let nodes: Vec<String> = inexact
            .iter()
            .take(8)
            .map(|&j| {
                mesh.joints
                    .get(j)
                    .map_or(format!("slot {j}"), |n| format!("node {n}"))
            })
            .collect();
        notes.push(format!(
            "dual-quaternion skinning keeps only the rotation and translation of each joint's skin matrix; \
             {} joint(s) carry scale, shear or a mirror that is dropped ({}{})",
            inexact.len(),
            nodes.join(", "),
            if inexact.len() > 8 { ", ..." } else { "" }
        ));
    }
    let positions = (0..mesh.positions.len())
        .map(|v| {
            let p = mesh.positions[v];
            let infl = mesh.influences_of(v);
            let Some(&(dom, _)) = infl.first() else {
                return p;
            };
            let pick = |j: u16| {
                dq.get(usize::from(j)).copied().unwrap_or(DualQuat {
                    real: DQuat::IDENTITY,
                    dual: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                })
            };
            let pivot = pick(dom).real;
            let mut real = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
            let mut dual = real;
            for &(j, w) in infl {
                let q = pick(j);
                let s = if q.real.dot(pivot) < 0.0 { -w } else { w };
                real += q.real * s;
                dual += q.dual * s;
            }
            let n = real.length();
            if !n.is_finite() || n <= 1e-12 {
                return p;
            }
            DualQuat {
                real: real / n,
                dual: dual / n,
            }
            .transform_point(p)
        })
        .collect();
    (positions, notes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::deform::synthetic::{HandSpec, tube_hand};

    fn rel_err(a: &[DVec3], b: &[DVec3]) -> f64 {
        let scale = b.iter().map(|p| p.length()).fold(0.0, f64::max);
        a.iter()
            .zip(b)
            .map(|(x, y)| (*x - *y).length())
            .fold(0.0, f64::max)
            / scale
    }

    #[test]
    fn the_identity_pose_returns_the_rest_mesh() {
        let rig = tube_hand(&HandSpec::default());
        let m = rig.mesh.skin_matrices(&rig.skeleton.world);
        for method in [Skinning::Lbs, Skinning::Dqs] {
            let (p, notes) = skin(method, &rig.mesh, &m);
            assert!(notes.is_empty(), "{notes:?}");
            let e = rel_err(&p, &rig.mesh.positions);
            assert!(e < 1e-9, "{method:?}: {e}");
        }
        // Identity matrices: the stored mesh up to the rounding of summing the weights.
        let id = vec![DMat4::IDENTITY; rig.mesh.joints.len()];
        assert!(rel_err(&lbs(&rig.mesh, &id), &rig.mesh.positions) < 1e-15);
        assert!(rel_err(&dqs(&rig.mesh, &id).0, &rig.mesh.positions) < 1e-15);
    }

    #[test]
    fn one_rigid_motion_of_all_joints_moves_the_mesh_rigidly() {
        let rig = tube_hand(&HandSpec::default());
        let motion = DMat4::from_rotation_translation(
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 2.5),
            DVec3::new(0.3, -0.2, 0.1),
        );
        let world: Vec<DMat4> = rig.skeleton.world.iter().map(|w| motion * *w).collect();
        let want: Vec<DVec3> = rig
            .mesh
            .positions
            .iter()
            .map(|p| motion.transform_point3(*p))
            .collect();
        for method in [Skinning::Lbs, Skinning::Dqs] {
            let (p, _) = skin(method, &rig.mesh, &rig.mesh.skin_matrices(&world));
            let e = rel_err(&p, &want);
            assert!(e < 1e-9, "{method:?}: {e}");
        }
    }

    #[test]
    fn blending_two_bones_by_hand() {
        // One vertex at (0, 0, 1), half on a bone that stays, half on one turned 90
        // degrees about x through the origin. By hand: LBS lands at the chord's
        // midpoint (0, -1/2, 1/2), at cos 45 from the origin; DQS turns it by 45
        // degrees: (0, -sin 45, cos 45), at distance 1.
        let mut rig = tube_hand(&HandSpec::default());
        rig.mesh.positions = vec![DVec3::Z];
        rig.mesh.influences = vec![(0, 0.5), (1, 0.5)];
        rig.mesh.influence_start = vec![0, 2];
        let mut s = vec![DMat4::IDENTITY; rig.mesh.joints.len()];
        s[1] = DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2);
        let l = lbs(&rig.mesh, &s)[0];
        assert!((l - DVec3::new(0.0, -0.5, 0.5)).length() < 1e-15, "{l}");
        let d = dqs(&rig.mesh, &s).0[0];
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((d - DVec3::new(0.0, -h, h)).length() < 1e-15, "{d}");
        // The same motion written as -q must blend the same (antipodality).
        let neg = DualQuat::from_rotation_translation(
            -DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
            DVec3::ZERO,
        );
        assert!((neg.transform_point(DVec3::Z) - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-15);
        // A 350-degree turn is -10 degrees: the flip keeps the blend on the short arc.
        s[1] = DMat4::from_rotation_x(350f64.to_radians());
        let d = dqs(&rig.mesh, &s).0[0];
        let want = DVec3::new(0.0, (5f64).to_radians().sin(), (5f64).to_radians().cos());
        assert!((d - want).length() < 1e-12, "{d} {want}");
    }

    #[test]
    fn scale_is_dropped_by_dqs_with_a_note() {
        let rig = tube_hand(&HandSpec::default());
        let mut s = rig.mesh.skin_matrices(&rig.skeleton.world);
        s[3] *= DMat4::from_scale(DVec3::splat(2.0));
        let (_, notes) = dqs(&rig.mesh, &s);
        assert!(notes.len() == 1 && notes[0].contains("node 4"), "{notes:?}");
    }
}
