//! Tracking a growing dataset through the binary: `phalanx add` (statistics of
//! the larger dataset, refusals that change nothing, concurrent additions,
//! SIGKILL in the middle of an addition, typo flags, the fingertip it records
//! for every row), `snapshot` and `history`, and `stats --group-by`.

use crate::common;

use common::*;
use serde_json::Value;
use std::path::Path;
use std::process::{Command as StdCommand, Stdio};
use std::time::{Duration, Instant};

/// The binary, for tests that spawn several processes or kill them.
const BIN: &str = env!("CARGO_BIN_EXE_phalanx");
/// The default dataset and history paths, relative to a [`Workdir`].
const DATA: &str = "data/measurements.csv";
const HISTORY: &str = "data/history.jsonl";

/// A small deterministic generator (Knuth's MMIX LCG), so every run of the
/// crash test sleeps and measures the same way.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        self.next() as f64 / (1u64 << 31) as f64
    }

    /// A length with one decimal in [lo, lo + span/10), as its shortest text.
    fn length(&mut self, lo: f64, span: u64) -> String {
        format!("{}", lo + (self.next() % span) as f64 / 10.0)
    }
}

/// The bytes of `name` in the work directory, or `None` when it does not exist.
fn read_opt(wd: &Workdir, name: &str) -> Option<Vec<u8>> {
    std::fs::read(wd.path().join(name)).ok()
}

/// Every line of a history file parsed as JSON (an absent file is empty).
/// Fails on a torn or unparsable line or a missing final line end.
#[track_caller]
fn history_at(path: &Path) -> Vec<Value> {
    let Ok(bytes) = std::fs::read(path) else {
        return Vec::new();
    };
    let text = String::from_utf8(bytes).expect("the history is UTF-8");
    assert!(
        text.is_empty() || text.ends_with('\n'),
        "the history's last line is torn:\n{text}"
    );
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            serde_json::from_str(l)
                .unwrap_or_else(|e| panic!("history line {} is not JSON ({e}): {l}", i + 1))
        })
        .collect()
}

fn history(wd: &Workdir) -> Vec<Value> {
    history_at(&wd.path().join(HISTORY))
}

/// Names of `.phalanx-*.tmp` files left in a directory.
fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| {
            e.expect("dir entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|n| n.starts_with(".phalanx-") && n.ends_with(".tmp"))
        .collect()
}

/// Asserts two JSON documents are equal, numbers within 1e-12; reports the
/// path of the first difference.
#[track_caller]
fn assert_json_close(a: &Value, b: &Value, path: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            let tol = 1e-12;
            assert!((x - y).abs() <= tol, "{path}: {x} != {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{path}: lengths differ");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                assert_json_close(x, y, &format!("{path}[{i}]"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            let kx: Vec<&String> = x.keys().collect();
            let ky: Vec<&String> = y.keys().collect();
            assert_eq!(kx, ky, "{path}: keys differ");
            for (k, v) in x {
                assert_json_close(v, &y[k], &format!("{path}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{path}"),
    }
}

/// The X-ray count of a stats document.
fn xrays(doc: &Value) -> u64 {
    doc["dataset"]["xrays"].as_u64().expect("dataset.xrays")
}

// ---------------------------------------------------------------------------
// 1. add, then stats: the statistics of the larger dataset
// ---------------------------------------------------------------------------

/// New rows added from a file, and one from options with metadata.
const NEW_FILE: &str = "xray,finger,j1,j2,j3\n\
    2a,index,352.1,201.4,178.0\n\
    2a,middle,391.5,250.2,190.7\n\
    2a,ring,370.3,230.9,205.4\n\
    2a,little,290.2,170.4,175.8\n\
    2a,thumb,268.4,236.1,\n\
    2b,index,345.9,193.3,176.2\n\
    2b,thumb,262.7,240.5,\n";

/// The same rows as the dataset's columns would hold them, typed by hand (in the
/// dataset's one unit and at its one tip, the skin, which rows without them take).
const NEW_ROWS_IN_DATASET: &str = "2a,index,352.1,201.4,178.0,,,,,image units,skin\n\
    2a,middle,391.5,250.2,190.7,,,,,image units,skin\n\
    2a,ring,370.3,230.9,205.4,,,,,image units,skin\n\
    2a,little,290.2,170.4,175.8,,,,,image units,skin\n\
    2a,thumb,268.4,236.1,,,,,,image units,skin\n\
    2b,index,345.9,193.3,176.2,,,,,image units,skin\n\
    2b,thumb,262.7,240.5,,,,,,image units,skin\n\
    2c,index,361.2,199.9,181.3,female,34,left,,image units,skin\n";

#[test]
fn add_then_stats_equals_stats_of_the_concatenated_file() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("new.csv", NEW_FILE);
    wd.run(&["add", "new.csv"])
        .ok()
        .stdout_has("added 7 rows to data/measurements.csv: 5 -> 7 X-rays");
    wd.run(&[
        "add",
        "--xray",
        "2c",
        "--finger",
        "index",
        "--lengths",
        "361.2,199.9,181.3",
        "--sex",
        "female",
        "--age",
        "34",
        "--side",
        "left",
    ])
    .ok()
    .stdout_has("added 1 row to data/measurements.csv: 7 -> 8 X-rays");

    let data = wd.read(DATA);
    assert!(
        data.starts_with(&paper_data()),
        "the existing bytes were not kept"
    );
    let mut cat = paper_data();
    cat.extend_from_slice(NEW_ROWS_IN_DATASET.as_bytes());
    assert_eq!(
        String::from_utf8(data).unwrap(),
        String::from_utf8(cat.clone()).unwrap(),
        "the dataset is not the paper's rows and the new ones"
    );
    wd.write("cat.csv", &cat);

    // At most 8 X-rays per finger: every bootstrap is exact enumeration, so
    // percentile and BCa intervals are comparable too, not only t intervals.
    for extra in [&[][..], &["--group-by", "sex"][..]] {
        let mut args = vec!["stats", "--format", "json"];
        args.extend(extra);
        let after = wd.run(&args).ok().json();
        args.extend(["--data", "cat.csv"]);
        let expect = wd.run(&args).ok().json();
        assert_eq!(xrays(&after), 8);
        assert_eq!(after["dataset"]["rows"], 33);
        assert_eq!(expect["dataset"]["rows"], 33);
        assert_eq!(finger(&after, "index")["n"], 8);
        assert_eq!(finger(&after, "thumb")["n"], 7);
        assert_eq!(finger(&after, "middle")["n"], 6);
        for f in after["fingers"].as_array().unwrap() {
            assert_eq!(f["bootstrap"]["method"], "exact", "{}", f["finger"]);
        }
        assert_json_close(&after["fingers"], &expect["fingers"], "fingers");
        assert_json_close(&after["groups"], &expect["groups"], "groups");
    }

    // The added rows really moved the statistics (the comparison is not vacuous).
    wd.write("paper.csv", paper_data());
    let paper = wd
        .run(&["stats", "--format", "json", "--data", "paper.csv"])
        .ok()
        .json();
    let after = wd.run(&["stats", "--format", "json"]).ok().json();
    let (m0, m1) = (
        num(&quantity(&paper, "index", "rel_j1")["mean"]),
        num(&quantity(&after, "index", "rel_j1")["mean"]),
    );
    assert!((m0 - m1).abs() > 1e-6, "{m0} {m1}");
    // By hand: the mean of the 8 index J1/J.
    let index_j1: Vec<f64> = paper_rows()
        .iter()
        .filter(|r| r.finger == "index")
        .map(|r| r.lengths[0] / r.lengths.iter().sum::<f64>())
        .chain([
            352.1 / (352.1 + 201.4 + 178.0),
            345.9 / (345.9 + 193.3 + 176.2),
            361.2 / (361.2 + 199.9 + 181.3),
        ])
        .collect();
    assert_close(
        m1,
        index_j1.iter().sum::<f64>() / 8.0,
        1e-12,
        "index rel_j1 mean",
    );

    // The last snapshot is of this dataset and has its statistics.
    let h = history(&wd);
    assert_eq!(h.len(), 2);
    let last = &h[1];
    assert_eq!(last["xrays"], 8);
    assert_eq!(
        last["sha256"].as_str().unwrap(),
        sha256sum(&wd.path().join(DATA))
    );
    let rec = last["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["finger"] == "index" && q["quantity"] == "rel_j1")
        .unwrap();
    assert_eq!(rec["n"], 8);
    assert_close(num(&rec["mean"]), m1, 1e-12, "snapshot mean");
    let q = quantity(&after, "index", "rel_j1");
    assert_json_close(&rec["ci_t"], &q["ci_t"], "snapshot ci_t");
    assert_json_close(&rec["ci_bca"], &q["ci_bca"], "snapshot ci_bca");
}

// ---------------------------------------------------------------------------
// 2. A refused add changes nothing
// ---------------------------------------------------------------------------

struct Refusal {
    what: &'static str,
    /// A file of new rows written as `new.csv` first, if any.
    file: Option<&'static str>,
    args: &'static [&'static str],
    /// Every one must be in stderr.
    says: &'static [&'static str],
    /// How many problem lines, when known.
    problems: Option<usize>,
}

const REFUSALS: &[Refusal] = &[
    Refusal {
        what: "duplicate of a shipped row",
        file: None,
        args: &[
            "--xray",
            "1a",
            "--finger",
            "index",
            "--lengths",
            "340,189,170",
            "--side",
            "right",
            "--unit",
            "image units",
        ],
        says: &[
            "<command line>: X-ray '1a' already has an index row in data/measurements.csv (line 2)",
        ],
        problems: Some(1),
    },
    Refusal {
        what: "duplicate of an added row",
        file: None,
        args: &[
            "--xray",
            "2a",
            "--finger",
            "index",
            "--lengths",
            "350,190,170",
        ],
        says: &[
            "<command line>: X-ray '2a' already has an index row in data/measurements.csv (line 27)",
        ],
        problems: Some(1),
    },
    Refusal {
        what: "length abc",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "abc,190,170",
        ],
        says: &["<command line>: --lengths: 'abc' is not a number"],
        problems: Some(1),
    },
    Refusal {
        what: "length -3",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "350,-3,170",
        ],
        says: &["<command line>: --lengths: '-3' is negative"],
        problems: Some(1),
    },
    Refusal {
        what: "length NaN",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "350,190,NaN",
        ],
        says: &["<command line>: --lengths: 'NaN'"],
        problems: Some(1),
    },
    Refusal {
        what: "length 0",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "0,190,170",
        ],
        says: &["<command line>: --lengths: ", "zero"],
        problems: Some(1),
    },
    Refusal {
        what: "thumb with j3",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "thumb",
            "--lengths",
            "270,230,100",
        ],
        says: &["<command line>: --lengths: the thumb has only J1 and J2"],
        problems: Some(1),
    },
    Refusal {
        what: "index without j3",
        file: None,
        args: &["--xray", "9a", "--finger", "index", "--lengths", "350,190"],
        says: &["<command line>: --lengths: ", "enter J3"],
        problems: Some(1),
    },
    Refusal {
        what: "four lengths",
        file: None,
        args: &["--xray", "9a", "--finger", "index", "--lengths", "1,2,3,4"],
        says: &["--lengths '1,2,3,4'"],
        problems: None,
    },
    Refusal {
        what: "unknown finger",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "toe",
            "--lengths",
            "350,190,170",
        ],
        says: &["<command line>: --finger: unknown finger 'toe'"],
        problems: Some(1),
    },
    Refusal {
        what: "bad age",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "350,190,170",
            "--age",
            "abc",
        ],
        says: &["<command line>: --age: 'abc' is not an age"],
        problems: Some(1),
    },
    Refusal {
        what: "side conflicts with the X-ray's other rows",
        file: None,
        args: &[
            "--xray",
            "1a",
            "--finger",
            "index",
            "--lengths",
            "350,190,170",
            "--side",
            "left",
        ],
        says: &[
            "<command line>: X-ray '1a' already has an index row",
            "<command line>: side is 'left' but data/measurements.csv line 2 gives 'right'",
            "omit --side",
            "edit line 2 of data/measurements.csv",
        ],
        // The unit, left out, is taken from the X-ray's rows.
        problems: Some(2),
    },
    Refusal {
        what: "a tenfold typo",
        file: None,
        args: &[
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "3399.6,188.83,169.67",
        ],
        says: &[
            "<command line>: flagged as a likely error: index",
            "X-ray '9a'",
            "j1 looks 10 times too large",
            "<command line>: nothing was added",
        ],
        problems: Some(2),
    },
    Refusal {
        what: "a tenfold typo with the old --strict",
        file: None,
        args: &[
            "--strict",
            "--xray",
            "9a",
            "--finger",
            "index",
            "--lengths",
            "3399.6,188.83,169.67",
        ],
        says: &["<command line>: flagged as a likely error: index"],
        problems: Some(2),
    },
    Refusal {
        what: "one bad length among several good rows",
        file: Some(
            "xray,finger,j1,j2,j3\n9a,index,350,190,170\n9a,thumb,270,230,\n9b,ring,360,abc,200\n9b,little,290,170,175\n",
        ),
        args: &["new.csv"],
        says: &["new.csv:4:4: j2: 'abc' is not a number"],
        problems: Some(1),
    },
    Refusal {
        what: "a file row repeating a shipped row",
        file: Some(
            "xray,finger,j1,j2,j3,side,unit\n9a,index,350,190,170,,\n1c,ring,366.78,247.01,200.40,right,image units\n",
        ),
        args: &["new.csv"],
        says: &["new.csv:3: X-ray '1c' already has a ring row in data/measurements.csv (line 14)"],
        problems: Some(1),
    },
    Refusal {
        what: "a file thumb with j3",
        file: Some("xray,finger,j1,j2,j3\n9a,index,350,190,170\n9a,thumb,270,230,100\n"),
        args: &["new.csv"],
        says: &["new.csv:3:5: j3: the thumb has only J1 and J2"],
        problems: Some(1),
    },
    Refusal {
        what: "a file repeating its own row",
        file: Some("xray,finger,j1,j2,j3\n9a,index,350,190,170\n9a,index,351,190,170\n"),
        args: &["new.csv"],
        says: &["new.csv:3:1: xray: duplicate row"],
        problems: Some(1),
    },
    Refusal {
        what: "a file row whose unit conflicts with the X-ray's added row",
        file: Some("xray,finger,j1,j2,j3,unit\n9a,index,350,190,170,\n2a,ring,37.0,23.0,20.5,mm\n"),
        args: &["new.csv"],
        says: &[
            "new.csv:3: unit is 'mm' but data/measurements.csv line 27 gives 'image units' for the same X-ray '2a'",
        ],
        problems: Some(1),
    },
    Refusal {
        what: "a file with a tenfold typo",
        file: Some(
            "xray,finger,j1,j2,j3\n9a,index,350,190,170\n9b,index,350,190,170\n9b,middle,380.2,2551.1,190.5\n",
        ),
        args: &["new.csv"],
        says: &[
            "new.csv:4: flagged as a likely error: middle",
            "X-ray '9b'",
            "j2 looks 10 times too large",
            "new.csv: nothing was added",
        ],
        problems: Some(2),
    },
];

