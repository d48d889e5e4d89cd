//! The examples of the README, CONTRIBUTING.md and docs/*.md are run, and their output checked.
//!
//! The convention (CONTRIBUTING.md, "Examples in the documentation"):
//!
//! - A fenced ` ```console ` block is run. Each line starting with `$ ` is a command; the lines
//!   after it, up to the next `$ ` line or the end of the block, are its expected output
//!   (standard output and standard error as they interleave; blank lines at the end of an
//!   output only separate it from the next command). A line `...` leaves out any number of
//!   lines, so `...` first, last or between lines shows an excerpt; an output without `...` is
//!   the whole output. Lines compare with trailing spaces trimmed, and an RFC 3339 time
//!   (`2026-11-22T00:34:21Z`) matches any other: `add` and `snapshot` stamp the clock.
//! - Each command runs with `sh -c`, `phalanx` on the PATH (the binary under test), no `COLUMNS`
//!   (so tables fit 100 columns), in a scratch directory that holds a copy of `data/` and
//!   `docs/examples/`, one directory per document, so a document's commands see what its earlier
//!   commands wrote and never touch the checkout's files. `$?` is the previous command's exit
//!   status, so `$ echo $?` shows it.
//! - A command must exit 0 unless its output shows an `error:` line or the next command is
//!   `echo $?`. Blessing never writes the output of a command that breaks this rule, except for a
//!   new example (one showing no output yet) whose output shows the error.
//! - A fenced block whose info string has `file=NAME` (` ```csv file=new.csv `) is written to
//!   NAME in the scratch directory when the document reaches it, for the commands after it.
//! - A command that names `../shared/` is skipped, with the rest of its block and a printed
//!   reason, when the shared rigs (`../shared/rigs`) are not beside the checkout; the scratch
//!   directory has `../shared` as a link to them when they are.
//! - Other blocks (` ```sh `, ` ```text `, plain ` ``` `) are not run.
//!
//! `PHALANX_BLESS=1 cargo test --test integration docs::` rewrites every expected output that
//! differs from the real one, keeping each `...` excerpt: each run of lines between `...`
//! markers is placed on the lines of the new output it resembles most (in order), and a run
//! that resembles none fails the test instead of guessing. Read the diff before committing it.

use crate::common::manifest_dir;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The documents whose examples are run: the README, CONTRIBUTING.md and every guide in docs/.
const DOCS: &[&str] = &[
    "README.md",
    "CONTRIBUTING.md",
    "docs/lab.md",
    "docs/rigger.md",
    "docs/statistics.md",
    "docs/json.md",
    "docs/internals.md",
];

/// The elision marker: any number of output lines left out.
const ELIDED: &str = "...";

#[test]
fn readme() {
    check_doc("README.md");
}

#[test]
fn contributing() {
    check_doc("CONTRIBUTING.md");
}

#[test]
fn lab_guide() {
    check_doc("docs/lab.md");
}

#[test]
fn rigger_guide() {
    check_doc("docs/rigger.md");
}

#[test]
fn statistics_guide() {
    check_doc("docs/statistics.md");
}

#[test]
fn json_guide() {
    check_doc("docs/json.md");
}

#[test]
fn internals_guide() {
    check_doc("docs/internals.md");
}

