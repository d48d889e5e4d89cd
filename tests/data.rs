//! The measurement file through the binary: every validation error with its
//! place (`FILE:LINE:COLUMN: FIELD: message`), exit codes of data errors, and
//! the inputs that must be accepted (BOM, CRLF, quotes, blank lines, aliases).

use crate::common;

use common::*;
use serde_json::Value;

/// Writes `contents` to `m.csv`, runs `stats --data m.csv` and asserts a data
/// error with exactly one problem whose line starts with `place` (the
/// `FILE:LINE:COLUMN: FIELD: ` prefix) and contains `message`.
#[track_caller]
fn one_problem(contents: &[u8], place: &str, message: &str) -> Run {
    let wd = Workdir::new();
    wd.write("m.csv", contents);
    let run = wd.run(&["stats", "--data", "m.csv", "--resamples", "10"]);
    run.data_error().stderr_has("error: 1 problem in m.csv:");
    let lines = run.problem_lines();
    assert_eq!(lines.len(), 1, "one problem expected:\n{}", run.stderr);
    assert!(
        lines[0].starts_with(place),
        "expected the problem at {place:?}, got:\n{}",
        run.stderr
    );
    assert!(
        lines[0].contains(message),
        "expected {message:?} in:\n{}",
        run.stderr
    );
    run
}

/// A file whose line 2 is valid and line 3 is `bad`.
fn with_bad_line3(bad: &str) -> Vec<u8> {
    format!("{HEADER}\n1a,index,339.96,188.83,169.67\n{bad}\n").into_bytes()
}

#[test]
fn missing_header_column_names_line_and_column() {
    // A missing column has no position of its own: the problem sits on the
    // header line and names the column.
    one_problem(
        b"xray,finger,j1,j2\n1a,index,1,2\n",
        "m.csv:1: ",
        "lacks the required column 'j3'",
    );
    one_problem(
        b"finger,j1,j2,j3\nindex,1,2,3\n",
        "m.csv:1: ",
        "lacks the required column 'xray'",
    );
}

#[test]
fn unknown_and_duplicated_header_columns() {
    one_problem(
        b"xray,finger,j1,j2,j3,colour\n1a,index,1,2,3,red\n",
        "m.csv:1:6: ",
        "unknown column 'colour'",
    );
    one_problem(
        b"xray,finger,j1,j2,j3,J1\n1a,index,1,2,3,4\n",
        "m.csv:1:6: j1: ",
        "appears twice",
    );
}

#[test]
fn unknown_finger() {
    one_problem(
        &with_bad_line3("1b,toe,1,2,3"),
        "m.csv:3:2: finger: ",
        "unknown finger 'toe'",
    );
}

#[test]
fn non_numeric_length() {
    one_problem(
        &with_bad_line3("1b,index,abc,2,3"),
        "m.csv:3:3: j1: ",
        "'abc' is not a number",
    );
    // A decimal comma is explained.
    one_problem(
        &with_bad_line3("1b,index,1,\"2,5\",3"),
        "m.csv:3:4: j2: ",
        "decimal comma",
    );
}

#[test]
fn empty_length() {
    one_problem(
        &with_bad_line3("1b,index,1,,3"),
        "m.csv:3:4: j2: ",
        "is empty",
    );
}

#[test]
fn zero_and_negative_lengths() {
    one_problem(
        &with_bad_line3("1b,index,0,2,3"),
        "m.csv:3:3: j1: ",
        "is zero",
    );
    one_problem(
        &with_bad_line3("1b,index,1,-2,3"),
        "m.csv:3:4: j2: ",
        "'-2' is negative",
    );
    one_problem(
        &with_bad_line3("1b,index,1,2,-0.0"),
        "m.csv:3:5: j3: ",
        "is zero",
    );
}

#[test]
fn nan_length() {
    for nan in ["NaN", "nan", "+NaN"] {
        one_problem(
            &with_bad_line3(&format!("1b,index,1,{nan},3")),
            "m.csv:3:4: j2: ",
            "(NaN)",
        );
    }
}