#[test]
fn a_refused_add_leaves_dataset_and_history_byte_identical() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // A history to protect, and an added row (2a, index, line 27) to repeat.
    wd.run(&[
        "add",
        "--xray",
        "2a",
        "--finger",
        "index",
        "--lengths",
        "352.1,201.4,178.0",
    ])
    .ok();
    let data = wd.read(DATA);
    let hist = wd.read(HISTORY);
    assert_eq!(history(&wd).len(), 1);
    for r in REFUSALS {
        if let Some(text) = r.file {
            wd.write("new.csv", text);
        }
        let mut args = vec!["add"];
        args.extend(r.args);
        let run = wd.run(&args);
        run.data_error();
        for s in r.says {
            assert!(
                run.stderr.contains(s),
                "{}: stderr lacks {s:?}:\n{}",
                r.what,
                run.stderr
            );
        }
        if let Some(n) = r.problems {
            assert_eq!(run.problem_lines().len(), n, "{}:\n{}", r.what, run.stderr);
        }
        if r.file.is_some() || r.says.iter().any(|s| s.contains("flagged")) {
            // Every problem names its row: FILE:LINE or <command line>.
            let place = if r.file.is_some() {
                "new.csv:"
            } else {
                "<command line>: "
            };
            for p in run.problem_lines() {
                assert!(p.starts_with(place), "{}: {p}", r.what);
            }
        }
        assert!(wd.read(DATA) == data, "{}: the dataset changed", r.what);
        assert!(wd.read(HISTORY) == hist, "{}: the history changed", r.what);
        assert!(
            temp_files(&wd.path().join("data")).is_empty(),
            "{}: temporary file left",
            r.what
        );
    }
    // The good rows of the refused files were not added either.
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(!text.contains("\n9a,") && !text.contains("\n9b,"), "{text}");
}

// ---------------------------------------------------------------------------
// 3. Concurrent additions
// ---------------------------------------------------------------------------

#[test]
fn eight_concurrent_adds_all_land_exactly_once() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let children: Vec<_> = (0..8)
        .map(|i| {
            StdCommand::new(BIN)
                .current_dir(wd.path())
                .args([
                    "add",
                    "--resamples",
                    "200",
                    "--xray",
                    &format!("c{i}"),
                    "--finger",
                    "index",
                    "--lengths",
                    &format!("{},190.5,171.25", 345 + i),
                ])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("spawn phalanx add")
        })
        .collect();
    for (i, c) in children.into_iter().enumerate() {
        let out = c.wait_with_output().expect("wait for phalanx add");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "add c{i} failed: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(text.as_bytes().starts_with(&paper_data()));
    for i in 0..8 {
        let row = format!("c{i},index,{},190.5,171.25,,,,,image units,skin", 345 + i);
        let n = text.lines().filter(|l| *l == row).count();
        assert_eq!(n, 1, "row {row} appears {n} times:\n{text}");
    }
    assert_eq!(text.lines().count(), 26 + 8);
    let doc = wd.run(&["stats", "--format", "json"]).ok().json();
    assert_eq!(xrays(&doc), 13);
    assert_eq!(finger(&doc, "index")["n"], 13);
    // The lock serialised them: each snapshot saw every earlier row.
    let h = history(&wd);
    let counts: Vec<u64> = h.iter().map(|s| s["xrays"].as_u64().unwrap()).collect();
    assert_eq!(counts, (6..=13).collect::<Vec<u64>>());
    assert_eq!(
        h[7]["sha256"].as_str().unwrap(),
        sha256sum(&wd.path().join(DATA))
    );
}

