//! What people read: terminal tables that fit the width (and `--wide`), CSV
//! numbers without float noise, coverage by sample size, the report's key
//! results and citation, files exported by other tools, and runs outside the
//! checkout.

use crate::audit::hand::{HandSpec, Naming, build};
use crate::common;

use common::*;

/// Terminal columns of the widest line (counted in characters, not bytes).
fn widest(text: &str) -> usize {
    text.lines().map(|l| l.chars().count()).max().unwrap_or(0)
}

/// A work directory with the paper's data, a history of one snapshot and two rigs.
fn paper_workdir() -> Workdir {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write(
        "data/history.jsonl",
        std::fs::read(manifest_dir().join("data/history.jsonl")).unwrap(),
    );
    wd.write("hand.glb", build(&HandSpec::new(Naming::Mixamo)));
    wd.write(
        "avatar.vrm",
        std::fs::read(manifest_dir().join("docs/examples/avatar.vrm")).unwrap(),
    );
    wd
}

/// Every table command, as a user would run it.
const COMMANDS: &[&[&str]] = &[
    &["stats"],
    &["stats", "--group-by", "side"],
    &["check"],
    &["coverage", "--sims", "200"],
    &["place", "--finger", "index", "--length", "1000"],
    &[
        "place",
        "--hand",
        "thumb=5.1,index=7.9,middle=8.6,ring=8.1,little=6.4",
    ],
    &["history"],
    &["audit", "--explain", "hand.glb"],
    &["audit", "--explain", "avatar.vrm"],
];

#[test]
fn every_table_command_fits_100_columns_when_not_a_terminal() {
    let wd = paper_workdir();
    for args in COMMANDS {
        let run = wd.run(args);
        run.ok();
        assert!(
            widest(&run.stdout) <= 100,
            "phalanx {args:?}: a line of {} columns:\n{}",
            widest(&run.stdout),
            run.stdout
        );
        assert!(run.stdout.lines().count() > 3, "{}", run.stdout);
    }
}

#[test]
fn columns_sets_a_narrower_width() {
    let wd = paper_workdir();
    for args in COMMANDS {
        let run = wd.run_env(args, &[("COLUMNS", "60")]);
        run.ok();
        assert!(
            widest(&run.stdout) <= 60,
            "COLUMNS=60 phalanx {args:?}: a line of {} columns:\n{}",
            widest(&run.stdout),
            run.stdout
        );
    }
}

#[test]
fn stats_keeps_what_matters_names_what_it_hid_and_wide_shows_everything() {
    let wd = paper_workdir();
    let run = wd.run(&["stats"]);
    run.ok();
    let header = run
        .stdout
        .lines()
        .find(|l| l.starts_with("| quantity"))
        .unwrap()
        .to_string();
    // The paper's four statistics (mean, min, max, range) stay at 100 columns.
    for kept in ["mean", "min", "max", "range", "sd", "t CI"] {
        assert!(header.contains(kept), "{kept} went: {header}");
    }
    for gone in ["percentile CI", "BCa CI", "prediction"] {
        assert!(!header.contains(gone), "{gone} stayed: {header}");
    }
    let flat = run.stdout.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat.contains("(Not shown to fit 100 columns: percentile CI, BCa CI, se, prediction. --wide shows every column"),
        "{}",
        run.stdout
    );
    // --wide: every column, on lines as long as they take (as before).
    let wide = wd.run(&["stats", "--wide"]);
    wide.ok();
    let header = wide
        .stdout
        .lines()
        .find(|l| l.starts_with("| quantity"))
        .unwrap();
    for col in [
        "mean",
        "min",
        "max",
        "range",
        "sd",
        "se",
        "t CI",
        "percentile CI",
        "BCa CI",
        "prediction",
    ] {
        assert!(header.contains(col), "--wide lacks {col}: {header}");
    }
    assert!(widest(&wide.stdout) > 140, "{}", wide.stdout);
    assert!(!wide.stdout.contains("Not shown"), "{}", wide.stdout);
    // A global option: also after the command's own, and for audit.
    let audit = wd.run(&["audit", "--explain", "hand.glb", "--wide"]);
    audit.ok().stdout_has("X-ray range");
    assert!(widest(&audit.stdout) > 100);
    let fitted = wd.run(&["audit", "--explain", "hand.glb"]);
    assert!(widest(&fitted.stdout) <= 100, "{}", fitted.stdout);
}

