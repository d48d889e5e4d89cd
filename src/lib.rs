//! phalanx: statistics of finger-joint positions from hand X-ray measurements.
//!
//! Reproduces Chaudhry, You, Jin and Zhang, "Statistical Analysis of Joint
//! Determination for Skeleton Driven Animation of Human Hands", and goes beyond
//! it. The `phalanx` command is a layer over this library: the statistics,
//! the rigs' audits, fixes, deformation and making, and the report's
//! rendering are reachable from here; the tracking of a dataset (`add`,
//! `remove`, `snapshot`), the gathering of the report's inputs from files
//! (`report::inputs`) and the terminal's text are internal to the crate, for
//! the command.
//!
//! # Example
//!
//! Load the paper's Table 1, analyse it, read a mean and place the joints of a
//! model finger:
//!
//! ```
//! use phalanx::analysis::{self, Settings, placement};
//! use phalanx::dataset::{Dataset, Finger, Quantity};
//! use std::path::Path;
//!
//! let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/measurements.csv");
//! let data = Dataset::load(&path)?;
//! let a = analysis::analyse(&data, &Settings::default());
//!
//! let index = a.finger(Finger::Index).expect("Table 1 has index fingers");
//! let j1 = index.quantity(Quantity::RelJ1).expect("every finger has J~1");
//! let t = j1.intervals.ci_t.expect("5 X-rays give a t interval");
//! println!("index J~1: mean {:.4}, 95% CI [{:.4}, {:.4}]", j1.mean, t.low, t.high);
//! // Eq. (6) by hand: (0.4865 + 0.4728 + 0.4862 + 0.5047 + 0.4728) / 5 = 0.4846
//! // (the paper prints 0.4946, a known erratum; Table 1's 1a gives 0.4867, not 0.4865).
//! assert!((j1.mean - 0.4846).abs() < 1e-4);
//!
//! // The PIP of an index finger 1000 units long sits at J1 = J~1 x 1000 from the MCP.
//! let placed = placement::place(&a, Finger::Index, 1000.0).expect("index statistics");
//! assert!((placed.joints[0].position.mean - 1000.0 * j1.mean).abs() < 1e-9);
//! # Ok::<(), phalanx::dataset::DataError>(())
//! ```
//!
//! # The public API
//!
//! - [`dataset`]: read and validate input. [`Dataset`](dataset::Dataset)
//!   (`load`, `from_bytes`, `from_reader`) holds the measurement rows;
//!   [`Finger`](dataset::Finger) and [`Quantity`](dataset::Quantity) name what
//!   is measured; [`claims::Claims`](dataset::claims::Claims) reads the numbers
//!   a paper states; [`history`](dataset::history) reads `history.jsonl`. Bad
//!   input is a [`DataError`](dataset::DataError) listing every
//!   [`Problem`](dataset::Problem) with its line and column.
//! - [`analysis`]: the statistics. [`analyse`](analysis::analyse) (or
//!   [`analyse_with`](analysis::analyse_with) and a
//!   [`Progress`](stats::bootstrap::Progress)) turns a dataset and
//!   [`Settings`](analysis::Settings) into an [`Analysis`](analysis::Analysis):
//!   per finger a [`FingerAnalysis`](analysis::FingerAnalysis) with each
//!   X-ray's values and a [`QuantityStats`](analysis::QuantityStats) per
//!   quantity (eqs. 1-10 of the paper plus SD, SE, median and four intervals).
//!   Beside it: [`claims::check`](analysis::claims::check) (the paper's numbers
//!   recomputed), [`coverage`](analysis::coverage) (how often each interval
//!   covers), [`groups`](analysis::groups) (statistics per sex, age band or
//!   side) and [`placement`](analysis::placement) (joint positions for a model
//!   finger of a given length).
//! - [`stats`]: the statistics types, [`Interval`](stats::Interval) and
//!   [`Intervals`](stats::Intervals) (t, percentile and BCa confidence intervals
//!   of the mean and the prediction interval), and the seeded bootstrap
//!   ([`bootstrap::resample_means`](stats::bootstrap::resample_means),
//!   [`bootstrap::Plan`](stats::bootstrap::Plan)).
//! - [`rig`]: glTF, VRM and FBX rigs (FBX read only), in sub-rooms
//!   [`read`](rig::read), [`find`](rig::find), [`judge`](rig::judge),
//!   [`fix`](rig::fix), [`make`](rig::make), [`deform`](rig::deform) and
//!   [`session`](rig::session);
//!   the paths below are re-exported. [`GltfFile`](rig::GltfFile) and [`Rig`](rig::Rig) read
//!   a file's finger chains (with a [`map::NameMap`](rig::map::NameMap) for
//!   unknown names); [`AuditedRig::of`](rig::AuditedRig::of) judges them
//!   ([`judge`](rig::judge)); [`fix::fix`](rig::fix::fix) writes a corrected
//!   copy; [`session::audit`](rig::session::audit) does all three for a file;
//!   [`reference`](rig::reference) reads the popular rigs of `data/rigs/`.
//!   [`deform`](rig::deform) and [`skin`](rig::skin) measure skin deformation
//!   of a curled hand (the `phalanx deform` command); [`find`](rig::find)
//!   finds a hand's fingers on its skin and [`make`](rig::make) rigs them
//!   ([`session::rig`](rig::session::rig), the `phalanx rig` command).
//! - [`report`]: everything shown. [`render`](report::render()) turns
//!   [`ReportInputs`](report::view::ReportInputs) into the report files
//!   ([`Formats`](report::Formats), [`Templates`](report::render::Templates)),
//!   written with [`writer::write_all`](report::writer::write_all);
//!   [`view`](report::view) is the data the templates see; [`json`](report::json)
//!   writes the JSON documents (schemas in `docs/schema/`); [`plots`](report::plots)
//!   draws the SVG plots and [`render3d`](report::render3d) deformation figures.
//! - [`error`]: [`Error`](error::Error), what stops a command, with its exit
//!   status ([`EXIT_DATA`](error::EXIT_DATA), [`EXIT_FAILURE`](error::EXIT_FAILURE)).
//! - [`synth`]: realistic synthetic datasets for benchmarks and tests.
//! - [`cli::main`]: the `phalanx` command itself.
//!
//! # Inside
//!
//! Modules depend one way: `dataset` (ingest, validate) -> `analysis`
//! (statistics) -> `rig` (read, find, judge, fix, make, deform rigs) ->
//! `report` (views, plots, writers) -> `cmd` (one module per command) -> `cli`
//! (dispatch); `track` holds the file operations of tracking a dataset (add,
//! remove, snapshot). Three leaves serve them all: `stats`, the self-contained
//! statistics core; `format`, where the numbers shown become text; and
//! `atomic`, which replaces a file whole or not at all. `atomic`, `format` and `track` are
//! `pub(crate)` and `cmd` private: free to change without breaking a library
//! user; every other module above is public.

pub mod analysis;
pub(crate) mod atomic;
pub mod cli;
mod cmd;
pub mod dataset;
pub mod error;
pub(crate) mod format;
pub mod report;
pub mod rig;
pub use phalanx_stats as stats;
pub mod synth;
pub(crate) mod track;
