//! `phalanx stats` through the binary: the JSON document's schema and values,
//! reproducibility (seeds, thread counts), scale invariance and the CSV export.

use crate::common;

use common::*;
use serde_json::Value;

/// SHA-256 of the shipped data/measurements.csv, as printed by
/// `sha256sum data/measurements.csv` (a change of Table 1 must be deliberate).
const PAPER_SHA256: &str = "4613281c408387af469c7a86cecea68af5aa0fa1765dff774be7dc8538219c64";

const FINGERS: [&str; 5] = ["thumb", "index", "middle", "ring", "little"];
const INTERVALS: [&str; 4] = ["ci_t", "ci_percentile", "ci_bca", "pi"];

/// `stats --format json` on the shipped data, run from a copy of `data/`.
fn paper_stats(extra: &[&str]) -> (Workdir, Value) {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let mut args = vec!["stats", "--format", "json"];
    args.extend(extra);
    let doc = wd.run(&args).ok().json();
    (wd, doc)
}

/// Asserts `obj` is an object holding every key of `keys`.
#[track_caller]
fn has_keys(obj: &Value, keys: &[&str], what: &str) {
    let map = obj
        .as_object()
        .unwrap_or_else(|| panic!("{what} is not an object: {obj}"));
    for k in keys {
        assert!(map.contains_key(*k), "{what} lacks key {k:?}: {obj}");
    }
}

/// Asserts `v` is null or a 2-element array [low, high] with low <= high.
#[track_caller]
fn interval_or_null(v: &Value, what: &str) -> Option<(f64, f64)> {
    if v.is_null() {
        return None;
    }
    let (lo, hi) = interval(v);
    assert!(lo <= hi, "{what}: low {lo} > high {hi}");
    Some((lo, hi))
}

