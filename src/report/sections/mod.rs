//! The report's sections, one file each: its view (strings for the templates) and its builder.
//!
//! Templates never compute or format numbers; every section's view is made of strings
//! from [`crate::format`] and [`super::phrases`], built from finished results only
//! ([`inputs::ReportInputs`]), never from raw measurement rows. [`super::view`] puts
//! them together into the page; adding a section is a file here and a block in each
//! template.

pub mod atlas;
pub mod claims;
pub mod common;
pub mod coverage;
pub mod deform;
pub mod derived;
pub mod figures;
pub mod groups;
pub mod inputs;
pub mod key_results;
pub mod literature;
pub mod made;
pub mod placement;
pub mod provenance;
pub mod region;
pub mod rigs;
pub mod statistics;
pub mod table1;
pub mod toc;
pub mod tracking;
