//! The harness every estimator runs in: the scenario and replay-model
//! traits, run results and errors, the Monte Carlo driver, shards and merge,
//! the JSON report and the plots.
//!
//! # Adding a scenario
//! Implement [`Scenario`] and add one line to [`crate::cli::scenarios`]. A run is a
//! pure function of its seed and [`RunOptions`] ([`Scenario::run_one`]); the driver
//! runs seeds `seed, seed + 1, ..., seed + runs - 1` in parallel and hands the results
//! to [`Scenario::summarize`] **in seed order**, so the JSON does not depend on the
//! number of threads or on how the seeds were split into shards.
//!
//! # Adding a replay model
//! Implement [`ReplayModel`] and add one line to [`crate::cli::replay_models`].
//! A vehicle made of the INS core block and any of the depth, DVL, compass and
//! USBL blocks needs no `ReplayModel` of its own: implement
//! [`crate::navigator::InsVehicle`] for it (which generated sensor reads
//! which log file) and register `crate::sdins25::InsReplay::<Vehicle, N>::new()`.
//!
//! # Shards
//! `--shard K/N` runs the seed indices `i` (0-based) with `i % N == K - 1` and writes a
//! [`ShardFile`] (`shard-K-of-N.json`) holding every per-run [`RunResult`];
//! [`merge_shards`] checks that a set of shard files covers every seed exactly once
//! and gives back the results in seed order, from which [`summary_json`] builds the
//! same JSON the unsharded run prints.

mod error;
mod health;
pub mod plot;
mod replay;
pub mod report;
mod run;
mod scenario;
mod shard;
#[cfg(test)]
mod temp_dir;

pub use error::RunError;
pub use health::{RunHealth, SensorHealth};
pub use replay::{ReplayModel, ReplayOptions, ReplayOutput};
pub use run::{
    metric_values, progress_bar, run_seeds, summary_json, write_run_tables, ProgressBar,
    RunOptions, RunResult, RunTable,
};
pub use scenario::Scenario;
pub use shard::{find_shard_files, merge_shards, seeds, Merged, Shard, ShardFile, SHARD_FORMAT};
#[cfg(test)]
pub(crate) use temp_dir::TempDir;
