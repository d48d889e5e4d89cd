//! `phalanx check` through the binary: the paper's misprints and their causes,
//! exit 1 for an unrecorded mismatch, and every problem of a claims file.

use crate::common;

use common::*;
use serde_json::Value;

/// The header of a claims file.
const CLAIMS_HEADER: &str =
    "id,location,refers_to,finger,xray,quantity,statistic,model_length,stated,erratum,note";

const SUMMARY: &str =
    "30 claims: 20 match, 2 match from rounded values, 8 known errata, 0 new mismatches";

/// The line of the "Why the disagreements" list about claim `id`.
#[track_caller]
fn cause_line<'a>(stdout: &'a str, id: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.starts_with(&format!("- {id} ")))
        .unwrap_or_else(|| panic!("no cause listed for {id}:\n{stdout}"))
}

#[test]
fn shipped_data_and_claims_pass_with_the_misprints_explained() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // Every cause on one line: --wide.
    let run = wd.run(&["check", "--wide"]);
    run.ok();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    let out = &run.stdout;
    assert!(
        out.lines().any(|l| l == SUMMARY),
        "summary line missing:\n{out}"
    );
    // eq. (6): the printed mean 0.4946 should be 0.4846.
    let mean = cause_line(out, "mean-rel1");
    assert!(mean.contains("0.4946") && mean.contains("0.4846"), "{mean}");
    // J3 of 1a: the text says 169.97, Table 1 prints 169.67.
    let j3 = cause_line(out, "1a-j3");
    assert!(j3.contains("169.97") && j3.contains("169.67"), "{j3}");
    let total = cause_line(out, "1a-total");
    assert!(
        total.contains("169.67") && total.contains("169.97"),
        "{total}"
    );
    // The worked example carries the misprinted mean over: 494.6.
    let model = cause_line(out, "model-mean");
    assert!(
        model.contains("494.6") && model.contains("mean-rel1"),
        "{model}"
    );
    // Every claim appears in the table with its verdict.
    let table_row = |id: &str| {
        out.lines()
            .find(|l| l.starts_with(&format!("| {id} ")))
            .unwrap_or_else(|| panic!("no row for {id}"))
    };
    assert!(table_row("mean-rel1").contains("known erratum"));
    assert!(table_row("range-rel1").contains("matches (from rounded values)"));
    assert!(table_row("1b-rel1").contains("matches"));
    assert!(!out.contains("MISMATCH"));
}

#[test]
fn json_summary_and_verdicts() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let doc = wd.run(&["check", "--format", "json"]).ok().json();
    assert_eq!(doc["schema_version"], 6);
    assert_eq!(doc["claims_file"], "data/paper_claims.csv");
    assert_eq!(
        doc["dataset"]["sha256"].as_str().unwrap(),
        sha256sum(&wd.path().join("data/measurements.csv"))
    );
    let s = &doc["summary"];
    assert_eq!(s["mismatches"], 0);
    assert_eq!(s["claims"], 30);
    assert_eq!(s["matches"], 20);
    assert_eq!(s["matches_rounded"], 2);
    assert_eq!(s["known_errata"], 8);
    let claims = doc["claims"].as_array().unwrap();
    assert_eq!(claims.len(), 30);
    let claim = |id: &str| -> &Value {
        claims
            .iter()
            .find(|c| c["id"] == id)
            .unwrap_or_else(|| panic!("no claim {id}"))
    };
    let mean = claim("mean-rel1");
    assert_eq!(mean["verdict"], "known_erratum");
    assert_eq!(mean["stated_text"], "0.4946");
    assert_close(num(&mean["computed"]), 0.484_636, 1e-6, "mean-rel1");
    assert!(mean["cause"].as_str().unwrap().contains("0.4846"));
    assert!(mean["erratum_note"].is_string());
    assert_eq!(claim("range-rel1")["verdict"], "matches_rounded");
    assert_eq!(claim("model-range")["verdict"], "matches_rounded");
    assert_eq!(claim("1a-j3")["verdict"], "known_erratum");
    assert_eq!(claim("model-mean")["verdict"], "known_erratum");
    assert_eq!(claim("1b-total")["verdict"], "matches");
    assert!(claim("1b-total")["cause"].is_null());
    let verdicts: Vec<&str> = claims
        .iter()
        .map(|c| c["verdict"].as_str().unwrap())
        .collect();
    assert_eq!(
        verdicts.iter().filter(|v| **v == "known_erratum").count(),
        8
    );
}

