//! Empty: Cargo resolves a crate's build-dependencies only when it has a build script,
//! and the build-dependencies are what unify the features of the host crates.
fn main() {}
