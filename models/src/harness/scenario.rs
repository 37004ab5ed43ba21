//! The trait of a built-in simulation scenario.

use std::path::Path;

use nav_runtime::log::LogDir;
use serde_json::{Map, Value};

use super::{write_run_tables, RunError, RunOptions, RunResult};

/// A built-in simulation scenario.
pub trait Scenario: Send + Sync {
    /// The name used on the command line (`navsim scenario <NAME>`).
    fn name(&self) -> &'static str;
    /// One line for `navsim list`.
    fn description(&self) -> &'static str {
        ""
    }
    /// Number of Monte Carlo runs without `--runs`.
    fn default_runs(&self) -> usize;
    /// Whether `--smooth` is supported (the run can be recorded and smoothed).
    fn can_smooth(&self) -> bool {
        false
    }
    /// Whether `--draw-biases` changes the runs of `navsim scenario`
    /// (default: no, and the flag is refused: it would change nothing).
    fn draws_biases(&self) -> bool {
        false
    }
    /// Whether `--draw-biases` changes the log of `navsim simulate`
    /// (default: as it changes the runs).
    fn draws_biases_in_log(&self) -> bool {
        self.draws_biases()
    }
    /// Fault names accepted by `--faults` (default: none).
    fn faults(&self) -> &'static [&'static str] {
        &[]
    }
    /// Runs one simulation + estimation with `seed`. Must be deterministic in
    /// `(seed, options)` and must not print to stdout.
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError>;
    /// Scenario-specific JSON keys from all runs (in seed order). The driver adds
    /// `scenario`, `runs` and `seed`.
    fn summarize(
        &self,
        runs: &[RunResult],
        options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError>;
    /// Writes per-run CSV files and plots into `dir` (which exists). The default writes
    /// each run's tables as `run-<seed>-<table>.csv`.
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        write_run_tables(runs, dir)
    }
    /// The synthetic sensor log of run `seed` (for `navsim simulate`), if the scenario
    /// can produce one. Replaying it should reproduce [`Scenario::run_one`].
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        let _ = (seed, options);
        None
    }
}
