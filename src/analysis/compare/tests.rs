//! Comparison statistics against SciPy (tests/independent/atlas_reference.py) and by hand.

use super::*;
use crate::dataset::landmarks::{self, Layout};
use crate::dataset::vendored;
use crate::dataset::{Dataset, Finger};

fn settings(resamples: usize) -> Settings {
    Settings {
        resamples,
        seed: 7,
        confidence: 0.95,
    }
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got - want).abs() <= tol, "{what}: {got} vs {want}");
}

const A: [f64; 5] = [1.1, 2.3, 2.9, 3.4, 4.0];
const B: [f64; 8] = [2.0, 3.1, 3.5, 4.8, 5.2, 6.0, 6.1, 7.9];

#[test]
fn welch_hedges_and_coverage_match_scipy_on_small_cohorts() {
    let c = compare(&A, &B, &settings(2000), 0).unwrap();
    // By hand: mean A = 13.7 / 5 = 2.74, mean B = 38.6 / 8 = 4.825, difference 2.085.
    close(c.difference, 2.085, 1e-12, "difference");
    // Section 1 of atlas_reference.py: scipy.stats.ttest_ind(B, A, equal_var=False):
    // df 10.9945890164, confidence_interval(0.95) [0.2451850900, 3.9248149100].
    let w = c.welch.unwrap();
    close(w.df, 10.994_589_016_4, 1e-8, "welch df");
    close(w.interval.low, 0.245_185_090_0, 1e-8, "welch low");
    close(w.interval.high, 3.924_814_910_0, 1e-8, "welch high");
    // Hedges' g 1.1696415415, interval [-0.0347682776, 2.3740513606].
    let g = c.hedges_g.unwrap();
    close(g.g, 1.169_641_541_5, 1e-9, "g");
    close(g.interval.low, -0.034_768_277_6, 1e-8, "g low");
    close(g.interval.high, 2.374_051_360_6, 1e-8, "g high");
    // A's PI [-0.6372347751, 6.1172347751] holds 7 of B's 8 (not 7.9); B's holds all of A.
    let b_in_a = c.b_in_a.unwrap();
    close(b_in_a.interval.low, -0.637_234_775_1, 1e-8, "pi A low");
    close(b_in_a.interval.high, 6.117_234_775_1, 1e-8, "pi A high");
    assert_eq!((b_in_a.inside, b_in_a.of), (7, 8));
    close(b_in_a.share, 0.875, 1e-15, "share");
    let a_in_b = c.a_in_b.unwrap();
    close(a_in_b.interval.low, 0.055_439_670_6, 1e-8, "pi B low");
    assert_eq!((a_in_b.inside, a_in_b.of), (5, 5));
    assert!(c.notes.is_empty(), "{:?}", c.notes);
}

