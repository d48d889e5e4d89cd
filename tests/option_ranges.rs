//! Every numeric option of every command at 0, 1, its maximum, just above it,
//! u64::MAX and -1: no panic, no abort (the harness checks both on every run),
//! exit 0 or 2, and on exit 2 a message that states the allowed range.

use crate::common;

use crate::audit::hand::{HandSpec, Naming, build};
use common::*;

const U64_MAX: &str = "18446744073709551615";

/// A numeric option: its name, its largest accepted value, a value just above,
/// and words that the error for a refused value must contain.
struct Numeric {
    option: &'static str,
    max: &'static str,
    above: &'static str,
    range: &'static str,
}

const RESAMPLES: Numeric = Numeric {
    option: "--resamples",
    max: "1000000",
    above: "1000001",
    range: "from 1 to 1000000",
};
const SEED: Numeric = Numeric {
    option: "--seed",
    max: U64_MAX,
    above: "18446744073709551616",
    range: "from 0 to 18446744073709551615",
};
const CONFIDENCE: Numeric = Numeric {
    option: "--confidence",
    max: "0.9999",
    above: "0.99991",
    range: "from 0.0001 to 0.9999",
};
const SIMS: Numeric = Numeric {
    option: "--sims",
    max: "100000",
    above: "100001",
    range: "from 1 to 100000",
};
const AGE_BINS: Numeric = Numeric {
    option: "--age-bins",
    max: "150",
    above: "151",
    range: "from 0 to 150",
};
const MODEL_LENGTH: Numeric = Numeric {
    option: "--model-length",
    max: "1000000000",
    above: "1000000001",
    range: "greater than 0 and at most 1e9",
};
const LENGTH: Numeric = Numeric {
    option: "--length",
    max: "1000000000",
    above: "1000000001",
    range: "greater than 0 and at most 1e9",
};
const TARGET: Numeric = Numeric {
    option: "--target",
    max: "1",
    above: "1.0001",
    range: "greater than 0 and at most 1",
};
const XRAYS: Numeric = Numeric {
    option: "--xrays",
    max: "1000000",
    above: "1000001",
    range: "from 1 to 1000000",
};

const BOOT: [&Numeric; 3] = [&RESAMPLES, &SEED, &CONFIDENCE];

/// Two X-rays of every finger: the cheapest data on which every interval exists
/// (3 distinct bootstrap resamples), for the runs at the largest --sims.
const TINY: &str = "xray,finger,j1,j2,j3\n\
                    a,thumb,270.83,230.95,\na,index,339.96,188.83,169.67\na,middle,375.28,255.60,184.37\n\
                    a,ring,358.40,226.47,191.09\na,little,284.66,174.72,169.11\n\
                    b,thumb,259.53,251.34,\nb,index,342.47,195.24,186.70\nb,middle,389.42,239.15,197.31\n\
                    b,ring,372.98,226.72,212.12\nb,little,291.24,166.72,170.56\n";

/// Runs `base` with `option=value` for each probe value; checks the outcome.
fn probe(wd: &Workdir, base: &[&str], n: &Numeric, values: &[&str]) {
    for value in values {
        let arg = format!("{}={value}", n.option);
        let mut args: Vec<&str> = base.to_vec();
        args.push(&arg);
        let run = wd.run(&args);
        match run.code {
            Some(0) => {}
            Some(2) => {
                run.stderr_has("error").stderr_has(n.range);
            }
            other => panic!("{args:?}: exit {other:?}\n{}", run.stderr),
        }
        if base[0] == "add" {
            continue; // an accepted add cannot be repeated with the same X-ray id
        }
        // Given apart (`--opt -1`), a value is never taken for a flag and the
        // message still states the range.
        let mut apart: Vec<&str> = base.to_vec();
        apart.extend([n.option, value]);
        let run = wd.run(&apart);
        assert!(matches!(run.code, Some(0 | 2)), "{apart:?}: {:?}", run.code);
        if run.code == Some(2) {
            run.stderr_has(n.range);
        }
    }
}

/// The values probed: 0, 1, the maximum, above it, u64::MAX, -1.
fn values(n: &Numeric) -> [&str; 6] {
    ["0", "1", n.max, n.above, U64_MAX, "-1"]
}

/// The values probed without the maximum (run separately on small data).
fn values_but_max(n: &Numeric) -> [&str; 5] {
    ["0", "1", n.above, U64_MAX, "-1"]
}