#[test]
fn infinite_length() {
    for inf in ["inf", "Infinity", "-inf", "+INF"] {
        one_problem(
            &with_bad_line3(&format!("1b,index,1,2,{inf}")),
            "m.csv:3:5: j3: ",
            "is infinite",
        );
    }
    // A finite spelling that overflows f64.
    one_problem(
        &with_bad_line3("1b,index,1e400,2,3"),
        "m.csv:3:3: j1: ",
        "too large",
    );
    // Finite lengths whose sum overflows.
    one_problem(
        &with_bad_line3("1b,index,1e308,1e308,1e308"),
        "m.csv:3: ",
        "add up to more than",
    );
}

#[test]
fn thumb_row_with_j3() {
    one_problem(
        &with_bad_line3("1a,thumb,270.83,230.95,99"),
        "m.csv:3:5: j3: ",
        "the thumb has only J1 and J2",
    );
}

#[test]
fn finger_row_without_j3() {
    one_problem(
        &with_bad_line3("1a,ring,358.40,226.47,"),
        "m.csv:3:5: j3: ",
        "the ring finger has three segments",
    );
}

#[test]
fn duplicate_xray_and_finger() {
    // Aliases count: 'grooming' is the index finger.
    let run = one_problem(
        &with_bad_line3("1a,grooming,1,2,3"),
        "m.csv:3:1: xray: ",
        "duplicate row",
    );
    run.stderr_has("X-ray '1a'").stderr_has("on line 2");
}

#[test]

fn duplicate_row_names_its_column() {
    one_problem(
        &with_bad_line3("1a,index,1,2,3"),
        "m.csv:3:1: xray: ",
        "duplicate row",
    );
}

#[test]
fn wrong_number_of_fields() {
    one_problem(
        &with_bad_line3("1b,index,1,2"),
        "m.csv:3: ",
        "has 4 fields but the header has 5",
    );
    one_problem(
        &with_bad_line3("1b,index,1,2,3,4"),
        "m.csv:3: ",
        "has 6 fields but the header has 5",
    );
}

#[test]
fn empty_file() {
    for contents in [&b""[..], b"\n\n  \n", b"\xEF\xBB\xBF"] {
        one_problem(contents, "m.csv: ", "is empty");
    }
    one_problem(
        format!("{HEADER}\n\n").as_bytes(),
        "m.csv: ",
        "has a header but no data rows",
    );
}

#[test]
fn non_utf8_bytes() {
    // Latin-1 'é' (0xE9) in the X-ray id on line 3.
    one_problem(
        b"xray,finger,j1,j2,j3\n1a,index,1,2,3\nr\xE9f,index,1,2,3\n",
        "m.csv:3:1: ",
        "is not UTF-8 text (bad byte 0xE9",
    );
    one_problem(b"\xFF\xFEx\x00r\x00a\x00y\x00", "m.csv: ", "is UTF-16 text");
    one_problem(
        b"xray,finger,j1,j2,j3\n1a,ind\x00ex,1,2,3\n",
        "m.csv:2:2: ",
        "NUL byte",
    );
}

#[test]
fn metadata_errors() {
    one_problem(
        b"xray,finger,j1,j2,j3,age\n1a,index,1,2,3,200\n",
        "m.csv:2:6: age: ",
        "'200' is not an age",
    );
    one_problem(
        b"xray,finger,j1,j2,j3,side\n1a,index,1,2,3,up\n",
        "m.csv:2:6: side: ",
        "'up' is not a side",
    );
    // One X-ray is one hand: its rows must agree on the side.
    one_problem(
        b"xray,finger,j1,j2,j3,side\n1a,index,1,2,3,left\n1a,ring,1,2,3,right\n",
        "m.csv:3:6: side: ",
        "line 2 gives 'left'",
    );
}

