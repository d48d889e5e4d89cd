//! The integration tests: one binary, one module per area.

mod common;

mod architecture;
mod audit;
mod bad_inputs;
mod browser;
mod check;
mod confidence_level;
mod coverage;
mod crash_report;
mod data;
mod deform;
mod docs;
mod everyday;
mod fbx;
mod import;
mod lab;
mod literature;
mod make;
mod make_fuzz;
mod option_ranges;
mod options;
mod place;
mod properties;
mod readable;
mod report;
mod rig;
mod schema;
mod stats;
mod synth;
mod track;