// ---------------------------------------------------------------------------
// 4. Crash safety
// ---------------------------------------------------------------------------

/// A dataset of `n` X-rays with five fingers each, lengths from the generator, every
/// tip at the bone (so a row added without one takes it, appended as `...,bone`).
fn big_dataset(n: usize, rng: &mut Lcg) -> String {
    let mut out = String::from("xray,finger,j1,j2,j3,tip\n");
    for i in 0..n {
        for (f, j1, j2, j3) in [
            ("thumb", 255.0, 225.0, None),
            ("index", 335.0, 185.0, Some(165.0)),
            ("middle", 370.0, 235.0, Some(180.0)),
            ("ring", 355.0, 220.0, Some(190.0)),
            ("little", 280.0, 160.0, Some(165.0)),
        ] {
            let j3 = j3.map_or_else(String::new, |l| rng.length(l, 200));
            out.push_str(&format!(
                "x{i},{f},{},{},{j3},bone\n",
                rng.length(j1, 300),
                rng.length(j2, 200)
            ));
        }
    }
    out
}

/// `add --data big.csv` of one index row, as a command.
fn add_big(wd: &Workdir, xray: &str, lengths: &str) -> StdCommand {
    let mut c = StdCommand::new(BIN);
    c.current_dir(wd.path())
        .args([
            "add",
            "--data",
            "big.csv",
            "--resamples",
            "200",
            "--xray",
            xray,
            "--finger",
            "index",
            "--lengths",
            lengths,
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    c
}

#[test]
#[ignore = "slow: 40 adds killed at random moments (run by .ci/run)"]
fn a_killed_add_leaves_the_old_or_the_new_dataset_never_a_torn_one() {
    const XRAYS: usize = 300;
    const KILLS: usize = 40;
    let wd = Workdir::new();
    let mut rng = Lcg(0x005E_ED0F_F1A1_A7C5);
    wd.write("big.csv", big_dataset(XRAYS, &mut rng));
    let hist_path = wd.path().join("history.jsonl");

    // Calibrate: how long one whole add takes here (two runs, the longer).
    let mut whole = Duration::ZERO;
    for k in 0..2 {
        let t = Instant::now();
        let st = add_big(&wd, &format!("w{k}"), "350,190,170")
            .status()
            .unwrap();
        assert!(st.success());
        whole = whole.max(t.elapsed());
    }
    assert_eq!(history_at(&hist_path).len(), 2);
    // Kill anywhere from before the lock to a little after the end.
    let window_ms = (1.25 * whole.as_millis() as f64).max(20.0);

    let (mut old_kept, mut new_kept, mut new_without_snapshot) = (0, 0, 0);
    for i in 0..KILLS {
        let old = wd.read("big.csv");
        let old_history = history_at(&hist_path);
        let (j1, j2, j3) = (
            rng.length(335.0, 300),
            rng.length(185.0, 200),
            rng.length(165.0, 200),
        );
        let xray = format!("k{i}");
        let row = format!("{xray},index,{j1},{j2},{j3},bone\n");
        let mut child = add_big(&wd, &xray, &format!("{j1},{j2},{j3}"))
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis((rng.unit() * window_ms) as u64));
        child.kill().expect("SIGKILL"); // Ok also when it already exited
        let status = child.wait().unwrap();

        let now = wd.read("big.csv");
        let new_history = history_at(&hist_path); // every line parses: never torn
        let grew = match new_history.len().checked_sub(old_history.len()) {
            Some(0) => false,
            Some(1) => true,
            d => panic!(
                "kill {i}: the history went from {} to {} lines ({d:?})",
                old_history.len(),
                new_history.len()
            ),
        };
        assert_eq!(
            new_history[..old_history.len()],
            old_history[..],
            "kill {i}: old snapshots changed"
        );
        if now == old {
            assert!(
                !grew,
                "kill {i}: a snapshot was recorded for a row not added"
            );
            assert!(!status.success(), "kill {i}: exit 0 without the row");
            old_kept += 1;
        } else {
            let mut expect = old.clone();
            expect.extend_from_slice(row.as_bytes());
            assert!(
                now == expect,
                "kill {i}: the dataset is neither the old nor the old plus {row:?}; its tail:\n{}",
                String::from_utf8_lossy(&now[now.len().saturating_sub(300)..])
            );
            let xrays_now = XRAYS + 2 + new_kept + 1;
            new_kept += 1;
            if grew {
                let last = &new_history[new_history.len() - 1];
                assert_eq!(last["xrays"].as_u64(), Some(xrays_now as u64), "kill {i}");
                assert_eq!(
                    last["sha256"].as_str().unwrap(),
                    sha256sum(&wd.path().join("big.csv")),
                    "kill {i}: the snapshot is not of the dataset"
                );
            } else {
                new_without_snapshot += 1;
            }
        }
    }
    // Stray `.phalanx-*.tmp` files may remain after SIGKILL (the process had no
    // chance to remove its staged file); they never replace the dataset.
    let strays = temp_files(wd.path());
    eprintln!(
        "{KILLS} kills in a {window_ms} ms window: {old_kept} old, {new_kept} new \
         ({new_without_snapshot} before the snapshot), {} stray temporary files",
        strays.len()
    );
    assert!(
        old_kept > 0 && new_kept > 0,
        "the kills did not land on both sides of the replacement \
         ({old_kept} old, {new_kept} new); the timing window is wrong"
    );

    // The lock of a killed process is gone: a normal add still works.
    let run = wd.run(&[
        "add",
        "--data",
        "big.csv",
        "--resamples",
        "200",
        "--xray",
        "after",
        "--finger",
        "index",
        "--lengths",
        "350,190,170",
    ]);
    run.ok();
    let total = XRAYS + 2 + new_kept + 1;
    run.stdout_has(&format!("-> {total} X-rays"));
    let doc = wd
        .run(&[
            "stats",
            "--data",
            "big.csv",
            "--resamples",
            "200",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert_eq!(xrays(&doc), total as u64);
    let last = history_at(&hist_path).pop().unwrap();
    assert_eq!(last["xrays"].as_u64(), Some(total as u64));
}

// ---------------------------------------------------------------------------
// 5. Typo flags
// ---------------------------------------------------------------------------

fn warnings(run: &Run) -> Vec<&str> {
    run.stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect()
}

#[test]
fn a_tenfold_typo_is_refused_unless_accepted() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // A plausible row (at the skin, as the paper's): no warning or note at all.
    let run = wd.run(&[
        "add",
        "--xray",
        "2a",
        "--finger",
        "index",
        "--lengths",
        "352.1,201.4,178.0",
        "--tip",
        "skin",
    ]);
    run.ok();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    // A misplaced decimal point: refused, with exactly one problem naming each value
    // with the interval it is outside, and the length to fix; accepted on demand, with
    // the same words as one warning.
    let typo = [
        "add",
        "--xray",
        "2b",
        "--finger",
        "ring",
        "--lengths",
        "3584.0,226.5,191.1",
    ];
    let refused = wd.run(&typo);
    refused.data_error();
    let flagged: Vec<&str> = refused
        .problem_lines()
        .into_iter()
        .filter(|l| l.contains("flagged as a likely error"))
        .collect();
    assert_eq!(flagged.len(), 1, "{}", refused.stderr);
    let mut accept = typo.to_vec();
    accept.push("--accept-flagged");
    let run = wd.run(&accept);
    run.ok();
    let warned = warnings(&run);
    assert_eq!(warned.len(), 1, "{}", run.stderr);
    let w = warned[0];
    assert!(
        flagged[0].ends_with(&w[w.find("ring X-ray").unwrap()..]),
        "{}\n{w}",
        flagged[0]
    );
    assert!(
        w.starts_with("warning: <command line>: added though flagged (--accept-flagged): ring X-ray '2b': J~1 = 0.8956 is outside ["),
        "{w}"
    );
    assert!(
        w.contains("99.67% prediction intervals of the current 5 X-rays"),
        "{w}"
    );
    assert!(w.contains("j1 = 3584 is 9.6 times the median j1"), "{w}");
    assert!(
        w.ends_with("j1 looks 10 times too large (a misplaced decimal point?)"),
        "{w}"
    );
    assert!(!w.contains("robust"), "{w}");
    // A second typo after the first is still refused with --strict.
    wd.run(&[
        "add",
        "--strict",
        "--xray",
        "2g",
        "--finger",
        "ring",
        "--lengths",
        "3729.8,226.7,212.1",
    ])
    .data_error()
    .stderr_has("flagged as a likely error: ring X-ray '2g'")
    .stderr_has("j1 looks 10 times too large");

    for (xray, finger, lengths, segment) in [
        ("2f", "index", "3399.6,188.83,169.67", "j1"),
        ("2c", "middle", "380.2,2551.1,190.5", "j2"),
        ("2d", "ring", "366.8,247.0,2004.0", "j3"),
        ("2e", "thumb", "2705.0,231.02", "j1"),
    ] {
        let data = wd.read(DATA);
        let hist = wd.read(HISTORY);
        let args = [
            "add",
            "--xray",
            xray,
            "--finger",
            finger,
            "--lengths",
            lengths,
        ];
        let run = wd.run(&args);
        run.data_error()
            .stderr_has("flagged as a likely error")
            .stderr_has(&format!("X-ray '{xray}'"))
            .stderr_has(&format!("{segment} looks 10 times too large"));
        assert!(wd.read(DATA) == data, "{xray}: the dataset changed");
        assert!(wd.read(HISTORY) == hist, "{xray}: the history changed");

        let mut accept = args.to_vec();
        accept.push("--accept-flagged");
        let run = wd.run(&accept);
        run.ok();
        let w = warnings(&run);
        assert_eq!(w.len(), 1, "{xray}: not one warning:\n{}", run.stderr);
        let line = w[0];
        assert!(line.contains(&format!("X-ray '{xray}'")), "{line}");
        assert!(
            line.starts_with(&format!(
                "warning: <command line>: added though flagged (--accept-flagged): {finger} "
            )),
            "{line}"
        );
        assert!(
            line.contains(&format!("{segment} looks 10 times too large")),
            "{line}"
        );
        let text = String::from_utf8(wd.read(DATA)).unwrap();
        // Kept as typed, in the dataset's unit, with why it was flagged.
        let j: Vec<String> = lengths.split(',').map(str::to_string).collect();
        let j3 = j.get(2).cloned().unwrap_or_default();
        let row = format!(
            "{xray},{finger},{},{},{j3},,,,,image units,skin,",
            j[0], j[1]
        );
        let last = text.lines().last().unwrap();
        assert!(last.starts_with(&row), "{row:?} not added:\n{text}");
        assert!(
            last.contains(&format!("{segment} looks 10 times too large")),
            "{last}"
        );
    }
}

/// For a two-segment finger, J1 ten times too small and J2 ten times too
/// large give the same relative values; only the total tells them apart.
#[test]
fn a_thumb_j2_tenfold_typo_is_hinted_as_j2_too_large() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let run = wd.run(&[
        "add",
        "--xray",
        "t1",
        "--finger",
        "thumb",
        "--lengths",
        "270.5,2310.2",
    ]);
    run.data_error().stderr_has("j2 looks 10 times too large");
    assert!(!run.stderr.contains("j1 looks"), "{}", run.stderr);
}

// ---------------------------------------------------------------------------
// 6. History
// ---------------------------------------------------------------------------

#[test]
fn history_has_one_snapshot_per_add_and_per_snapshot_command() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let data_path = wd.path().join(DATA);
    assert!(read_opt(&wd, HISTORY).is_none());
    // Quantities per snapshot: as many as `stats` computes.
    let n_quantities: usize = wd.run(&["stats", "--format", "json"]).ok().json()["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["quantities"].as_array().unwrap().len())
        .sum();
    assert!(n_quantities >= 19, "{n_quantities}");
    wd.run(&["history"])
        .ok()
        .stdout_has("No snapshots in data/history.jsonl yet");
    for (i, (xray, lengths)) in [
        ("3a", "352.1,201.4,178.0"),
        ("3b", "345.9,193.3,176.2"),
        ("3c", "361.2,199.9,181.3"),
    ]
    .into_iter()
    .enumerate()
    {
        wd.run(&[
            "add",
            "--xray",
            xray,
            "--finger",
            "index",
            "--lengths",
            lengths,
        ])
        .ok()
        .stdout_has("snapshot appended to data/history.jsonl");
        let h = history(&wd);
        assert_eq!(h.len(), i + 1);
        let last = &h[i];
        assert_eq!(last["event"], "add");
        assert_eq!(last["xrays"].as_u64(), Some(6 + i as u64));
        assert_eq!(last["dataset"], DATA);
        assert_eq!(last["sha256"].as_str().unwrap(), sha256sum(&data_path));
        assert_eq!(last["quantities"].as_array().unwrap().len(), n_quantities);
        let index = last["fingers"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["finger"] == "index")
            .unwrap();
        assert_eq!(index["n"].as_u64(), Some(6 + i as u64));
    }
    // Nothing changed since the last add: a snapshot says so and writes nothing.
    wd.run(&["snapshot"])
        .ok()
        .stdout_has("no change since snapshot 3");
    assert_eq!(history(&wd).len(), 3);
    // Another seed is another setting (the bootstraps here are exact, so the same numbers).
    wd.run(&["snapshot", "--seed", "7"])
        .ok()
        .stdout_has("snapshot of data/measurements.csv (8 X-rays");
    let h = history(&wd);
    assert_eq!(h.len(), 4);
    assert_eq!(h[3]["event"], "snapshot");
    assert_eq!(h[3]["xrays"], 8);
    assert_eq!(h[3]["sha256"], h[2]["sha256"]);
    assert_json_close(&h[3]["quantities"], &h[2]["quantities"], "snapshot");

    // Table: one section, one row per snapshot.
    let run = wd.run(&["history", "--finger", "index", "--quantity", "rel_j1"]);
    run.ok().stdout_has("4 snapshots in data/history.jsonl");
    let rows: Vec<Vec<&str>> = run
        .stdout
        .lines()
        .map(|l| l.split('|').map(str::trim).collect::<Vec<_>>())
        .filter(|c| c.len() > 2 && c[1].parse::<usize>().is_ok())
        .collect();
    let numbers: Vec<&str> = rows.iter().map(|c| c[1]).collect();
    assert_eq!(numbers, ["1", "2", "3", "4"], "{}", run.stdout);
    let events: Vec<&str> = rows.iter().map(|c| c[3]).collect();
    assert_eq!(events, ["add", "add", "add", "snapshot"]);
    let ns: Vec<&str> = rows.iter().map(|c| c[4]).collect();
    assert_eq!(ns, ["6", "7", "8", "8"]);
    assert_eq!(run.stdout.matches("index J~1").count(), 1, "{}", run.stdout);
    assert!(!run.stdout.contains("thumb"), "{}", run.stdout);

    // JSON: a series per quantity, a point per snapshot.
    let doc = wd.run(&["history", "--format", "json"]).ok().json();
    assert_eq!(doc["snapshots"], 4);
    let series = doc["series"].as_array().unwrap();
    assert_eq!(series.len(), n_quantities);
    for s in series {
        let snaps: Vec<u64> = s["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["snapshot"].as_u64().unwrap())
            .collect();
        assert_eq!(snaps, [1, 2, 3, 4], "{}", s["finger"]);
    }
    let doc = wd
        .run(&[
            "history",
            "--format",
            "json",
            "--finger",
            "index",
            "--quantity",
            "rel_j1",
        ])
        .ok()
        .json();
    let series = doc["series"].as_array().unwrap();
    assert_eq!(series.len(), 1);
    let points = series[0]["points"].as_array().unwrap();
    let ns: Vec<u64> = points
        .iter()
        .map(|p| p["record"]["n"].as_u64().unwrap())
        .collect();
    assert_eq!(ns, [6, 7, 8, 8]);
    // The last point is today's statistics.
    let stats = wd.run(&["stats", "--format", "json"]).ok().json();
    let q = quantity(&stats, "index", "rel_j1");
    assert_close(
        num(&points[3]["record"]["mean"]),
        num(&q["mean"]),
        1e-12,
        "mean",
    );
    assert_json_close(&points[3]["record"]["ci_t"], &q["ci_t"], "ci_t");
}

#[test]

fn an_add_whose_history_cannot_be_written_changes_nothing() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.mkdir("hdir");
    let data = wd.read(DATA);
    let run = wd.run(&[
        "add",
        "--history",
        "hdir",
        "--xray",
        "z",
        "--finger",
        "index",
        "--lengths",
        "350,190,170",
    ]);
    assert_ne!(run.code, Some(0), "{}", run.stderr);
    assert!(
        wd.read(DATA) == data,
        "add failed ({}) but the dataset changed",
        run.stderr.trim()
    );
}

#[test]

fn add_through_a_symlinked_dataset_updates_its_target() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("real/m.csv", paper_data());
    std::fs::remove_file(wd.path().join(DATA)).unwrap();
    std::os::unix::fs::symlink("../real/m.csv", wd.path().join(DATA)).unwrap();
    wd.run(&[
        "add",
        "--xray",
        "z",
        "--finger",
        "index",
        "--lengths",
        "350,190,170",
    ])
    .ok();
    let link = std::fs::symlink_metadata(wd.path().join(DATA)).unwrap();
    let target = String::from_utf8(wd.read("real/m.csv")).unwrap();
    assert!(
        target.ends_with("z,index,350,190,170,,,,,image units,skin\n"),
        "the link's target was not updated"
    );
    assert!(link.file_type().is_symlink(), "the link was replaced");
}

