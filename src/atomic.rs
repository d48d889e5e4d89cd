//! Atomic file replacement: the one mechanism behind every file phalanx writes.
//!
//! A file is written in full to a temporary file beside its target, synced, and
//! renamed over the target, so a reader (or a crash) sees the old or the new
//! content, never a mix.

use std::io::Write;
use std::path::Path;
use tempfile::NamedTempFile;

/// The file a path really names: a symbolic link is followed, so replacing
/// it updates the link's target instead of turning the link into a file.
pub(crate) fn resolve(target: &Path) -> std::path::PathBuf {
    std::fs::canonicalize(target).unwrap_or_else(|_| target.to_path_buf())
}

/// True when `a` and `b` name the same file (`b` may not exist yet).
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| {
        let p = resolve(p);
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

/// Writes `bytes` to a synced temporary file in the directory of `target`
/// (created if missing). Rename it into place with [`commit`] (given the same
/// `target`; links are followed by both).
pub(crate) fn stage(target: &Path, bytes: &[u8]) -> std::io::Result<NamedTempFile> {
    let target = &resolve(target);
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(".phalanx-")
        .suffix(".tmp")
        .tempfile_in(dir)?;
    tmp.write_all(bytes)?;
    // Temporary files are private (0600); the result gets the target's
    // permissions, or the usual 0644 for a new file, so reports can be served.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(target).map_or(0o644, |m| m.permissions().mode());
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))?;
    }
    tmp.as_file().sync_all()?;
    Ok(tmp)
}

/// Renames a staged file over `target` and syncs the directory so the rename is durable.
pub(crate) fn commit(staged: NamedTempFile, target: &Path) -> std::io::Result<()> {
    let target = &resolve(target);
    staged.persist(target).map_err(|e| e.error)?;
    if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
        // Directory fsync is best effort: not every platform or file system allows it.
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// Replaces `target` with `bytes` atomically.
pub(crate) fn replace(target: &Path, bytes: &[u8]) -> std::io::Result<()> {
    commit(stage(target, bytes)?, target)
}

/// The first existing ancestor of `path` (itself included) that is not a directory.
fn file_above(path: &Path) -> Option<&Path> {
    path.ancestors()
        .filter(|p| !p.as_os_str().is_empty())
        .find(|p| p.exists())
        .filter(|p| !p.is_dir())
}

/// Whether a file can be written at `target`, checked before any work: it is
/// not a directory, nothing above it is a file, and it does not exist unless
/// `force`. The error says what to do.
pub(crate) fn check_target(target: &Path, force: bool) -> Result<(), String> {
    if target.is_dir() {
        return Err("this is a directory; name the file to write".into());
    }
    if let Some(f) = target.parent().and_then(file_above) {
        return Err(format!(
            "{} is a file, not a directory, so nothing can be written under it",
            f.display()
        ));
    }
    if target.exists() && !force {
        return Err("the file exists; give --force to replace it, or name a new file".into());
    }
    Ok(())
}

/// Whether the files `names` can be written in the directory `dir`, checked
/// before any work: it is not a file (nor under one), and none of them exists
/// unless `force`; every existing one is named.
pub(crate) fn check_dir_targets(dir: &Path, names: &[String], force: bool) -> Result<(), String> {
    if let Some(f) = file_above(dir) {
        let what = if f == dir {
            "this is a file, not a directory".to_string()
        } else {
            format!("{} is a file, not a directory", f.display())
        };
        return Err(format!(
            "{what}; give a directory (it is created when missing)"
        ));
    }
    let existing: Vec<String> = names
        .iter()
        .map(|n| dir.join(n))
        .filter(|p| p.exists())
        .map(|p| p.display().to_string())
        .collect();
    if existing.is_empty() || force {
        return Ok(());
    }
    let one = existing.len() == 1;
    Err(format!(
        "{} exist{}; give --force to replace {}, or another directory",
        existing.join(", "),
        if one { "s" } else { "" },
        if one { "it" } else { "them" }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_content_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        std::fs::write(&p, "old").unwrap();
        replace(&p, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let fresh = dir.path().join("b.csv");
            replace(&fresh, b"x").unwrap();
            let mode = std::fs::metadata(&fresh).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644);
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
            replace(&p, b"newer").unwrap();
            let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o600, "the target's permissions are kept");
            // A link is followed: its target is replaced, the link stays a link.
            let real = dir.path().join("real.csv");
            std::fs::write(&real, "old").unwrap();
            let link = dir.path().join("link.csv");
            std::os::unix::fs::symlink(&real, &link).unwrap();
            replace(&link, b"via link").unwrap();
            assert_eq!(std::fs::read_to_string(&real).unwrap(), "via link");
            assert!(
                std::fs::symlink_metadata(&link)
                    .unwrap()
                    .file_type()
                    .is_symlink()
            );
        }
    }
}