/// Section 2 of tests/independent/atlas_reference.py, as printed (SciPy 1.17).
const PAPER_VS_ATLAS: &str = "\
thumb rel_j1: diff 0.0448311764 welch df 4.076044 [0.0276254092, 0.0620369436] g 2.4592675965 [1.5731474873, 3.3453877057] b_in_a 398/910 a_in_b 1/5
thumb rel_j2: diff -0.0448311764 welch df 4.076044 [-0.0620369436, -0.0276254092] g -2.4592675965 [-3.3453877057, -1.5731474873] b_in_a 398/910 a_in_b 1/5
thumb tip offset: share_of_a 0.0777976343 share_of_bone 0.0843606970 in_a_units 40.4546142602 in_b_units 41.8311938779
index rel_j1: diff 0.0025437533 welch df 4.031524 [-0.0137588672, 0.0188463738] g 0.2283557599 [-0.6506337798, 1.1073452996] b_in_a 909/910 a_in_b 5/5
index rel_j2: diff 0.0217070152 welch df 4.243431 [0.0168544027, 0.0265596278] g 2.3617936873 [1.4762303663, 3.2473570083] b_in_a 119/910 a_in_b 1/5
index rel_j3: diff -0.0242507685 welch df 4.022087 [-0.0428415921, -0.0056599450] g -2.2778469171 [-3.1629484987, -1.3927453356] b_in_a 878/910 a_in_b 2/5
index tip offset: share_of_a 0.0310314030 share_of_bone 0.0320251895 in_a_units 23.4774905941 in_b_units 23.8524127754
middle rel_j1: diff 0.0131371992 welch df 4.038022 [-0.0009794917, 0.0272538901] g 1.2407560019 [0.3599922712, 2.1215197327] b_in_a 888/910 a_in_b 3/5
middle rel_j2: diff 0.0143965545 welch df 4.024076 [-0.0001995474, 0.0289926564] g 1.6502483135 [0.7680749604, 2.5324216665] b_in_a 905/910 a_in_b 3/5
middle rel_j3: diff -0.0275337537 welch df 4.066288 [-0.0371190799, -0.0179484275] g -2.9033762435 [-3.7923127963, -2.0144396907] b_in_a 314/910 a_in_b 0/5
middle tip offset: share_of_a 0.0346734029 share_of_bone 0.0359188310 in_a_units 29.9877085532 in_b_units 30.5121766535
ring rel_j1: diff 0.0125811523 welch df 4.055056 [0.0011599013, 0.0240024033] g 1.2213833543 [0.3406764658, 2.1020902428] b_in_a 852/910 a_in_b 3/5
ring rel_j2: diff 0.0189812858 welch df 4.046349 [0.0079062169, 0.0300563547] g 2.0705060734 [1.1864742712, 2.9545378757] b_in_a 736/910 a_in_b 3/5
ring rel_j3: diff -0.0315624381 welch df 4.056585 [-0.0420403634, -0.0210845128] g -3.2946654189 [-4.1864608709, -2.4028699669] b_in_a 244/910 a_in_b 0/5
ring tip offset: share_of_a 0.0404310497 share_of_bone 0.0421345956 in_a_units 33.8724056761 in_b_units 34.2588265009
little rel_j1: diff 0.0159563426 welch df 4.108482 [0.0040190559, 0.0278936293] g 1.0566144876 [0.1763550264, 1.9368739487] b_in_a 755/910 a_in_b 5/5
little rel_j2: diff 0.0126424061 welch df 4.136617 [0.0005336289, 0.0247511833] g 0.7355470375 [-0.1440260712, 1.6151201463] b_in_a 776/910 a_in_b 5/5
little rel_j3: diff -0.0285987487 welch df 4.084120 [-0.0420989981, -0.0150984993] g -1.9012229670 [-2.7844561557, -1.0179897782] b_in_a 595/910 a_in_b 3/5
little tip offset: share_of_a 0.0381362907 share_of_bone 0.0396483309 in_a_units 24.9287779428 in_b_units 25.0283394284
";

/// The values after `key ` in a reference line.
fn after(line: &str, key: &str) -> Vec<f64> {
    let rest = &line[line.find(&format!(" {key} ")).unwrap() + key.len() + 2..];
    let mut out = Vec::new();
    for tok in rest.split(' ') {
        let t = tok.trim_matches(|c| c == '[' || c == ']' || c == ',');
        let t = t.split('/').next().unwrap();
        match t.parse::<f64>() {
            Ok(v) => out.push(v),
            Err(_) => break,
        }
    }
    out
}

/// One finger of both cohorts: relative values (eq. 2) by segment, and mean totals.
type FingerData = (Finger, Vec<Vec<f64>>, Vec<Vec<f64>>, f64, f64);

/// Relative values (eq. 2) of each finger: the paper's X-rays, then the atlas's hands.
fn paper_and_atlas() -> Option<Vec<FingerData>> {
    let bytes = vendored::read(vendored::ATLAS_LANDMARKS)?;
    let atlas = landmarks::import(Layout::Atlas37, "atlas", &bytes, &Default::default()).unwrap();
    let paper = Dataset::load(std::path::Path::new("data/measurements.csv")).unwrap();
    let rel = |segs: &[f64]| -> Vec<f64> {
        let t: f64 = segs.iter().sum();
        segs.iter().map(|s| s / t).collect()
    };
    let columns = |rows: Vec<Vec<f64>>| -> Vec<Vec<f64>> {
        (0..rows[0].len())
            .map(|k| rows.iter().map(|r| r[k]).collect())
            .collect()
    };
    let mean = |xs: Vec<f64>| xs.iter().sum::<f64>() / xs.len() as f64;
    Some(
        Finger::ALL
            .into_iter()
            .map(|f| {
                let p: Vec<_> = paper.rows_of(f).map(|r| r.segments().to_vec()).collect();
                let a: Vec<_> = atlas
                    .rows
                    .iter()
                    .filter(|r| r.finger == f)
                    .map(|r| r.segments().to_vec())
                    .collect();
                let (tp, ta) = (
                    mean(p.iter().map(|s| s.iter().sum()).collect()),
                    mean(a.iter().map(|s| s.iter().sum()).collect()),
                );
                (
                    f,
                    columns(p.iter().map(|s| rel(s)).collect()),
                    columns(a.iter().map(|s| rel(s)).collect()),
                    tp,
                    ta,
                )
            })
            .collect(),
    )
}