/// Every Markdown file of docs/ (and the two top-level ones) is in [`DOCS`], so a new guide's
/// examples cannot go unrun.
#[test]
fn every_guide_is_run() {
    let mut found: Vec<String> = std::fs::read_dir(manifest_dir().join("docs"))
        .expect("read docs/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| format!("docs/{}", p.file_name().unwrap().to_string_lossy()))
        .collect();
    found.extend(["README.md".to_string(), "CONTRIBUTING.md".to_string()]);
    for doc in &found {
        assert!(
            DOCS.contains(&doc.as_str()),
            "{doc} is not in tests/docs.rs's DOCS (add it there, with a test)"
        );
    }
}

/// The README's command table lists every command `phalanx --help` lists, each as
/// ``| `phalanx NAME``.
#[test]
fn the_readme_lists_every_command() {
    let readme = read_doc("README.md");
    let help = crate::common::Workdir::new().run(&["--help"]);
    help.ok();
    let commands: Vec<&str> = help
        .stdout
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter(|l| !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() > 10, "{}", help.stdout);
    for c in commands {
        assert!(
            readme.contains(&format!("| `phalanx {c}")),
            "the README's command table lacks `phalanx {c}`"
        );
    }
}

/// One document's text.
fn read_doc(doc: &str) -> String {
    std::fs::read_to_string(manifest_dir().join(doc)).unwrap_or_else(|e| panic!("read {doc}: {e}"))
}

/// Runs every example of `doc` and checks (or, with `PHALANX_BLESS=1`, rewrites) its output.
fn check_doc(doc: &str) {
    let text = read_doc(doc);
    let parsed = parse(&text).unwrap_or_else(|e| panic!("{doc}: {e}"));
    let bless = std::env::var_os("PHALANX_BLESS").is_some_and(|v| v == "1");
    let sandbox = Sandbox::new();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // Blocks are rewritten from the last, so earlier line numbers stay valid.
    let mut rewrites: Vec<(usize, usize, Vec<String>)> = Vec::new();
    let mut failures = Vec::new();
    let (mut ran, mut skipped) = (0, 0);
    for item in &parsed {
        match item {
            Item::File { name, contents } => sandbox.write(name, contents),
            Item::Console(block) => {
                let mut prev_code = 0;
                let mut new_steps = Vec::new();
                let mut skip = None;
                for (k, step) in block.steps.iter().enumerate() {
                    if skip.is_none() && step.command.contains("../shared/") && !sandbox.shared {
                        skip = Some(format!(
                            "skipped: {doc}:{}: `{}` and the rest of its block need \
                             ../shared/rigs, which is not beside the checkout",
                            step.line + 1,
                            step.command
                        ));
                    }
                    if skip.is_some() {
                        skipped += 1;
                        new_steps.push(step.expected.clone());
                        continue;
                    }
                    let (out, code) = sandbox.run(&step.command, prev_code);
                    prev_code = code;
                    ran += 1;
                    let where_ = format!("{doc}:{}: $ {}", step.line + 1, step.command);
                    if out.contains("panicked") {
                        failures.push(format!("{where_}\nphalanx panicked:\n{out}"));
                    }
                    let next_shows_code = block
                        .steps
                        .get(k + 1)
                        .is_some_and(|s| s.command.trim() == "echo $?");
                    // A new example (no output shown yet) is judged by the output it will show.
                    let shown = if bless && step.expected.is_empty() {
                        output_lines(&out)
                    } else {
                        step.expected.clone()
                    };
                    let shows_error = shown.iter().any(|l| l.starts_with("error"));
                    if code != 0 && !next_shows_code && !shows_error {
                        failures.push(format!(
                            "{where_}\nexited with {code}, and the example shows no error and \
                             no `echo $?`:\n{out}"
                        ));
                        new_steps.push(step.expected.clone());
                        continue;
                    }
                    let actual = output_lines(&out);
                    if let Err(e) = matches(&step.expected, &actual) {
                        if bless {
                            match blessed(&step.expected, &actual) {
                                Ok(new) => {
                                    eprintln!("blessed {where_}");
                                    new_steps.push(new);
                                    continue;
                                }
                                Err(b) => failures.push(format!(
                                    "{where_}\ncannot bless: {b}\n--- real output\n{out}"
                                )),
                            }
                        } else {
                            failures.push(format!(
                                "{where_}\n{e}\n--- shown\n{}\n--- real output\n{out}",
                                step.expected.join("\n")
                            ));
                        }
                    }
                    new_steps.push(step.expected.clone());
                }
                if let Some(reason) = skip {
                    eprintln!("{reason}");
                }
                let mut body = Vec::new();
                for (step, new) in block.steps.iter().zip(new_steps) {
                    body.push(format!("$ {}", step.command));
                    body.extend(new);
                    body.extend(std::iter::repeat_n(String::new(), step.blank_after));
                }
                rewrites.push((block.start, block.end, body));
            }
        }
    }
    eprintln!("{doc}: {ran} commands run, {skipped} skipped");
    if bless {
        for (start, end, body) in rewrites.into_iter().rev() {
            lines.splice(start..end, body);
        }
        let mut new = lines.join("\n");
        new.push('\n');
        if new != text {
            std::fs::write(manifest_dir().join(doc), new).expect("write the blessed document");
            eprintln!("{doc}: rewritten from the real output; read the diff before committing");
        }
    }
    assert!(
        failures.is_empty(),
        "{} example(s) of {doc} differ from what phalanx prints (PHALANX_BLESS=1 cargo test \
         --test integration docs:: rewrites them):\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

/// What a document holds that the harness acts on, in order.
#[derive(Debug, PartialEq)]
enum Item {
    /// A block written to a file of the scratch directory (` ```csv file=new.csv `).
    File { name: String, contents: String },
    /// A ` ```console ` block.
    Console(Console),
}

/// A console block: its body's lines `start..end` of the document, and its commands.
#[derive(Debug, PartialEq)]
struct Console {
    start: usize,
    end: usize,
    steps: Vec<Step>,
}

/// One command of a console block and the output shown after it.
#[derive(Debug, PartialEq)]
struct Step {
    /// The document's line (0-based) of the `$ ` line.
    line: usize,
    command: String,
    /// The output shown, blank lines at its end taken off.
    expected: Vec<String>,
    /// How many blank lines followed it (kept when blessing).
    blank_after: usize,
}

/// The console blocks and file blocks of a Markdown text.
fn parse(text: &str) -> Result<Vec<Item>, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut items = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let Some(info) = lines[i].strip_prefix("```") else {
            i += 1;
            continue;
        };
        let start = i + 1;
        let end = (start..lines.len())
            .find(|&j| lines[j].trim_end() == "```")
            .ok_or_else(|| format!("line {}: the block is never closed", i + 1))?;
        let mut words = info.split_whitespace();
        let lang = words.next().unwrap_or("");
        let file = words.find_map(|w| w.strip_prefix("file="));
        if let Some(name) = file {
            let mut contents = lines[start..end].join("\n");
            contents.push('\n');
            items.push(Item::File {
                name: name.to_string(),
                contents,
            });
        } else if lang == "console" {
            items.push(Item::Console(console(&lines, start, end)?));
        }
        i = end + 1;
    }
    Ok(items)
}

/// The steps of the console block whose body is `lines[start..end]`.
fn console(lines: &[&str], start: usize, end: usize) -> Result<Console, String> {
    let mut steps: Vec<Step> = Vec::new();
    for (j, line) in lines.iter().enumerate().take(end).skip(start) {
        if let Some(command) = line.strip_prefix("$ ") {
            steps.push(Step {
                line: j,
                command: command.to_string(),
                expected: Vec::new(),
                blank_after: 0,
            });
        } else if let Some(step) = steps.last_mut() {
            step.expected.push(line.trim_end().to_string());
        } else if !line.trim().is_empty() {
            return Err(format!(
                "line {}: a console block starts with a `$ ` command",
                j + 1
            ));
        }
    }
    if steps.is_empty() {
        return Err(format!("line {start}: a console block without a command"));
    }
    for step in &mut steps {
        while step.expected.last().is_some_and(|l| l.is_empty()) {
            step.expected.pop();
            step.blank_after += 1;
        }
    }
    Ok(Console { start, end, steps })
}

/// A command's output as lines, trailing spaces and blank lines at the end taken off.
fn output_lines(out: &str) -> Vec<String> {
    let mut lines: Vec<String> = out.lines().map(|l| l.trim_end().to_string()).collect();
    while lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    lines
}

/// A line as compared: trailing spaces off, every RFC 3339 time (`2026-11-22T00:34:21Z`)
/// replaced by one placeholder.
fn normal(line: &str) -> String {
    let b = line.trim_end().as_bytes();
    let shape = b"dddd-dd-ddTdd:dd:ddZ";
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let is_time = b.len() - i >= shape.len()
            && shape.iter().zip(&b[i..]).all(|(s, c)| match s {
                b'd' => c.is_ascii_digit(),
                s => s == c,
            });
        if is_time {
            out.extend_from_slice(b"<time>");
            i += shape.len();
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap_or_else(|_| line.to_string())
}

/// The runs of lines between `...` markers, and whether the output shown starts and ends
/// with one.
fn segments(expected: &[String]) -> (Vec<Vec<String>>, bool, bool) {
    let lead = expected.first().is_some_and(|l| l == ELIDED);
    let trail = expected.last().is_some_and(|l| l == ELIDED);
    let segs = expected
        .split(|l| l == ELIDED)
        .filter(|s| !s.is_empty())
        .map(<[String]>::to_vec)
        .collect();
    (segs, lead, trail)
}

/// Whether `actual` shows `expected`: its runs in order, each run's lines consecutive, the
/// first at the start and the last at the end unless `...` stands there.
fn matches(expected: &[String], actual: &[String]) -> Result<(), String> {
    let (segs, lead, trail) = segments(expected);
    let actual: Vec<String> = actual.iter().map(|l| normal(l)).collect();
    if segs.is_empty() {
        return if lead || actual.is_empty() {
            Ok(())
        } else {
            Err("the example shows no output, but there is some".into())
        };
    }
    let at = |seg: &[String], p: usize| {
        p + seg.len() <= actual.len() && seg.iter().zip(&actual[p..]).all(|(e, a)| normal(e) == *a)
    };
    let mut pos = 0;
    let last = segs.len() - 1;
    for (k, seg) in segs.iter().enumerate() {
        let found = if k == last && !trail {
            let p = actual.len().checked_sub(seg.len()).filter(|&p| p >= pos);
            p.filter(|&p| at(seg, p) && (k > 0 || lead || p == 0))
        } else if k == 0 && !lead {
            Some(0).filter(|&p| at(seg, p))
        } else {
            (pos..=actual.len().saturating_sub(seg.len())).find(|&p| at(seg, p))
        };
        match found {
            Some(p) => pos = p + seg.len(),
            None => {
                return Err(format!(
                    "the real output lacks, {}, the lines:\n{}",
                    match (k == 0 && !lead, k == last && !trail) {
                        (true, true) => "as the whole output",
                        (true, false) => "at its start",
                        (false, true) => "at its end",
                        (false, false) => "in order after the lines before them",
                    },
                    seg.join("\n")
                ));
            }
        }
    }
    Ok(())
}

/// The expected output rewritten from `actual`, keeping its `...` excerpts: each run between
/// markers goes to the lines of `actual` it resembles most, in order; an error where a run
/// resembles nothing there.
fn blessed(expected: &[String], actual: &[String]) -> Result<Vec<String>, String> {
    let (segs, lead, trail) = segments(expected);
    // A line unchanged but for its time keeps the shown time, so blessing twice changes nothing.
    let keep = |old: &[String], new: &[String]| -> Vec<String> {
        new.iter()
            .enumerate()
            .map(|(i, n)| match old.get(i) {
                Some(o) if normal(o) == normal(n) => o.clone(),
                _ => n.clone(),
            })
            .collect()
    };
    if segs.is_empty() {
        return Ok(if lead || trail {
            vec![ELIDED.to_string()]
        } else {
            actual.to_vec()
        });
    }
    if segs.len() == 1 && !lead && !trail {
        return Ok(keep(&segs[0], actual));
    }
    let mut out = Vec::new();
    if lead {
        out.push(ELIDED.to_string());
    }
    let mut pos = 0;
    let last = segs.len() - 1;
    for (k, seg) in segs.iter().enumerate() {
        let anchor_start = k == 0 && !lead;
        let anchor_end = k == last && !trail;
        let (from, to) = place(seg, actual, pos, anchor_start, anchor_end).ok_or_else(|| {
            format!(
                "the run of lines {} of the example resembles no lines of the real output \
                 after those before it; edit the example by hand:\n{}",
                k + 1,
                seg.join("\n")
            )
        })?;
        if k > 0 {
            out.push(ELIDED.to_string());
        }
        out.extend(keep(seg, &actual[from..to]));
        pos = to;
    }
    if trail {
        out.push(ELIDED.to_string());
    }
    Ok(out)
}

/// How alike two lines are, from 0 to 1: the share of their words they have in common.
fn similarity(a: &str, b: &str) -> f64 {
    let (a, b) = (normal(a), normal(b));
    if a == b {
        return 1.0;
    }
    let mut x: Vec<&str> = a.split_whitespace().collect();
    let mut y: Vec<&str> = b.split_whitespace().collect();
    if x.is_empty() || y.is_empty() {
        return 0.0;
    }
    x.sort_unstable();
    y.sort_unstable();
    let (mut i, mut j, mut common) = (0, 0, 0);
    while i < x.len() && j < y.len() {
        match x[i].cmp(y[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                common += 1;
                i += 1;
                j += 1;
            }
        }
    }
    // A shared word or two (a `|`, a `the`) is no resemblance.
    (2.0 * common as f64 / (x.len() + y.len()) as f64 - 0.1).max(0.0)
}

/// Where the run `seg` lies in `actual[pos..]`: the span `from..to` that aligns best with it
/// (lines alike score up to +1, unlike down to -1, a line skipped on either side -0.6),
/// starting at `pos` if `anchor_start` and ending at the end if `anchor_end`. `None` when no
/// span scores above 0.
fn place(
    seg: &[String],
    actual: &[String],
    pos: usize,
    anchor_start: bool,
    anchor_end: bool,
) -> Option<(usize, usize)> {
    const GAP: f64 = 0.6;
    let n = actual.len();
    if pos > n {
        return None;
    }
    let m = seg.len();
    let w = n - pos + 1;
    // score[i][j]: the best alignment of seg[..i] with a span of actual ending at pos + j;
    // start[i][j]: where that span starts.
    let mut score = vec![vec![f64::NEG_INFINITY; w]; m + 1];
    let mut start = vec![vec![0usize; w]; m + 1];
    for j in 0..w {
        if !anchor_start || j == 0 {
            score[0][j] = 0.0;
            start[0][j] = pos + j;
        }
    }
    for i in 1..=m {
        for j in 0..w {
            let mut best = (score[i - 1][j] - GAP, start[i - 1][j]);
            if j > 0 {
                let s = 2.0 * similarity(&seg[i - 1], &actual[pos + j - 1]) - 1.0;
                for cand in [
                    (score[i - 1][j - 1] + s, start[i - 1][j - 1]),
                    (score[i][j - 1] - GAP, start[i][j - 1]),
                ] {
                    if cand.0 > best.0 {
                        best = cand;
                    }
                }
            }
            score[i][j] = best.0;
            start[i][j] = best.1;
        }
    }
    let ends: Vec<usize> = if anchor_end {
        vec![w - 1]
    } else {
        (0..w).collect()
    };
    let j = ends
        .into_iter()
        .filter(|&j| score[m][j] > 0.0)
        .max_by(|&a, &b| score[m][a].total_cmp(&score[m][b]).then(b.cmp(&a)))?;
    let (from, to) = (start[m][j], pos + j);
    (from < to).then_some((from, to))
}

/// The scratch directory of one document: `ROOT/phalanx` (the current directory of its
/// commands) with copies of `data/` and `docs/examples/`, and `ROOT/shared` linked to the
/// shared rigs when they are beside the checkout.
struct Sandbox {
    _root: tempfile::TempDir,
    cwd: PathBuf,
    shared: bool,
    path: std::ffi::OsString,
}

impl Sandbox {
    fn new() -> Sandbox {
        let root = tempfile::Builder::new()
            .prefix("phalanx-docs-")
            .tempdir()
            .expect("create the scratch directory");
        let cwd = root.path().join("phalanx");
        let repo = manifest_dir();
        copy_dir(&repo.join("data"), &cwd.join("data"));
        copy_dir(&repo.join("docs/examples"), &cwd.join("docs/examples"));
        let shared_dir = repo.join("../shared");
        let shared = shared_dir.join("rigs").is_dir();
        if shared {
            let target = shared_dir.canonicalize().expect("the shared folder's path");
            std::os::unix::fs::symlink(target, root.path().join("shared")).expect("link ../shared");
        }
        let bin = PathBuf::from(env!("CARGO_BIN_EXE_phalanx"));
        let mut dirs = vec![bin.parent().expect("the binary's folder").to_path_buf()];
        dirs.extend(std::env::split_paths(
            &std::env::var_os("PATH").unwrap_or_default(),
        ));
        let path = std::env::join_paths(dirs).expect("a PATH");
        Sandbox {
            _root: root,
            cwd,
            shared,
            path,
        }
    }

    /// Writes a file block's contents to `name`.
    fn write(&self, name: &str, contents: &str) {
        let p = self.cwd.join(name);
        std::fs::create_dir_all(p.parent().unwrap()).expect("create the file's folder");
        std::fs::write(p, contents).expect("write the file block");
    }

    /// Runs `command` with `sh -c`, `$?` set to `prev_code`; its output (stdout and stderr
    /// as they interleave) and exit status.
    fn run(&self, command: &str, prev_code: i32) -> (String, i32) {
        let script = format!("exec 2>&1\n(exit {prev_code})\n{command}\n");
        let out = assert_cmd::Command::new("sh")
            .arg("-c")
            .arg(script)
            .current_dir(&self.cwd)
            .env("PATH", &self.path)
            .env_remove("COLUMNS")
            .env_remove("PHALANX_BLESS")
            .timeout(Duration::from_secs(300))
            .output()
            .expect("run sh");
        let code = out.status.code().unwrap_or_else(|| {
            panic!(
                "`{command}` was killed (a timeout or a signal):\n{}",
                String::from_utf8_lossy(&out.stdout)
            )
        });
        (String::from_utf8_lossy(&out.stdout).into_owned(), code)
    }
}

/// Copies the folder `from` to `to`, recursively.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create a folder");
    for entry in std::fs::read_dir(from).expect("read a folder").flatten() {
        let (src, dst) = (entry.path(), to.join(entry.file_name()));
        if src.is_dir() {
            copy_dir(&src, &dst);
        } else {
            std::fs::copy(&src, &dst).expect("copy a file");
        }
    }
}

/// The harness's own rules, on made-up text (no binary run).
mod harness {
    use super::*;

    fn v(lines: &[&str]) -> Vec<String> {
        lines.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_console_block_is_commands_and_their_output() {
        let doc = "text\n```console\n$ phalanx a\none\n\ntwo\n\n$ echo $?\n0\n```\n\
                   ```csv file=new.csv\nx,y\n```\n```sh\n$ cargo test\n```\n";
        let items = parse(doc).unwrap();
        assert_eq!(items.len(), 2);
        let Item::Console(c) = &items[0] else {
            panic!("{items:?}")
        };
        assert_eq!((c.start, c.end), (2, 9));
        assert_eq!(c.steps[0].command, "phalanx a");
        assert_eq!(c.steps[0].expected, v(&["one", "", "two"]));
        assert_eq!(c.steps[0].blank_after, 1);
        assert_eq!(c.steps[1].expected, v(&["0"]));
        assert_eq!(
            items[1],
            Item::File {
                name: "new.csv".into(),
                contents: "x,y\n".into()
            }
        );
        assert!(parse("```console\nno command\n```\n").is_err());
        assert!(parse("```console\n$ phalanx a\n").is_err());
    }

    #[test]
    fn the_output_shown_is_whole_unless_elided() {
        let out = v(&["a", "b", "c", "d"]);
        assert!(matches(&v(&["a", "b", "c", "d"]), &out).is_ok());
        assert!(matches(&v(&["a", "b", "c"]), &out).is_err());
        assert!(matches(&v(&["b", "c", "d"]), &out).is_err());
        assert!(matches(&v(&["a", "b", "..."]), &out).is_ok());
        assert!(matches(&v(&["...", "c", "d"]), &out).is_ok());
        assert!(matches(&v(&["...", "c", "..."]), &out).is_ok());
        assert!(matches(&v(&["a", "...", "d"]), &out).is_ok());
        assert!(matches(&v(&["a", "...", "b", "...", "d"]), &out).is_ok());
        // Lines of one run are consecutive; runs keep their order.
        assert!(matches(&v(&["...", "a", "c", "..."]), &out).is_err());
        assert!(matches(&v(&["...", "c", "...", "b", "..."]), &out).is_err());
        assert!(matches(&v(&[]), &out).is_err());
        assert!(matches(&v(&["..."]), &out).is_ok());
        assert!(matches(&v(&[]), &[]).is_ok());
        // Times match any time; trailing spaces do not count.
        let timed = v(&["| 2 | 2026-12-06T09:10:11Z | add |  "]);
        assert!(matches(&v(&["| 2 | 2026-11-22T00:43:56Z | add |"]), &timed).is_ok());
        assert!(matches(&v(&["| 2 | 2026-11-22T00:43:56Z | remove |"]), &timed).is_err());
    }

    #[test]
    fn blessing_keeps_the_excerpts_and_passes_afterwards() {
        let old = v(&[
            "...",
            "thumb   keep",
            "index   move the PIP 3.1 mm towards the tip",
            "...",
            "Summary: 1 of 5 judged fingers lie outside",
        ]);
        let new = v(&[
            "Rig audit of x",
            "",
            "thumb   keep",
            "index   move the PIP 3.2 mm towards the tip",
            "middle  keep",
            "notes",
            "Summary: 2 of 5 judged fingers lie outside",
        ]);
        let b = blessed(&old, &new).unwrap();
        assert_eq!(
            b,
            v(&[
                "...",
                "thumb   keep",
                "index   move the PIP 3.2 mm towards the tip",
                "...",
                "Summary: 2 of 5 judged fingers lie outside",
            ])
        );
        assert!(matches(&b, &new).is_ok());
        // Blessing what matches changes nothing; a whole output is replaced whole, its times kept.
        assert_eq!(blessed(&b, &new).unwrap(), b);
        let old = v(&["at 2026-11-22T00:43:56Z", "n 5"]);
        let new = v(&["at 2030-01-01T00:00:00Z", "n 6", "more"]);
        assert_eq!(
            blessed(&old, &new).unwrap(),
            v(&["at 2026-11-22T00:43:56Z", "n 6", "more"])
        );
        // A run like nothing in the output is not guessed at.
        let old = v(&["...", "completely different words here", "..."]);
        assert!(blessed(&old, &v(&["a b c", "d e f"])).is_err());
    }
}
