//! What a user sees in everyday use: notes instead of empty groups, refusals
//! that say what to do, numbers kept as typed, implausible data named, and
//! calibrated outlier warnings (one per row).

use crate::common;

use common::*;

const DATA: &str = "data/measurements.csv";

fn text(wd: &Workdir, name: &str) -> String {
    String::from_utf8(wd.read(name)).unwrap()
}

#[test]
fn group_by_a_column_without_values_gives_a_note_not_an_unknown_group() {
    let wd = Workdir::new();
    wd.copy_paper_data(); // the paper gives no sex and no age
    for column in ["sex", "age"] {
        let run = wd.run(&["stats", "--group-by", column]);
        run.ok().stderr_has(&format!(
            "note: --group-by {column}: no row of {DATA} gives a value in the {column} column, so there is nothing to group by"
        ));
        assert!(!run.stdout.contains("unknown"), "{}", run.stdout);
        let json = wd.run(&["stats", "--group-by", column, "--format", "json"]);
        json.ok();
        assert!(!json.stdout.contains("\"unknown\""), "{}", json.stdout);
    }
    // The side is given: groups as before.
    let run = wd.run(&["stats", "--group-by", "side"]);
    run.ok();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert!(run.stdout.contains("right"), "{}", run.stdout);
}

#[test]
fn conflicting_metadata_says_what_to_do_and_omitting_it_takes_the_xrays_value() {
    let wd = Workdir::new();
    wd.write(
        DATA,
        "xray,finger,j1,j2,j3,sex,age,side,source,unit,tip\na,index,339.96,188.83,169.67,female,34,right,,,skin\nb,index,342.47,195.24,186.70,,,,,,skin\n",
    );
    let before = wd.read(DATA);
    wd.run(&[
        "add",
        "--xray",
        "a",
        "--finger",
        "ring",
        "--lengths",
        "358.4,226.47,191.09",
        "--side",
        "left",
    ])
    .data_error()
    .stderr_has(
        "side is 'left' but data/measurements.csv line 2 gives 'right' for the same X-ray 'a'",
    )
    .stderr_has("omit --side")
    .stderr_has("edit line 2 of data/measurements.csv");
    assert_eq!(wd.read(DATA), before, "a refused add changed the dataset");
    // Omitted: the new row takes the X-ray's sex, age and side.
    wd.run(&[
        "add",
        "--xray",
        "a",
        "--finger",
        "ring",
        "--lengths",
        "358.4,226.47,191.09",
    ])
    .ok();
    assert!(
        text(&wd, DATA).ends_with("a,ring,358.4,226.47,191.09,female,34,right,,,skin\n"),
        "{}",
        text(&wd, DATA)
    );
}

#[test]
fn numbers_are_kept_as_typed() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&[
        "add",
        "--xray",
        "2a",
        "--finger",
        "thumb",
        "--lengths",
        "275.00,231.10",
    ])
    .ok();
    assert!(
        // The dataset names one unit and one tip, so the new row is written with them.
        text(&wd, DATA).ends_with("2a,thumb,275.00,231.10,,,,,,image units,skin\n"),
        "{}",
        text(&wd, DATA)
    );
    wd.write(
        "new.csv",
        "xray,finger,j1,j2,j3,age\n2b,index,352.10, 201.40 ,1.78e2,\n",
    );
    wd.run(&["add", "new.csv"]).ok();
    assert!(
        text(&wd, DATA).ends_with("2b,index,352.10,201.40,1.78e2,,,,,image units,skin\n"),
        "{}",
        text(&wd, DATA)
    );
}

#[test]
fn history_names_every_quantity_and_explains_an_empty_selection() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&["history", "--quantity", "j1"])
        .data_error()
        .stderr_has("rel_j1, rel_j2, rel_j3, ratio_j2_j1, ratio_j3_j2, total");
    let help = wd.run(&["history", "--help"]);
    help.ok()
        .stdout_has("ratio_j2_j1")
        .stdout_has("ratio_j3_j2");
    wd.run(&["snapshot"]).ok();
    wd.run(&["history", "--quantity", "ratio_j3_j2"])
        .ok()
        .stdout_has("J3/J2");
    wd.run(&["history", "--finger", "thumb", "--quantity", "rel_j3"])
        .data_error()
        .stderr_has("the thumb has no rel_j3 (2 segments); its quantities are rel_j1, rel_j2, ratio_j2_j1, total");
    // A finger the history lacks.
    wd.write(
        "one.csv",
        "xray,finger,j1,j2,j3\na,index,4,3,3\nb,index,5,3,3\n",
    );
    wd.run(&["snapshot", "--data", "one.csv", "--history", "h.jsonl"])
        .ok();
    wd.run(&["history", "--history", "h.jsonl", "--finger", "ring"])
        .data_error()
        .stderr_has("none of the 1 snapshots in h.jsonl has ring rows (fingers recorded: index)");
}

#[test]
fn swapped_columns_are_named_in_stats_report_and_add() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    // The index finger typed tip first: j1 and j3 swapped in every row.
    let swapped: String = text(&wd, DATA)
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            if f[1] == "index" {
                let mut g = f.clone();
                g.swap(2, 4);
                g.join(",")
            } else {
                l.to_string()
            }
        })
        .map(|l| l + "\n")
        .collect();
    wd.write("swapped.csv", &swapped);
    let warning =
        "warning: index: J3 (distal) is longer than J1 (proximal) in every one of its 5 X-rays";
    wd.run(&["stats", "--data", "swapped.csv"])
        .ok()
        .stderr_has(warning)
        .stderr_has("j1 and j3 look swapped");
    let out = wd.path().join("site");
    wd.run(&[
        "report",
        "--data",
        "swapped.csv",
        "--sims",
        "5",
        "--out",
        out.to_str().unwrap(),
        "--format",
        "md",
    ])
    .ok()
    .stderr_has(warning);
    let md = String::from_utf8(std::fs::read(out.join("report.md")).unwrap()).unwrap();
    assert!(
        md.contains("j1 and j3 look swapped"),
        "report.md lacks the warning"
    );
    wd.run(&[
        "add",
        "--data",
        "swapped.csv",
        "--xray",
        "2a",
        "--finger",
        "index",
        "--lengths",
        "178.0,201.4,352.1",
    ])
    .ok()
    .stderr_has("in every one of its 6 X-rays");
    // The paper's data: no warning.
    let run = wd.run(&["stats"]);
    assert!(run.stderr.is_empty(), "{}", run.stderr);
}

#[test]
fn report_out_naming_a_file_says_it_is_a_file() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("notes.txt", "mine");
    wd.run(&["report", "--out", "notes.txt"])
        .data_error()
        .stderr_has("--out notes.txt: this is a file, not a directory");
    wd.run(&["report", "--out", "notes.txt/site"])
        .data_error()
        .stderr_has("notes.txt is a file, not a directory");
    assert_eq!(wd.read("notes.txt"), b"mine");
}