#[test]
fn csv_numbers_carry_no_float_noise() {
    let wd = paper_workdir();
    let run = wd.run(&["stats", "--format", "csv"]);
    run.ok();
    // The thumb's mean total J: (501.78 + 510.87 + 495.38 + 566.39 + 525.57) / 5 = 519.998
    // (Table 1), which f64 arithmetic gives as 519.9979999999999.
    assert!(run.stdout.contains(",519.998,"), "{}", run.stdout);
    assert!(!run.stdout.contains("9999999"), "{}", run.stdout);
    assert!(!run.stdout.contains("0000000001"), "{}", run.stdout);
    // JSON keeps every bit.
    let doc = wd.run(&["stats", "--format", "json"]).ok().json();
    let total = num(&quantity(&doc, "thumb", "total")["mean"]);
    assert_eq!(total, 519.9979999999999);
}

#[test]
fn coverage_has_one_row_per_sample_size() {
    let wd = paper_workdir();
    let run = wd.run(&["coverage", "--sims", "400"]);
    run.ok();
    let rows: Vec<Vec<String>> = run
        .stdout
        .lines()
        .filter(|l| l.starts_with('|') && !l.starts_with("|-") && !l.contains("n (X-rays)"))
        .map(|l| l.split('|').map(|c| c.trim().to_string()).collect())
        .collect();
    let sizes: Vec<&str> = rows.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(
        sizes,
        ["3", "4", "5", "6", "8", "10", "15", "20", "30", "50"],
        "{}",
        run.stdout
    );
    // The paper's n is marked; its numbers are coverages.
    let five = &rows[2];
    assert_eq!(five[6], "this data", "{five:?}");
    for cell in &five[2..6] {
        assert!(cell.ends_with('%'), "{five:?}");
    }
    // Which interval to use, from the simulation at n = 5 X-rays.
    let flat = run.stdout.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat.contains("At n = 5 X-rays, the t interval covers the mean"),
        "{flat}"
    );
    assert!(flat.contains("the bootstrap percentile ("), "{flat}");
    assert!(flat.contains("Use the t interval for the mean"), "{flat}");
}

#[test]
fn report_opens_with_key_results_and_says_how_to_cite() {
    let wd = paper_workdir();
    wd.run(&["report", "--out", "site", "--sims", "400"]).ok();
    let html = String::from_utf8(wd.read("site/index.html")).unwrap();
    let md = String::from_utf8(wd.read("site/report.md")).unwrap();
    // The box comes before the table of contents.
    let key = html.find("id=\"key-results\"").expect("key results box");
    assert!(key < html.find("<nav").unwrap());
    for needle in [
        "PIP at 48.5% (",
        "IP at 53.1% (",
        "8 of the paper&#x27;s 30 stated numbers disagree",
        "href=\"#claim-mean-rel1\"",
        "id=\"claim-mean-rel1\"",
        "At n = 5 X-rays, the t interval covers the mean",
        "How to cite",
        "Jian J. Zhang",
        "names no venue, year or pages",
        "CITATION.cff",
        "(n = 5 X-rays; bootstrap",
    ] {
        assert!(html.contains(needle), "index.html lacks {needle:?}");
    }
    for needle in [
        "> ## Key results",
        "PIP at 48.5% (",
        "How to cite",
        "(n = 5 X-rays; bootstrap",
    ] {
        assert!(md.contains(needle), "report.md lacks {needle:?}");
    }
    // "n = 5" is always followed by its unit.
    for (name, text) in [("index.html", &html), ("report.md", &md)] {
        for (i, _) in text.match_indices("n = 5") {
            assert!(
                text[i..].starts_with("n = 5 X-ray"),
                "{name}: {}",
                &text[i.saturating_sub(40)..(i + 40).min(text.len())]
            );
        }
    }
    // Coverage: one row per sample size, and a plot of it.
    let section = &html[html.find("id=\"coverage-table\"").unwrap()..];
    let table = &section[..section.find("</table>").unwrap()];
    assert_eq!(table.matches("<tr").count(), 11, "{table}");
    assert_eq!(table.matches("class=\"this-data\"").count(), 1, "{table}");
    assert!(html.contains("id=\"plot-coverage\""));
    assert!(wd.path().join("site/plots/coverage.svg").exists());
}