#[test]
fn several_errors_are_all_reported_together() {
    let wd = Workdir::new();
    let text = "\
xray,finger,j1,j2,j3
1a,index,339.96,188.83,169.67
1a,toe,1,2,3
1b,index,abc,2,3

1c,thumb,1,2,3
1c,middle,1,2,
1a,index,1,2,3
1d,little,1,NaN,-4
";
    wd.write("bad.csv", text);
    let run = wd.run(&["stats", "--data", "bad.csv"]);
    run.data_error();
    let lines = run.problem_lines();
    let expected = [
        "bad.csv:3:2: finger: ",
        "bad.csv:4:3: j1: ",
        "bad.csv:6:5: j3: ",
        "bad.csv:7:5: j3: ",
        "bad.csv:8:1: xray: ",
        "bad.csv:9:4: j2: ",
        "bad.csv:9:5: j3: ",
    ];
    run.stderr_has(&format!("error: {} problems in bad.csv:", expected.len()));
    assert_eq!(lines.len(), expected.len(), "{}", run.stderr);
    for (line, want) in lines.iter().zip(expected) {
        assert!(line.starts_with(want), "expected {want:?}, got {line:?}");
    }
    // The same problems from every command that reads the file.
    wd.copy_paper_data();
    for args in [
        &["check", "--data", "bad.csv"][..],
        &["coverage", "--data", "bad.csv", "--sims", "1"],
    ] {
        let other = wd.run(args);
        other.data_error();
        assert_eq!(other.problem_lines(), lines, "{args:?}");
    }
}

#[test]
fn line_numbers_survive_bom_crlf_blank_lines_and_quoted_newlines() {
    // BOM + CRLF + blank lines: the bad row is on line 5.
    one_problem(
        b"\xEF\xBB\xBFxray,finger,j1,j2,j3\r\n1a,index,1,2,3\r\n\r\n   \r\n1b,index,x,2,3\r\n",
        "m.csv:5:3: j1: ",
        "'x' is not a number",
    );
    // A quoted field spanning two lines: the next row is on line 4.
    one_problem(
        b"xray,finger,j1,j2,j3,source\n1a,index,1,2,3,\"two\nlines\"\n1b,index,1,x,3,\n",
        "m.csv:4:4: j2: ",
        "'x' is not a number",
    );
    // A line of empty fields counts as blank.
    one_problem(
        b"xray,finger,j1,j2,j3\n,,,,\n1b,index,1,2,0\n",
        "m.csv:3:5: j3: ",
        "is zero",
    );
}

#[test]

fn line_numbers_with_cr_only_line_ends() {
    one_problem(
        b"xray,finger,j1,j2,j3\r1a,index,1,2,3\r1b,index,x,2,3\r",
        "m.csv:3:3: j1: ",
        "'x' is not a number",
    );
}

#[test]

fn non_utf8_problem_names_its_field() {
    one_problem(
        b"xray,finger,j1,j2,j3\n1a,ind\xFFex,1,2,3\n",
        "m.csv:2:2: finger: ",
        "is not UTF-8",
    );
}

#[test]
fn missing_file_and_directory_are_data_errors_for_every_command() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.mkdir("adir");
    for cmd in [&["stats"][..], &["check"], &["coverage", "--sims", "10"]] {
        let mut args = cmd.to_vec();
        args.extend(["--data", "nope.csv"]);
        wd.run(&args)
            .data_error()
            .stderr_has("nope.csv: no such file");
        let mut args = cmd.to_vec();
        args.extend(["--data", "adir"]);
        wd.run(&args)
            .data_error()
            .stderr_has("adir: is a directory");
    }
}

/// Runs `stats --format json` on `contents` and returns the document.
fn stats_json(contents: &[u8]) -> Value {
    let wd = Workdir::new();
    wd.write("m.csv", contents);
    wd.run(&["stats", "--data", "m.csv", "--format", "json"])
        .ok()
        .json()
}

/// The paper's data rewritten by `edit` (applied to each data line).
fn paper_lines(edit: impl Fn(&str) -> String) -> String {
    let text = String::from_utf8(paper_data()).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let mut out = vec![header];
    out.extend(lines.map(edit));
    out.join("\n") + "\n"
}

