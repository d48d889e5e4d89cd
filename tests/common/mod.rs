//! A small xsv-style harness for running the real `phalanx` binary.
//!
//! Every test gets its own [`Workdir`]: an empty temporary directory that is
//! the current directory of every command it runs. Files are written into it
//! with [`Workdir::write`]; [`Workdir::run`] runs `phalanx` there and returns a
//! [`Run`] with stdout, stderr and the exit code. Every run is checked for a
//! panic, so no test can pass while the binary panics.

use assert_cmd::Command;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Writes a synthetic tube hand built from `spec` (joints and weights known exactly)
/// to `name` in `wd`.
pub fn write_hand(
    wd: &Workdir,
    name: &str,
    spec: &phalanx::rig::deform::synthetic::HandSpec,
) -> PathBuf {
    let hand = phalanx::rig::deform::synthetic::tube_hand(spec);
    wd.write(name, hand.to_glb().expect("a GLB"))
}

/// Says that the running test skips (the whole test, or the part of it that needs
/// what is absent) and why, as one line `skipped: <test>: <reason>` on standard error,
/// the test named by its thread (the harness names each test's thread after it).
///
/// Every skip of the integration tests comes through here, written past the harness's
/// capture in one write, so that `cargo test 2>&1 | grep -c 'skipped: '` counts them
/// (a line per skip; `| grep 'skipped: ' | cut -d: -f2 | sort -u` names the tests).
pub fn skip(reason: impl std::fmt::Display) {
    use std::io::Write;
    let thread = std::thread::current();
    // One line, whatever the reason (a `DataError` is several).
    let reason = reason.to_string();
    let reason: Vec<&str> = reason.lines().map(str::trim).collect();
    let test = thread.name().unwrap_or("main");
    let line = format!("skipped: {test}: {}\n", reason.join(" "));
    let _ = std::io::stderr().write_all(line.as_bytes());
}

/// The bytes of `path` (relative to the crate's root), or `None` with the reason
/// printed ([`skip`]): a package of the crate may leave vendored data (the GPL-3.0
/// atlas, the rigs) out, and a test needing it then skips.
pub fn vendored(path: &str) -> Option<Vec<u8>> {
    let path = manifest_dir().join(path);
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            skip(format!("{} could not be read ({e})", path.display()));
            None
        }
    }
}

/// The crate's root, where `data/` lives.
pub fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped measurement file (Table 1 of the paper).
pub fn paper_data_path() -> PathBuf {
    manifest_dir().join("data/measurements.csv")
}

/// The shipped claims file.
pub fn paper_claims_path() -> PathBuf {
    manifest_dir().join("data/paper_claims.csv")
}

/// The bytes of the shipped measurement file.
pub fn paper_data() -> Vec<u8> {
    std::fs::read(paper_data_path()).expect("read data/measurements.csv")
}

/// The bytes of the shipped claims file.
pub fn paper_claims() -> Vec<u8> {
    std::fs::read(paper_claims_path()).expect("read data/paper_claims.csv")
}

/// The header of a minimal measurement file.
pub const HEADER: &str = "xray,finger,j1,j2,j3";

/// One row of the paper's Table 1: X-ray, finger, lengths (2 for the thumb).
#[derive(Debug, Clone)]
pub struct PaperRow {
    pub xray: String,
    pub finger: String,
    pub lengths: Vec<f64>,
}

/// The rows of the shipped measurement file, parsed here (not by phalanx).
pub fn paper_rows() -> Vec<PaperRow> {
    let bytes = paper_data();
    let mut r = csv::Reader::from_reader(&bytes[..]);
    r.records()
        .map(|rec| {
            let rec = rec.expect("paper data is valid CSV");
            let lengths = (2..5)
                .filter(|&i| !rec[i].is_empty())
                .map(|i| rec[i].parse::<f64>().expect("length"))
                .collect();
            PaperRow {
                xray: rec[0].to_string(),
                finger: rec[1].to_string(),
                lengths,
            }
        })
        .collect()
}

/// A minimal measurement CSV (`xray,finger,j1,j2,j3`, LF line ends) from rows.
pub fn measurement_csv(rows: &[PaperRow]) -> String {
    let mut out = format!("{HEADER}\n");
    for r in rows {
        let mut l: Vec<String> = r.lengths.iter().map(|x| format!("{x}")).collect();
        if l.len() == 2 {
            l.push(String::new());
        }
        out.push_str(&format!("{},{},{}\n", r.xray, r.finger, l.join(",")));
    }
    out
}

/// An isolated temporary working directory; removed when dropped.
pub struct Workdir {
    dir: tempfile::TempDir,
}

impl Workdir {
    /// A fresh empty directory.
    pub fn new() -> Workdir {
        Workdir {
            dir: tempfile::Builder::new()
                .prefix("phalanx-test-")
                .tempdir()
                .expect("create temp dir"),
        }
    }

