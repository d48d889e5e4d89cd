//! phalanx: statistics of finger-joint positions from hand X-ray measurements.
//!
//! Reproduces Chaudhry, You, Jin and Zhang, "Statistical Analysis of Joint
//! Determination for Skeleton Driven Animation of Human Hands", and goes beyond it.
//! Modules depend one way: [`dataset`] (ingest, validate) -> [`analysis`]
//! (statistics, bootstrap, claims, rig audit) -> [`rig`] (glTF rigs in and
//! out) -> [`report`] (views, plots, writers) -> `cmd` (one module per
//! command) -> [`cli`] (dispatch). [`track`] holds the file operations of
//! tracking a dataset (add, snapshot). Two leaves serve them all:
//! [`stats`], the self-contained statistics core, and [`format`], where every
//! number shown becomes text.

pub mod analysis;
pub(crate) mod atomic;
pub mod cli;
mod cmd;
pub mod dataset;
pub mod error;
pub(crate) mod format;
pub mod report;
pub mod rig;
pub mod stats;
pub mod synth;
pub(crate) mod track;