// ---------------------------------------------------------------------------
// 7. Groups
// ---------------------------------------------------------------------------

/// 3 female, 2 male and 1 unknown X-ray; ages 25, 45, 70, 12, 35 and unknown;
/// sides left, right, right, left, right and unknown.
const GROUPED: &str = "xray,finger,j1,j2,j3,sex,age,side\n\
    a,index,340,189,170,female,25,left\n\
    a,thumb,270,231,,female,25,left\n\
    b,index,342,195,187,f,45,right\n\
    b,thumb,260,251,,f,45,right\n\
    c,index,360,207,174,female,70,right\n\
    c,ring,367,247,200,female,70,right\n\
    d,index,417,226,184,male,12,left\n\
    d,thumb,302,265,,male,12,left\n\
    e,index,345,200,180,m,35,right\n\
    f,index,350,199,181,,,\n";

/// Each group of a stats document as `GROUP XRAYS: FINGER N, ...`, in order.
fn group_sizes(doc: &Value) -> Vec<String> {
    doc["groups"]["groups"]
        .as_array()
        .unwrap_or_else(|| panic!("no groups: {}", doc["groups"]))
        .iter()
        .map(|g| {
            let fingers: Vec<String> = g["fingers"]
                .as_array()
                .unwrap()
                .iter()
                .map(|f| format!("{} {}", f["finger"].as_str().unwrap(), f["n"]))
                .collect();
            format!(
                "{} {}: {}",
                g["group"].as_str().unwrap(),
                g["xrays"],
                fingers.join(", ")
            )
        })
        .collect()
}

