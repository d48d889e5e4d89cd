//! `phalanx place`: joint positions for a model finger, against the paper's worked example.

use crate::common;

use common::*;

/// The paper's worked example (model length 1000, index finger): mean 494.6 (a misprint:
/// 0.4846 x 1000 = 484.6), max 504.7, min 472.8, range 31.9 (0.5047 - 0.4728 from rounded
/// values; unrounded 504.712 - 472.757 = 31.955, printed here as 32.0).
#[test]
fn worked_example_to_the_paper_precision_with_the_corrected_mean() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let run = wd.run(&["place", "--finger", "grooming", "--length", "1000"]);
    run.ok()
        .stdout_has("| PIP joint  | 484.6 | 472.8 | 504.7 |  32.0 |")
        .stdout_has("index (the paper's 'grooming' finger) - model length 1000");
    let doc = wd
        .run(&[
            "place", "--finger", "index", "--length", "1000", "--format", "json",
        ])
        .ok()
        .json();
    let p = &doc["placements"][0];
    assert_eq!(p["finger"], "index");
    let pip = &p["joints"][0];
    assert_eq!(pip["joint"], "PIP");
    let pos = &pip["position"];
    assert_eq!(format!("{:.1}", num(&pos["mean"])), "484.6");
    assert_eq!(format!("{:.1}", num(&pos["max"])), "504.7");
    assert_eq!(format!("{:.1}", num(&pos["min"])), "472.8");
    // DIP at (J~1 + J~2) x 1000 = (0.484636 + 0.272604) x 1000 = 757.24 (means from
    // tests/independent/reference_values.py).
    let dip = &p["joints"][1];
    assert_eq!(dip["joint"], "DIP");
    assert_close(num(&dip["position"]["mean"]), 757.24, 0.01, "DIP");
    // Segment lengths add up to the model length.
    let sum: f64 = p["segments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| num(&s["length"]["mean"]))
        .sum();
    assert_close(sum, 1000.0, 1e-9, "segments");
    // Intervals in model units: the t interval of J~1 [0.468315, 0.500957] (scipy) x 1000.
    let (lo, hi) = interval(&pos["ci_t"]);
    assert_close(lo, 468.315, 1e-3, "t low");
    assert_close(hi, 500.957, 1e-3, "t high");
}

#[test]
fn several_fingers_scale_with_the_model() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let doc = wd
        .run(&[
            "place",
            "--hand",
            "thumb=5.1,index=7.9,little=6.4",
            "--format",
            "json",
        ])
        .ok()
        .json();
    let ps = doc["placements"].as_array().unwrap();
    assert_eq!(ps.len(), 3);
    assert_eq!(
        ps[0]["joints"].as_array().unwrap().len(),
        1,
        "the thumb has one IP joint"
    );
    assert_eq!(ps[0]["joints"][0]["joint"], "IP");
    // Thumb J~1 mean 0.531423 (reference_values.py) x 5.1.
    assert_close(
        num(&ps[0]["joints"][0]["position"]["mean"]),
        0.531423 * 5.1,
        1e-5,
        "IP",
    );
    assert_close(
        num(&ps[1]["joints"][0]["position"]["mean"]),
        0.484636 * 7.9,
        1e-5,
        "PIP",
    );
}

#[test]
fn bad_place_requests_exit_2() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    for args in [
        vec!["place", "--finger", "index"],
        vec!["place", "--finger", "toe", "--length", "10"],
        vec!["place", "--finger", "index", "--length", "-5"],
        vec!["place", "--finger", "index", "--length", "0"],
        vec!["place", "--hand", "thumb=5,thumb=6"],
        vec!["place", "--hand", "index"],
        vec!["place"],
    ] {
        wd.run(&args).expect_code(2);
    }
    wd.write("thumbs.csv", "xray,finger,j1,j2,j3\na,thumb,1,2,\n");
    wd.run(&[
        "place",
        "--data",
        "thumbs.csv",
        "--finger",
        "ring",
        "--length",
        "9",
    ])
    .expect_code(2)
    .stderr_has("no ring rows");
}

/// The committed atlas works with --data like any dataset, and where the metacarpal is
/// measured `place` gives the MCP's distance from the CMC: (mc/J) L, whose mean is the
/// mean over the rows of mc / (J1 + J2 + J3), computed here from the CSV itself.
#[test]
fn place_on_the_atlas_reports_the_mcp_from_the_cmc() {
    let wd = Workdir::new();
    let atlas = manifest_dir().join("data/atlas/measurements.csv");
    let text = std::fs::read_to_string(&atlas).unwrap();
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let ratios: Vec<f64> = r
        .records()
        .map(|rec| rec.unwrap())
        .filter(|rec| &rec[1] == "index")
        .map(|rec| {
            let f = |i: usize| rec[i].parse::<f64>().unwrap();
            f(5) / (f(2) + f(3) + f(4))
        })
        .collect();
    assert_eq!(ratios.len(), 910);
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let run = wd.run(&[
        "place",
        "--data",
        atlas.to_str().unwrap(),
        "--finger",
        "index",
        "--length",
        "100",
    ]);
    run.ok()
        .stdout_has("from 910 X-rays")
        .stdout_has("MCP from the CMC");
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("| MCP from the CMC"))
        .unwrap();
    let shown: f64 = line.split('|').nth(2).unwrap().trim().parse().unwrap();
    assert_close(
        shown,
        mean * 100.0,
        0.005,
        "MCP from the CMC, index, L = 100",
    );
}
