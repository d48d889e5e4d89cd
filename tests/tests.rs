//! The integration tests: one binary, one module per area.

#[path = "audit.rs"]
mod audit;
#[path = "bad_inputs.rs"]
mod bad_inputs;
#[path = "browser.rs"]
mod browser;
#[path = "check.rs"]
mod check;
#[path = "coverage.rs"]
mod coverage;
#[path = "crash_report.rs"]
mod crash_report;
#[path = "data.rs"]
mod data;
#[path = "options.rs"]
mod options;
#[path = "place.rs"]
mod place;
#[path = "properties.rs"]
mod properties;
#[path = "report.rs"]
mod report;
#[path = "stats.rs"]
mod stats;
#[path = "synth.rs"]
mod synth;
#[path = "track.rs"]
mod track;
