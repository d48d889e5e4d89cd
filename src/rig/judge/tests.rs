//! The tests of the finger judgement and the MCP from its ray's base.

use super::chain::on_chain;
use super::*;
use crate::analysis::placement::Joint;
use crate::analysis::{Analysis, Interval, Quantity, Settings, analyse};
use crate::dataset::{Dataset, Finger};
use glam::DVec3;
use std::path::Path;

fn paper() -> Analysis {
    let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
    analyse(&d, &Settings::default())
}

/// Tips compared as they are: the rig's tips read as the data's kind.
fn alike(a: &Analysis) -> JudgeOptions {
    JudgeOptions::new(data_tip_of(&a.tips), SoftTissue::Unknown, a)
}

/// The paper's X-rays with every tip recorded at the bone instead of the skin.
fn paper_with_bone_tips() -> Analysis {
    let text = std::fs::read_to_string("data/measurements.csv").unwrap();
    let bone = text.replace(",skin\n", ",bone\n");
    assert_ne!(bone, text, "the paper's rows record skin tips");
    let d = Dataset::from_bytes("bone.csv", bone.as_bytes()).unwrap();
    let a = analyse(&d, &Settings::default());
    assert_eq!(data_tip_of(&a.tips), TipKind::Bone);
    a
}

/// The soft tissue of the vendored table, Buryanov & Kotiuk 2010.
fn table_soft_tissue() -> SoftTissue {
    let t = crate::dataset::SummaryTable::load(Path::new(SOFT_TISSUE_TABLE)).unwrap();
    SoftTissue::from_table(&t, None)
}

/// A straight finger along x with the given segment lengths (and a tip).
fn straight(finger: Finger, segs: &[f64]) -> ChainInput {
    let mut points = vec![DVec3::ZERO];
    let mut x = 0.0;
    for s in segs {
        x += s;
        points.push(DVec3::new(x, 0.0, 0.0));
    }
    ChainInput {
        finger,
        points,
        has_tip: true,
    }
}

/// The mean of mc / (J1 + J2 + J3) over the atlas's rows of `finger` that
/// measure the metacarpal, read from the CSV by hand (not by the dataset reader).
fn atlas_mean_mc_over_j(finger: &str) -> f64 {
    let text = std::fs::read_to_string("data/atlas/measurements.csv").unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (f, mc, js) = (col("finger"), col("mc"), [col("j1"), col("j2"), col("j3")]);
    let ratios: Vec<f64> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[f] == finger && !r[mc].is_empty())
        .map(|r| {
            let j: f64 = js.iter().filter_map(|&k| r[k].parse::<f64>().ok()).sum();
            r[mc].parse::<f64>().unwrap() / j
        })
        .collect();
    assert!(
        ratios.len() > 100,
        "{} atlas rows for {finger}",
        ratios.len()
    );
    ratios.iter().sum::<f64>() / ratios.len() as f64
}

