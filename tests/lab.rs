//! A lab's first hour through the real binary, step by step: import a COCO file in
//! millimetres, add it to the paper's data, try a tenfold typo (refused), accept it
//! (recorded as flagged), see it listed in the report, remove it, and find the whole
//! sequence in the history and the report. Every step asserts what a researcher would
//! check, against values computed here from the paper's Table 1 (not by phalanx).

use crate::common;

use common::*;
use serde_json::Value;

const DATA: &str = "data/measurements.csv";
const HISTORY: &str = "data/history.jsonl";
/// The typo of the issue: the ring J1 of a new X-ray typed 36.70 for 367.0.
const TYPO: [&str; 8] = [
    "add",
    "--xray",
    "L11",
    "--finger",
    "ring",
    "--lengths",
    "36.70,238.1,195.5",
    "--unit=image units",
];
/// Terminal text unwrapped, so each sentence is one line.
const WIDE: &[(&str, &str)] = &[("COLUMNS", "400")];
/// Small enough for the debug build; the sections under test do not depend on it.
const QUICK: [&str; 4] = ["--resamples", "200", "--sims", "20"];

/// The relative J1 of the paper's index fingers (Table 1), J1 / (J1 + J2 + J3),
/// computed here from the shipped file's text.
fn paper_index_rel_j1() -> Vec<f64> {
    paper_rows()
        .iter()
        .filter(|r| r.finger == "index")
        .map(|r| r.lengths[0] / r.lengths.iter().sum::<f64>())
        .collect()
}

fn history_json(wd: &Workdir) -> Value {
    wd.run(&["history", "--format", "json"]).ok().json()
}

fn report(wd: &Workdir, out: &str) -> String {
    let mut args = vec!["report", "--out", out, "--format", "md"];
    args.extend(QUICK);
    wd.run(&args).ok();
    String::from_utf8(wd.read(&format!("{out}/report.md"))).expect("UTF-8 report")
}