#[test]
fn group_by_gives_the_right_n_per_group() {
    let wd = Workdir::new();
    wd.write("g.csv", GROUPED);
    let stats = |extra: &[&str]| {
        let mut args = vec!["stats", "--data", "g.csv", "--format", "json"];
        args.extend(extra);
        wd.run(&args).ok().json()
    };

    let doc = stats(&["--group-by", "sex"]);
    assert_eq!(doc["groups"]["by"], "sex");
    assert_eq!(finger(&doc, "index")["n"], 6, "the whole dataset");
    assert_eq!(
        group_sizes(&doc),
        [
            "female 3: thumb 2, index 3, ring 1",
            "male 2: thumb 1, index 2",
            "unknown 1: index 1",
        ]
    );
    let groups = doc["groups"]["groups"].as_array().unwrap();
    // Under 5 X-rays a group carries the small-sample note.
    for (g, n) in [(0, 3), (1, 2)] {
        let note = groups[g]["note"].as_str().unwrap();
        assert!(
            note.contains(&format!("only {n} X-rays, fewer than 5")),
            "{note}"
        );
    }
    // Male against female, as 'compare' puts two cohorts: the difference of the means
    // (computed here from the rows) inside its Welch and bootstrap intervals.
    let d = &doc["groups"]["differences"][0];
    assert_eq!(
        (d["a"].as_str(), d["b"].as_str()),
        (Some("female"), Some("male"))
    );
    assert_eq!(doc["groups"]["differences"].as_array().unwrap().len(), 1);
    let rel = |rows: &[[f64; 3]]| {
        rows.iter()
            .map(|r| r[0] / (r[0] + r[1] + r[2]))
            .sum::<f64>()
            / rows.len() as f64
    };
    let expect = rel(&[[417.0, 226.0, 184.0], [345.0, 200.0, 180.0]])
        - rel(&[
            [340.0, 189.0, 170.0],
            [342.0, 195.0, 187.0],
            [360.0, 207.0, 174.0],
        ]);
    let index = d["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["finger"] == "index")
        .unwrap();
    let j1 = index["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["quantity"] == "rel_j1")
        .unwrap();
    assert_close(num(&j1["difference"]), expect, 1e-12, "male - female J~1");
    for k in ["welch", "bootstrap"] {
        let iv = if k == "welch" {
            &j1[k]["interval"]
        } else {
            &j1[k]
        };
        let (lo, hi) = interval(iv);
        assert!(lo < expect && expect < hi, "{k}: [{lo}, {hi}]");
    }
    assert!(num(&j1["hedges_g"]["g"]) > 0.0);
    // The one-X-ray group: present, with a note and no intervals.
    let unknown = &groups[2];
    assert!(
        unknown["note"].as_str().unwrap().contains("only 1 X-ray"),
        "{}",
        unknown["note"]
    );
    for q in unknown["fingers"][0]["quantities"].as_array().unwrap() {
        assert_eq!(q["n"], 1);
        for k in ["sd", "ci_t", "ci_percentile", "ci_bca", "pi"] {
            assert!(q[k].is_null(), "{k} of {}: {}", q["name"], q[k]);
        }
    }
    // The female group is the statistics of the female rows alone (means
    // and t intervals; the bootstrap uses the group's own seed).
    let female: String = GROUPED
        .lines()
        .enumerate()
        .filter(|(i, l)| *i == 0 || l.contains(",female,") || l.contains(",f,"))
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    wd.write("female.csv", female);
    let alone = wd
        .run(&["stats", "--data", "female.csv", "--format", "json"])
        .ok()
        .json();
    assert_eq!(xrays(&alone), 3);
    let g = json_wrap(&groups[0]);
    for (f, q) in [
        ("index", "rel_j1"),
        ("index", "rel_j3"),
        ("index", "total"),
        ("thumb", "rel_j2"),
    ] {
        let (a, b) = (quantity(&g, f, q), quantity(&alone, f, q));
        assert_close(num(&a["mean"]), num(&b["mean"]), 1e-12, "mean");
        assert_json_close(&a["ci_t"], &b["ci_t"], "ci_t");
        assert_json_close(&a["sd"], &b["sd"], "sd");
    }

    let doc = stats(&["--group-by", "age", "--age-bins", "0,30,60"]);
    assert_eq!(doc["groups"]["by"], "age");
    assert_eq!(
        group_sizes(&doc),
        [
            "0-30 2: thumb 2, index 2",
            "30-60 2: thumb 1, index 2",
            "60+ 1: index 1, ring 1",
            "unknown 1: index 1",
        ]
    );
    let doc = stats(&["--group-by", "side"]);
    assert_eq!(doc["groups"]["by"], "side");
    assert_eq!(
        group_sizes(&doc),
        [
            "left 2: thumb 2, index 2",
            "right 3: thumb 1, index 3, ring 1",
            "unknown 1: index 1",
        ]
    );
    assert!(stats(&[])["groups"].is_null(), "no groups unless asked");

    // CSV: group_by and group lead, and the whole dataset is the group `all`.
    let run = wd.run(&[
        "stats",
        "--data",
        "g.csv",
        "--group-by",
        "sex",
        "--format",
        "csv",
    ]);
    run.ok();
    let mut r = csv::Reader::from_reader(run.stdout.as_bytes());
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        header[..5],
        ["group_by", "group", "finger", "quantity", "n"]
    );
    let mut n_of = std::collections::BTreeMap::new();
    for rec in r.records() {
        let rec = rec.unwrap();
        assert_eq!(&rec[0], "sex");
        if &rec[3] == "rel_j1" {
            n_of.insert((rec[1].to_string(), rec[2].to_string()), rec[4].to_string());
        }
    }
    let expect: std::collections::BTreeMap<(String, String), String> = [
        ("all", "thumb", "3"),
        ("all", "index", "6"),
        ("all", "ring", "1"),
        ("female", "thumb", "2"),
        ("female", "index", "3"),
        ("female", "ring", "1"),
        ("male", "thumb", "1"),
        ("male", "index", "2"),
        ("unknown", "index", "1"),
    ]
    .into_iter()
    .map(|(g, f, n)| ((g.to_string(), f.to_string()), n.to_string()))
    .collect();
    assert_eq!(n_of, expect);

    for bins in ["5,5", "30,10", "0,inf"] {
        wd.run(&[
            "stats",
            "--data",
            "g.csv",
            "--group-by",
            "age",
            "--age-bins",
            bins,
        ])
        .data_error()
        .stderr_has("--age-bins");
    }
}

/// A group object seen as a stats document (its `fingers` array), so the
/// `quantity` helper applies.
fn json_wrap(group: &Value) -> Value {
    serde_json::json!({ "fingers": group["fingers"] })
}

// ---------------------------------------------------------------------------
// 8. Flagged rows, removal, filled metadata, units, the compact history
// ---------------------------------------------------------------------------

/// Two plausible X-rays in the dataset's columns and unit (index and ring of each).
const TWO_XRAYS: &str = "xray,finger,j1,j2,j3,sex,age,side,source,unit\n\
    4a,index,352.1,201.4,178.0,,,right,lab,image units\n\
    4a,ring,370.2,231.0,205.9,,,right,lab,image units\n\
    4b,index,345.9,193.3,176.2,,,right,lab,image units\n\
    4b,ring,366.0,240.1,210.3,,,right,lab,image units\n";

#[test]
fn add_then_remove_restores_the_dataset_and_its_statistics_bit_for_bit() {
    let wd = Workdir::with_paper_data();
    let stats = || {
        wd.run(&["stats", "--format", "json"])
            .ok()
            .stdout_bytes
            .clone()
    };
    let before = stats();
    wd.write("new.csv", TWO_XRAYS);
    wd.run(&["add", "new.csv"]).ok();
    assert_ne!(stats(), before, "the add changed nothing");
    wd.run(&["remove", "--xray", "4a,4b", "--note", "back to the paper"])
        .ok()
        .stdout_has("removed 4 rows from data/measurements.csv: 4a index (line 27), 4a ring (line 28), 4b index (line 29), 4b ring (line 30); 7 -> 5 X-rays");
    assert_eq!(
        wd.read(DATA),
        paper_data(),
        "the file is not the paper's again"
    );
    // Every byte of the statistics document, the dataset's SHA-256 included.
    assert_eq!(stats(), before);
    let h = history(&wd);
    assert_eq!(h.len(), 2);
    assert_eq!(h[1]["event"], "remove");
    assert_eq!(h[1]["change"]["xrays"], serde_json::json!(["4a", "4b"]));
    assert_eq!(h[1]["change"]["rows"], 4);
    assert_eq!(h[1]["note"], "back to the paper");
    assert_eq!(h[1]["sha256"], sha256sum(&wd.path().join(DATA)));
    // One finger of one X-ray.
    wd.run(&["add", "new.csv"]).ok();
    wd.run(&["remove", "--xray", "4b", "--finger", "ring"])
        .ok()
        .stdout_has("removed 1 row from data/measurements.csv: 4b ring (line 30); 7 -> 7 X-rays");
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(
        text.ends_with("4b,index,345.9,193.3,176.2,,,right,lab,image units,skin\n"),
        "{text}"
    );
}

#[test]
fn remove_refuses_what_is_not_there_and_changes_nothing() {
    let wd = Workdir::with_paper_data();
    wd.run(&["snapshot"]).ok();
    let (data, hist) = (wd.read(DATA), wd.read(HISTORY));
    let run = wd.run(&["remove", "--xray", "1a,9z"]);
    run.data_error()
        .stderr_has("data/measurements.csv: has no X-ray '9z'; nothing was removed. Its X-rays are '1a', '1b', '1c', '1d', '1e'");
    wd.run(&["remove", "--xray", "1a", "--finger", "pinky"])
        .ok();
    let run = wd.run(&["remove", "--xray", "1a", "--finger", "little"]);
    run.data_error()
        .stderr_has("X-ray '1a' has no little row (it has 4 rows of other fingers)");
    let run = wd.run(&["remove", "--xray", "1b,1c,1d,1e"]);
    run.ok();
    wd.run(&["remove", "--xray", "1a"])
        .data_error()
        .stderr_has("would leave no row");
    wd.run(&["remove"]).expect_code(2).stderr_has("--xray");
    // The refusals wrote nothing: the history has the snapshot and the two removals.
    assert_eq!(history(&wd).len(), 3);
    assert_ne!(wd.read(DATA), data);
    assert_ne!(wd.read(HISTORY), hist);
}

#[test]
fn flagged_rows_of_a_batch_are_refused_with_their_lines_and_a_swap_is_named() {
    let wd = Workdir::with_paper_data();
    // Line 3: a tenfold typo; line 4: J1 and J3 swapped (measured from the tip).
    wd.write(
        "batch.csv",
        "xray,finger,j1,j2,j3\n5a,index,352.1,201.4,178.0\n5b,middle,38.02,255.1,190.5\n5c,ring,201.3,231.0,370.2\n",
    );
    let (data, hist) = (wd.read(DATA), read_opt(&wd, HISTORY));
    let run = wd.run(&["add", "batch.csv"]);
    run.data_error();
    assert_eq!(
        run.problem_lines().len(),
        3,
        "two rows and what to do:\n{}",
        run.stderr
    );
    run.stderr_has("batch.csv:3: flagged as a likely error: middle X-ray '5b'")
        .stderr_has("j1 looks 10 times too small")
        .stderr_has("batch.csv:4: flagged as a likely error: ring X-ray '5c'")
        .stderr_has("j1 and j3 look swapped (J3 = 370.2 is longer than J1 = 201.3")
        .stderr_has("batch.csv: nothing was added");
    assert!(!run.stderr.contains("batch.csv:2"), "{}", run.stderr);
    assert_eq!(wd.read(DATA), data);
    assert_eq!(read_opt(&wd, HISTORY), hist);
    // Accepted: each warning names its line; the rows carry why they were flagged.
    let run = wd.run(&["add", "batch.csv", "--accept-flagged"]);
    run.ok().stdout_has(
        "added 3 rows to data/measurements.csv: 5 -> 8 X-rays, 2 of them recorded as flagged",
    );
    let w = warnings(&run);
    assert_eq!(w.len(), 2, "{}", run.stderr);
    assert!(
        w[0].starts_with("warning: batch.csv:3: added though flagged"),
        "{}",
        w[0]
    );
    assert!(
        w[1].starts_with("warning: batch.csv:4: added though flagged"),
        "{}",
        w[1]
    );
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].ends_with(",unit,tip,flagged"), "{}", lines[0]);
    assert!(lines[1].ends_with(",image units,skin,"), "{}", lines[1]);
    assert!(lines[26].starts_with("5a,index,352.1,201.4,178.0,") && lines[26].ends_with(','));
    assert!(
        lines[28].contains("j1 and j3 look swapped"),
        "{}",
        lines[28]
    );
    let h = history(&wd);
    let flagged = h[0]["change"]["flagged"].as_array().unwrap();
    assert_eq!(flagged.len(), 2);
    assert_eq!(
        (&flagged[0]["xray"], &flagged[1]["xray"]),
        (&"5b".into(), &"5c".into())
    );
    // --strict, the old spelling of the default, still refuses.
    wd.write(
        "more.csv",
        "xray,finger,j1,j2,j3\n6a,index,35.21,201.4,178.0\n",
    );
    wd.run(&["add", "--strict", "more.csv"]).data_error();
}