#[test]
fn bootstrap_options_of_every_command() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("hand.glb", build(&HandSpec::new(Naming::Mixamo)));
    let out = wd.path().join("site");
    let out = out.to_str().unwrap();
    let bases: [&[&str]; 7] = [
        &["stats"],
        &["coverage", "--sims", "5"],
        &["report", "--sims", "5", "--out", out, "--format", "json"],
        &["place", "--finger", "index", "--length", "1000"],
        &["audit", "--explain", "hand.glb"],
        &["snapshot"],
        // add: every accepted run adds a row, so each run gets its own X-ray id.
        &["add", "--finger", "index", "--lengths", "352.1,201.4,178.0"],
    ];
    for base in bases {
        for n in BOOT {
            if base[0] == "add" {
                for (i, v) in values(n).iter().enumerate() {
                    let x = format!("{}{i}", n.option.trim_start_matches('-'));
                    let mut args = base.to_vec();
                    args.extend(["--xray", &x]);
                    probe(&wd, &args, n, &[v]);
                }
            } else {
                probe(&wd, base, n, &values(n));
            }
        }
    }
}

#[test]
fn refused_values_state_the_range_in_the_message_and_the_help() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&["stats", "--seed", "-1"])
        .data_error()
        .stderr_has("'-1' is not a whole number from 0 to 18446744073709551615");
    wd.run(&["coverage", "--sims", U64_MAX])
        .data_error()
        .stderr_has("from 1 to 100000");
    wd.run(&["report", "--sims", "4294967296"])
        .data_error()
        .stderr_has("from 1 to 100000");
    for (cmd, words) in [
        (
            "stats",
            &[
                "1 to 1000000",
                "0 to 18446744073709551615",
                "0.0001 to 0.9999",
                "comma-separated",
                "each from 0 to 150",
            ][..],
        ),
        ("coverage", &["1 to 100000", "1 to 1000000"]),
        (
            "report",
            &[
                "1 to 100000",
                "at most 1e9",
                "greater than 0, at most 1",
                "comma-separated",
            ],
        ),
        ("place", &["at most 1e9"]),
        ("synth", &["1 to 1000000", "0 to 18446744073709551615"]),
    ] {
        let help = wd.run(&[cmd, "--help"]);
        help.ok();
        for w in words {
            // The help wraps lines: compare with white space collapsed.
            let flat = help.stdout.split_whitespace().collect::<Vec<_>>().join(" ");
            assert!(
                flat.contains(w),
                "{cmd} --help lacks {w:?}:\n{}",
                help.stdout
            );
        }
    }
}

#[test]
fn model_lengths_targets_and_age_bins() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let out = wd.path().join("site");
    let out = out.to_str().unwrap();
    // The full report (HTML, Markdown, plots) at each value.
    let report: &[&str] = &["report", "--sims", "5", "--out", out];
    probe(&wd, report, &MODEL_LENGTH, &values(&MODEL_LENGTH));
    probe(&wd, report, &TARGET, &values(&TARGET));
    probe(
        &wd,
        &["place", "--finger", "index"],
        &LENGTH,
        &values(&LENGTH),
    );
    for v in values(&LENGTH) {
        let hand = format!("index={v}");
        let run = wd.run(&["place", "--hand", &hand]);
        assert!(matches!(run.code, Some(0 | 2)), "{hand}");
        if run.code == Some(2) {
            run.stderr_has(LENGTH.range);
        }
    }
    probe(
        &wd,
        &["stats", "--group-by", "age"],
        &AGE_BINS,
        &values(&AGE_BINS),
    );
    probe(
        &wd,
        &[
            "report",
            "--sims",
            "5",
            "--out",
            out,
            "--group-by",
            "age",
            "--format",
            "json",
        ],
        &AGE_BINS,
        &values(&AGE_BINS),
    );
    // Semicolons are refused with the format that is expected.
    wd.run(&["stats", "--group-by", "age", "--age-bins", "0;18"])
        .data_error()
        .stderr_has("comma-separated");
    wd.run(&["stats", "--group-by", "age", "--age-bins", "0,18,40"])
        .ok();
}

#[test]
fn sims_at_every_value_including_the_largest() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("tiny.csv", TINY);
    let out = wd.path().join("site");
    let out = out.to_str().unwrap();
    probe(&wd, &["coverage"], &SIMS, &values_but_max(&SIMS));
    probe(
        &wd,
        &["report", "--out", out, "--format", "json"],
        &SIMS,
        &values_but_max(&SIMS),
    );
    // The largest, on two X-rays: 10^5 simulated datasets (the JSON has the
    // data's n alone; the table's sizes from 3 to 50 cost 30 times more).
    wd.run(&[
        "coverage", "--data", "tiny.csv", "--sims", SIMS.max, "--format", "json",
    ])
    .ok();
    wd.run(&[
        "report", "--data", "tiny.csv", "--out", out, "--format", "json", "--sims", SIMS.max,
    ])
    .ok();
}