#[test]
fn a_labs_first_hour() {
    let wd = Workdir::with_paper_data();
    wd.run(&["snapshot"]).ok();

    // 1. Import a COCO file in mm: the example's two hands are the paper's figures 1a and
    //    1b drawn at 1 px = 0.1 mm, so every length is the paper's tenth.
    let coco = std::fs::read(manifest_dir().join("docs/examples/hands-coco.json")).unwrap();
    wd.write("hands.json", coco);
    let import = wd.run(&[
        "import",
        "hands.json",
        "--layout",
        "coco",
        "--pixel-spacing",
        "0.1",
        "--side",
        "right",
        "--tip",
        "skin",
        "--out",
        "new.csv",
    ]);
    import.ok().stderr_has("imported 9 rows from 2 hands");
    let new = String::from_utf8(wd.read("new.csv")).unwrap();
    let index_1a = new
        .lines()
        .find(|l| l.starts_with("figure-1a.png,index,"))
        .expect("the index of figure 1a");
    let f: Vec<&str> = index_1a.split(',').collect();
    // Table 1: 1a index 339.96, 188.83, 169.67 (image units) -> mm at 0.1.
    assert_close(f[2].parse().unwrap(), 33.996, 1e-9, "1a index J1 in mm");
    assert_close(f[4].parse().unwrap(), 16.967, 1e-9, "1a index J3 in mm");
    assert!(index_1a.contains(",mm,"), "{index_1a}");

    // 2. Add it to the paper's data (in image units): relative values pool, lengths not.
    let added = wd.run(&["add", "new.csv", "--note", "COCO batch, 0.1 mm/px"]);
    added
        .ok()
        .stdout_has("added 9 rows to data/measurements.csv: 5 -> 7 X-rays");
    // The paper's rows record their tips at the skin, as the import's rows do: the header
    // has every column the new rows fill (their mc is empty), so it is left as it was.
    assert!(!added.stderr.contains("header gained"), "{}", added.stderr);
    let header = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(
        header.starts_with("xray,finger,j1,j2,j3,sex,age,side,source,unit,tip\n"),
        "{header}"
    );
    let stats = wd.run(&["stats", "--format", "json"]).ok().json();
    let idx = finger(&stats, "index");
    assert_eq!(idx["n"], 7);
    let mut rel = paper_index_rel_j1();
    rel.extend([rel[0], rel[1]]); // figures 1a and 1b again, at another scale
    let mean = rel.iter().sum::<f64>() / rel.len() as f64;
    assert_close(
        num(&quantity(&stats, "index", "rel_j1")["mean"]),
        mean,
        1e-12,
        "pooled J~1",
    );
    let names: Vec<&str> = idx["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["name"].as_str().unwrap())
        .collect();
    assert!(
        !names.contains(&"total"),
        "J averaged across units: {names:?}"
    );
    let table = wd.run_env(&["stats"], WIDE);
    table
        .ok()
        .stdout_has("lengths in 2 units: image units (25 rows), mm (9 rows)");
    let before_typo = wd.run(&["stats", "--format", "json"]).ok().json();

    // 3. A tenfold typo is refused: exit 2, the reason, nothing written.
    let data_before = wd.read(DATA);
    let history_before = wd.read(HISTORY);
    let refused = wd.run(&TYPO);
    refused.data_error();
    refused
        .stderr_has("flagged as a likely error: ring X-ray 'L11'")
        .stderr_has("j1 looks 10 times too small")
        .stderr_has("add with --accept-flagged");
    assert_eq!(
        wd.read(DATA),
        data_before,
        "a refused add changed the dataset"
    );
    assert_eq!(
        wd.read(HISTORY),
        history_before,
        "a refused add changed the history"
    );

    // 4. Accepted with --accept-flagged: in, and recorded as flagged in data and history.
    let mut accept = TYPO.to_vec();
    accept.extend(["--accept-flagged", "--note", "as typed on the form"]);
    let accepted = wd.run(&accept);
    accepted
        .ok()
        .stdout_has("7 -> 8 X-rays, 1 of them recorded as flagged")
        .stderr_has("added though flagged (--accept-flagged): ring X-ray 'L11'");
    let csv = String::from_utf8(wd.read(DATA)).unwrap();
    assert!(
        csv.lines().next().unwrap().ends_with(",tip,flagged"),
        "{csv}"
    );
    let last = csv.lines().last().unwrap();
    assert!(last.starts_with("L11,ring,36.70,238.1,195.5,"), "{last}");
    assert!(last.contains("j1 looks 10 times too small"), "{last}");
    let h = history_json(&wd);
    let rec = &h["records"][2];
    assert_eq!(rec["event"], "add");
    assert_eq!(rec["change"]["flagged"][0]["xray"], "L11");
    assert_eq!(rec["change"]["flagged"][0]["finger"], "ring");
    assert_eq!(rec["note"], "as typed on the form");
    let flagged = wd.run(&["stats", "--format", "json"]).ok().json();
    assert_eq!(flagged["flagged"][0]["xray"], "L11");
    wd.run_env(&["stats"], WIDE)
        .ok()
        .stdout_has("flagged: 1 row of the data was added though flagged")
        .stdout_has("X-ray L11 ring (line 36)");

    // 5. The report lists it, in the key results and with the statistics.
    let md = report(&wd, "rep-flagged");
    let key = md.split("## 1. Provenance").next().unwrap();
    assert!(
        key.contains("**Flagged rows in the data.** 1 row of the data was added though flagged"),
        "{key}"
    );
    assert!(key.contains("L11 ring"), "{key}");
    let listed = md
        .split("### Rows added though flagged")
        .nth(1)
        .expect("the list of flagged rows");
    assert!(
        listed.contains("| L11 | ring | 36 |")
            && listed.contains("`phalanx remove --xray L11 --finger ring`"),
        "{}",
        &listed[..listed.len().min(800)]
    );

    // 6. Removed: the statistics are those before the typo, bit for bit (the dataset
    //    keeps its new 'flagged' column, empty now, so only its hash differs).
    let removed = wd.run(&["remove", "--xray", "L11", "--note", "j1 was 367.0"]);
    removed
        .ok()
        .stdout_has("removed 1 row from data/measurements.csv: L11 ring (line 36, added flagged); 8 -> 7 X-rays");
    let after = wd.run(&["stats", "--format", "json"]).ok().json();
    assert_eq!(after["fingers"], before_typo["fingers"]);
    assert!(after.get("flagged").is_none(), "{}", after["flagged"]);

    // 7. The history and the report show the sequence: snapshot, add (file), add
    //    (flagged), remove (it had been flagged), each with its note.
    let h = history_json(&wd);
    let events: Vec<&str> = h["records"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["event"].as_str().unwrap())
        .collect();
    assert_eq!(events, ["snapshot", "add", "add", "remove"]);
    assert_eq!(h["records"][1]["change"]["file"], "new.csv");
    assert_eq!(h["records"][1]["change"]["rows"], 9);
    assert_eq!(h["records"][3]["change"]["xrays"][0], "L11");
    assert_eq!(h["records"][3]["change"]["flagged"][0]["xray"], "L11");
    let text = wd.run_env(&["history"], WIDE);
    text.ok()
        .stdout_has("4 snapshots in data/history.jsonl")
        .stdout_has("add, 7 X-rays: +9 rows (2 X-rays: figure-1a.png, figure-1b.png) from new.csv")
        .stdout_has("added though flagged: L11 ring; note: as typed on the form")
        .stdout_has("remove, 7 X-rays: -1 row (X-ray L11); had been added flagged: L11 ring; note: j1 was 367.0");
    let md = report(&wd, "rep");
    let tracking = md
        .split("## 9. Tracking new X-rays")
        .nth(1)
        .expect("the tracking section");
    let tracking = tracking.split("## 10.").next().unwrap();
    for needle in [
        "| 1 | ",
        "| 2 | ",
        "from new.csv; note: COCO batch, 0.1 mm/px |",
        "added though flagged: L11 ring",
        "| remove | 7 | -1 row (X-ray L11); had been added flagged: L11 ring; note: j1 was 367.0 |",
        "What changed: snapshot 4 (",
        "against snapshot 1 (",
    ] {
        assert!(tracking.contains(needle), "no {needle:?} in:\n{tracking}");
    }
    assert!(
        !md.contains("### Rows added though flagged"),
        "L11 is still listed"
    );
}

/// Ten rows of a lab's first two X-rays (the lab's own session, issue 41).
const LAB: &str = "xray,finger,j1,j2,j3,side,source,unit,tip
L01,thumb,277.69,237.72,,right,lab X-ray,image units,skin
L01,index,356.72,195.54,179.05,right,lab X-ray,image units,skin
L01,middle,416.55,258.19,207.14,right,lab X-ray,image units,skin
L01,ring,382.42,243.19,208.39,right,lab X-ray,image units,skin
L01,little,274.65,175.75,183.07,right,lab X-ray,image units,skin
L02,thumb,265.38,233.42,,right,lab X-ray,image units,skin
L02,index,364.44,208.46,191.21,right,lab X-ray,image units,skin
L02,middle,416.38,271.10,202.69,right,lab X-ray,image units,skin
L02,ring,400.96,254.37,210.65,right,lab X-ray,image units,skin
L02,little,328.94,181.71,196.68,right,lab X-ray,image units,skin
";

#[test]
fn a_labs_session_says_everything_once() {
    let wd = Workdir::with_paper_data();
    // One pass: the decimal comma of line 4 and the tenfold typo of line 9 together.
    let bad = LAB
        .replace("416.55", "\"416,55\"")
        .replace("271.10", "2711.0");
    wd.write("bad.csv", &bad);
    let run = wd.run(&["add", "bad.csv"]);
    run.data_error()
        .stderr_has("bad.csv:4:3: j1: '416,55' uses a decimal comma")
        .stderr_has("bad.csv:9: flagged as a likely error: middle X-ray 'L02'")
        .stderr_has("j2 looks 10 times too large");
    // Added, then added again: one summary line, not ten.
    wd.write("lab.csv", LAB);
    wd.run(&["add", "lab.csv", "--note", "first X-rays"]).ok();
    let again = wd.run(&["add", "lab.csv"]);
    again.data_error().stderr_has(
        "10 rows already present in data/measurements.csv (its lines 27-36): X-rays L01, L02, all fingers (lines 2-11 of this file)",
    );
    assert_eq!(
        again.problem_lines().len(),
        1,
        "{:?}",
        again.problem_lines()
    );
    // A milestone on unchanged data: recorded with the note and the same sha.
    wd.run(&["snapshot", "--note", "submitted"])
        .ok()
        .stdout_has("milestone snapshot 2 appended")
        .stdout_has("the same data as snapshot 1");
    let h = history_json(&wd);
    let snaps = h["records"].as_array().expect("records");
    assert_eq!(snaps.len(), 2, "{h}");
    assert_eq!(snaps[1]["note"], "submitted");
    assert_eq!(snaps[1]["sha256"], snaps[0]["sha256"]);
    wd.run(&["history"]).ok().stdout_has("note: submitted");
    // Without a note, an unchanged dataset still writes nothing.
    wd.run(&["snapshot"]).ok().stdout_has("nothing written");
    assert_eq!(history_json(&wd)["snapshots"], 2);
    // The lab's file holds the paper's X-rays: compare refuses, naming them.
    let paper = wd.write("paper.csv", paper_data());
    let paper = paper.to_str().expect("UTF-8 path");
    wd.run(&["compare", paper, DATA])
        .data_error()
        .stderr_has("share 5 of B's 7 X-rays (the same rows): X-rays 1a, 1b, 1c, 1d, 1e")
        .stderr_has("--drop-shared");
    let dropped = wd.run(&[
        "compare",
        paper,
        DATA,
        "--drop-shared",
        "--resamples",
        "200",
    ]);
    dropped
        .ok()
        .stderr_has("without the 5 X-rays it shares with A")
        .stdout_has("B: data/measurements.csv (2 X-rays");
    // The paper's four statistics stay at 100 columns.
    let stats = wd.run(&["stats", "--resamples", "200"]);
    let out = stats.ok().stdout.clone();
    let head = out
        .lines()
        .find(|l| l.starts_with("| quantity"))
        .expect("a table");
    for col in ["mean", "min", "max", "range"] {
        assert!(head.contains(&format!(" {col} |")), "{head}");
    }
    assert!(out.lines().all(|l| l.chars().count() <= 100), "{out}");
}

#[test]
fn compare_says_no_fingertip_below_what_the_data_tell() {
    let wd = Workdir::with_paper_data();
    wd.write("lab.csv", LAB);
    let lab = wd.path().join("lab.csv");
    let run = wd.run_env(
        &[
            "compare",
            DATA,
            lab.to_str().expect("UTF-8 path"),
            "--resamples",
            "200",
        ],
        WIDE,
    );
    let out = run.ok().stdout.clone();
    assert!(!out.contains("a fingertip 0.0%"), "{out}");
    for line in out.lines().filter(|l| l.contains("would explain it.")) {
        assert!(!line.contains(" 0.0% of the finger"), "{line}");
    }
}
