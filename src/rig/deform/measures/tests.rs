//! Measures on synthetic tube fingers whose joints and weights are known.

use super::*;
use crate::rig::deform::pose::{PalmFrame, Pose, pose_hand, pose_in_frame};
use crate::rig::deform::skinning::{Skinning, skin};
use crate::rig::deform::synthetic::{HandSpec, SyntheticRig, tube_hand};
use crate::rig::read::naming::Side;

/// One index finger (a tube along +y, palm facing -z), posed with only its
/// PIP bent by `pip` degrees, skinned by `method`; the PIP's measures.
fn pip_bent(spec: &HandSpec, pip: f64, method: Skinning) -> (FingerMeasures, SyntheticRig) {
    let rig = tube_hand(spec);
    let frame = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
    let pose = Pose::from_angles("pip", 0.0, pip, 0.0).unwrap();
    let posed = pose_in_frame(&rig.skeleton, &rig.chains, frame, &pose).unwrap();
    let (rest, _) = skin(
        method,
        &rig.mesh,
        &rig.mesh.skin_matrices(&rig.skeleton.world),
    );
    let (moved, _) = skin(method, &rig.mesh, &rig.mesh.skin_matrices(&posed.world));
    let m = measure(&rig.mesh, &rest, &moved, &posed);
    (m.fingers[0].clone(), rig)
}

fn index_only() -> HandSpec {
    HandSpec {
        fingers: vec![Finger::Index],
        ..HandSpec::default()
    }
}

#[test]
fn lbs_and_dqs_lose_what_the_closed_forms_say() {
    // The joint ring (weight 1/2 each side) lands in the bisecting plane: LBS
    // shrinks it across the bend by cos(theta/2), DQS only turns it. By hand at
    // 90 degrees: LBS loss 1 - cos 45 = 0.2929, DQS 0.
    let (lbs, _) = pip_bent(&index_only(), 90.0, Skinning::Lbs);
    let (dqs, _) = pip_bent(&index_only(), 90.0, Skinning::Dqs);
    let l = lbs.joints[1].volume_loss.unwrap();
    let d = dqs.joints[1].volume_loss.unwrap();
    assert!(
        (l - (1.0 - 45f64.to_radians().cos())).abs() < 0.01,
        "LBS {l}"
    );
    assert!(d.abs() < 0.01, "DQS {d}");
    assert!(d < l);
    // The rest area is the 16-gon's: (n/2) r^2 sin(2 pi / n).
    let want = 8.0 * 0.008f64.powi(2) * (std::f64::consts::TAU / 16.0).sin();
    assert!((lbs.joints[1].rest_area.unwrap() - want).abs() < 1e-9 * want + 1e-12);
    // Unbent joints keep their section.
    assert!(lbs.joints[0].volume_loss.unwrap().abs() < 1e-9);
}

/// The signed volume of the tube closed by a fan at its base (the base ring
/// is rigid with the metacarpal, so the fan is the same at rest and posed):
/// the divergence theorem, sum of det(a, b, c) / 6 over outward triangles.
fn closed_volume(rig: &SyntheticRig, p: &[DVec3]) -> f64 {
    let n = 16;
    let centre = (0..n).map(|i| p[i]).sum::<DVec3>() / n as f64;
    let skin: f64 = rig
        .mesh
        .triangles
        .iter()
        .map(|t| p[t[0] as usize].dot(p[t[1] as usize].cross(p[t[2] as usize])))
        .sum();
    let cap: f64 = (0..n).map(|i| centre.dot(p[(i + 1) % n].cross(p[i]))).sum();
    (skin + cap) / 6.0
}

