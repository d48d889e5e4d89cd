//! Multi-step operations on the dataset files: adding X-rays and taking snapshots.
//!
//! `add` holds the dataset's lock from reading to replacing the file, so two
//! additions at the same time both land; the dataset is replaced atomically,
//! so a killed run leaves the old or the new file, never a torn one; on any
//! problem nothing is written.

use crate::analysis::tracking::{self, Flag};
use crate::analysis::{self, Settings};
use crate::atomic;
use crate::dataset::append::{self, DatasetLock};
use crate::dataset::history::{self, Event, Snapshot};
use crate::dataset::{DataError, Dataset, Problem, csvinput};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Where new rows come from.
pub enum NewRows {
    /// A CSV file in the dataset's format (with its own header).
    File(PathBuf),
    /// One row given as options: (column, value) pairs.
    Fields(Vec<(&'static str, String)>),
}

/// What `add` is asked to do.
pub struct AddRequest {
    pub data: PathBuf,
    pub history: PathBuf,
    pub rows: NewRows,
    /// Refuse rows whose relative values fall outside the prediction intervals.
    pub strict: bool,
    pub settings: Settings,
}

/// What `add` did.
#[derive(Debug)]
pub struct AddOutcome {
    pub added: usize,
    pub xrays_before: usize,
    pub xrays_after: usize,
    /// Values outside the current prediction intervals (warnings unless strict).
    pub flags: Vec<Flag>,
    pub snapshot: Snapshot,
}

/// The current UTC time, RFC 3339, for history records.
pub fn now() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Adds new rows to a dataset, then appends a snapshot to its history.
pub fn add(req: &AddRequest) -> Result<AddOutcome, Error> {
    req.settings.validate().map_err(Error::Usage)?;
    let new = match &req.rows {
        NewRows::File(p) => Dataset::load(p)?,
        NewRows::Fields(fields) => append::single_row(fields)?,
    };
    csvinput::open_input(&req.data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(&req.data).map_err(io_err(&req.data))?;
    let current_bytes = csvinput::read_input(&req.data)?;
    let label = req.data.display().to_string();
    let current = Dataset::from_bytes(&label, &current_bytes)?;
    let from_options = matches!(req.rows, NewRows::Fields(_));
    let (bytes, after) =
        append::appended_bytes(&current_bytes, &current, &new).map_err(|mut e| {
            if from_options {
                e.problems.iter_mut().for_each(|p| p.line = None);
            }
            e
        })?;
    let before = analysis::analyse(&current, &req.settings);
    let flags: Vec<Flag> = new
        .rows
        .iter()
        .flat_map(|r| tracking::flag_row(&before, r))
        .collect();
    if req.strict && !flags.is_empty() {
        let problems = new
            .rows
            .iter()
            .flat_map(|r| {
                flags
                    .iter()
                    .filter(move |f| f.xray == *r.xray && f.finger == r.finger.name())
                    .map(move |f| {
                        Problem::line(r.line, format!("refused (--strict): {}", f.reason))
                    })
            })
            .map(|mut p| {
                if from_options {
                    p.line = None;
                }
                p
            })
            .collect();
        return Err(DataError {
            file: new.path.clone(),
            problems,
        }
        .into());
    }
    let a = analysis::analyse(&after, &req.settings);
    let snapshot = tracking::snapshot(&a, now(), Event::Add);
    // Stage both files in full before replacing either: a history that cannot be
    // written stops the add with the dataset untouched. Between the two renames
    // a crash can only lose the snapshot ('phalanx snapshot' records it again).
    let history_bytes =
        history::appended_bytes(&req.history, &snapshot).map_err(io_err(&req.history))?;
    let staged_data = atomic::stage(&req.data, &bytes).map_err(io_err(&req.data))?;
    let staged_history =
        atomic::stage(&req.history, &history_bytes).map_err(io_err(&req.history))?;
    atomic::commit(staged_data, &req.data).map_err(io_err(&req.data))?;
    atomic::commit(staged_history, &req.history).map_err(io_err(&req.history))?;
    Ok(AddOutcome {
        added: new.rows.len(),
        xrays_before: current.xray_count(),
        xrays_after: after.xray_count(),
        flags,
        snapshot,
    })
}

/// Appends a snapshot of the dataset's current statistics to its history
/// (for data edited by hand). Holds the dataset's lock while it reads.
pub fn snapshot(data: &Path, history_path: &Path, settings: &Settings) -> Result<Snapshot, Error> {
    settings.validate().map_err(Error::Usage)?;
    csvinput::open_input(data)?; // a missing dataset is reported before any lock file is made
    let _lock = DatasetLock::acquire(data).map_err(io_err(data))?;
    let dataset = Dataset::load(data)?;
    let a = analysis::analyse(&dataset, settings);
    let snap = tracking::snapshot(&a, now(), Event::Snapshot);
    history::append(history_path, &snap).map_err(io_err(history_path))?;
    Ok(snap)
}

/// What `phalanx audit` asks for.
pub struct AuditRequest<'a> {
    pub rig: &'a Path,
    pub map: Option<&'a Path>,
    pub fix: Option<&'a Path>,
    pub data: &'a Path,
    pub settings: Settings,
    pub json: bool,
}

/// What `phalanx audit` found (and did).
pub struct AuditOutcome {
    /// The table or JSON document for standard output.
    pub output: Vec<u8>,
    /// Fingers outside the prediction interval in the input rig.
    pub outside: usize,
    /// Lines for standard error: what --fix wrote, warnings.
    pub messages: Vec<String>,
}

/// True when `a` and `b` name the same file (`b` may not exist yet).
fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| {
        let p = crate::atomic::resolve(p);
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        dir.canonicalize()
            .ok()
            .map(|d| d.join(p.file_name().unwrap_or_default()))
    };
    canon(a).is_some() && canon(a) == canon(b)
}

/// Audits a rig against the statistics, and with `fix` writes a corrected copy.
pub fn audit(req: &AuditRequest<'_>) -> Result<AuditOutcome, Error> {
    use crate::rig::{AuditedRig, Rig, map::NameMap};
    let map = req.map.map(NameMap::load).transpose()?;
    let fix_glb = match req.fix {
        Some(out) => {
            if same_file(req.rig, out) {
                return Err(Error::Usage(format!(
                    "--fix {} would overwrite the input rig; name a new file (the input is never modified)",
                    out.display()
                )));
            }
            match out
                .extension()
                .and_then(|e| e.to_str())
                .map(str::to_ascii_lowercase)
                .as_deref()
            {
                Some("glb" | "vrm") => Some(true),
                Some("gltf") => Some(false),
                _ => {
                    return Err(Error::Usage(format!(
                        "--fix {}: name the output .glb or .vrm (or .gltf for an embedded buffer)",
                        out.display()
                    )));
                }
            }
        }
        None => None,
    };
    let rig = Rig::load(req.rig, map.as_ref())?;
    let dataset = Dataset::load(req.data)?;
    let a = crate::analysis::analyse(&dataset, &req.settings);
    let chains = rig.chains.clone();
    let audited = AuditedRig::of(&rig.file.label, &chains, &rig.notes, &a);
    let mut messages = Vec::new();
    let mut fix_view = None;
    let fixed;
    if let (Some(out), Some(glb)) = (req.fix, fix_glb) {
        let dir = req.rig.parent().unwrap_or(Path::new("."));
        fixed = crate::rig::fix::fix(&rig.file, &audited.fingers, dir, glb)?;
        // Read the new file back before it is written: a copy that would not
        // load is never left on disk.
        let out_label = out.display().to_string();
        let re = crate::rig::GltfFile::from_bytes(&out_label, &fixed.bytes)
            .and_then(|f| Rig::from_file(f, map.as_ref()))
            .map_err(|e| {
                Error::render(
                    format!(
                        "the fixed copy of {} did not read back; nothing was written",
                        rig.file.label
                    ),
                    e,
                )
            })?;
        crate::atomic::replace(out, &fixed.bytes).map_err(io_err(out))?;
        let again = AuditedRig::of(&re.file.label, &re.chains, &re.notes, &a);
        messages.push(format!(
            "wrote {}: {} joints moved; re-audited, {} of {} fingers outside the prediction interval",
            out.display(),
            fixed.moved.iter().filter(|(_, d)| *d > 0.0).count(),
            again.outside(),
            again.fingers.len()
        ));
        messages.extend(fixed.warnings.iter().map(|w| format!("warning: {w}")));
        fix_view = Some(crate::report::json::FixView {
            output: out.to_str().unwrap_or("(non-UTF-8 path)"),
            moved: fixed
                .moved
                .iter()
                .map(|(node, shift)| crate::report::json::MovedView {
                    node,
                    shift: *shift,
                })
                .collect(),
            warnings: &fixed.warnings,
        });
    }
    let n_note = format!("{} X-rays", a.dataset.xrays);
    let output = if req.json {
        crate::report::json::audit(&a, &audited, fix_view)?
    } else {
        crate::report::audit::text(&audited, &a.dataset.path, &n_note, a.settings.confidence)
            .into_bytes()
    };
    Ok(AuditOutcome {
        output,
        outside: audited.outside(),
        messages,
    })
}