    /// The directory's path.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Writes `contents` to `name` (relative to the directory, parents
    /// created) and returns the full path.
    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let p = self.dir.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).expect("create parent dir");
        }
        std::fs::write(&p, contents).expect("write file");
        p
    }

    /// Creates a subdirectory.
    pub fn mkdir(&self, name: &str) -> PathBuf {
        let p = self.dir.path().join(name);
        std::fs::create_dir_all(&p).expect("create dir");
        p
    }

    /// Reads a file of the directory.
    pub fn read(&self, name: &str) -> Vec<u8> {
        std::fs::read(self.dir.path().join(name)).expect("read file")
    }

    /// Copies the shipped `data/measurements.csv` and `data/paper_claims.csv`
    /// to `data/` here, so the commands' default paths find them.
    pub fn copy_paper_data(&self) {
        self.write("data/measurements.csv", paper_data());
        self.write("data/paper_claims.csv", paper_claims());
    }

    /// A fresh directory holding the paper's data ([`Workdir::copy_paper_data`]).
    pub fn with_paper_data() -> Workdir {
        let wd = Workdir::new();
        wd.copy_paper_data();
        wd
    }

    /// A `phalanx` command with this directory as its current directory.
    pub fn command(&self, args: &[&str]) -> Command {
        let mut cmd = Command::cargo_bin("phalanx").expect("the phalanx binary");
        // Tables fit 100 columns when not on a terminal; a COLUMNS of the caller's would change that.
        cmd.current_dir(self.dir.path())
            .args(args)
            .env_remove("COLUMNS")
            .timeout(Duration::from_secs(120));
        cmd
    }

    /// Runs `phalanx` with `args`.
    pub fn run(&self, args: &[&str]) -> Run {
        self.run_env(args, &[])
    }

    /// Runs `phalanx` with `args` from the repository's root, where the
    /// vendored data (the atlas, the soft-tissue table) is found; paths in
    /// `args` are best absolute.
    pub fn run_in_repo(&self, args: &[&str]) -> Run {
        self.run_cmd(args, self.command(args).current_dir(manifest_dir()))
    }

    /// Runs `phalanx` with `args` and extra environment variables.
    pub fn run_env(&self, args: &[&str], env: &[(&str, &str)]) -> Run {
        let mut cmd = self.command(args);
        for (k, v) in env {
            cmd.env(k, v);
        }
        self.run_cmd(args, &mut cmd)
    }

    /// Runs a prepared `phalanx` command; no panic, no signal.
    fn run_cmd(&self, args: &[&str], cmd: &mut Command) -> Run {
        let out = cmd.output().expect("run phalanx");
        let run = Run {
            args: args.iter().map(|s| s.to_string()).collect(),
            code: out.status.code(),
            stdout_bytes: out.stdout.clone(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        };
        assert!(
            !run.stderr.contains("panicked"),
            "phalanx panicked on {:?}:\n{}",
            run.args,
            run.stderr
        );
        assert!(
            run.code.is_some(),
            "phalanx was killed by a signal on {:?}:\n{}",
            run.args,
            run.stderr
        );
        run
    }
}

/// The outcome of one run of `phalanx`.
#[derive(Debug, Clone)]
pub struct Run {
    pub args: Vec<String>,
    /// Exit code (`None` only when killed by a signal, which the harness rejects).
    pub code: Option<i32>,
    pub stdout: String,
    pub stdout_bytes: Vec<u8>,
    pub stderr: String,
}

impl Run {
    /// Asserts the exit code, showing the run's output when it differs.
    #[track_caller]
    pub fn expect_code(&self, code: i32) -> &Run {
        assert_eq!(
            self.code,
            Some(code),
            "phalanx {:?}: expected exit {code}, got {:?}\n--- stdout\n{}\n--- stderr\n{}",
            self.args,
            self.code,
            self.stdout,
            self.stderr
        );
        self
    }

    /// Asserts success (exit 0) and returns the run.
    #[track_caller]
    pub fn ok(&self) -> &Run {
        self.expect_code(0)
    }

    /// Asserts exit 2 (bad input data or options), an `error` on stderr and
    /// nothing on stdout; returns the run.
    #[track_caller]
    pub fn data_error(&self) -> &Run {
        self.expect_code(2);
        assert!(
            self.stderr.contains("error"),
            "phalanx {:?}: exit 2 without an error message:\n{}",
            self.args,
            self.stderr
        );
        assert!(
            self.stdout.is_empty(),
            "phalanx {:?}: a failed run wrote to stdout:\n{}",
            self.args,
            self.stdout
        );
        self
    }

    /// Asserts that stderr contains `needle`.
    #[track_caller]
    pub fn stderr_has(&self, needle: &str) -> &Run {
        assert!(
            self.stderr.contains(needle),
            "phalanx {:?}: stderr lacks {needle:?}:\n{}",
            self.args,
            self.stderr
        );
        self
    }