#[test]
fn the_paper_against_the_atlas_matches_scipy() {
    let Some(data) = paper_and_atlas() else {
        return;
    };
    let mut checked = 0;
    for (f, paper, atlas, total_p, total_a) in &data {
        for (k, (a, b)) in paper.iter().zip(atlas).enumerate() {
            let head = format!("{} rel_j{}:", f.name(), k + 1);
            let line = PAPER_VS_ATLAS
                .lines()
                .find(|l| l.starts_with(&head))
                .unwrap();
            // One resample: the bootstrap is checked on its own below (and is slow in debug builds).
            let c = compare(a, b, &settings(1), k as u64).unwrap();
            close(c.difference, after(line, "diff")[0], 1e-9, &head);
            let w = after(line, "df");
            let welch = c.welch.unwrap();
            close(welch.df, w[0], 1e-6, &head);
            close(welch.interval.low, w[1], 1e-9, &head);
            close(welch.interval.high, w[2], 1e-9, &head);
            let g = after(line, "g");
            let hg = c.hedges_g.unwrap();
            close(hg.g, g[0], 1e-8, &head);
            close(hg.interval.low, g[1], 1e-8, &head);
            close(hg.interval.high, g[2], 1e-8, &head);
            let b_in_a = c.b_in_a.unwrap();
            let a_in_b = c.a_in_b.unwrap();
            let counts = |key: &str| {
                let rest = &line[line.find(key).unwrap() + key.len() + 1..];
                let t = rest.split(' ').next().unwrap();
                let (i, n) = t.split_once('/').unwrap();
                (i.parse::<usize>().unwrap(), n.parse::<usize>().unwrap())
            };
            assert_eq!((b_in_a.inside, b_in_a.of), counts("b_in_a"), "{head}");
            assert_eq!((a_in_b.inside, a_in_b.of), counts("a_in_b"), "{head}");
            checked += 1;
        }
        let last = paper.len() - 1;
        let mean = |xs: &[f64]| xs.iter().sum::<f64>() / xs.len() as f64;
        let t =
            soft_tissue_offset(mean(&paper[last]), mean(&atlas[last]), *total_p, *total_a).unwrap();
        let line = PAPER_VS_ATLAS
            .lines()
            .find(|l| l.starts_with(&format!("{} tip offset:", f.name())))
            .unwrap();
        close(
            t.share_of_a,
            after(line, "share_of_a")[0],
            1e-9,
            "share_of_a",
        );
        close(
            t.share_of_bone,
            after(line, "share_of_bone")[0],
            1e-9,
            "share_of_bone",
        );
        close(
            t.in_a_units,
            after(line, "in_a_units")[0],
            1e-7,
            "in_a_units",
        );
        close(
            t.in_b_units,
            after(line, "in_b_units")[0],
            1e-7,
            "in_b_units",
        );
    }
    assert_eq!(checked, 14);
}

#[test]
fn the_tip_offset_undoes_a_known_extension() {
    // A bone finger of 100 with a last segment of 20 (r_B = 0.2), its tip moved out by 5:
    // the last segment is 25 of 105 (r_A = 25/105). The offset found is the 5 put in.
    let t = soft_tissue_offset(25.0 / 105.0, 0.2, 105.0, 100.0).unwrap();
    close(t.share_of_a, 5.0 / 105.0, 1e-15, "share_of_a");
    close(t.share_of_bone, 0.05, 1e-15, "share_of_bone");
    close(t.in_a_units, 5.0, 1e-12, "in_a_units");
    close(t.in_b_units, 5.0, 1e-12, "in_b_units");
    // A shorter last segment in A: a negative offset.
    assert!(
        soft_tissue_offset(0.19, 0.2, 100.0, 100.0)
            .unwrap()
            .share_of_a
            < 0.0
    );
    assert!(soft_tissue_offset(1.0, 0.2, 100.0, 100.0).is_none());
    assert!(soft_tissue_offset(0.2, 0.2, 0.0, 100.0).is_none());
    assert!(soft_tissue_offset(f64::NAN, 0.2, 1.0, 1.0).is_none());
}

