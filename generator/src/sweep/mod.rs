//! Parameter sweeps over pressure, flux, contact temperature and surface
//! samples (`tcgen sweep`), through the two-phase self-consistent solver:
//!
//! | module | content |
//! |---|---|
//! | [`config`] | the sweep file: case keys plus `[sweep]` |
//! | [`path`] | one path (sample, flux, temperature) over all pressures |
//! | [`run`] | the parallel runner, checkpoints, atomic output |
//! | [`checkpoint`] | the checkpoint file of `--resume` |
//! | [`shard`] | deterministic subsets for clusters |
//! | [`merge`] | shards into one table |
//! | [`ensemble`] | statistics over the samples |
//! | [`progress`] | progress bar or log lines |

pub mod checkpoint;
pub mod config;
pub mod ensemble;
pub mod merge;
pub mod path;
pub mod progress;
pub mod run;
pub mod shard;

pub use config::SweepConfig;
pub use merge::merge_tables;
pub use progress::ProgressMode;
pub use run::{SweepOptions, SweepReport, Timing, run_sweep};
pub use shard::Shard;