#[test]
fn weights_centred_on_the_joint_deform_less_than_weights_5mm_off() {
    let centred = index_only();
    let off = HandSpec {
        weight_shift: 0.005,
        ..index_only()
    };
    for method in [Skinning::Lbs, Skinning::Dqs] {
        let (c, _) = pip_bent(&centred, 90.0, method);
        let (o, _) = pip_bent(&off, 90.0, method);
        let (c, o) = (&c.joints[1], &o.joints[1]);
        // Less strain with the weights centred on the joint, under LBS. (Not under
        // DQS: there each ring turns rigidly about the joint, and rings away from
        // it sweep apart instead of piling up on the palm side, so this tube,
        // whose blend is narrower than its radius, folds less with the joint off.)
        if method == Skinning::Lbs {
            assert!(c.strain_p95.unwrap() < o.strain_p95.unwrap(), "{c:?} {o:?}");
            assert!(c.strain_max.unwrap() < o.strain_max.unwrap());
        }
        // The skin folds where the weights blend: at the joint, or 5 mm distal.
        assert!(c.crease_offset.unwrap().abs() < 1e-9, "{method:?} {c:?}");
        assert!(
            (o.crease_offset.unwrap() - 0.005).abs() < 0.001,
            "{method:?} {o:?}"
        );
        // The same collapse, moved with the weights: LBS's ring at the blend's
        // middle keeps cos 45 of its area however far the joint is from it.
        let want = if method == Skinning::Lbs {
            1.0 - 45f64.to_radians().cos()
        } else {
            0.0
        };
        for (m, at) in [(c, 0.0), (o, 0.005)] {
            assert!(
                (m.volume_loss.unwrap() - want).abs() < 0.01,
                "{method:?} {m:?}"
            );
            if method == Skinning::Lbs {
                assert!((m.volume_loss_at.unwrap() - at).abs() < 0.001, "{m:?}");
            }
        }
    }
    // Independently, by the divergence theorem: the whole tube loses the same volume
    // with the joint 5 mm off its weights as with the joint in their middle.
    let volume_lost = |spec: &HandSpec| {
        let rig = tube_hand(spec);
        let frame = PalmFrame::new(Side::Right, DVec3::ZERO, DVec3::NEG_Z, DVec3::Y).unwrap();
        let pose = Pose::from_angles("pip", 0.0, 90.0, 0.0).unwrap();
        let posed = pose_in_frame(&rig.skeleton, &rig.chains, frame, &pose).unwrap();
        let (rest, _) = skin(
            Skinning::Lbs,
            &rig.mesh,
            &rig.mesh.skin_matrices(&rig.skeleton.world),
        );
        let (moved, _) = skin(
            Skinning::Lbs,
            &rig.mesh,
            &rig.mesh.skin_matrices(&posed.world),
        );
        closed_volume(&rig, &rest) - closed_volume(&rig, &moved)
    };
    let (vc, vo) = (volume_lost(&centred), volume_lost(&off));
    assert!(vc > 0.0 && ((vc - vo) / vc).abs() < 1e-3, "{vc} {vo}");
}

#[test]
fn folding_the_tube_onto_itself_crosses_the_skin() {
    let (folded, _) = pip_bent(&index_only(), 170.0, Skinning::Lbs);
    assert!(folded.joints[1].self_intersections > 0, "{folded:?}");
    assert_eq!(
        folded.self_intersections,
        folded
            .joints
            .iter()
            .map(|j| j.self_intersections)
            .sum::<usize>()
    );
    let (straight, _) = pip_bent(&index_only(), 0.0, Skinning::Lbs);
    assert_eq!(straight.self_intersections, 0);
    assert_eq!(straight.strain_max, Some(0.0));
    assert!(straight.joints.iter().all(|j| j.crease_offset.is_none()));
}

#[test]
fn a_mirrored_hand_measures_the_same() {
    let measure_of = |side| {
        let rig = tube_hand(&HandSpec {
            side,
            ..HandSpec::default()
        });
        let posed = pose_hand(&rig.skeleton, &rig.chains, &Pose::fist()).unwrap();
        crate::rig::deform::deform(&rig.mesh, &rig.skeleton, &posed, Skinning::Lbs).measures
    };
    let (r, l) = (measure_of(Side::Right), measure_of(Side::Left));
    for (fr, fl) in r.fingers.iter().zip(&l.fingers) {
        assert_eq!(
            fr.self_intersections, fl.self_intersections,
            "{}",
            fr.finger
        );
        for (a, b) in fr.joints.iter().zip(&fl.joints) {
            let close = |x: Option<f64>, y: Option<f64>| match (x, y) {
                (Some(x), Some(y)) => (x - y).abs() < 1e-9,
                (None, None) => true,
                _ => false,
            };
            assert!(
                close(a.volume_loss, b.volume_loss),
                "{} {a:?} {b:?}",
                fr.finger
            );
            assert!(close(a.strain_p95, b.strain_p95) && close(a.crease_offset, b.crease_offset));
        }
    }
}

#[test]
fn percentiles_by_nearest_rank() {
    let mut v: Vec<f64> = (1..=20).map(f64::from).collect();
    // 20 values: rank ceil(0.95 * 20) = 19.
    assert_eq!(p95_max(&mut v), (Some(19.0), Some(20.0)));
    let mut one = vec![3.0];
    assert_eq!(p95_max(&mut one), (Some(3.0), Some(3.0)));
    assert_eq!(p95_max(&mut []), (None, None));
}