#[test]
fn filling_an_empty_sex_age_or_side_is_no_conflict() {
    let wd = Workdir::with_paper_data();
    let add = |finger: &str, lengths: &str, extra: &[&str]| {
        let mut args = vec![
            "add",
            "--xray",
            "7a",
            "--finger",
            finger,
            "--lengths",
            lengths,
        ];
        args.extend(extra);
        wd.run(&args)
    };
    add("index", "352.1,201.4,178.0", &[]).ok();
    add(
        "middle",
        "390.0,250.1,200.2",
        &["--sex", "F", "--age", "41"],
    )
    .ok();
    add("ring", "370.2,231.0,205.9", &["--side", "left"]).ok();
    // The hand's values, once given, hold for its other rows.
    let run = add("little", "290.1,170.2,175.3", &["--sex", "male"]);
    run.data_error().stderr_has(
        "sex is 'male' but data/measurements.csv line 28 gives 'female' for the same X-ray '7a'",
    );
    add("little", "290.1,170.2,175.3", &[]).ok();
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    let rows: Vec<&str> = text.lines().skip(26).collect();
    assert_eq!(
        rows,
        [
            "7a,index,352.1,201.4,178.0,,,,,image units,skin",
            "7a,middle,390.0,250.1,200.2,female,41,,,image units,skin",
            "7a,ring,370.2,231.0,205.9,female,41,left,,image units,skin",
            "7a,little,290.1,170.2,175.3,female,41,left,,image units,skin",
        ]
    );
    // Grouped, 7a is one female hand (its index row leaves sex empty).
    let doc = wd
        .run(&["stats", "--format", "json", "--group-by", "sex"])
        .ok()
        .json();
    let groups = doc["groups"]["groups"].as_array().unwrap();
    assert_eq!(groups[0]["group"], "female");
    assert_eq!(groups[0]["xrays"], 1);
    assert_eq!(groups[0]["fingers"][0]["finger"], "index");
}