#[test]
fn an_mcp_10_mm_towards_the_web_is_out_too_distal_on_the_metacarpal_line() {
    // The atlas is GPL data a package leaves out (Cargo.toml's exclude).
    let Some(d) = crate::dataset::vendored::atlas() else {
        return;
    };
    let atlas = analyse(&d, &Settings::default());
    let x = atlas_mean_mc_over_j("index");
    // A straight index finger along x: CMC at the origin, the metacarpal
    // at the atlas's mean mc/J of an 80 mm finger (J~ at the paper's
    // means), the skin tip 4 mm past the atlas's bone tip (--tip-soft-tissue 4).
    let length = 0.080;
    let mc = x * length;
    let segs = [0.4846 * length, 0.2726 * length, 0.2428 * length + 0.004];
    let finger = |mcp: f64| {
        let mut c = straight(Finger::Index, &segs);
        c.points[0].x = mcp;
        for (k, p) in c.points.iter_mut().enumerate().skip(1) {
            p.x = mc + segs[..k].iter().sum::<f64>();
        }
        c
    };
    let opts = JudgeOptions::new(TipKind::Skin, SoftTissue::Length { length: 0.004 }, &atlas);
    let judge = |c: &ChainInput| {
        let audit = audit_with(&atlas, c, &opts).unwrap();
        let length = opts
            .length_against(&atlas.tips, Finger::Index, &audit.segments)
            .unwrap();
        metacarpal(
            &atlas,
            &audit,
            length,
            "index_metacarpal_r",
            DVec3::ZERO,
            c.points[0],
        )
        .unwrap()
    };
    let at_mean = judge(&finger(mc));
    assert!((at_mean.length - length).abs() < 1e-12);
    assert!((at_mean.values[0].measured - x).abs() < 1e-9);
    assert!(
        (at_mean.values[0].mean - x).abs() < 1e-9,
        "the atlas mean, by hand"
    );
    assert_eq!(at_mean.standing, Standing::InRange);
    let moved = judge(&finger(mc + 0.010));
    // CMC and tip held, the atlas still puts the MCP where it was.
    assert!(
        (moved.expected - mc).abs() < 1e-9,
        "{} vs {mc}",
        moved.expected
    );
    assert!((moved.suggested.x - mc).abs() < 1e-9);
    let pi = moved.pi.unwrap();
    match moved.standing {
        Standing::Above { by } => {
            assert!((by - (mc + 0.010 - pi.high)).abs() < 1e-12);
            assert!(by > 0.0 && by < 0.010, "{by}");
        }
        s => panic!("expected too distal, got {s:?}"),
    }
    assert!(matches!(moved.values[0].standing, Standing::Above { .. }));
}

/// [`WristRatios::load`] against an independent reading of the atlas's
/// landmarks (split by hand here, not by the dataset reader): y = |landmark
/// 10 - MCP| / (J1 + J2 + J3) per X-ray, J along MCP, PIP, DIP, tip
/// (data/atlas/README.md). The published values were computed from the same
/// file with Python (statistics.mean / stdev, math.dist; scipy.stats.t.ppf
/// for the 95 % prediction interval, mean -/+ t sd sqrt(1 + 1/n)).
#[test]
fn wrist_ratios_are_the_atlas_means() {
    let path = std::path::Path::new("data/atlas/landmarks.csv");
    let Ok(text) = std::fs::read_to_string(path) else {
        crate::dataset::vendored::skip("data/atlas/landmarks.csv is not readable");
        return;
    };
    // (finger, MCP, PIP, DIP, tip, Python's mean, SD, 95 % prediction interval)
    let rays = [
        (
            Finger::Index,
            [21, 22, 23, 24],
            1.16467,
            0.04963,
            [1.0672, 1.2621],
        ),
        (
            Finger::Middle,
            [25, 26, 27, 28],
            0.98944,
            0.04095,
            [0.9090, 1.0698],
        ),
        (
            Finger::Ring,
            [29, 30, 31, 32],
            0.96133,
            0.03966,
            [0.8835, 1.0392],
        ),
        (
            Finger::Little,
            [33, 34, 35, 36],
            1.18625,
            0.05998,
            [1.0685, 1.3040],
        ),
    ];
    let mut samples: [Vec<f64>; 4] = Default::default();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap()).collect();
        let p = |i: usize| DVec3::new(v[1 + 2 * i], v[2 + 2 * i], 0.0);
        for (k, &(_, m, ..)) in rays.iter().enumerate() {
            let j =
                p(m[0]).distance(p(m[1])) + p(m[1]).distance(p(m[2])) + p(m[2]).distance(p(m[3]));
            samples[k].push(p(10).distance(p(m[0])) / j);
        }
    }
    let read = WristRatios::load(path).unwrap();
    assert_eq!(read.ratios.len(), 4);
    for (k, &(finger, _, published, published_sd, published_pi)) in rays.iter().enumerate() {
        let ys = &samples[k];
        let n = ys.len() as f64;
        assert_eq!(ys.len(), 910);
        let mean = ys.iter().sum::<f64>() / n;
        let sd = (ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let r = read.of(finger).unwrap();
        assert_eq!(r.n, 910);
        assert!(
            (r.mean - mean).abs() < 1e-12,
            "{finger:?}: {} vs {mean}",
            r.mean
        );
        assert!((r.sd - sd).abs() < 1e-12, "{finger:?}: {} vs {sd}", r.sd);
        assert_eq!((r.range.low, r.range.high), (lo, hi), "{finger:?}");
        assert!((mean - published).abs() < 5e-6, "{finger:?}: {mean}");
        assert!((sd - published_sd).abs() < 5e-6, "{finger:?}: {sd}");
        let pi = r.pi(0.95).unwrap();
        assert!(
            (pi.low - published_pi[0]).abs() < 5e-5 && (pi.high - published_pi[1]).abs() < 5e-5,
            "{finger:?}: {pi:?}"
        );
    }
    assert!(read.of(Finger::Thumb).is_none());
}