#[test]
fn the_bootstrap_interval_has_the_width_theory_gives_and_is_seeded() {
    // Two deterministic samples of 100: the bootstrap SD of the difference of means is
    // sqrt(v_A / n_A + v_B / n_B) with population (1/n) variances, so the 95% percentile
    // interval is about 2 * 1.96 times it wide (2000 resamples: within 8%).
    let a: Vec<f64> = (0..100).map(|i| ((i * 37) % 101) as f64 / 10.0).collect();
    let b: Vec<f64> = (0..100)
        .map(|i| 3.0 + ((i * 53) % 89) as f64 / 7.0)
        .collect();
    let pv = |xs: &[f64]| {
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / xs.len() as f64
    };
    let sd = (pv(&a) / 100.0 + pv(&b) / 100.0).sqrt();
    let i = bootstrap_difference(&a, &b, 2000, 1, 0, 0.95).unwrap();
    let ratio = i.width() / (2.0 * 1.959_964 * sd);
    assert!((ratio - 1.0).abs() < 0.08, "{ratio}");
    let d = b.iter().sum::<f64>() / 100.0 - a.iter().sum::<f64>() / 100.0;
    assert!(i.contains(d));
    let run = |threads: usize, seed: u64| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| bootstrap_difference(&a, &b, 300, seed, 3, 0.95))
    };
    assert_eq!(run(1, 9), run(3, 9));
    assert_ne!(run(1, 9), run(1, 10));
    assert_ne!(run(1, 9), bootstrap_difference(&a, &b, 300, 9, 4, 0.95));
}

#[test]
fn degenerate_cohorts_leave_notes_not_numbers() {
    let c = compare(&[1.0], &B, &settings(100), 0).unwrap();
    assert!(c.welch.is_none() && c.hedges_g.is_none() && c.b_in_a.is_none());
    assert!(c.a_in_b.is_some());
    assert!(
        c.notes[0].contains("cohort A has one X-ray"),
        "{:?}",
        c.notes
    );
    let c = compare(&[2.0, 2.0], &[3.0, 3.0, 3.0], &settings(100), 0).unwrap();
    assert!(c.welch.is_none() && c.hedges_g.is_none());
    assert_eq!(c.notes.len(), 3, "{:?}", c.notes);
    assert_eq!(c.bootstrap, Interval::new(1.0, 1.0));
    assert!(compare(&[], &B, &settings(100), 0).is_none());
    assert!(compare(&A, &[1.0, f64::NAN], &settings(100), 0).is_none());
    // Large df: the expansion takes over from statrs without a jump.
    let big: Vec<f64> = (0..3000).map(|i| (i % 17) as f64).collect();
    let w = welch(&Cohort::of(&big).unwrap(), &Cohort::of(&big).unwrap(), 0.95).unwrap();
    assert!(w.df > 1000.0);
    close(w.interval.high / w.se, 1.960_9, 1e-3, "t at ~6000 df");
}

#[test]
fn quantities_of_the_same_x_rays_share_the_resamples() {
    // Columns: A's values, their squares, and a constant; B likewise. Each column's
    // interval is bit for bit the one it gets alone: the draws do not depend on the columns.
    let sq = |xs: &[f64]| xs.iter().map(|x| x * x).collect::<Vec<f64>>();
    let (a2, b2) = (sq(&A), sq(&B));
    let (a3, b3) = ([1.0; 5], [2.0; 8]);
    let all = compare_all(&[&A, &a2, &a3], &[&B, &b2, &b3], &settings(500), 4).unwrap();
    assert_eq!(all.len(), 3);
    assert_eq!(all[0], compare(&A, &B, &settings(500), 4).unwrap());
    assert_eq!(all[1], compare(&a2, &b2, &settings(500), 4).unwrap());
    assert_eq!(all[2].bootstrap, Interval::new(1.0, 1.0));
    assert!(compare_all(&[&A, &A[..4]], &[&B, &B], &settings(10), 0).is_none());
    assert!(compare_all(&[&A], &[&B, &B], &settings(10), 0).is_none());
    assert!(compare_all(&[], &[], &settings(10), 0).is_none());
    let threads = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| bootstrap_differences(&[&A, &a2], &[&B, &b2], 700, 5, 1, 0.9))
    };
    assert_eq!(threads(1), threads(3));
}

