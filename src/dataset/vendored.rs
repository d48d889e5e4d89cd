//! For the unit tests: the vendored data a package of the crate leaves out (the GPL-3.0
//! atlas, Cargo.toml's `exclude`), or the test's skip, printed.

use super::Dataset;
use std::path::Path;

/// Where the atlas's measurements are, from the crate's root (the tests' directory).
pub(crate) const ATLAS: &str = "data/atlas/measurements.csv";

/// Where the atlas's landmarks are.
pub(crate) const ATLAS_LANDMARKS: &str = "data/atlas/landmarks.csv";

/// Says that the running test skips (all of it, or the part that needs what is absent)
/// and why: one line `skipped: <test>: <reason>` on standard error, the test named by its
/// thread, written past the harness's capture in one write, as the integration tests'
/// `common::skip` does; `cargo test 2>&1 | grep -c 'skipped: '` counts them.
pub(crate) fn skip(reason: impl std::fmt::Display) {
    use std::io::Write;
    let thread = std::thread::current();
    // One line, whatever the reason (a `DataError` is several).
    let reason = reason.to_string();
    let reason: Vec<&str> = reason.lines().map(str::trim).collect();
    let test = thread.name().unwrap_or("main");
    let line = format!("skipped: {test}: {}\n", reason.join(" "));
    let _ = std::io::stderr().write_all(line.as_bytes());
}

/// The bytes of `path`, or `None` with the skip printed.
pub(crate) fn read(path: &str) -> Option<Vec<u8>> {
    std::fs::read(path)
        .map_err(|e| skip(format!("{path} could not be read ({e})")))
        .ok()
}

/// The text of `path`, or `None` with the skip printed.
pub(crate) fn text(path: &str) -> Option<String> {
    std::fs::read_to_string(path)
        .map_err(|e| skip(format!("{path} could not be read ({e})")))
        .ok()
}

/// The atlas's measurements ([`ATLAS`]), or `None` with the skip printed.
pub(crate) fn atlas() -> Option<Dataset> {
    Dataset::load(Path::new(ATLAS))
        .map_err(|e| skip(format!("{ATLAS} could not be read ({e})")))
        .ok()
}