    /// Asserts that stdout contains `needle`.
    #[track_caller]
    pub fn stdout_has(&self, needle: &str) -> &Run {
        assert!(
            self.stdout.contains(needle),
            "phalanx {:?}: stdout lacks {needle:?}:\n{}",
            self.args,
            self.stdout
        );
        self
    }

    /// stdout parsed as JSON.
    #[track_caller]
    pub fn json(&self) -> Value {
        serde_json::from_str(&self.stdout).unwrap_or_else(|e| {
            panic!(
                "phalanx {:?}: stdout is not JSON ({e}):\n{}",
                self.args, self.stdout
            )
        })
    }

    /// The problem lines of a data error: the indented `  FILE...` lines
    /// after the `error: N problems in FILE:` line.
    pub fn problem_lines(&self) -> Vec<&str> {
        self.stderr
            .lines()
            .filter(|l| l.starts_with("  ") && !l.trim_start().starts_with("caused by"))
            .map(str::trim_start)
            .collect()
    }
}

/// The finger object named `finger` of a stats document.
#[track_caller]
pub fn finger<'a>(doc: &'a Value, finger: &str) -> &'a Value {
    doc["fingers"]
        .as_array()
        .expect("fingers is an array")
        .iter()
        .find(|f| f["finger"] == finger)
        .unwrap_or_else(|| panic!("no finger {finger} in the document"))
}

/// The quantity object `quantity` of finger `finger` of a stats document.
#[track_caller]
pub fn quantity<'a>(doc: &'a Value, finger_name: &str, quantity: &str) -> &'a Value {
    finger(doc, finger_name)["quantities"]
        .as_array()
        .expect("quantities is an array")
        .iter()
        .find(|q| q["name"] == quantity)
        .unwrap_or_else(|| panic!("no quantity {quantity} for {finger_name}"))
}

/// A JSON number as f64.
#[track_caller]
/// Every rig file (.glb, .gltf, .vrm, .fbx) in the folders of ../shared/rigs,
/// sorted; `None`, with the reason printed ([`skip`]), when the folder is not there.
pub fn shared_rig_files() -> Option<Vec<PathBuf>> {
    let shared = manifest_dir().join("../shared/rigs");
    let dirs = match std::fs::read_dir(&shared) {
        Ok(dirs) => dirs,
        Err(e) => {
            skip(format!(
                "../shared/rigs: {} is not readable ({e})",
                shared.display()
            ));
            return None;
        }
    };
    let mut rigs: Vec<PathBuf> = dirs
        .flatten()
        .filter_map(|d| std::fs::read_dir(d.path()).ok())
        .flat_map(|files| files.flatten().map(|f| f.path()))
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("glb" | "gltf" | "vrm" | "fbx")
            )
        })
        .collect();
    rigs.sort();
    Some(rigs)
}

pub fn num(v: &Value) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("expected a number, got {v}"))
}

/// A JSON interval (a 2-element array of numbers) as (low, high).
#[track_caller]
pub fn interval(v: &Value) -> (f64, f64) {
    let a = v
        .as_array()
        .unwrap_or_else(|| panic!("expected an interval, got {v}"));
    assert_eq!(a.len(), 2, "an interval has 2 elements: {v}");
    (num(&a[0]), num(&a[1]))
}

/// Asserts |a - b| <= tol, with a message.
#[track_caller]
pub fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} differs from {b} by {} (tolerance {tol})",
        (a - b).abs()
    );
}

/// Asserts a and b agree within `rel` relative error (of the larger magnitude).
#[track_caller]
pub fn assert_rel(a: f64, b: f64, rel: f64, what: &str) {
    let scale = a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
    assert!(
        (a - b).abs() <= rel * scale,
        "{what}: {a} and {b} differ by {:e} relative (tolerance {rel:e})",
        (a - b).abs() / scale
    );
}

/// Lower-case hex SHA-256 of a file, computed by the system's `sha256sum`
/// (independently of phalanx's own hashing).
pub fn sha256sum(path: &Path) -> String {
    let out = std::process::Command::new("sha256sum")
        .arg(path)
        .output()
        .expect("run sha256sum");
    assert!(out.status.success(), "sha256sum failed");
    String::from_utf8(out.stdout)
        .expect("sha256sum output is text")
        .split_whitespace()
        .next()
        .expect("sha256sum printed a digest")
        .to_string()
}

/// A GLB container of `json` and `bin` (glTF 2.0's binary layout, written
/// here from the specification: a 12-byte header, a JSON chunk padded with
/// spaces and a BIN chunk padded with zeros, each to 4 bytes).
pub fn glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(0x4E4F_534Au32.to_le_bytes());
    out.extend(text);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(0x004E_4942u32.to_le_bytes());
    out.extend(bin);
    out
}

/// The JSON and binary chunk of a GLB written as [`glb`] writes one.
pub fn unglb(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let len = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    let at = 20 + len;
    let bin = bytes[at + 8..at + 8 + word(at)].to_vec();
    (json, bin)
}
