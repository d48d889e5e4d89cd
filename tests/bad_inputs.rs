//! A corpus of malformed inputs, each with the error it must produce.
//!
//! Every file in `tests/fixtures/bad/` is a fixture, except the sidecars
//! `<name>.expect` and the `support/` directory (valid companion files that
//! fixtures may name). A fixture is either a literal file `<name>.csv` or a
//! recipe `<name>.recipe`, generated at test time by replacing each
//! `{{repeat N C}}` with N copies of the character C (so a 1 MiB field needs
//! no 1 MiB file in git).
//!
//! The sidecar `<name>.expect` holds one `key: value` per line (`#` starts a
//! comment line):
//!
//! - `kind: data` (default) or `kind: claims`: a measurement file, run as
//!   `phalanx stats --data bad.csv`, or a claims file, run as
//!   `phalanx check --claims bad.csv` against the paper's data;
//! - `exit: N`: the exit status (2 for every bad input);
//! - `stderr: TEXT` (repeatable): a substring stderr must contain. The fixture
//!   is copied into a fresh temporary directory as `bad.csv` and passed by
//!   that relative path, so messages read `bad.csv:LINE:COLUMN: FIELD: ...`;
//! - `data: PATH` (claims only): the dataset to check against, a path under
//!   `tests/fixtures/bad/` (default: the paper's `data/measurements.csv`);
//! - `report: ok`: `phalanx report` accepts this input (it notes claims it
//!   cannot check instead of failing); otherwise `report` must fail with the
//!   same exit status and leave the previous report byte-identical.
//!
//! Every run must not panic, must print nothing on stdout, and must leave
//! every file of its directory as it was (no new, changed or removed file).
//!
//! The `stats`/`check` runs are one test; the `report` runs, most of the
//! corpus's time, are another, which a plain `cargo test` skips and `.ci/run`
//! runs (`cargo test -- --ignored`).

use crate::common;

use common::{Run, Workdir, paper_claims, paper_data};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The corpus directory.
fn corpus_dir() -> PathBuf {
    common::manifest_dir().join("tests/fixtures/bad")
}

/// Which command reads a fixture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Data,
    Claims,
}

/// The parsed sidecar of one fixture.
#[derive(Debug)]
struct Expect {
    kind: Kind,
    exit: i32,
    stderr: Vec<String>,
    data: Option<String>,
    report_ok: bool,
}

fn parse_expect(text: &str) -> Result<Expect, String> {
    let mut e = Expect {
        kind: Kind::Data,
        exit: -1,
        stderr: Vec::new(),
        data: None,
        report_ok: false,
    };
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        let (key, value) = line
            .split_once(": ")
            .ok_or_else(|| format!("line {}: not 'key: value': {line:?}", i + 1))?;
        match key {
            "kind" => {
                e.kind = match value.trim() {
                    "data" => Kind::Data,
                    "claims" => Kind::Claims,
                    other => return Err(format!("line {}: unknown kind {other:?}", i + 1)),
                }
            }
            "exit" => {
                e.exit = value
                    .trim()
                    .parse()
                    .map_err(|_| format!("line {}: exit is not a number", i + 1))?
            }
            "stderr" => e.stderr.push(value.to_string()),
            "data" => e.data = Some(value.trim().to_string()),
            "report" if value.trim() == "ok" => e.report_ok = true,
            other => return Err(format!("line {}: unknown key {other:?}", i + 1)),
        }
    }
    if e.exit < 0 {
        return Err("no 'exit:' line".into());
    }
    if e.stderr.is_empty() {
        return Err("no 'stderr:' line".into());
    }
    Ok(e)
}

/// Expands `{{repeat N C}}` in a recipe.
fn expand_recipe(recipe: &str) -> Result<Vec<u8>, String> {
    let mut out = String::new();
    let mut rest = recipe;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let end = rest[start..].find("}}").ok_or("unclosed {{ in recipe")? + start;
        let directive = &rest[start + 2..end];
        let mut parts = directive.split(' ');
        match (parts.next(), parts.next(), parts.next(), parts.next()) {
            (Some("repeat"), Some(n), Some(c), None) if c.chars().count() == 1 => {
                let n: usize = n
                    .parse()
                    .map_err(|_| format!("bad count in {directive:?}"))?;
                out.push_str(&c.repeat(n));
            }
            _ => return Err(format!("unknown directive {{{{{directive}}}}}")),
        }
        rest = &rest[end + 2..];
    }
    out.push_str(rest);
    Ok(out.into_bytes())
}