#[test]
fn json_has_the_documented_schema() {
    let (wd, doc) = paper_stats(&[]);
    has_keys(
        &doc,
        &["schema_version", "dataset", "settings", "fingers"],
        "document",
    );
    assert_eq!(doc["schema_version"], 6);

    has_keys(
        &doc["dataset"],
        &["path", "sha256", "xrays", "rows"],
        "dataset",
    );
    assert_eq!(doc["dataset"]["path"], "data/measurements.csv");
    assert_eq!(doc["dataset"]["xrays"], 5);
    assert_eq!(doc["dataset"]["rows"], 25);
    let sha = doc["dataset"]["sha256"].as_str().unwrap();
    assert_eq!(sha, sha256sum(&wd.path().join("data/measurements.csv")));
    assert_eq!(sha, PAPER_SHA256);

    let s = &doc["settings"];
    has_keys(
        s,
        &["resamples", "seed", "confidence", "rng", "phalanx_version"],
        "settings",
    );
    assert_eq!(s["resamples"], 10000);
    assert_eq!(s["seed"], 20130101u64);
    assert_eq!(s["confidence"], 0.95);
    assert!(
        s["rng"].as_str().is_some_and(|r| r.contains("ChaCha")),
        "{s}"
    );
    assert_eq!(s["phalanx_version"], env!("CARGO_PKG_VERSION"));

    let fingers = doc["fingers"].as_array().unwrap();
    let names: Vec<&str> = fingers
        .iter()
        .map(|f| f["finger"].as_str().unwrap())
        .collect();
    assert_eq!(names, FINGERS);
    let paper = paper_rows();
    for f in fingers {
        let name = f["finger"].as_str().unwrap();
        has_keys(f, &["finger", "n", "xrays", "quantities"], name);
        assert_eq!(f["n"], 5, "{name}");
        let segments = if name == "thumb" { 2 } else { 3 };

        // Per X-ray values: the file's lengths, their sum and the ratios (eqs. 1-2).
        let xrays = f["xrays"].as_array().unwrap();
        assert_eq!(xrays.len(), 5, "{name}");
        for x in xrays {
            has_keys(x, &["xray", "lengths", "total", "relative"], name);
            let id = x["xray"].as_str().unwrap();
            let want = paper
                .iter()
                .find(|r| r.finger == name && r.xray == id)
                .unwrap_or_else(|| panic!("{name} {id} is not in the data"));
            let lengths: Vec<f64> = x["lengths"].as_array().unwrap().iter().map(num).collect();
            assert_eq!(lengths.len(), want.lengths.len(), "{name} {id}");
            for (got, want) in lengths.iter().zip(&want.lengths) {
                // serde_json parses floats to within 1 ulp (no float_roundtrip).
                assert_rel(*got, *want, 1e-15, &format!("{name} {id} length"));
            }
            assert_eq!(lengths.len(), segments);
            let total: f64 = lengths.iter().sum();
            assert_close(num(&x["total"]), total, 1e-9, "total");
            let rel: Vec<f64> = x["relative"].as_array().unwrap().iter().map(num).collect();
            assert_eq!(rel.len(), segments);
            for (r, l) in rel.iter().zip(&lengths) {
                assert_close(*r, l / total, 1e-15, "relative");
            }
        }

        // Statistics: the thumb has no J3.
        let qs = f["quantities"].as_array().unwrap();
        let qnames: Vec<&str> = qs.iter().map(|q| q["name"].as_str().unwrap()).collect();
        if name == "thumb" {
            assert_eq!(qnames, ["rel_j1", "rel_j2", "ratio_j2_j1", "total"]);
        } else {
            assert_eq!(
                qnames,
                [
                    "rel_j1",
                    "rel_j2",
                    "rel_j3",
                    "ratio_j2_j1",
                    "ratio_j3_j2",
                    "total"
                ],
                "{name}"
            );
        }
        for q in qs {
            let what = format!("{name} {}", q["name"]);
            has_keys(
                q,
                &[
                    "name",
                    "n",
                    "mean",
                    "sd",
                    "se",
                    "median",
                    "min",
                    "max",
                    "range",
                    "cv",
                    "ci_t",
                    "ci_percentile",
                    "ci_bca",
                    "pi",
                ],
                &what,
            );
            assert_eq!(q["n"], 5, "{what}");
            let (mean, sd, se) = (num(&q["mean"]), num(&q["sd"]), num(&q["se"]));
            let (min, max, median) = (num(&q["min"]), num(&q["max"]), num(&q["median"]));
            assert!(min <= median && median <= max, "{what}");
            assert!(min < mean && mean < max, "{what}");
            assert_close(num(&q["range"]), max - min, 1e-12, &what);
            assert_rel(se, sd / 5f64.sqrt(), 1e-12, &what);
            assert_rel(num(&q["cv"]), sd / mean, 1e-12, &what);
            for k in INTERVALS {
                let (lo, hi) = interval_or_null(&q[k], &what)
                    .unwrap_or_else(|| panic!("{what}: {k} is null for n = 5"));
                assert!(
                    lo < mean && mean < hi,
                    "{what} {k} [{lo}, {hi}] misses {mean}"
                );
            }
            // The prediction interval is wider than the t interval of the mean.
            let (tl, th) = interval(&q["ci_t"]);
            let (pl, ph) = interval(&q["pi"]);
            assert!(pl < tl && th < ph, "{what}");
        }
        // The relative values of a finger add up to 1, and so do their means.
        let rel_mean_sum: f64 = qs
            .iter()
            .filter(|q| q["name"].as_str().is_some_and(|n| n.starts_with("rel_")))
            .map(|q| num(&q["mean"]))
            .sum();
        assert_close(rel_mean_sum, 1.0, 1e-12, name);
    }
}