#[test]
fn absolute_paths_work_from_any_directory() {
    let wd = Workdir::new(); // empty: the defaults would not be found
    let data = paper_data_path();
    let claims = paper_claims_path();
    let run = wd.run(&[
        "check",
        "--data",
        data.to_str().unwrap(),
        "--claims",
        claims.to_str().unwrap(),
    ]);
    run.ok().stdout_has(SUMMARY);
    // Without them the defaults are missing: a data error naming the path and what to do.
    wd.run(&["check"])
        .data_error()
        .stderr_has("data/measurements.csv is not in ")
        .stderr_has("or give --data PATH");
    wd.write("data/measurements.csv", paper_data());
    wd.run(&["check"])
        .data_error()
        .stderr_has("data/paper_claims.csv is not in ")
        .stderr_has("or give --claims PATH");
}

/// A claims file with the mean of eq. (6) stated as `stated`, erratum `erratum`.
fn mean_claim(stated: &str, erratum: &str) -> String {
    format!("{CLAIMS_HEADER}\nmy-mean,eq. (6),mean J~1,index,,rel_j1,mean,,{stated},{erratum},\n")
}

#[test]
fn an_unrecorded_mismatch_exits_1() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("wrong.csv", mean_claim("0.4946", ""));
    let run = wd.run(&["check", "--claims", "wrong.csv"]);
    run.expect_code(1)
        .stdout_has("MISMATCH")
        .stdout_has(
            "1 claims: 0 match, 0 match from rounded values, 0 known errata, 1 new mismatches",
        )
        .stderr_has("1 claim(s) disagree");
    // The cause names the value the data give.
    let cause = cause_line(&run.stdout, "my-mean");
    assert!(cause.contains("0.484636"), "{cause}");

    let run = wd.run(&["check", "--claims", "wrong.csv", "--format", "json"]);
    run.expect_code(1);
    let doc = run.json();
    assert_eq!(doc["summary"]["mismatches"], 1);
    assert_eq!(doc["claims"][0]["verdict"], "mismatch");

    // Recorded as an erratum: exit 0.
    wd.write("erratum.csv", mean_claim("0.4946", "yes"));
    let doc = wd
        .run(&["check", "--claims", "erratum.csv", "--format", "json"])
        .ok()
        .json();
    assert_eq!(doc["claims"][0]["verdict"], "known_erratum");
    // The right value: exit 0, and an erratum flag is not needed.
    wd.write("right.csv", mean_claim("0.4846", ""));
    let doc = wd
        .run(&["check", "--claims", "right.csv", "--format", "json"])
        .ok()
        .json();
    assert_eq!(doc["claims"][0]["verdict"], "matches");
    // Half a unit of the last digit decides: 0.48464 is right, 0.48465 is not.
    wd.write("close.csv", mean_claim("0.48465", ""));
    wd.run(&["check", "--claims", "close.csv"]).expect_code(1);
}

#[test]
fn a_changed_dataset_turns_claims_into_mismatches() {
    // Table 1 with 1a's J1 of the index finger changed: claims about 1a break.
    let wd = Workdir::new();
    wd.copy_paper_data();
    let text = String::from_utf8(paper_data())
        .unwrap()
        .replace("1a,index,339.96,", "1a,index,349.96,");
    wd.write("changed.csv", text);
    let run = wd.run(&["check", "--data", "changed.csv"]);
    run.expect_code(1).stdout_has("MISMATCH");
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("| 1a-j1 "))
        .unwrap();
    assert!(line.contains("MISMATCH"), "{line}");
}

#[test]
fn claims_about_a_finger_the_dataset_lacks() {
    let wd = Workdir::new();
    // Table 1 without the little finger.
    let rows: Vec<PaperRow> = paper_rows()
        .into_iter()
        .filter(|r| r.finger != "little")
        .collect();
    wd.write("m.csv", measurement_csv(&rows));
    wd.write(
        "c.csv",
        format!(
            "{CLAIMS_HEADER}\n\
             a,l,r,index,,rel_j1,mean,,0.4846,,\n\
             b,l,r,pinky,,rel_j1,mean,,0.4570,,\n"
        ),
    );
    wd.run(&["check", "--data", "m.csv", "--claims", "c.csv"])
        .data_error()
        .stderr_has("1 problem in c.csv:")
        .stderr_has("c.csv:3:4: finger: ")
        .stderr_has("has no little rows");
}