/// One fixture of the corpus.
struct Fixture {
    name: String,
    bytes: Vec<u8>,
    expect: Expect,
}

/// Loads the corpus; every fixture without a valid sidecar (and every sidecar
/// without a fixture) is returned as a problem.
fn load_corpus() -> (Vec<Fixture>, Vec<String>) {
    let dir = corpus_dir();
    let mut fixtures = Vec::new();
    let mut problems = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("read tests/fixtures/bad")
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    let mut stems = Vec::new();
    for path in &entries {
        if path.is_dir() {
            continue; // support/: companion files, not fixtures
        }
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let (stem, ext) = file.rsplit_once('.').unwrap_or((&file, ""));
        if ext == "expect" {
            continue;
        }
        stems.push(stem.to_string());
        let bytes = match ext {
            "recipe" => {
                let text = std::fs::read_to_string(path).expect("read recipe");
                match expand_recipe(&text) {
                    Ok(b) => b,
                    Err(e) => {
                        problems.push(format!("{file}: {e}"));
                        continue;
                    }
                }
            }
            _ => std::fs::read(path).expect("read fixture"),
        };
        let sidecar = dir.join(format!("{stem}.expect"));
        let Ok(text) = std::fs::read_to_string(&sidecar) else {
            problems.push(format!("{file}: no sidecar {stem}.expect"));
            continue;
        };
        match parse_expect(&text) {
            Ok(expect) => fixtures.push(Fixture {
                name: file,
                bytes,
                expect,
            }),
            Err(e) => problems.push(format!("{stem}.expect: {e}")),
        }
    }
    for path in &entries {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        if let Some(stem) = file.strip_suffix(".expect")
            && !stems.iter().any(|s| s == stem)
        {
            problems.push(format!("{file}: no fixture {stem}.csv or {stem}.recipe"));
        }
    }
    (fixtures, problems)
}

/// Every file under `root` with its bytes (paths relative to `root`).
fn tree(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).expect("read dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_path_buf();
                out.insert(rel, std::fs::read(&p).expect("read file"));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(root, root, &mut out);
    out
}

/// Describes how two snapshots of a directory differ (empty when equal).
fn tree_diff(before: &BTreeMap<PathBuf, Vec<u8>>, after: &BTreeMap<PathBuf, Vec<u8>>) -> String {
    let mut d = Vec::new();
    for (p, b) in before {
        match after.get(p) {
            None => d.push(format!("removed {}", p.display())),
            Some(a) if a != b => d.push(format!("changed {}", p.display())),
            _ => {}
        }
    }
    for p in after.keys().filter(|p| !before.contains_key(*p)) {
        d.push(format!("created {}", p.display()));
    }
    d.join(", ")
}

/// A report of the paper's data, rendered once: the "previous report" every
/// failing run must leave untouched.
fn previous_report() -> &'static BTreeMap<PathBuf, Vec<u8>> {
    static REPORT: OnceLock<BTreeMap<PathBuf, Vec<u8>>> = OnceLock::new();
    REPORT.get_or_init(|| {
        let wd = Workdir::new();
        wd.copy_paper_data();
        // A small coverage simulation: any complete report serves as the previous one.
        wd.run(&["report", "-q", "--out", "out", "--sims", "200"])
            .ok();
        let files = tree(&wd.path().join("out"));
        assert!(
            files.keys().any(|p| p.ends_with("index.html")),
            "the previous report has an index.html"
        );
        files
    })
}

/// A fresh directory with the paper's data, a previous report in `out/`, the
/// companion files of `support/` and the fixture as `bad.csv`.
fn stage(fixture: &Fixture) -> Workdir {
    let wd = Workdir::new();
    wd.write("data/measurements.csv", paper_data());
    wd.write("data/paper_claims.csv", paper_claims());
    for (rel, bytes) in previous_report() {
        wd.write(&format!("out/{}", rel.display()), bytes);
    }
    if let Some(data) = &fixture.expect.data {
        let src = corpus_dir().join(data);
        wd.write(
            data,
            std::fs::read(&src).expect("read the fixture's data: file"),
        );
    }
    wd.write("bad.csv", &fixture.bytes);
    wd
}