#[test]
fn index_rel_j1_agrees_with_independent_reference_values() {
    let (_wd, doc) = paper_stats(&[]);
    let q = quantity(&doc, "index", "rel_j1");
    // tests/independent/reference_values.py (NumPy mean, std(ddof=1);
    // scipy.stats.t.ppf(0.975, 4) for the t and prediction intervals).
    assert_close(num(&q["mean"]), 0.484_636, 1e-6, "mean");
    assert_close(num(&q["sd"]), 0.013_144, 1e-6, "sd");
    let (lo, hi) = interval(&q["ci_t"]);
    assert_close(lo, 0.468_315, 1e-6, "ci_t low");
    assert_close(hi, 0.500_957, 1e-6, "ci_t high");
    let (lo, hi) = interval(&q["pi"]);
    assert_close(lo, 0.444_658, 1e-6, "pi low");
    assert_close(hi, 0.524_614, 1e-6, "pi high");
    // The paper's eq. (8): max 0.5047, min 0.4728.
    assert_close(num(&q["max"]), 0.504_712, 1e-6, "max");
    assert_close(num(&q["min"]), 0.472_757, 1e-6, "min");
    // Table 1, index finger of X-ray 1a: 339.96 + 188.83 + 169.67 = 698.46.
    let x1a = &finger(&doc, "index")["xrays"][0];
    assert_eq!(x1a["xray"], "1a");
    assert_close(num(&x1a["total"]), 698.46, 1e-9, "1a total");
}

#[test]
fn confidence_option_changes_every_interval() {
    let (_wd, doc) = paper_stats(&["--confidence", "0.9"]);
    assert_eq!(doc["settings"]["confidence"], 0.9);
    let q = quantity(&doc, "index", "rel_j1");
    // scipy: mean -/+ stats.t.ppf(0.95, 4) * sd / sqrt(5).
    let (lo, hi) = interval(&q["ci_t"]);
    assert_close(lo, 0.472_104, 1e-6, "90% ci_t low");
    assert_close(hi, 0.497_168, 1e-6, "90% ci_t high");
    let (_wd, wide) = paper_stats(&[]);
    let w = quantity(&wide, "index", "rel_j1");
    for k in INTERVALS {
        let (a, b) = interval(&q[k]);
        let (c, d) = interval(&w[k]);
        assert!(
            c <= a && b <= d,
            "90% {k} [{a}, {b}] not inside 95% [{c}, {d}]"
        );
        assert!(b - a < d - c, "{k}: 90% is not narrower");
    }
}

#[test]
fn same_seed_gives_byte_identical_json() {
    for extra in [&["--resamples", "100", "--seed", "42"][..], &[]] {
        let wd = Workdir::new();
        wd.copy_paper_data();
        let mut args = vec!["stats", "--format", "json"];
        args.extend(extra);
        let a = wd.run(&args).ok().stdout_bytes.clone();
        let b = wd.run(&args).ok().stdout_bytes.clone();
        assert!(!a.is_empty());
        assert_eq!(a, b, "two runs of {args:?} differ");
    }
}

/// `stats --format json` on the shipped data with a seed and resamples.
fn seeded(seed: &str, resamples: Option<&str>) -> Value {
    let mut extra = vec!["--seed", seed];
    if let Some(r) = resamples {
        extra.extend(["--resamples", r]);
    }
    paper_stats(&extra).1
}

#[test]
fn random_bootstrap_depends_on_the_seed() {
    // 100 < 126 distinct resamples of n = 5: a random bootstrap.
    let a = seeded("1", Some("100"));
    let b = seeded("2", Some("100"));
    for doc in [&a, &b] {
        for f in FINGERS {
            assert_eq!(
                finger(doc, f)["bootstrap"],
                serde_json::json!({"method": "random", "resamples": 100}),
                "{f}"
            );
        }
    }
    let mut differing = 0;
    for f in FINGERS {
        for q in finger(&a, f)["quantities"].as_array().unwrap() {
            let name = q["name"].as_str().unwrap();
            let other = quantity(&b, f, name);
            // The t interval and the descriptive statistics do not use the bootstrap.
            for k in ["mean", "sd", "ci_t", "pi"] {
                assert_eq!(q[k], other[k], "{f} {name} {k}");
            }
            if q["ci_percentile"] != other["ci_percentile"] && q["ci_bca"] != other["ci_bca"] {
                differing += 1;
            }
        }
    }
    let q = quantity(&a, "index", "rel_j1");
    let other = quantity(&b, "index", "rel_j1");
    assert_ne!(q["ci_percentile"], other["ci_percentile"]);
    assert_ne!(q["ci_bca"], other["ci_bca"]);
    assert!(
        differing >= 15,
        "only {differing} of 19 quantities changed with the seed"
    );
}

