//! The one place that writes report files: all or nothing, each file atomically.

use crate::atomic;
use crate::error::Error;
use std::path::{Path, PathBuf};

/// A rendered output file: its path relative to the output directory, and its bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    pub path: PathBuf,
    pub bytes: Vec<u8>,
}

impl OutputFile {
    pub fn new(path: impl Into<PathBuf>, bytes: Vec<u8>) -> OutputFile {
        OutputFile {
            path: path.into(),
            bytes,
        }
    }
}

/// Writes every file under `dir`. Each is first written in full to a temporary
/// file beside its target and synced; only when all are staged are they renamed
/// into place. A failure before that point leaves every existing file untouched.
/// Afterwards, `.svg` files in the directories written to that this run did not
/// produce (plots of an older run) are removed, so the directory holds exactly
/// one report.
pub fn write_all(dir: &Path, files: &[OutputFile]) -> Result<(), Error> {
    let mut staged = Vec::with_capacity(files.len());
    for f in files {
        let target = dir.join(&f.path);
        let tmp = atomic::stage(&target, &f.bytes).map_err(Error::write(&target))?;
        staged.push((tmp, target));
    }
    let mut written: Vec<PathBuf> = Vec::new();
    for (tmp, target) in staged {
        atomic::commit(tmp, &target).map_err(Error::write(&target))?;
        written.push(target);
    }
    remove_stale_plots(&written)?;
    Ok(())
}

/// Removes `.svg` files beside the written ones that were not written now.
fn remove_stale_plots(written: &[PathBuf]) -> Result<(), Error> {
    let mut dirs: Vec<&Path> = written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .filter_map(|p| p.parent())
        .collect();
    dirs.sort();
    dirs.dedup();
    for d in dirs {
        let entries = std::fs::read_dir(d).map_err(Error::write(d))?;
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "svg") && !written.contains(&p) {
                std::fs::remove_file(&p).map_err(Error::write(&p))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_all_files_and_removes_stale_plots() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("plots")).unwrap();
        std::fs::write(dir.path().join("plots/old.svg"), "old").unwrap();
        let files = vec![
            OutputFile::new("index.html", b"<html>".to_vec()),
            OutputFile::new("plots/new.svg", b"<svg/>".to_vec()),
        ];
        write_all(dir.path(), &files).unwrap();
        assert_eq!(
            std::fs::read(dir.path().join("index.html")).unwrap(),
            b"<html>"
        );
        assert_eq!(
            std::fs::read(dir.path().join("plots/new.svg")).unwrap(),
            b"<svg/>"
        );
        assert!(!dir.path().join("plots/old.svg").exists());
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .collect();
        assert!(leftovers.is_empty());
    }

    #[test]
    fn an_unwritable_target_leaves_the_others_untouched() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("index.html"), "previous").unwrap();
        // A directory where a file should go: staging works, the rename fails... but the
        // file staged first must not have replaced its target either, since staging of
        // the second (inside a path that is a file) fails before any rename.
        std::fs::write(dir.path().join("plots"), "a file, not a directory").unwrap();
        let files = vec![
            OutputFile::new("index.html", b"new".to_vec()),
            OutputFile::new("plots/x.svg", b"<svg/>".to_vec()),
        ];
        assert!(write_all(dir.path(), &files).is_err());
        assert_eq!(
            std::fs::read_to_string(dir.path().join("index.html")).unwrap(),
            "previous"
        );
    }
}