#[test]
fn a_bootstrap_too_large_to_serve_is_refused_with_what_fits() {
    let wd = Workdir::new();
    // 12 X-rays: a random bootstrap; 10^6 resamples x 12 X-rays fits, and a
    // coverage simulation of 10^5 datasets x 10^6 resamples does not.
    let mut text = String::from("xray,finger,j1,j2,j3\n");
    for i in 0..12 {
        text.push_str(&format!(
            "x{i},index,{},{},{}\n",
            340 + i,
            190 + i % 3,
            170 + i % 5
        ));
    }
    wd.write("twelve.csv", &text);
    wd.run(&[
        "coverage",
        "--data",
        "twelve.csv",
        "--sims",
        "100000",
        "--resamples",
        "1000000",
    ])
    .data_error()
    .stderr_has("more than 10000000000")
    // 10^10 / (12 x 10^6 + 28,600 for the sizes 3 to 50 at 200 resamples each) = 831.4.
    .stderr_has("give --sims 831 or fewer");
}

#[test]
fn synth_options() {
    let wd = Workdir::new();
    // Every probe writes s.csv again: --force replaces it.
    let base: &[&str] = &["synth", "--out", "s.csv", "--force"];
    probe(&wd, base, &XRAYS, &values_but_max(&XRAYS));
    probe(
        &wd,
        &["synth", "--xrays", "2", "--out", "s.csv", "--force"],
        &SEED,
        &values(&SEED),
    );
}

#[test]
#[ignore = "slow: 5 million rows, 530 MB (6 s in release); run with --ignored"]
fn synth_at_its_largest() {
    let wd = Workdir::new();
    wd.run(&["synth", "--out", "s.csv", "--xrays", XRAYS.max])
        .ok();
}

#[test]
fn add_lengths_and_age_at_every_value() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    for (i, v) in values(&RESAMPLES).iter().enumerate() {
        for (j, lengths) in [format!("{v},201.4,178.0"), format!("352.1,{v},178.0")]
            .iter()
            .enumerate()
        {
            let x = format!("l{i}{j}");
            let run = wd.run(&[
                "add",
                "--xray",
                &x,
                "--finger",
                "index",
                "--lengths",
                lengths,
            ]);
            assert!(matches!(run.code, Some(0 | 2)), "{lengths}: {:?}", run.code);
            // Refused: a bad value of --lengths, or a row its rules flag (a length
            // far from its median, proportions far outside the X-rays').
            if run.code == Some(2) {
                assert!(
                    run.stderr.contains("lengths")
                        || run.stderr.contains("flagged as a likely error"),
                    "{lengths}: {}",
                    run.stderr
                );
            }
        }
        let x = format!("a{i}");
        let run = wd.run(&[
            "add",
            "--xray",
            &x,
            "--finger",
            "index",
            "--lengths",
            "352.1,201.4,178.0",
            "--age",
            v,
        ]);
        assert!(matches!(run.code, Some(0 | 2)), "--age {v}: {:?}", run.code);
        if run.code == Some(2) {
            run.stderr_has("from 0 to 150");
        }
    }
}

/// `deform --angles`: each of the probe values as every one of the three
/// angles; exit 0 or 2, and on 2 the range in the message.
#[test]
fn deform_angles() {
    use phalanx::rig::deform::synthetic::{HandSpec, tube_hand};
    let wd = Workdir::new();
    wd.write(
        "right.glb",
        tube_hand(&HandSpec {
            around: 6,
            ring_spacing: 0.004,
            ..HandSpec::default()
        })
        .to_glb()
        .unwrap(),
    );
    for v in [
        "0", "1", "180", "180.0001", "-30", "-30.0001", U64_MAX, "-1", "inf", "NaN",
    ] {
        for k in 0..3 {
            let mut angles = ["0"; 3];
            angles[k] = v;
            let angles = angles.join(",");
            let run = wd.run(&["deform", "right.glb", "--angles", &angles]);
            match run.code {
                Some(0) => {}
                Some(2) => {
                    run.stderr_has("from -30 to 180");
                }
                other => panic!("--angles {angles}: exit {other:?}\n{}", run.stderr),
            }
        }
    }
    let help = wd.run(&["deform", "--help"]);
    help.ok().stdout_has("from -30 to 180");
}