#[test]
fn exact_bootstrap_ignores_the_seed() {
    let a = seeded("1", None);
    let b = seeded("987654321", None);
    assert_eq!(a["settings"]["seed"], 1);
    assert_eq!(b["settings"]["seed"], 987654321);
    for f in FINGERS {
        let boot = &finger(&a, f)["bootstrap"];
        assert_eq!(boot["method"], "exact", "{f}");
        assert_eq!(boot["distinct"], 126, "{f}");
    }
    assert_eq!(a["fingers"], b["fingers"]);
    // 126 resamples asked for is enough for exact enumeration, 125 is not.
    let at = seeded("1", Some("126"));
    assert_eq!(finger(&at, "index")["bootstrap"]["method"], "exact");
    assert_eq!(at["fingers"], a["fingers"]);
    let below = seeded("1", Some("125"));
    assert_eq!(finger(&below, "index")["bootstrap"]["method"], "random");
}

/// A measurement file of `n` X-rays with varied lengths (deterministic).
fn many_xrays(n: usize) -> String {
    let mut out = format!("{HEADER}\n");
    let mut x: u64 = 12345;
    let mut next = || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (x >> 33) as f64 / (1u64 << 31) as f64 // in [0, 1)
    };
    for i in 0..n {
        for (f, base) in [
            ("thumb", [270.0, 240.0, 0.0]),
            ("index", [360.0, 205.0, 180.0]),
            ("middle", [400.0, 255.0, 200.0]),
            ("ring", [380.0, 240.0, 210.0]),
            ("little", [300.0, 170.0, 180.0]),
        ] {
            let l: Vec<String> = base
                .iter()
                .take(if f == "thumb" { 2 } else { 3 })
                .map(|b| format!("{:.2}", b * (0.85 + 0.3 * next())))
                .collect();
            let j3 = l.get(2).cloned().unwrap_or_default();
            out.push_str(&format!("x{i:02},{f},{},{},{j3}\n", l[0], l[1]));
        }
    }
    out
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let wd = Workdir::new();
    wd.write("big.csv", many_xrays(30));
    let args = [
        "stats",
        "--data",
        "big.csv",
        "--format",
        "json",
        "--resamples",
        "2000",
    ];
    let one = wd.run_env(&args, &[("RAYON_NUM_THREADS", "1")]);
    let two = wd.run_env(&args, &[("RAYON_NUM_THREADS", "2")]);
    let three = wd.run_env(&args, &[("RAYON_NUM_THREADS", "3")]);
    let doc = one.ok().json();
    assert_eq!(doc["dataset"]["xrays"], 30);
    for f in FINGERS {
        assert_eq!(finger(&doc, f)["n"], 30);
        assert_eq!(
            finger(&doc, f)["bootstrap"],
            serde_json::json!({"method": "random", "resamples": 2000})
        );
    }
    assert_eq!(one.stdout, two.ok().stdout, "1 vs 2 threads");
    assert_eq!(one.stdout, three.ok().stdout, "1 vs 3 threads");

    // The coverage simulation too.
    let args = [
        "coverage",
        "--data",
        "big.csv",
        "--format",
        "json",
        "--sims",
        "50",
        "--resamples",
        "200",
    ];
    let one = wd.run_env(&args, &[("RAYON_NUM_THREADS", "1")]);
    let two = wd.run_env(&args, &[("RAYON_NUM_THREADS", "2")]);
    assert_eq!(one.ok().stdout, two.ok().stdout, "coverage: 1 vs 2 threads");
}