/// Checks one run's exit status, stderr and stdout, pushing what is wrong.
fn check_run(wrong: &mut Vec<String>, exit: i32, what: &str, run: &Run, needles: &[String]) {
    if run.code != Some(exit) {
        wrong.push(format!(
            "{what}: exit {:?}, expected {exit}; stderr:\n{}",
            run.code, run.stderr
        ));
    }
    for needle in needles {
        if !run.stderr.contains(needle.as_str()) {
            wrong.push(format!(
                "{what}: stderr lacks {needle:?}; stderr:\n{}",
                run.stderr
            ));
        }
    }
    if !run.stdout.is_empty() {
        wrong.push(format!("{what}: wrote to stdout:\n{}", run.stdout));
    }
}

/// Checks the command that reads one fixture (`stats` or `check`); returns
/// what went wrong, if anything.
fn check_fixture(fixture: &Fixture) -> Vec<String> {
    let e = &fixture.expect;
    let wd = stage(fixture);
    let data = e.data.as_deref().unwrap_or("data/measurements.csv");
    let mut wrong = Vec::new();

    // The command that reads the fixture.
    let before = tree(wd.path());
    let args: Vec<&str> = match e.kind {
        Kind::Data => vec!["stats", "-q", "--data", "bad.csv"],
        Kind::Claims => vec!["check", "-q", "--claims", "bad.csv", "--data", data],
    };
    let run = wd.run(&args);
    check_run(&mut wrong, e.exit, &args.join(" "), &run, &e.stderr);
    let diff = tree_diff(&before, &tree(wd.path()));
    if !diff.is_empty() {
        wrong.push(format!("{}: files changed: {diff}", args.join(" ")));
    }
    wrong
}

/// Checks `report` over a previous report with one fixture as input; returns
/// what went wrong, if anything.
fn check_fixture_report(fixture: &Fixture) -> Vec<String> {
    let e = &fixture.expect;
    let wd = stage(fixture);
    let data = e.data.as_deref().unwrap_or("data/measurements.csv");
    let mut wrong = Vec::new();
    let before = tree(wd.path());

    // `report` over a previous report: fails and leaves it byte-identical.
    let args: Vec<&str> = match e.kind {
        // A small coverage simulation: what is checked is how the input is refused or noted.
        Kind::Data => vec![
            "report", "-q", "--out", "out", "--sims", "200", "--data", "bad.csv",
        ],
        Kind::Claims => vec![
            "report", "-q", "--out", "out", "--sims", "200", "--claims", "bad.csv", "--data", data,
        ],
    };
    let run = wd.run(&args);
    if e.report_ok {
        if run.code != Some(0) {
            wrong.push(format!(
                "{}: expected success (report: ok), got {:?}:\n{}",
                args.join(" "),
                run.code,
                run.stderr
            ));
        } else {
            let md = String::from_utf8_lossy(&wd.read("out/report.md")).into_owned();
            if !md.contains("The claims were not checked") {
                wrong.push(format!(
                    "{}: the report does not say the claims were not checked",
                    args.join(" ")
                ));
            }
        }
    } else {
        // The same problems, whatever the command.
        check_run(&mut wrong, e.exit, &args.join(" "), &run, &e.stderr);
        let diff = tree_diff(&before, &tree(wd.path()));
        if !diff.is_empty() {
            wrong.push(format!("{}: files changed: {diff}", args.join(" ")));
        }
    }
    wrong
}