#[test]
fn claims_about_an_xray_the_dataset_lacks() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write(
        "c.csv",
        format!(
            "{CLAIMS_HEADER}\n\
             a,l,r,index,1a,j1,value,,339.96,,\n\
             b,l,r,index,1z,j1,value,,339.96,,\n\
             c,l,r,thumb,1b,rel_j1,value,,0.508,,\n"
        ),
    );
    let run = wd.run(&["check", "--claims", "c.csv"]);
    run.data_error()
        .stderr_has("1 problem in c.csv:")
        .stderr_has("c.csv:3:5: xray: ")
        .stderr_has("X-ray '1z'");
}

#[test]

fn dataset_mismatch_problems_use_the_real_column() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write(
        "c.csv",
        "finger,xray,id,location,refers_to,quantity,statistic,model_length,stated,erratum,note\n\
         index,1z,b,l,r,j1,value,,339.96,,\n",
    );
    wd.run(&["check", "--claims", "c.csv"])
        .data_error()
        .stderr_has("c.csv:2:2: xray: ");
}

#[test]

fn exponent_notation_keeps_its_precision() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // 0.4846 matches; the same number written 4.846e-1 must too.
    wd.write("c.csv", mean_claim("4.846e-1", ""));
    let doc = wd
        .run(&["check", "--claims", "c.csv", "--format", "json"])
        .ok()
        .json();
    assert_eq!(doc["claims"][0]["verdict"], "matches");
}

/// Runs `check` with `claims` (on the shipped data) and asserts exactly one
/// problem at `place` containing `message`.
#[track_caller]
fn claims_problem(claims: &str, place: &str, message: &str) {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("c.csv", claims);
    let run = wd.run(&["check", "--claims", "c.csv"]);
    run.data_error().stderr_has("1 problem in c.csv:");
    let lines = run.problem_lines();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].starts_with(place) && lines[0].contains(message),
        "expected {place:?} ... {message:?}, got:\n{}",
        run.stderr
    );
}

#[test]
fn every_claims_file_problem_names_its_place() {
    let row =
        |fields: &str| format!("{CLAIMS_HEADER}\nok,l,r,index,,rel_j1,mean,,0.4846,,\n{fields}\n");
    claims_problem(
        &row("x,l,r,toe,,rel_j1,mean,,0.5,,"),
        "c.csv:3:4: finger: ",
        "unknown finger 'toe'",
    );
    claims_problem(
        &row("x,l,r,index,,j4,mean,,0.5,,"),
        "c.csv:3:6: quantity: ",
        "unknown quantity 'j4'",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,average,,0.5,,"),
        "c.csv:3:7: statistic: ",
        "unknown statistic 'average'",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,mean,,about half,,"),
        "c.csv:3:9: stated: ",
        "'about half' is not a number",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,mean,,NaN,,"),
        "c.csv:3:9: stated: ",
        "is not a number",
    );
    claims_problem(
        &row("ok,l,r,index,,rel_j1,mean,,0.4846,,"),
        "c.csv:3:1: id: ",
        "already used on line 2",
    );
    claims_problem(
        &row(",l,r,index,,rel_j1,mean,,0.4846,,"),
        "c.csv:3:1: id: ",
        "is empty",
    );
    claims_problem(
        &row("x,l,r,thumb,,rel_j3,mean,,0.2,,"),
        "c.csv:3:6: quantity: ",
        "the thumb has no rel_j3",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,value,,0.5,,"),
        "c.csv:3:5: xray: ",
        "a 'value' claim is about one X-ray",
    );
    claims_problem(
        &row("x,l,r,index,,j1,mean,,300,,"),
        "c.csv:3:7: statistic: ",
        "raw lengths",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,mean,-5,0.5,,"),
        "c.csv:3:8: model_length: ",
        "'-5' is not a positive number",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,mean,,0.5,maybe,"),
        "c.csv:3:10: erratum: ",
        "'maybe' must be 'yes' or empty",
    );
    claims_problem(
        &row("x,l,r,index,,rel_j1,mean,,0.5"),
        "c.csv:3: ",
        "has 9 fields but the header has 11",
    );
    claims_problem(
        "id,location,refers_to,finger,xray,quantity,statistic,model_length,stated,erratum\n\
         a,l,r,index,,rel_j1,mean,,0.4846,\n",
        "c.csv:1: ",
        "lacks the required column 'note'",
    );
    claims_problem(
        &format!("{CLAIMS_HEADER}\n"),
        "c.csv: ",
        "has a header but no claims",
    );
    claims_problem("", "c.csv: ", "is empty");
}

