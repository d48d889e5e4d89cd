//! Everything phalanx shows: exporters that turn finished results into bytes.
//!
//! Reads analysis results only, never raw measurement rows. Every exporter is
//! pure (returns bytes or text); writing files happens in one place.

pub mod csv_out;
pub mod format;
pub mod json;
pub mod plots;
pub mod text;