#[test]
fn standing_orders_range_then_prediction_then_outside() {
    let range = Interval::new(0.4, 0.5);
    let pi = Some(Interval::new(0.3, 0.6));
    assert_eq!(Standing::of(0.45, range, pi), Standing::InRange);
    assert_eq!(Standing::of(0.55, range, pi), Standing::InPrediction);
    match Standing::of(0.7, range, pi) {
        Standing::Above { by } => assert!((by - 0.1).abs() < 1e-12),
        s => panic!("{s:?}"),
    }
    match Standing::of(0.35, range, None) {
        Standing::Below { by } => assert!((by - 0.05).abs() < 1e-12),
        s => panic!("{s:?}"),
    }
}

#[test]
fn a_finger_with_the_paper_means_is_in_range_and_needs_no_move() {
    let a = paper();
    let f = a.finger(Finger::Index).unwrap();
    let m: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
        .iter()
        .map(|&q| f.quantity(q).unwrap().mean * 80.0)
        .collect();
    let r = audit_with(&a, &straight(Finger::Index, &m), &alike(&a)).unwrap();
    assert_eq!(r.basis, Basis::Relative);
    assert!(r.is_consistent());
    let kinds: Vec<Joint> = r.joints.iter().map(|j| j.joint).collect();
    assert_eq!(kinds, [Joint::Mcp, Joint::Pip, Joint::Dip, Joint::Tip]);
    for j in &r.joints {
        assert_eq!(j.standing, Standing::InRange);
        assert!(j.shift < 1e-9, "{j:?}");
        // MCP and tip: the mean's x / (1 - x) of the rest is the mean's own segment.
        assert!((j.measured - j.expected).abs() < 1e-9, "{j:?}");
    }
    assert!(r.explanation.consistent && r.explanation.moved.is_empty());
    // PIP at J~1 L = 0.4846 x 80 (the corrected eq. 6 mean).
    let pip = r.joint(Joint::Pip).unwrap();
    assert!((pip.expected - 0.4846 * 80.0).abs() < 0.01);
}

#[test]
fn a_pip_far_towards_the_tip_is_flagged_above_with_its_distance() {
    let a = paper();
    // J~1 = 0.6 of 100 units: the paper's index max is 0.5047.
    let r = audit_with(
        &a,
        &straight(Finger::Index, &[60.0, 22.0, 18.0]),
        &alike(&a),
    )
    .unwrap();
    let pip = r.joint(Joint::Pip).unwrap();
    let pi = pip.pi.unwrap();
    match pip.standing {
        Standing::Above { by } => assert!((by - (60.0 - pi.high)).abs() < 1e-9),
        s => panic!("{s:?}"),
    }
    assert!(!r.is_consistent());
    // One joint explains it: the PIP alone cannot fit as well (moved back to
    // fit J~1 it leaves J2 too long), the MCP moved towards the tip can, on
    // the (straight) chain; it goes where the finger is most likely given
    // the joints that stay (its best place on its line), not to the edge,
    // and that place lies inside the 50% region: sqrt(T^2 / bound) at most
    // sqrt(bound_50 / bound_95) = sqrt(2.3496 / 25.4723) = 0.3037 at n = 5,
    // p = 2 (scipy.stats.f.ppf(0.5, 2, 3) = 0.88111, f.ppf(0.95, 2, 3) = 9.5521).
    assert!(r.explanation.consistent, "{:?}", r.explanation);
    assert_eq!(r.explanation.moved, vec![Joint::Mcp], "{:?}", r.explanation);
    let mcp = r.joint(Joint::Mcp).unwrap();
    assert!(mcp.moves && mcp.shift_along > 0.0 && !pip.moves);
    assert!(mcp.held.is_none(), "{mcp:?}");
    assert!((mcp.suggested[0] - mcp.shift_along).abs() < 1e-9);
    let score = r.explanation.score.unwrap();
    assert!(score <= 0.3037, "{score}");
    // The best place: moving the MCP 0.2 units either way fits worse.
    for d in [-0.2, 0.2] {
        let at = mcp.shift_along + d;
        let moved = audit_with(
            &a,
            &straight(Finger::Index, &[60.0 - at, 22.0, 18.0]),
            &alike(&a),
        )
        .unwrap();
        let t2 = moved.region.as_ref().unwrap().t2;
        let bound = moved.region.as_ref().unwrap().bound;
        assert!((t2 / bound).sqrt() > score, "{d}: {t2}");
    }
}