#[test]
fn every_malformed_input_is_refused_with_its_expected_error() {
    let (fixtures, mut failures) = load_corpus();
    assert!(
        fixtures.len() >= 32,
        "the corpus has only {} fixtures",
        fixtures.len()
    );
    for f in &fixtures {
        for w in check_fixture(f) {
            failures.push(format!("{}: {w}", f.name));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failure(s) over {} fixtures:\n\n{}",
        failures.len(),
        fixtures.len(),
        failures.join("\n\n")
    );
}

/// The corpus through `report`, over a previous report.
#[test]
#[ignore = "slow: a report run per fixture (run by .ci/run)"]
fn a_report_over_a_malformed_input_fails_the_same_way_or_notes_it() {
    let (fixtures, mut failures) = load_corpus();
    for f in &fixtures {
        for w in check_fixture_report(f) {
            failures.push(format!("{}: {w}", f.name));
        }
    }
    assert!(
        failures.is_empty(),
        "{} failure(s) over {} fixtures:\n\n{}",
        failures.len(),
        fixtures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn the_corpus_covers_both_kinds_of_file() {
    let (fixtures, _) = load_corpus();
    let claims = fixtures
        .iter()
        .filter(|f| f.expect.kind == Kind::Claims)
        .count();
    assert!(claims >= 6, "only {claims} claims fixtures");
    assert!(fixtures.len() - claims >= 26, "too few data fixtures");
}

#[test]
fn recipes_expand() {
    assert_eq!(
        expand_recipe("a,{{repeat 3 9}},b{{repeat 2 x}}").unwrap(),
        b"a,999,bxx"
    );
    assert!(expand_recipe("{{repeat 3}}").is_err());
    assert!(expand_recipe("{{repeat 3 9").is_err());
}

/// A directory and a missing file, for every option that names an input.
#[test]
fn a_directory_or_a_missing_file_is_bad_input() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    for (rel, bytes) in previous_report() {
        wd.write(&format!("out/{}", rel.display()), bytes);
    }
    wd.mkdir("adir");
    let before = tree(wd.path());
    for (path, message) in [
        ("adir", "adir: is a directory, not a CSV file"),
        ("missing.csv", "missing.csv: no such file"),
    ] {
        let runs: Vec<Vec<&str>> = vec![
            vec!["stats", "-q", "--data", path],
            vec!["check", "-q", "--data", path],
            vec!["check", "-q", "--claims", path],
            vec!["report", "-q", "--out", "out", "--data", path],
            vec!["report", "-q", "--out", "out", "--claims", path],
        ];
        for args in runs {
            wd.run(&args)
                .data_error()
                .stderr_has(&format!("error: 1 problem in {path}:"))
                .stderr_has(message);
            let diff = tree_diff(&before, &tree(wd.path()));
            assert!(diff.is_empty(), "{args:?} changed files: {diff}");
        }
    }
}

/// The csv reader reads an unterminated quote to the end of the file, so the
/// message only counts fields and advises adding commas; it should say that a
/// quote is not closed.
#[test]

fn an_unterminated_quote_is_named_as_such() {
    let wd = Workdir::new();
    wd.write(
        "bad.csv",
        "xray,finger,j1,j2,j3\n1a,index,339.96,188.83,169.67\n1b,\"index,342.47,195.24,186.70\n",
    );
    let run = wd.run(&["stats", "-q", "--data", "bad.csv"]);
    run.data_error().stderr_has("bad.csv:3");
    assert!(
        run.stderr.contains("quote"),
        "the message does not mention the unclosed quote:\n{}",
        run.stderr
    );
    assert!(
        !run.stderr.contains("add the missing fields"),
        "the message advises adding fields:\n{}",
        run.stderr
    );
}

/// A missing claims file is reported with the hint "(see --data)".
#[test]

fn a_missing_claims_file_points_at_the_claims_option() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let run = wd.run(&["check", "-q", "--claims", "missing.csv"]);
    run.data_error().stderr_has("missing.csv: no such file");
    assert!(
        !run.stderr.contains("--data"),
        "the hint names --data for a claims file:\n{}",
        run.stderr
    );
}

/// Every length is positive and finite and so is each sum, but J2/J1 =
/// 1e300 / 1e-300 overflows to infinity: the statistics hold infinities
/// (serialised as null intervals `[null, null]`, a null mean with the note
/// "every X-ray gives the same value", since inf - x <= 1e-12 * inf), and the
/// SD of the total overflows to null without a note. Either the loader should
/// refuse such rows (as it refuses sums that overflow) or every statistic
/// should be finite or null with a note.
#[test]
fn lengths_whose_ratio_overflows_are_refused_or_analysed_finitely() {
    let wd = Workdir::new();
    wd.write(
        "bad.csv",
        "xray,finger,j1,j2,j3\n1a,index,339.96,188.83,169.67\n1b,index,1e-300,1e300,1\n1c,index,300,200,100\n",
    );
    let run = wd.run(&["stats", "-q", "--format", "json", "--data", "bad.csv"]);
    if run.code == Some(2) {
        run.stderr_has("bad.csv:3");
        return;
    }
    run.ok();
    let doc = run.json();
    for q in common::finger(&doc, "index")["quantities"]
        .as_array()
        .unwrap()
    {
        let name = &q["name"];
        for key in ["mean", "min", "max", "range", "median"] {
            assert!(q[key].is_number(), "{name} {key} is {}", q[key]);
        }
        for key in ["ci_t", "ci_percentile", "ci_bca", "pi", "sd"] {
            let v = &q[key];
            if v.is_null() {
                assert!(
                    !q["notes"].as_array().unwrap().is_empty(),
                    "{name} {key} is null without a note"
                );
            } else if let Some(a) = v.as_array() {
                assert!(
                    a.iter().all(|x| x.is_number()),
                    "{name} {key} is {v}, not [low, high] or null"
                );
            }
        }
    }
}
