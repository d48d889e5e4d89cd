//! phalanx: statistics of finger-joint positions from hand X-ray measurements.
//!
//! Reproduces Chaudhry, You, Jin and Zhang, "Statistical Analysis of Joint
//! Determination for Skeleton Driven Animation of Human Hands", and goes beyond it.
//! Modules depend one way: [`dataset`] (ingest, validate) -> [`analysis`]
//! (statistics, bootstrap, claims, rig audit) -> [`rig`] (glTF rigs in and
//! out) -> [`report`] (views, plots, writers) -> `cmd` (one module per
//! command) -> [`cli`] (dispatch). [`track`] holds the file operations of
//! tracking a dataset (add, snapshot).

pub mod analysis;
pub mod atomic;
pub mod cli;
mod cmd;
pub mod dataset;
pub mod error;
pub mod report;
pub mod rig;
pub mod synth;
pub mod track;