#[test]
fn sharp_bends_keep_the_joints_in_order_or_decline() {
    // 120 degrees at each joint, segments 20, 40, 40 (a case a per-point
    // correction got out of order).
    let turn = |a: f64| DVec3::new(a.cos(), a.sin(), 0.0);
    let mut pts = vec![DVec3::ZERO];
    let mut dir = 0.0f64;
    for len in [20.0, 40.0, 40.0] {
        let p = *pts.last().unwrap();
        pts.push(p + len * turn(dir));
        dir += 120f64.to_radians();
    }
    let shares = [0.48, 0.29, 0.23];
    // A finger curled 60 degrees at each joint is solved exactly, in order.
    let mut bent = vec![DVec3::ZERO];
    let mut dir = 0.0f64;
    for len in [45.0, 28.0, 22.0] {
        let p = *bent.last().unwrap();
        bent.push(p + len * turn(dir));
        dir += 60f64.to_radians();
    }
    let (q, u) = on_chain(&bent, &shares).expect("a 60-degree curl is solvable");
    assert!(u[0] < u[1]);
    let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
    let total: f64 = c.iter().sum();
    for (ck, s) in c.iter().zip(shares) {
        assert!((ck / total - s).abs() < 1e-9, "{c:?}");
    }
    if let Some((q, u)) = on_chain(&pts, &shares) {
        assert!(u.windows(2).all(|w| w[0] <= w[1]), "{u:?}");
        let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = c.iter().sum();
        for (ck, s) in c.iter().zip(shares) {
            assert!((ck / total - s).abs() < 1e-9, "{c:?}");
        }
    }
    // Degenerate chains are declined, never a panic.
    assert!(on_chain(&[DVec3::ZERO; 4], &shares).is_none());
    assert!(
        on_chain(
            &[
                DVec3::new(f64::NAN, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(3.0, 0.0, 0.0)
            ],
            &shares
        )
        .is_none()
    );
    let a = paper();
    let nan = ChainInput {
        finger: Finger::Index,
        points: vec![
            DVec3::ZERO,
            DVec3::new(f64::INFINITY, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
        ],
        has_tip: true,
    };
    assert!(audit(&a, &nan).is_none());
    let zero = ChainInput {
        points: vec![
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
        ],
        ..nan
    };
    assert!(audit(&a, &zero).is_none());
}

#[test]
fn with_many_xrays_the_prediction_interval_decides() {
    // Range wider than the interval (large n): inside the range but outside the interval is outside.
    let range = Interval::new(0.3, 0.7);
    let pi = Some(Interval::new(0.45, 0.55));
    assert!(matches!(
        Standing::of(0.65, range, pi),
        Standing::Above { .. }
    ));
    assert_eq!(Standing::of(0.5, range, pi), Standing::InRange);
}

#[test]
fn without_a_tip_a_finger_is_judged_on_its_ratio_and_the_thumb_not_at_all() {
    let a = paper();
    let s = a
        .finger(Finger::Middle)
        .unwrap()
        .quantity(Quantity::RatioJ2J1)
        .unwrap();
    let chain = ChainInput {
        finger: Finger::Middle,
        points: vec![
            DVec3::ZERO,
            DVec3::new(0.0, 50.0, 0.0),
            DVec3::new(0.0, 50.0 + 50.0 * s.mean, 0.0),
        ],
        has_tip: false,
    };
    let r = audit(&a, &chain).unwrap();
    assert_eq!(r.basis, Basis::Ratio);
    assert_eq!(r.unjudged, vec![Joint::Dip]);
    assert!((r.values[0].measured - s.mean).abs() < 1e-12);
    assert!(r.joints.iter().all(|j| j.shift < 1e-9));
    // MCP at c1 - c2 / r: at the mean ratio exactly where it is.
    let mcp = r.joint(Joint::Mcp).unwrap();
    assert!(mcp.expected.abs() < 1e-9, "{mcp:?}");
    // A PIP too close to the root makes J2/J1 too large: flagged below.
    let close = ChainInput {
        points: vec![
            DVec3::ZERO,
            DVec3::new(0.0, 20.0, 0.0),
            DVec3::new(0.0, 80.0, 0.0),
        ],
        ..chain
    };
    let r = audit(&a, &close).unwrap();
    let pip = r.joint(Joint::Pip).unwrap();
    assert!(matches!(pip.standing, Standing::Below { .. }));
    assert!(matches!(r.values[0].standing, Standing::Above { .. }));
    assert!(pip.range.low < pip.range.high);
    // J2/J1 = 3: the X-rays put the MCP 60/0.64 = 94 back, so the rig's is far
    // towards the tip; but it may move at most one segment (20) back, so the
    // PIP alone explains it.
    let mcp = r.joint(Joint::Mcp).unwrap();
    assert!(matches!(mcp.standing, Standing::Above { .. }), "{mcp:?}");
    assert!(mcp.range.low < mcp.range.high);
    assert!((mcp.expected - (20.0 - 60.0 / s.mean)).abs() < 1e-9);
    assert_eq!(r.explanation.moved, vec![Joint::Pip]);
    assert!(r.explanation.also.is_empty());
    let thumb = ChainInput {
        finger: Finger::Thumb,
        points: vec![DVec3::ZERO, DVec3::new(1.0, 0.0, 0.0)],
        has_tip: false,
    };
    let r = audit(&a, &thumb).unwrap();
    assert_eq!(r.basis, Basis::None);
    assert!(r.joints.is_empty() && r.values.is_empty());
}

#[test]
fn a_skin_tip_is_compared_without_its_soft_tissue() {
    let a = paper_with_bone_tips();
    let f = a.finger(Finger::Index).unwrap();
    let m: Vec<f64> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
        .iter()
        .map(|&q| f.quantity(q).unwrap().mean * 80.0)
        .collect();
    // The X-ray mean finger with 4 units of soft tissue past the bone tip.
    let skin = [m[0], m[1], m[2] + 4.0];
    let opts = JudgeOptions::new(TipKind::Skin, SoftTissue::Length { length: 4.0 }, &a);
    let r = audit_with(&a, &straight(Finger::Index, &skin), &opts).unwrap();
    assert_eq!(r.tip_correction, 4.0);
    assert!((r.compared[2] - m[2]).abs() < 1e-12);
    assert!((r.length.unwrap() - 80.0).abs() < 1e-9);
    assert!(r.is_consistent() && r.explanation.moved.is_empty());
    // The tip stands where the X-rays put the bone tip plus the soft tissue: 84.
    let tip = r.joint(Joint::Tip).unwrap();
    assert!((tip.measured - 84.0).abs() < 1e-9 && (tip.expected - 84.0).abs() < 1e-9);
    // Read as a bone tip, the same rig's J~3 is too long.
    let r = audit_with(&a, &straight(Finger::Index, &skin), &alike(&a)).unwrap();
    assert_eq!(r.tip_correction, 0.0);
    assert!((r.values[2].measured - (m[2] + 4.0) / 84.0).abs() < 1e-12);
    // The paper's data (skin tips) and a skin tip: nothing to correct,
    // whatever figure is given; a bone tip gains the soft tissue.
    let p = paper();
    let both = JudgeOptions::new(TipKind::Skin, SoftTissue::Length { length: 4.0 }, &p);
    assert_eq!(both.data_tip, TipKind::Skin);
    assert_eq!(both.tip_correction(Finger::Index, 80.0), Some(0.0));
    let rig_bone = JudgeOptions::new(TipKind::Bone, SoftTissue::Length { length: 4.0 }, &p);
    assert_eq!(rig_bone.tip_correction(Finger::Index, 80.0), Some(-4.0));
    // Unlike tips and no figure: not judged, and said to lack it.
    let none = JudgeOptions::new(TipKind::Bone, SoftTissue::Unknown, &p);
    assert!(none.lacks_soft_tissue() && !both.lacks_soft_tissue());
    assert!(audit_with(&p, &straight(Finger::Index, &m), &none).is_none());
    assert!(audit(&p, &straight(Finger::Index, &m)).is_some());
}

/// The table's soft tissue as a share of the finger: a rig finger with
/// Buryanov & Kotiuk's mean index (Table I: proximal 39.78, middle 22.38,
/// distal 15.82, soft tissue 3.84 mm) to the skin, against bone-tip data, is
/// compared as their bone finger; to the bone, against skin-tip data, as their
/// finger to the skin. The same in any unit.
#[test]
fn the_table_soft_tissue_is_a_share_of_the_finger_in_any_unit() {
    let soft = table_soft_tissue();
    let bone_data = paper_with_bone_tips();
    let skin_data = paper();
    for scale in [1.0, 0.001, 1e-5] {
        let skin = [39.78 * scale, 22.38 * scale, (15.82 + 3.84) * scale];
        let opts = JudgeOptions::new(TipKind::Skin, soft.clone(), &bone_data);
        let r = audit_with(&bone_data, &straight(Finger::Index, &skin), &opts).unwrap();
        // 81.82 x 3.84 / 81.82 = 3.84, by hand.
        assert!((r.tip_correction - 3.84 * scale).abs() < 1e-12 * scale.max(1e-3));
        assert!((r.compared[2] - 15.82 * scale).abs() < 1e-9 * scale);
        assert!((r.values[2].measured - 15.82 / 77.98).abs() < 1e-12);
        let bone = [39.78 * scale, 22.38 * scale, 15.82 * scale];
        let opts = JudgeOptions::new(TipKind::Bone, soft.clone(), &skin_data);
        let r = audit_with(&skin_data, &straight(Finger::Index, &bone), &opts).unwrap();
        assert!((r.tip_correction + 3.84 * scale).abs() < 1e-12 * scale.max(1e-3));
        assert!((r.values[2].measured - 19.66 / 81.82).abs() < 1e-12);
    }
    // The thumb (distal 21.67, proximal 31.57, soft tissue 5.67): a share
    // 5.67 / 58.91 of a skin finger, by hand.
    let thumb = soft.of(Finger::Thumb).unwrap();
    assert!((thumb.share(TipKind::Skin) - 5.67 / 58.91).abs() < 1e-15);
    assert!((thumb.share(TipKind::Bone) - 5.67 / 53.24).abs() < 1e-15);
}

/// A rig in the wrong unit (a Mixamo Soldier 0.21 units tall: its fingers
/// a thousandth of a finger in metres) gets the same standings as the same
/// rig in metres when the soft tissue is the table's share; a fixed 4 mm
/// takes most of its last segment.
#[test]
fn a_rig_scaled_to_a_thousandth_stands_as_in_metres() {
    let a = paper_with_bone_tips();
    let soft = table_soft_tissue();
    // The WebXR hand's index, in metres, with its skin tip (README).
    let metres = [0.04191, 0.02430, 0.02271];
    let thousandth: Vec<f64> = metres.iter().map(|s| s / 1000.0).collect();
    let standings = |segs: &[f64], soft: &SoftTissue| {
        let opts = JudgeOptions::new(TipKind::Skin, soft.clone(), &a);
        let r = audit_with(&a, &straight(Finger::Index, segs), &opts)?;
        let kind = |s: Standing| std::mem::discriminant(&s);
        Some((
            r.values
                .iter()
                .map(|v| (v.measured, kind(v.standing)))
                .collect::<Vec<_>>(),
            r.joints
                .iter()
                .map(|j| kind(j.standing))
                .collect::<Vec<_>>(),
            r.explanation.moved,
        ))
    };
    let (v1, j1, m1) = standings(&metres, &soft).unwrap();
    let (v2, j2, m2) = standings(&thousandth, &soft).unwrap();
    for (x, y) in v1.iter().zip(&v2) {
        assert!((x.0 - y.0).abs() < 1e-12, "{x:?} {y:?}");
        assert_eq!(x.1, y.1);
    }
    assert_eq!((j1, m1), (j2, m2));
    // 4 mm of a 0.0227 mm segment: nothing is left to compare.
    let fixed = SoftTissue::Length { length: 0.004 };
    assert!(standings(&metres, &fixed).is_some());
    assert!(standings(&thousandth, &fixed).is_none());
}

#[test]
fn an_mcp_at_the_web_is_named_not_the_pip() {
    // X-ray 1b's index (Table 1, image units x 0.1 = mm-like units), with
    // its MCP 10 units towards the tip: J1 shrinks by 10, nothing else moves.
    let a = paper();
    let segs = [34.247 - 10.0, 19.524, 18.670];
    let r = audit_with(&a, &straight(Finger::Index, &segs), &alike(&a)).unwrap();
    assert!(!r.is_consistent());
    assert_eq!(r.explanation.moved, vec![Joint::Mcp], "{:?}", r.explanation);
    let mcp = r.joint(Joint::Mcp).unwrap();
    assert!(matches!(mcp.standing, Standing::Above { .. }), "{mcp:?}");
    // Moved back towards the root to its best place given the PIP, the DIP
    // and the tip: near the X-ray's own place, 10 units back (within 3: the
    // best place is where this finger's u is nearest the mean, not 1b's own),
    // and inside the 50% region (sqrt(T^2 / bound) <= 0.3037 at n = 5).
    assert!(
        mcp.moves && mcp.shift_along < -7.0 && mcp.shift_along > -13.0,
        "{mcp:?}"
    );
    assert!(!r.joint(Joint::Pip).unwrap().moves);
    assert!(
        r.explanation.score.is_some_and(|s| s <= 0.3037),
        "{:?}",
        r.explanation
    );
}

#[test]
fn pairs_move_to_the_means() {
    // PIP and DIP both far off: no single joint fits; the pair moves to the
    // placement at the means (MCP and tip held), the paper's rule: every
    // relative value is then its mean (share 1 of the way) and T^2 = 0.
    let a = paper();
    let before = [60.0, 10.0, 30.0];
    let r = audit_with(&a, &straight(Finger::Middle, &before), &alike(&a)).unwrap();
    assert_eq!(r.explanation.moved.len(), 2, "{:?}", r.explanation);
    assert!(
        r.explanation.score.is_some_and(|s| s < 1e-6),
        "{:?}",
        r.explanation
    );
    let f = a.finger(Finger::Middle).unwrap();
    let shares: Vec<f64> = r
        .explanation
        .values
        .iter()
        .filter(|v| v.quantity.is_relative())
        .map(|v| {
            let k = match v.quantity {
                Quantity::RelJ1 => 0,
                Quantity::RelJ2 => 1,
                _ => 2,
            };
            let x0 = before[k] / 100.0;
            let mean = f.quantity(v.quantity).unwrap().mean;
            (v.measured - x0) / (mean - x0)
        })
        .collect();
    assert_eq!(shares.len(), 3);
    for t in &shares {
        assert!((t - 1.0).abs() < 1e-6, "{shares:?}");
    }
}