#[test]
fn citation_cff_has_the_required_keys() {
    let text = std::fs::read_to_string(manifest_dir().join("CITATION.cff")).unwrap();
    let cargo = std::fs::read_to_string(manifest_dir().join("Cargo.toml")).unwrap();
    let version = cargo
        .lines()
        .find_map(|l| l.strip_prefix("version = "))
        .unwrap()
        .trim_matches('"');
    // Top-level keys: every line that is neither indented, a comment nor a list item.
    let keys: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with([' ', '#', '-']) && !l.is_empty())
        .map(|l| l.split(':').next().unwrap())
        .collect();
    for required in ["cff-version", "message", "title", "authors"] {
        assert!(
            keys.contains(&required),
            "CITATION.cff lacks {required}: {keys:?}"
        );
    }
    assert!(
        !text.contains('\t'),
        "YAML does not allow tabs for indentation"
    );
    assert!(text.contains("\ncff-version: 1.2.0\n") || text.starts_with("cff-version: 1.2.0\n"));
    assert!(
        text.contains(&format!("\nversion: {version}\n")),
        "version differs from Cargo.toml"
    );
    // MIT OR Apache-2.0, as CFF writes an SPDX disjunction: a list.
    assert!(text.contains("license:\n  - MIT\n  - Apache-2.0\n"));
    assert!(cargo.contains("license = \"MIT OR Apache-2.0\""));
    assert!(text.contains("Statistical Analysis of Joint Determination"));
    // The README says how to cite.
    let readme = std::fs::read_to_string(manifest_dir().join("README.md")).unwrap();
    assert!(
        readme.contains("## How to cite"),
        "README lacks How to cite"
    );
    assert!(readme.contains("CITATION.cff"));
}

/// The paper's measurements with another separator (and decimal commas for `;`).
fn other_separator(sep: char) -> String {
    let text = String::from_utf8(paper_data()).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let mut out = rdr
        .headers()
        .unwrap()
        .iter()
        .collect::<Vec<_>>()
        .join(&sep.to_string());
    out.push('\n');
    for r in rdr.records() {
        let r = r.unwrap();
        let cells: Vec<String> = r
            .iter()
            .map(|c| {
                if sep == ';' {
                    c.replace('.', ",")
                } else {
                    c.to_string()
                }
            })
            .collect();
        out.push_str(&cells.join(&sep.to_string()));
        out.push('\n');
    }
    out
}