#[test]
fn rows_in_another_unit_pool_their_relative_values_and_gain_columns() {
    let wd = Workdir::with_paper_data();
    // The paper's X-ray 1a again, in mm (a tenth), with its metacarpal (a column the
    // dataset lacks) and its tip (at the skin, as the paper's rows record).
    wd.write(
        "mm.csv",
        "xray,finger,j1,j2,j3,mc,unit,tip\nmm1,index,33.996,18.883,16.967,60.1,mm,skin\n",
    );
    let run = wd.run(&["add", "mm.csv"]);
    run.ok()
        .stderr_has("the dataset's header gained the column mc (empty on its existing rows)")
        .stderr_has("no current X-ray gives index lengths in 'mm', so the new rows in 'mm' are checked on their relative values only");
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(text.starts_with("xray,finger,j1,j2,j3,sex,age,side,source,unit,tip,mc\n1a,index,339.96,188.83,169.67,,,right,\"Figure 1a, Table 1; tip at the skin: bone tips rejected against Buryanov & Kotiuk 2010 Table I (Welch test of the last segment's share, every correlation 0-0.9), skin tips not rejected; not stated by the paper\",image units,skin,\n"), "{text}");
    assert!(
        text.ends_with("mm1,index,33.996,18.883,16.967,,,,,mm,skin,60.1\n"),
        "{text}"
    );
    let doc = wd.run(&["stats", "--format", "json"]).ok().json();
    // J~1 of the index: the paper's five and 1a's again (the same proportions in mm).
    let rel: Vec<f64> = paper_rows()
        .iter()
        .filter(|r| r.finger == "index")
        .map(|r| r.lengths[0] / r.lengths.iter().sum::<f64>())
        .collect();
    let expect = (rel.iter().sum::<f64>() + rel[0]) / 6.0;
    assert_close(
        num(&quantity(&doc, "index", "rel_j1")["mean"]),
        expect,
        1e-12,
        "J~1",
    );
    let names = |f: &str| -> Vec<String> {
        finger(&doc, f)["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .map(|q| q["name"].as_str().unwrap().to_string())
            .collect()
    };
    // The index mixes units: no J; the thumb does not: J as before.
    assert!(
        !names("index").contains(&"total".to_string()),
        "{:?}",
        names("index")
    );
    assert!(names("thumb").contains(&"total".to_string()));
    // A row without a unit cannot say which of the two it is in.
    let run = wd.run(&[
        "add",
        "--xray",
        "u1",
        "--finger",
        "index",
        "--lengths",
        "35.2,20.1,17.8",
    ]);
    run.data_error().stderr_has(
        "names no unit, but the rows of data/measurements.csv are in 2 units ('image units', 'mm')",
    );
}

#[test]
fn a_snapshot_without_a_change_writes_nothing_but_a_noted_milestone() {
    let wd = Workdir::with_paper_data();
    wd.run(&["snapshot", "--note", "the paper as printed"])
        .ok()
        .stdout_has("snapshot of data/measurements.csv (5 X-rays");
    let hist = wd.read(HISTORY);
    wd.run(&["snapshot"])
        .ok()
        .stdout_has("no change since snapshot 1 of data/history.jsonl (snapshot, ")
        .stdout_has("nothing written");
    assert_eq!(wd.read(HISTORY), hist);
    // With a note, the same data is a milestone: the note, the same statistics.
    wd.run(&["snapshot", "--note", "submitted"])
        .ok()
        .stdout_has(
            "milestone snapshot 2 appended to data/history.jsonl: the same data as snapshot 1",
        );
    // Other settings are another snapshot.
    wd.run(&["snapshot", "--seed", "7"])
        .ok()
        .stdout_has("snapshot of data/measurements.csv");
    let h = history(&wd);
    assert_eq!(h.len(), 3);
    assert_eq!(h[0]["note"], "the paper as printed");
    assert_eq!(h[1]["note"], "submitted");
    assert_eq!(h[1]["sha256"], h[0]["sha256"]);
    assert_eq!(h[1]["quantities"], h[0]["quantities"]);
    assert!(h[2].get("note").is_none());
}

#[test]
fn history_is_one_compact_table_by_default() {
    let wd = Workdir::with_paper_data();
    wd.run(&["snapshot"]).ok();
    wd.write("new.csv", TWO_XRAYS);
    wd.run(&["add", "new.csv", "--note", "batch 1"]).ok();
    wd.run(&["remove", "--xray", "4b"]).ok();
    let run = wd.run_env(&["history"], &[("COLUMNS", "300")]);
    run.ok()
        .stdout_has("3 snapshots in data/history.jsonl")
        .stdout_has("add, 7 X-rays: +4 rows (2 X-rays: 4a, 4b) from new.csv; note: batch 1")
        .stdout_has("remove, 6 X-rays: -2 rows (X-ray 4b)")
        .stdout_has(&format!(
            "The {} quantities that moved most from snapshot 1 to 3",
            6
        ));
    let tables = |out: &str| out.lines().filter(|l| l.starts_with("|---")).count();
    assert_eq!(tables(&run.stdout), 1, "{}", run.stdout);
    // The rows: 6 quantities, ranked by the shift in SDs, largest first.
    let shifts: Vec<f64> = run
        .stdout
        .lines()
        .filter(|l| l.starts_with("| index") || l.starts_with("| ring"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            cells[6].parse::<f64>().unwrap().abs()
        })
        .collect();
    assert_eq!(shifts.len(), 6, "{}", run.stdout);
    assert!(shifts.windows(2).all(|w| w[0] >= w[1]), "{shifts:?}");
    // --all: every quantity, record by record (28 quantities of the paper's fingers).
    let all = wd.run_env(&["history", "--all"], &[("COLUMNS", "300")]);
    all.ok();
    assert_eq!(tables(&all.stdout), 28, "{}", all.stdout);
    // One quantity picked: its table record by record, then the records.
    let one = wd.run(&["history", "--finger", "ring", "--quantity", "rel_j1"]);
    one.ok();
    assert_eq!(tables(&one.stdout), 1, "{}", one.stdout);
    assert!(
        one.stdout.contains("| 3 |") && one.stdout.contains("remove"),
        "{}",
        one.stdout
    );
}

#[test]
fn the_report_says_what_changed_since_any_record() {
    let wd = Workdir::with_paper_data();
    wd.run(&["snapshot"]).ok();
    wd.write("new.csv", TWO_XRAYS);
    wd.run(&["add", "new.csv"]).ok();
    wd.run(&[
        "add",
        "--xray",
        "4c",
        "--finger",
        "index",
        "--lengths",
        "349.0,197.2,177.1",
    ])
    .ok();
    let md = |extra: &[&str]| {
        let mut args = vec![
            "report",
            "--out",
            "rep",
            "--format",
            "md",
            "--resamples",
            "200",
            "--sims",
            "20",
        ];
        args.extend(extra);
        wd.run(&args).ok();
        String::from_utf8(wd.read("rep/report.md")).unwrap()
    };
    // By default since the first record: the batch is not hidden behind the last row.
    let all = md(&[]);
    assert!(all.contains("What changed: snapshot 3 ("), "{all}");
    assert!(all.contains("against snapshot 1 ("), "{all}");
    assert!(all.contains("| index | J\\~1 = J1/J | 5 -> 8 |"), "{all}");
    assert!(
        all.contains("+4 rows (2 X-rays: 4a, 4b) from new.csv"),
        "{all}"
    );
    let since = md(&["--since", "2"]);
    assert!(since.contains("against snapshot 2 ("), "{since}");
    assert!(
        since.contains("| index | J\\~1 = J1/J | 7 -> 8 |"),
        "{since}"
    );
    wd.run(&["report", "--out", "rep", "--since", "3"])
        .expect_code(2)
        .stderr_has("--since 3: data/history.jsonl has 3 snapshots");
}

// ---------------------------------------------------------------------------
// 9. The fingertips `add` records
// ---------------------------------------------------------------------------

/// Two new X-rays measured without a tip column (lines 2-5).
const TIPLESS: &str = "xray,finger,j1,j2,j3\n\
    5a,index,352.1,201.4,178.0\n\
    5a,ring,370.2,231.0,205.9\n\
    5b,index,345.9,193.3,176.2\n\
    5b,thumb,268.4,236.1,\n";

/// Terminal text unwrapped, so each note is one line.
const WIDE: &[(&str, &str)] = &[("COLUMNS", "400")];

/// The paper's rows without their tip column (and, with `drop`, without some of them),
/// written to `name`: a lab's dataset whose fingertips are not recorded.
fn untipped_paper(wd: &Workdir, name: &str, drop: &[(&str, &str)]) {
    let rows: Vec<PaperRow> = paper_rows()
        .into_iter()
        .filter(|r| !drop.contains(&(r.xray.as_str(), r.finger.as_str())))
        .collect();
    wd.write(name, measurement_csv(&rows));
}

#[test]
fn rows_without_a_tip_take_the_papers_skin_and_add_says_so() {
    let wd = Workdir::with_paper_data();
    wd.write("new.csv", TIPLESS);
    let run = wd.run(&["add", "new.csv"]);
    run.ok()
        .stdout_has("added 4 rows to data/measurements.csv: 5 -> 7 X-rays");
    assert_eq!(
        run.stderr,
        "note: 4 rows of new.csv give no tip: recorded at the skin, as every row of \
         data/measurements.csv is; give --tip bone if these were measured to the bone (take \
         them out first: phalanx remove --xray 5a,5b)\n"
    );
    let mut want = paper_data();
    want.extend_from_slice(
        b"5a,index,352.1,201.4,178.0,,,,,image units,skin\n\
          5a,ring,370.2,231.0,205.9,,,,,image units,skin\n\
          5b,index,345.9,193.3,176.2,,,,,image units,skin\n\
          5b,thumb,268.4,236.1,,,,,,image units,skin\n",
    );
    assert_eq!(
        String::from_utf8(wd.read(DATA)).unwrap(),
        String::from_utf8(want).unwrap()
    );
    // One row given as options says it of itself.
    let run = wd.run(&[
        "add",
        "--xray",
        "5c",
        "--finger",
        "index",
        "--lengths",
        "349.0,197.2,177.1",
    ]);
    run.ok();
    assert_eq!(
        run.stderr,
        "note: the new row gives no tip: recorded at the skin, as every row of \
         data/measurements.csv is; give --tip bone if it was measured to the bone (take it out \
         first: phalanx remove --xray 5c)\n"
    );
    // Every row still records the one tip, and stats says so.
    wd.run_env(&["stats"], WIDE)
        .ok()
        .stdout_has("\nnote: fingertips: at the skin's outline (soft tissue included)\n");
}

#[test]
fn tip_bone_into_the_papers_skin_is_refused_unless_mixed_tips_and_a_contradiction_is_named() {
    let wd = Workdir::with_paper_data();
    wd.write("new.csv", TIPLESS);
    wd.run(&["add", "new.csv", "--tip", "bone"])
        .data_error()
        .stderr_has(
            "nothing added: the rows measure the last segment to different fingertips: 4 rows \
             of new.csv (lines 2-5) at the end of the bone, 25 rows of data/measurements.csv \
             (lines 2-26) at the skin's outline.",
        )
        .stderr_has("or give --mixed-tips to pool them anyway");
    assert_eq!(
        wd.read(DATA),
        paper_data(),
        "a refused add changed the dataset"
    );
    assert!(
        read_opt(&wd, HISTORY).is_none(),
        "a refused add wrote a history"
    );
    // A row whose own tip is not --tip's: refused at its field, whatever the dataset.
    wd.write(
        "own.csv",
        "xray,finger,j1,j2,j3,tip\n5a,index,352.1,201.4,178.0,\n5b,index,345.9,193.3,176.2,skin\n",
    );
    let run = wd.run(&["add", "own.csv", "--tip", "bone", "--mixed-tips"]);
    run.data_error();
    assert_eq!(
        run.problem_lines(),
        [
            "own.csv:3:6: tip: is 'skin', but --tip bone records every row of own.csv at the bone; \
          leave this field empty (the row then takes --tip bone), or give no --tip"
        ]
    );
    assert_eq!(wd.read(DATA), paper_data());
    // Pooled on demand: recorded at the bone, and no note (the tip was given).
    let run = wd.run(&["add", "new.csv", "--tip", "bone", "--mixed-tips"]);
    run.ok();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    let text = String::from_utf8(wd.read(DATA)).unwrap();
    let added: Vec<&str> = text.lines().skip(26).collect();
    assert_eq!(added.len(), 4, "{text}");
    assert!(added.iter().all(|l| l.ends_with(",bone")), "{text}");
}

#[test]
fn rows_without_a_tip_into_unrecorded_tips_are_refused_with_the_fix_and_nothing_written() {
    let wd = Workdir::new();
    // The paper's rows but X-ray 1a's thumb, with no tip column; and a history to keep.
    untipped_paper(&wd, "lab/lab.csv", &[("1a", "thumb")]);
    wd.run(&["snapshot", "--data", "lab/lab.csv"]).ok();
    let data = wd.read("lab/lab.csv");
    let hist = wd.read("lab/history.jsonl");
    let unchanged = |what: &str| {
        assert!(
            wd.read("lab/lab.csv") == data,
            "{what}: the dataset changed"
        );
        assert!(
            wd.read("lab/history.jsonl") == hist,
            "{what}: the history changed"
        );
        assert!(
            temp_files(&wd.path().join("lab")).is_empty(),
            "{what}: temporary file left"
        );
    };
    wd.write("new.csv", TIPLESS);
    let run = wd.run(&["add", "new.csv", "--data", "lab/lab.csv"]);
    run.data_error();
    assert_eq!(
        run.problem_lines(),
        [
            "new.csv: 4 rows (lines 2-5) give no tip, and lab/lab.csv has no one tip for them to \
          take (its fingertips: not recorded). Give --tip skin or --tip bone: where their \
          fingertips were measured (or add a tip column); nothing was added"
        ]
    );
    unchanged("a file without tips");
    // One row given as options names its X-ray.
    let one = [
        "add",
        "--xray",
        "5c",
        "--finger",
        "index",
        "--lengths",
        "349.0,197.2,177.1",
        "--data",
        "lab/lab.csv",
    ];
    let run = wd.run(&one);
    run.data_error();
    assert_eq!(
        run.problem_lines(),
        [
            "<command line>: 1 row of X-ray '5c' gives no tip, and lab/lab.csv has no one tip for \
          it to take (its fingertips: not recorded). Give --tip skin or --tip bone: where its \
          fingertip was measured; nothing was added"
        ]
    );
    unchanged("a row without a tip");
    // A new finger of an X-ray whose rows record no tip: one hand has one tip, so it is
    // recorded there first, with or without --tip.
    let thumb = [
        "add",
        "--xray",
        "1a",
        "--finger",
        "thumb",
        "--lengths",
        "270.83,230.95",
        "--data",
        "lab/lab.csv",
    ];
    let run = wd.run(&thumb);
    run.data_error();
    assert_eq!(
        run.problem_lines(),
        [
            "<command line>: 1 row of X-ray '1a' gives no tip, and the X-ray's rows in lab/lab.csv \
          (lines 2-5) record none; one hand has one tip, so record it in their tip column there \
          first (bone or skin), and the new rows take it; nothing was added"
        ]
    );
    let mut with_tip = thumb.to_vec();
    with_tip.extend(["--tip", "skin"]);
    wd.run(&with_tip).data_error().stderr_has(
        "<command line>: tip is 'skin' but lab/lab.csv line 2 records no tip for the same X-ray \
         '1a'; one hand has one tip, and every row added records one: record it on the X-ray's \
         rows of lab/lab.csv first (edit line 2), then add this row",
    );
    unchanged("a finger of an X-ray without a tip");
    // With --tip: added, the header gaining the column.
    let run = wd.run(&["add", "new.csv", "--data", "lab/lab.csv", "--tip", "bone"]);
    run.ok()
        .stdout_has("added 4 rows to lab/lab.csv: 5 -> 7 X-rays")
        .stderr_has(
            "note: the dataset's header gained the column tip (empty on its existing rows)",
        );
    let text = String::from_utf8(wd.read("lab/lab.csv")).unwrap();
    assert!(
        text.starts_with("xray,finger,j1,j2,j3,tip\n1a,index,"),
        "{text}"
    );
    assert!(
        text.ends_with(
            "5a,index,352.1,201.4,178.0,bone\n5a,ring,370.2,231.0,205.9,bone\n\
             5b,index,345.9,193.3,176.2,bone\n5b,thumb,268.4,236.1,,bone\n"
        ),
        "{text}"
    );
    assert_eq!(history_at(&wd.path().join("lab/history.jsonl")).len(), 2);
}

#[test]
fn rows_without_a_tip_into_mixed_tips_are_refused_and_stats_names_the_unrecorded_rows() {
    // The lab: new X-rays added to the paper's data before add recorded tips, so
    // 4 of its rows record none (lines 27-30).
    let wd = Workdir::new();
    let mut data = paper_data();
    data.extend_from_slice(
        b"5a,index,352.1,201.4,178.0,,,,,image units,\n\
          5a,ring,370.2,231.0,205.9,,,,,image units,\n\
          5b,index,345.9,193.3,176.2,,,,,image units,\n\
          5b,thumb,268.4,236.1,,,,,,image units,\n",
    );
    wd.write(DATA, &data);
    wd.run_env(&["stats"], WIDE).ok().stdout_has(
        "\nnote: fingertips: mixed: 25 rows at the skin, 4 rows not recorded (lines 27-30 of \
         data/measurements.csv); the statistics pool the rows without a tip with the others as \
         if measured to the same tip, and 'phalanx audit' and the report's rigs take every tip \
         here as a bone tip, so their verdicts rest on that assumption. Record where they were \
         measured in their tip column (bone or skin)\n",
    );
    wd.write(
        "more.csv",
        "xray,finger,j1,j2,j3\n6a,index,349.0,197.2,177.1\n6b,index,347.3,195.0,175.2\n",
    );
    let run = wd.run(&["add", "more.csv"]);
    run.data_error();
    assert_eq!(
        run.problem_lines(),
        [
            "more.csv: 2 rows (lines 2-3) give no tip, and data/measurements.csv has no one tip \
          for them to take (its fingertips: mixed: 25 rows at the skin, 4 rows not recorded). \
          Give --tip skin or --tip bone: where their fingertips were measured (or add a tip \
          column); nothing was added"
        ]
    );
    assert_eq!(wd.read(DATA), data, "a refused add changed the dataset");
    assert!(
        read_opt(&wd, HISTORY).is_none(),
        "a refused add wrote a history"
    );
    // A dataset with no tip at all says so too.
    untipped_paper(&wd, "lab.csv", &[]);
    wd.run_env(&["stats", "--data", "lab.csv"], WIDE)
        .ok()
        .stdout_has(
            "\nnote: fingertips: not recorded (no row of lab.csv gives a tip); 'phalanx audit' \
             and the report's rigs take every tip here as a bone tip, so their verdicts rest on \
             that assumption. Record where they were measured in a tip column (bone or skin)\n",
        );
}
