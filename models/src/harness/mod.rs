//! The harness every estimator of this crate runs in: the scenario trait,
//! the Monte Carlo driver, shards and merge. Run results, replay models,
//! the JSON report and the plots are the replay library's
//! (`nav_replay`), re-exported here for the scenarios.
//!
//! # Adding a scenario
//! Implement [`Scenario`] and add one line to `navsim`'s registry. A run is a
//! pure function of its seed and [`RunOptions`] ([`Scenario::run_one`]); the driver
//! runs seeds `seed, seed + 1, ..., seed + runs - 1` in parallel and hands the results
//! to [`Scenario::summarize`] **in seed order**, so the JSON does not depend on the
//! number of threads or on how the seeds were split into shards.
//!
//! # Adding a replay model
//! Implement [`ReplayModel`] and add one line to `navsim`'s registry. A
//! vehicle made of the INS core block and its sensor blocks needs no
//! `ReplayModel` of its own: implement [`nav_ins::InsVehicle`] for it and
//! register `nav_replay::ins::InsReplay::<Vehicle, N>::new()`.
//!
//! # Shards
//! `--shard K/N` runs the seed indices `i` (0-based) with `i % N == K - 1` and writes a
//! [`ShardFile`] (`shard-K-of-N.json`) holding every per-run [`RunResult`];
//! [`merge_shards`] checks that a set of shard files covers every seed exactly once
//! and gives back the results in seed order, from which [`summary_json`] builds the
//! same JSON the unsharded run prints.

mod driver;
mod scenario;
mod shard;

pub use driver::{run_seeds, summary_json, RunOptions};
pub use nav_replay::output::{plot, report};
#[cfg(test)]
pub(crate) use nav_replay::temp_dir::TempDir;
pub use nav_replay::{
    metric_values, progress_bar, write_run_tables, ProgressBar, ReplayModel, ReplayOptions,
    ReplayOutput, RunError, RunHealth, RunResult, RunTable, SensorHealth,
};
pub use scenario::Scenario;
pub use shard::{find_shard_files, merge_shards, seeds, Merged, Shard, ShardFile, SHARD_FORMAT};

#[cfg(test)]
mod tests {
    use super::{RunHealth, RunResult, SensorHealth};

    fn counts(accepted: u64) -> SensorHealth {
        SensorHealth {
            accepted,
            ..SensorHealth::default()
        }
    }

    /// A run's health survives a shard file (JSON) unchanged.
    #[test]
    fn health_travels_through_shard_files() {
        let mut r = RunResult::new(7).with_metric("x", 1.5);
        r.health = RunHealth {
            sensors: vec![("dvl".into(), counts(3))],
            covariance_repairs: 2,
            replays: Some(9),
            imu_gaps: None,
            lockout_releases: Some(1),
        };
        let text = serde_json::to_string(&r).unwrap();
        let back: RunResult = serde_json::from_str(&text).unwrap();
        assert_eq!(back, r);
    }
}