#[test]
fn a_semicolon_or_tab_separated_or_headerless_file_gets_one_message() {
    let wd = paper_workdir();
    wd.write("semi.csv", other_separator(';'));
    wd.write("tab.tsv", other_separator('\t'));
    let data = String::from_utf8(paper_data()).unwrap();
    wd.write("nohead.csv", data.split_once('\n').unwrap().1);
    let cases = [
        (
            "semi.csv",
            "looks semicolon-separated",
            "replace each ';' with ','",
        ),
        (
            "tab.tsv",
            "looks tab-separated",
            "replace each tab with ','",
        ),
        (
            "nohead.csv",
            "has no header line",
            "add the header line xray,finger,j1,j2,j3",
        ),
    ];
    for (file, what, todo) in cases {
        let run = wd.run(&["stats", "--data", file]);
        run.data_error()
            .stderr_has(&format!("error: 1 problem in {file}:"))
            .stderr_has(what)
            .stderr_has(todo);
        assert_eq!(run.problem_lines().len(), 1, "{}", run.stderr);
    }
    let run = wd.run(&["stats", "--data", "semi.csv"]);
    run.stderr_has("save it as 'CSV UTF-8 (Comma delimited)'")
        .stderr_has("339,96 -> 339.96");
    // Claims.
    let claims = String::from_utf8(paper_claims()).unwrap();
    wd.write("claims-semi.csv", claims.replace(',', ";"));
    wd.write("claims-nohead.csv", claims.split_once('\n').unwrap().1);
    for (file, what) in [
        ("claims-semi.csv", "looks semicolon-separated"),
        ("claims-nohead.csv", "has no header line"),
    ] {
        let run = wd.run(&["check", "--claims", file]);
        run.data_error().stderr_has(what);
        assert_eq!(run.problem_lines().len(), 1, "{}", run.stderr);
    }
    // Rig name maps.
    wd.write("bones.glb", build(&HandSpec::new(Naming::Anonymous)));
    wd.write(
        "map-semi.csv",
        "node;side;finger;joint\nBone.003;right;index;MCP\n",
    );
    wd.write(
        "map-tab.csv",
        "node\tside\tfinger\tjoint\nBone.003\tright\tindex\tMCP\n",
    );
    wd.write(
        "map-nohead.csv",
        "Bone.003,right,index,MCP\nBone.004,right,index,PIP\n",
    );
    for (file, what, todo) in [
        (
            "map-semi.csv",
            "looks semicolon-separated",
            "replace each ';'",
        ),
        ("map-tab.csv", "looks tab-separated", "replace each tab"),
        (
            "map-nohead.csv",
            "has no header line",
            "add the header line node,side,finger,joint above it",
        ),
    ] {
        let run = wd.run(&["audit", "--explain", "bones.glb", "--map", file]);
        run.data_error().stderr_has(what).stderr_has(todo);
        assert_eq!(run.problem_lines().len(), 1, "{}", run.stderr);
    }
    // A header with mistakes is still reported column by column.
    wd.write("typo.csv", "xray,fingr,j1,j2,j3\n1a,index,1,2,3\n");
    let run = wd.run(&["stats", "--data", "typo.csv"]);
    run.data_error().stderr_has("unknown column 'fingr'");
}

#[test]
fn outside_the_checkout_the_error_says_what_to_do() {
    let wd = Workdir::new(); // no data/ here
    for args in [
        &["stats"][..],
        &["check"],
        &["report"],
        &["place", "--finger", "index", "--length", "1"],
        &["history"],
    ] {
        let run = wd.run(args);
        run.data_error()
            .stderr_has("data/measurements.csv is not in ")
            .stderr_has("Run it from the phalanx checkout")
            .stderr_has("or give --data PATH");
    }
    // With the data given, the claims are missing next.
    wd.write("m.csv", paper_data());
    wd.run(&["check", "--data", "m.csv"])
        .data_error()
        .stderr_has("data/paper_claims.csv is not in ")
        .stderr_has("or give --claims PATH");
    // A path the user typed keeps the plain message.
    wd.run(&["stats", "--data", "nope.csv"])
        .data_error()
        .stderr_has("nope.csv: no such file; check the path");
}

/// The README's set-up states the minimum Rust version Cargo.toml declares, that
/// the first build takes minutes, and what happens outside the checkout (the
/// message quoted is the one the binary prints).
#[test]
fn the_readme_setup_states_rust_version_first_build_and_outside_the_checkout() {
    let readme = std::fs::read_to_string(manifest_dir().join("README.md")).unwrap();
    let cargo = std::fs::read_to_string(manifest_dir().join("Cargo.toml")).unwrap();
    let msrv = cargo
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = "))
        .expect("Cargo.toml declares rust-version")
        .trim_matches('"');
    let setup = readme
        .split("## Set-up")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("README has a Set-up section");
    assert!(
        setup.contains(&format!("version {msrv} or later")),
        "Set-up does not state rust-version {msrv}"
    );
    assert!(setup.contains("takes several minutes"));
    let wd = Workdir::new();
    let run = wd.run(&["stats"]);
    run.data_error();
    // The directory differs from the README's /tmp; the rest of the line does not.
    let line = run.stderr.lines().next().unwrap();
    let (head, tail) = line
        .split_once(": phalanx reads")
        .expect("the message says where phalanx reads from");
    assert!(
        head.starts_with("error: data/measurements.csv is not in "),
        "{line}"
    );
    assert!(
        setup.contains(&format!(
            "error: data/measurements.csv is not in /tmp: phalanx reads{tail}"
        )),
        "README's outside-the-checkout example differs from:\n{line}"
    );
}