#[test]
fn relative_statistics_are_scale_invariant() {
    const K: f64 = 2.54;
    let wd = Workdir::new();
    let scaled: Vec<PaperRow> = paper_rows()
        .into_iter()
        .map(|mut r| {
            r.lengths.iter_mut().for_each(|l| *l *= K);
            r
        })
        .collect();
    wd.write("paper.csv", measurement_csv(&paper_rows()));
    wd.write("inches.csv", measurement_csv(&scaled));
    let stats = |file: &str| {
        wd.run(&["stats", "--data", file, "--format", "json"])
            .ok()
            .json()
    };
    let (a, b) = (stats("paper.csv"), stats("inches.csv"));
    let scalars = ["mean", "sd", "se", "median", "min", "max", "range"];
    let mut compared = 0;
    for f in FINGERS {
        for q in finger(&a, f)["quantities"].as_array().unwrap() {
            let name = q["name"].as_str().unwrap();
            let s = quantity(&b, f, name);
            let k = if name == "total" { K } else { 1.0 };
            let what = |key: &str| format!("{f} {name} {key}");
            for key in scalars {
                assert_rel(num(&s[key]), k * num(&q[key]), 1e-12, &what(key));
                compared += 1;
            }
            // The CV is unitless for every quantity.
            assert_rel(num(&s["cv"]), num(&q["cv"]), 1e-12, &what("cv"));
            for key in INTERVALS {
                let (lo, hi) = interval(&q[key]);
                let (slo, shi) = interval(&s[key]);
                assert_rel(slo, k * lo, 1e-12, &what(key));
                assert_rel(shi, k * hi, 1e-12, &what(key));
                compared += 2;
            }
        }
    }
    assert_eq!(compared, 28 * (scalars.len() + 8));
}

#[test]
fn csv_format_has_one_row_per_finger_and_quantity() {
    let (wd, doc) = paper_stats(&[]);
    let run = wd.run(&["stats", "--format", "csv"]);
    run.ok();
    let mut rdr = csv::Reader::from_reader(run.stdout.as_bytes());
    let header: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    for col in [
        "finger",
        "quantity",
        "n",
        "mean",
        "sd",
        "ci_t_low",
        "ci_t_high",
        "ci_bca_low",
        "ci_bca_high",
        "pi_low",
        "pi_high",
    ] {
        assert!(
            header.iter().any(|h| h == col),
            "no column {col}: {header:?}"
        );
    }
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let records: Vec<csv::StringRecord> = rdr.records().map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), 28, "4 thumb + 4 x 6 finger rows");
    let pairs: Vec<(String, String)> = records
        .iter()
        .map(|r| (r[col("finger")].to_string(), r[col("quantity")].to_string()))
        .collect();
    let mut want = Vec::new();
    for f in FINGERS {
        let qs: &[&str] = if f == "thumb" {
            &["rel_j1", "rel_j2", "ratio_j2_j1", "total"]
        } else {
            &[
                "rel_j1",
                "rel_j2",
                "rel_j3",
                "ratio_j2_j1",
                "ratio_j3_j2",
                "total",
            ]
        };
        want.extend(qs.iter().map(|q| (f.to_string(), q.to_string())));
    }
    assert_eq!(pairs, want);
    // The numbers are the JSON document's, to 1e-12 relatively (the CSV
    // drops the noise of binary arithmetic: 519.998, not 519.9979999999999).
    for r in &records {
        assert_eq!(r.len(), header.len());
        assert_eq!(&r[col("n")], "5");
        let what = format!("{} {}", &r[col("finger")], &r[col("quantity")]);
        let q = quantity(&doc, &r[col("finger")], &r[col("quantity")]);
        let cell = |name: &str| -> f64 { r[col(name)].parse().unwrap() };
        assert_rel(cell("mean"), num(&q["mean"]), 1e-12, &what);
        assert_rel(cell("sd"), num(&q["sd"]), 1e-12, &what);
        for k in ["ci_t", "ci_percentile", "ci_bca", "pi"] {
            let (lo, hi) = interval(&q[k]);
            assert_rel(cell(&format!("{k}_low")), lo, 1e-12, &what);
            assert_rel(cell(&format!("{k}_high")), hi, 1e-12, &what);
        }
        assert_eq!(&r[col("bootstrap")], "exact", "{what}");
        assert_eq!(&r[col("confidence")], "0.95", "{what}");
    }
    let index_rel1 = &records[4];
    assert_eq!(&index_rel1[col("finger")], "index");
    assert_close(
        index_rel1[col("mean")].parse().unwrap(),
        0.484_636,
        1e-6,
        "csv mean",
    );
}

