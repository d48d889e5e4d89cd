//! `phalanx synth`: synthetic datasets that load, are reproducible, and scale.

use crate::common;

use common::*;

#[test]
fn synthetic_data_is_reproducible_and_loads() {
    let wd = Workdir::new();
    wd.run(&["synth", "--xrays", "50", "--seed", "3", "--out", "a.csv"])
        .ok();
    wd.run(&["synth", "--xrays", "50", "--seed", "3", "--out", "b.csv"])
        .ok();
    wd.run(&["synth", "--xrays", "50", "--seed", "4", "--out", "c.csv"])
        .ok();
    assert_eq!(wd.read("a.csv"), wd.read("b.csv"));
    assert_ne!(wd.read("a.csv"), wd.read("c.csv"));
    let stdout = wd
        .run(&["synth", "--xrays", "50", "--seed", "3"])
        .ok()
        .stdout
        .clone();
    assert_eq!(stdout.as_bytes(), wd.read("a.csv").as_slice());
    let doc = wd
        .run(&[
            "stats",
            "--data",
            "a.csv",
            "--format",
            "json",
            "--resamples",
            "200",
        ])
        .ok()
        .json();
    assert_eq!(doc["dataset"]["xrays"], 50);
    assert_eq!(doc["dataset"]["rows"], 250);
    for f in ["thumb", "index", "middle", "ring", "little"] {
        assert_eq!(finger(&doc, f)["n"], 50, "{f}");
        assert_eq!(finger(&doc, f)["bootstrap"]["method"], "random", "{f}");
    }
    // Relative values near the paper's (the model's means): index J~1 0.4846, SD 0.0131
    // -> with 50 X-rays the mean is within 4 SE = 0.0074.
    let m = num(&quantity(&doc, "index", "rel_j1")["mean"]);
    assert_close(m, 0.4846, 0.0074, "index J~1");
    let grouped = wd
        .run(&[
            "stats",
            "--data",
            "a.csv",
            "--format",
            "json",
            "--resamples",
            "100",
            "--group-by",
            "sex",
        ])
        .ok()
        .json();
    let total: u64 = grouped["groups"]["groups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["xrays"].as_u64().unwrap())
        .sum();
    assert_eq!(total, 50);
}

#[test]
fn bad_synth_options_exit_2() {
    let wd = Workdir::new();
    wd.run(&["synth", "--xrays", "0"]).expect_code(2);
    wd.run(&["synth"]).expect_code(2);
    wd.run(&["synth", "--xrays", "many"]).expect_code(2);
}
