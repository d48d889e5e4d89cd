//! The statistics core: descriptive statistics, Student-t and normal
//! quantiles, the bootstrap of means, seeded randomness, and intervals.
//!
//! Self-contained in the manner of criterion's `stats` module: it depends on no
//! other module of phalanx (not on the dataset, not on the analysis) and works
//! on plain slices of `f64`. What a value means (a finger, a quantity) is the
//! caller's business; [`crate::analysis`] builds on it. Its documentation and
//! its few messages call the unit resampled an X-ray, as phalanx's users do.

pub mod bootstrap;
pub mod delta;
pub mod describe;
pub mod estimate;
pub mod interval;
pub mod region;
pub mod rng;

pub use estimate::Intervals;
pub use interval::Interval;