#[test]
fn several_claims_problems_are_reported_together() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write(
        "c.csv",
        format!(
            "{CLAIMS_HEADER}\n\
             a,l,r,toe,,rel_j1,mean,,0.5,,\n\
             b,l,r,index,,rel_j1,mean,,x,,\n\
             c,l,r,index,,rel_j1,mean,,0.4846,,\n\
             a,l,r,index,,rel_j1,mean,,0.4846,,\n"
        ),
    );
    let run = wd.run(&["check", "--claims", "c.csv"]);
    run.data_error().stderr_has("3 problems in c.csv:");
    let lines = run.problem_lines();
    assert_eq!(lines.len(), 3, "{}", run.stderr);
    assert!(lines[0].starts_with("c.csv:2:4: finger: "));
    assert!(lines[1].starts_with("c.csv:3:9: stated: "));
    assert!(lines[2].starts_with("c.csv:5:1: id: "));
}

#[test]
fn claims_file_accepts_bom_crlf_and_blank_lines() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    let text = String::from_utf8(paper_claims())
        .unwrap()
        .replace('\n', "\r\n\r\n");
    bytes.extend(text.as_bytes());
    wd.write("c.csv", &bytes);
    wd.run(&["check", "--claims", "c.csv"])
        .ok()
        .stdout_has(SUMMARY);
}

#[test]
fn missing_or_directory_claims_file_is_a_data_error() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&["check", "--claims", "none.csv"])
        .data_error()
        .stderr_has("none.csv: no such file");
    wd.mkdir("claims_dir");
    wd.run(&["check", "--claims", "claims_dir"])
        .data_error()
        .stderr_has("claims_dir: is a directory");
    wd.write("bin.csv", b"\x00\x01\x02\xFF\xFE");
    wd.run(&["check", "--claims", "bin.csv"]).data_error();
}

/// The paper's X-rays plus 20 lab X-rays (each paper X-ray's lengths scaled and bent
/// a little, under new ids): the claims are about 1a-1e, so `check` still finds every
/// number the paper states where it found it (exit 0, the same summary), and the report
/// no longer calls the data "Table 1" or the placement "the paper's worked example".
#[test]
fn check_on_the_paper_plus_added_xrays_exits_0_and_titles_follow_the_data() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let paper = paper_rows();
    let mut rows = paper.clone();
    for k in 0..20 {
        let scale = 0.8 + 0.02 * k as f64;
        for r in paper
            .iter()
            .filter(|r| r.xray == ["1a", "1b", "1c", "1d", "1e"][k % 5])
        {
            let lengths = r
                .lengths
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    (x * scale * (1.0 + 0.01 * ((k + i) % 3) as f64) * 100.0).round() / 100.0
                })
                .collect();
            rows.push(PaperRow {
                xray: format!("lab{k:02}"),
                finger: r.finger.clone(),
                lengths,
            });
        }
    }
    assert_eq!(rows.len(), paper.len() * 5);
    wd.write("data/measurements.csv", measurement_csv(&rows));
    let run = wd.run(&["check"]);
    run.ok().stdout_has(SUMMARY);

    // The same claims against the paper alone give the same summary.
    let wd2 = Workdir::new();
    wd2.copy_paper_data();
    wd2.run(&["check"]).ok().stdout_has(SUMMARY);

    wd.run(&["report", "--format", "md", "--sims", "50", "--out", "out"])
        .ok();
    let md = String::from_utf8(wd.read("out/report.md")).unwrap();
    assert!(!md.contains("## 2. Table 1"), "{}", &md[..2000]);
    assert!(md.contains("## 2. The measurements"));
    assert!(md.contains("the 5 X-rays of the paper's Table 1 and 20 added since"));
    assert!(!md.contains("the paper's worked example"));
    wd2.run(&["report", "--format", "md", "--sims", "50", "--out", "out"])
        .ok();
    let md = String::from_utf8(wd2.read("out/report.md")).unwrap();
    assert!(md.contains("## 2. Table 1: the measurements"));
    assert!(md.contains("This is the paper's worked example"));
}