/// Asserts the statistics of `doc` equal those of the shipped file.
#[track_caller]
fn same_statistics_as_paper(doc: &Value) {
    let paper = stats_json(&paper_data());
    assert_eq!(doc["dataset"]["xrays"], 5);
    assert_eq!(doc["dataset"]["rows"], 25);
    let names: Vec<&Value> = doc["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| &f["finger"])
        .collect();
    assert_eq!(
        names,
        ["thumb", "index", "middle", "ring", "little"],
        "fingers in hand order, canonical names"
    );
    for f in doc["fingers"].as_array().unwrap() {
        assert_eq!(f["n"], 5, "{}", f["finger"]);
    }
    assert_eq!(doc["fingers"], paper["fingers"]);
}

#[test]
fn accepts_utf8_bom() {
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(paper_data());
    same_statistics_as_paper(&stats_json(&bytes));
}

#[test]
fn accepts_crlf() {
    let text = String::from_utf8(paper_data())
        .unwrap()
        .replace('\n', "\r\n");
    same_statistics_as_paper(&stats_json(text.as_bytes()));
}

#[test]
fn accepts_quoted_fields_and_spaces() {
    let text = paper_lines(|l| {
        // Quote every field (the source field is quoted already).
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(l.as_bytes());
        let rec = rdr.records().next().unwrap().unwrap();
        rec.iter()
            .map(|f| format!("\" {} \"", f.replace('"', "\"\"")))
            .collect::<Vec<_>>()
            .join(",")
    });
    same_statistics_as_paper(&stats_json(text.as_bytes()));
}

#[test]
fn accepts_blank_lines_anywhere() {
    let text = paper_lines(|l| format!("{l}\n")) + "\n\n   \n";
    same_statistics_as_paper(&stats_json(text.as_bytes()));
}

#[test]
fn accepts_finger_aliases_in_any_case() {
    let text = paper_lines(|l| {
        l.replace(",index,", ",Grooming,")
            .replace(",little,", ",pinky,")
            .replace(",thumb,", ",THUMB,")
            .replace(",middle,", ",Middle,")
            .replace(",ring,", ", rInG ,")
    });
    assert!(text.contains("Grooming") && text.contains("pinky"));
    same_statistics_as_paper(&stats_json(text.as_bytes()));
    // The other aliases too.
    let text = paper_lines(|l| {
        l.replace(",index,", ",Pointer,")
            .replace(",little,", ",SMALL,")
    });
    same_statistics_as_paper(&stats_json(text.as_bytes()));
}

#[test]
fn accepts_columns_in_any_order_and_without_metadata() {
    let mut text = String::from("j3,j2,j1,finger,xray\n");
    for r in paper_rows() {
        let j3 = r.lengths.get(2).map_or(String::new(), |x| x.to_string());
        text.push_str(&format!(
            "{j3},{},{},{},{}\n",
            r.lengths[1], r.lengths[0], r.finger, r.xray
        ));
    }
    same_statistics_as_paper(&stats_json(text.as_bytes()));
}

#[test]
fn no_panic_on_garbage() {
    // Deterministic pseudo-random bytes.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut noise = Vec::new();
    for _ in 0..4096 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        noise.push((x >> 24) as u8);
    }
    let long_line = format!("{HEADER}\n1a,index,{},2,3\n", "9".repeat(100_000));
    let many_columns = format!("{HEADER}{}\n", ",x".repeat(2000));
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("noise", noise),
        ("commas", b",,,,,,,,\n,,,\n".to_vec()),
        ("quotes", b"\"\"\"\"\"\n\"".to_vec()),
        (
            "unterminated quote",
            format!("{HEADER}\n1a,index,\"1,2,3\n1b,index,1,2,3\n").into_bytes(),
        ),
        ("long line", long_line.into_bytes()),
        ("many columns", many_columns.into_bytes()),
        ("header twice", format!("{HEADER}\n{HEADER}\n").into_bytes()),
        ("lone CR", b"\r".to_vec()),
        ("NUL bytes", vec![0u8; 64]),
        (
            "huge id",
            format!("{HEADER}\n{},index,1,2,3\n", "x".repeat(50_000)).into_bytes(),
        ),
        (
            "tiny lengths",
            format!("{HEADER}\n1a,index,1e-320,1e-320,1e-320\n1b,index,5e-324,1,1\n").into_bytes(),
        ),
    ];
    let wd = Workdir::new();
    for (name, bytes) in cases {
        wd.write("g.csv", &bytes);
        for args in [
            &["stats", "--data", "g.csv", "--format", "json"][..],
            &["coverage", "--data", "g.csv", "--sims", "20"],
        ] {
            let run = wd.run(args);
            // The harness has already asserted that nothing panicked.
            assert!(
                matches!(run.code, Some(0 | 2)),
                "{name}: exit {:?}\n{}",
                run.code,
                run.stderr
            );
            if run.code == Some(0) {
                assert!(!run.stdout.is_empty(), "{name}: success without output");
            } else {
                assert!(run.stderr.contains("g.csv"), "{name}: {}", run.stderr);
            }
        }
    }
}