#[test]
fn degenerate_samples_give_null_or_collapsed_intervals() {
    let wd = Workdir::new();
    // n = 1: no spread can be estimated.
    wd.write(
        "one.csv",
        format!("{HEADER}\n1a,index,339.96,188.83,169.67\n"),
    );
    let doc = wd
        .run(&["stats", "--data", "one.csv", "--format", "json"])
        .ok()
        .json();
    let q = quantity(&doc, "index", "rel_j1");
    assert_eq!(q["n"], 1);
    for k in ["sd", "se", "cv"].iter().chain(&INTERVALS) {
        assert!(q[*k].is_null(), "n = 1: {k} should be null: {q}");
    }
    assert!(q["notes"].as_array().is_some_and(|n| !n.is_empty()));
    // Every X-ray with the same proportions: relative intervals collapse.
    wd.write(
        "same.csv",
        format!("{HEADER}\n1a,index,1,2,3\n1b,index,2,4,6\n1c,index,3,6,9\n"),
    );
    let doc = wd
        .run(&["stats", "--data", "same.csv", "--format", "json"])
        .ok()
        .json();
    let q = quantity(&doc, "index", "rel_j1");
    for k in INTERVALS {
        let (lo, hi) = interval(&q[k]);
        assert_close(lo, 1.0 / 6.0, 1e-12, k);
        assert_close(hi, 1.0 / 6.0, 1e-12, k);
    }
    assert_eq!(num(&q["sd"]), 0.0);
    // The total still varies.
    let t = quantity(&doc, "index", "total");
    let (lo, hi) = interval(&t["ci_t"]);
    assert!(lo < 12.0 && 12.0 < hi);
    // The table and CSV formats cope too.
    for file in ["one.csv", "same.csv"] {
        for format in ["table", "csv"] {
            wd.run(&["stats", "--data", file, "--format", format]).ok();
        }
    }
}

#[test]
fn table_format_names_the_paper_and_its_numbers() {
    let (wd, _) = paper_stats(&[]);
    let run = wd.run(&["stats"]);
    run.ok()
        .stdout_has("data/measurements.csv (5 X-rays, 25 rows)")
        .stdout_has("index (the paper's 'grooming' finger) - n = 5")
        .stdout_has("[0.4683, 0.5010]")
        .stdout_has("0.4846");
    // J in image units keeps the paper's numbers (the index's mean 756.57 and t interval),
    // with a note that its spread describes no physical length.
    let flat = run.stdout.replace("\n  ", " ");
    assert!(flat.contains("note: J (total length) is in image units, pixels of X-ray images with no common scale: its SD and intervals pool the images' scales with the hands' sizes and describe no physical length."), "{}", run.stdout);
    assert!(
        flat.contains("| J (total length) | 756.57 |"),
        "{}",
        run.stdout
    );
    assert!(flat.contains("[691.56, 821.58]"), "{}", run.stdout);
    // Exactly one table per finger.
    assert_eq!(run.stdout.matches("| quantity").count(), 5);
}
