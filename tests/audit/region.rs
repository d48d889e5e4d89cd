//! The joint region as the finger's verdict: T^2 of a rig finger's relative
//! joint positions, computed here from the paper's X-rays with the test's own
//! arithmetic, is the audit's, and the audit's verdict, its count and its
//! explanation follow it.

use super::hand::{HandSpec, Naming, build};
use super::{audit_json, fingers};
use crate::common::*;
use serde_json::Value;

/// The paper's X-rays of `finger` (data/measurements.csv, Table 1), as
/// relative joint positions u = (J~1, J~1 + J~2), or (J~1) for the thumb.
fn reference(finger: &str) -> Vec<Vec<f64>> {
    let text = String::from_utf8(paper_data()).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some(finger))
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let j: Vec<f64> = f[2..5]
                .iter()
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect();
            positions(&j)
        })
        .collect()
}

fn positions(segments: &[f64]) -> Vec<f64> {
    let total: f64 = segments.iter().sum();
    let mut run = 0.0;
    segments[..segments.len() - 1]
        .iter()
        .map(|s| {
            run += s;
            run / total
        })
        .collect()
}

/// T^2 of `u` against the reference hands: (u - mean)' [S (1 + 1/n)]^-1
/// (u - mean), the 2 x 2 inverse written out (or the 1 x 1).
fn t2(hands: &[Vec<f64>], u: &[f64]) -> f64 {
    let n = hands.len() as f64;
    let p = u.len();
    let mean: Vec<f64> = (0..p)
        .map(|k| hands.iter().map(|h| h[k]).sum::<f64>() / n)
        .collect();
    let c = |a: usize, b: usize| {
        hands
            .iter()
            .map(|h| (h[a] - mean[a]) * (h[b] - mean[b]))
            .sum::<f64>()
            / (n - 1.0)
            * (1.0 + 1.0 / n)
    };
    let d: Vec<f64> = u.iter().zip(&mean).map(|(x, m)| x - m).collect();
    if p == 1 {
        return d[0] * d[0] / c(0, 0);
    }
    let (a, b, e) = (c(0, 0), c(0, 1), c(1, 1));
    (e * d[0] * d[0] - 2.0 * b * d[0] * d[1] + a * d[1] * d[1]) / (a * e - b * b)
}

/// The 95% bounds at n = 5: 2 * 4 / 3 * F(0.95; 2, 3) = 25.4723 for a finger
/// and t(0.975; 4)^2 = 7.7086 for the thumb (scipy.stats.f.ppf(0.95, 2, 3) =
/// 9.5521, scipy.stats.t.ppf(0.975, 4) = 2.7764).
fn bound(finger: &str) -> f64 {
    if finger == "thumb" { 7.7086 } else { 25.4723 }
}

fn check(doc: &Value) {
    let mut outside = 0;
    for f in fingers(doc) {
        let name = f["finger"].as_str().unwrap();
        let audit = &f["audit"];
        let region = &audit["region"];
        let compared: Vec<f64> = audit["compared"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let expected = t2(&reference(name), &positions(&compared));
        let got = region["t2"].as_f64().unwrap();
        assert!(
            (got - expected).abs() < 1e-9 * expected.max(1.0),
            "{name}: T^2 {got}, by hand {expected}"
        );
        assert!((region["bound"].as_f64().unwrap() - bound(name)).abs() < 1e-4);
        let inside = expected <= bound(name);
        assert_eq!(region["inside"], inside, "{name}");
        outside += usize::from(!inside);
        // The explanation keeps a finger inside and moves something in one outside.
        let e = &audit["explanation"];
        let keeps = e["moved"].as_array().unwrap().is_empty() && e["consistent"] == true;
        assert_eq!(keeps, inside, "{name}: {e}");
        if let Some(score) = e["score"].as_f64()
            && keeps
        {
            let b = region["bound"].as_f64().unwrap();
            assert!((score - (expected / b).sqrt()).abs() < 1e-9, "{name}");
        }
    }
    assert_eq!(doc["fingers_outside"], outside);
}

#[test]
fn the_verdict_is_the_joint_region_computed_by_hand() {
    let wd = Workdir::with_paper_data();
    // A built hand with its index PIP 3 mm off (T^2 far above 25.5), and the
    // vendored WebXR hand, whose fingers stand inside and outside.
    let mut spec = HandSpec::new(Naming::Mixamo).moved("index", 1, 0.3);
    // A skin that bends at each joint: the moves its weights can follow.
    spec.smooth = Some(Vec::new());
    wd.write("hand.glb", build(&spec));
    let doc = audit_json(&wd, "hand.glb");
    let index = fingers(&doc)
        .iter()
        .find(|f| f["finger"] == "index")
        .unwrap();
    assert!(index["audit"]["region"]["t2"].as_f64().unwrap() > 50.0);
    assert_eq!(
        index["audit"]["explanation"]["moved"],
        serde_json::json!(["PIP"])
    );
    check(&doc);
    wd.write(
        "webxr.glb",
        std::fs::read(manifest_dir().join("data/rigs/webxr-generic-hand/right.glb")).unwrap(),
    );
    check(&audit_json(&wd, "webxr.glb"));
}