#[test]
fn datasets_compared_finger_by_finger_match_scipy() {
    // data/atlas/measurements.csv (lengths to 6 decimals) against the paper, through
    // cohorts(): the same values as section 2 of atlas_reference.py, from raw coordinates.
    let Some(atlas) = vendored::atlas() else {
        return;
    };
    let paper = Dataset::load(std::path::Path::new("data/measurements.csv")).unwrap();
    let c = cohorts(&paper, &atlas, &settings(200));
    assert_eq!((c.a.xrays, c.b.xrays), (5, 910));
    assert_eq!(c.b.unit.as_deref(), Some("px"));
    assert_eq!(c.b.tips.single(), Some(TipKind::Bone));
    assert_eq!(c.fingers.len(), 5);
    // Not compared: the total (image units against px) and the metacarpal (paper: none).
    assert!(
        c.notes.iter().any(|n| n.starts_with("J (total length)")),
        "{:?}",
        c.notes
    );
    assert!(
        c.notes.iter().any(|n| n.starts_with("mc/J and J1/mc")),
        "{:?}",
        c.notes
    );
    for f in &c.fingers {
        assert_eq!((f.n_a, f.n_b), (5, 910));
        let rel: Vec<&QuantityComparison> = f
            .quantities
            .iter()
            .filter(|q| q.quantity.is_relative())
            .collect();
        assert_eq!(rel.len(), f.finger.segments());
        assert!(
            f.quantities
                .iter()
                .all(|q| q.quantity != Quantity::Total && !q.quantity.needs_mc())
        );
        for q in rel {
            let head = format!("{} {}:", f.finger.name(), q.quantity.name());
            let line = PAPER_VS_ATLAS
                .lines()
                .find(|l| l.starts_with(&head))
                .unwrap();
            let w = after(line, "df");
            let welch = q.comparison.welch.unwrap();
            close(welch.interval.low, w[1], 1e-8, &head);
            close(welch.interval.high, w[2], 1e-8, &head);
            let share = |key: &str| {
                let rest = &line[line.find(key).unwrap() + key.len() + 1..];
                let (i, n) = rest.split(' ').next().unwrap().split_once('/').unwrap();
                i.parse::<f64>().unwrap() / n.parse::<f64>().unwrap()
            };
            close(
                q.comparison.b_in_a.unwrap().share,
                share("b_in_a"),
                1e-12,
                &head,
            );
            close(
                q.comparison.a_in_b.unwrap().share,
                share("a_in_b"),
                1e-12,
                &head,
            );
            assert!(
                q.comparison.bootstrap.contains(q.comparison.difference),
                "{head}"
            );
        }
        // The atlas records bone tips and the paper none: the paper is taken as measured
        // to the skin, and the offset is section 2's.
        let last = f.last_segment.as_ref().unwrap();
        assert_eq!((last.skin, last.basis), ("a", TipBasis::Recorded));
        let line = PAPER_VS_ATLAS
            .lines()
            .find(|l| l.starts_with(&format!("{} tip offset:", f.finger.name())))
            .unwrap();
        close(
            last.offset.share_of_a,
            after(line, "share_of_a")[0],
            1e-8,
            "share_of_a",
        );
    }
    // One bootstrap for the five fingers (same X-rays in each cohort): each quantity's
    // interval is the one it gets alone under the thumb's key.
    let index = c.fingers[1].quantity(Quantity::RelJ2).unwrap();
    let col = |d: &Dataset| -> Vec<f64> {
        d.rows_of(Finger::Index)
            .map(|r| r.lengths[1] / r.total())
            .collect()
    };
    let alone = bootstrap_difference(&col(&paper), &col(&atlas), 200, 7, 0, 0.95).unwrap();
    assert_eq!(index.bootstrap, alone);
}
